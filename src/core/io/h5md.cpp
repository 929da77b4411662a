// H5MD trajectory writer (see h5md.hpp, doc/io.md).
#include "io/h5md.hpp"

#include "config/features.hpp"
#include "utils/errors.hpp"
#ifdef SRD
#include "srd/Fluid.hpp"
#endif

#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <sys/stat.h>
#include <cstdint>
#include <string>
#include <vector>

namespace Marble::IO {

namespace {

constexpr hsize_t unlimited = H5S_UNLIMITED;
constexpr hsize_t chunk_frames = 256; // step/time/edges chunks
constexpr hsize_t max_chunk_rows = 1 << 16;

/** The system error of a failed call, if there is one. */
std::string errno_text(int err) {
  // only causes a user can act on; the MPI-IO layer leaves unrelated codes behind
  switch (err) {
  case ENOENT: case EACCES: case EPERM: case ENOSPC: case EROFS: case EFBIG: case EDQUOT:
  case ENOTDIR: case EISDIR:
    return std::strerror(err);
  default:
    return "unknown cause";
  }
}

/** A time-series group: value [frames, N(, 3)] with shared step/time. */
struct Series {
  std::string name;
  hid_t group = -1, value = -1;
  int cols = 0; // 0: one value per particle, 3: a vector per particle
  hid_t file_type = -1, mem_type = -1;
};

/** Where this rank's particles go in a frame whose rows are ordered by id:
 * (row, local index) in increasing row order, and the runs [first row,
 * length) of consecutive rows. */
struct RowLayout {
  std::vector<std::pair<hsize_t, int>> rows;
  std::vector<std::array<hsize_t, 2>> runs;
};

/** @p all_ids: every rank's ids, sorted; @p local: this rank's @p n ids. */
RowLayout row_layout(std::vector<int> const &all_ids, int const *local, int n) {
  RowLayout l;
  l.rows.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    auto const it = std::lower_bound(all_ids.begin(), all_ids.end(), local[i]);
    l.rows.emplace_back(static_cast<hsize_t>(it - all_ids.begin()), i);
  }
  std::sort(l.rows.begin(), l.rows.end());
  for (auto const &[r, i] : l.rows) {
    if (!l.runs.empty() && l.runs.back()[0] + l.runs.back()[1] == r)
      ++l.runs.back()[1];
    else
      l.runs.push_back({r, 1});
  }
  return l;
}

} // namespace

struct H5mdFile::Impl {
  Communicator comm;
  std::string path;
  H5mdFields fields;
  hid_t file = -1, particles = -1, atoms = -1, box = -1, edges_group = -1, edges = -1;
  hid_t step = -1, time = -1; // owned by the first series group; hard links elsewhere
  std::vector<Series> series;
  long frames = 0, n = -1;
  // SRD particles: /particles/srd (n_srd = -1: the file has none)
  hid_t srd = -1, srd_box = -1;
  std::vector<Series> srd_series;
  long n_srd = -1;
  bool mpio = false; // MPI-IO driver (MPI initialised, parallel HDF5)
  std::array<bool, 3> box_periodic{true, true, true};

  // errno is reset at the start of each public call, so a system error seen
  // here (e.g. "File too large", "No space left on device") is this call's.
  void check(herr_t rc, char const *what) const {
    if (rc < 0)
      throw Utils::RuntimeError("H5MD: " + std::string(what) + " failed for '" + path + "'" +
                                (errno ? " (" + std::string(std::strerror(errno)) + ")" : ""));
  }
  hid_t check_id(hid_t id, char const *what) const {
    check(id < 0 ? -1 : 0, what);
    return id;
  }

  hid_t group(hid_t loc, char const *name) const {
    return check_id(H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "creating a group");
  }

  void attr_string(hid_t loc, char const *name, std::string const &value) const {
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, std::max<std::size_t>(value.size(), 1) + 1);
    H5Tset_strpad(t, H5T_STR_NULLTERM);
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = check_id(H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT), "creating an attribute");
    std::vector<char> buf(value.size() + 2, '\0');
    std::copy(value.begin(), value.end(), buf.begin());
    check(H5Awrite(a, t, buf.data()), "writing an attribute");
    H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
  }

  void attr_strings(hid_t loc, char const *name, std::vector<std::string> const &values) const {
    std::size_t len = 1;
    for (auto const &v : values)
      len = std::max(len, v.size() + 1);
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, len);
    H5Tset_strpad(t, H5T_STR_NULLTERM);
    hsize_t const dim = values.size();
    hid_t sp = H5Screate_simple(1, &dim, nullptr);
    hid_t a = check_id(H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT), "creating an attribute");
    std::vector<char> buf(len * values.size(), '\0');
    for (std::size_t i = 0; i < values.size(); ++i)
      std::copy(values[i].begin(), values[i].end(), buf.begin() + i * len);
    check(H5Awrite(a, t, buf.data()), "writing an attribute");
    H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
  }

  void attr_ints(hid_t loc, char const *name, std::vector<int> const &values) const {
    hsize_t const dim = values.size();
    hid_t sp = values.size() == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &dim, nullptr);
    hid_t a = check_id(H5Acreate2(loc, name, H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT),
                       "creating an attribute");
    check(H5Awrite(a, H5T_NATIVE_INT, values.data()), "writing an attribute");
    H5Aclose(a);
    H5Sclose(sp);
  }

  /** Extensible dataset of shape [0, dims...]. */
  hid_t dataset(hid_t loc, char const *name, hid_t type, std::vector<hsize_t> const &inner,
                hsize_t chunk_first) const {
    std::vector<hsize_t> dims{0}, maxdims{unlimited}, chunk{chunk_first};
    for (auto d : inner) {
      dims.push_back(d);
      maxdims.push_back(d);
      chunk.push_back(std::max<hsize_t>(1, std::min(d, max_chunk_rows)));
    }
    hid_t sp = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data());
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    check(H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data()), "setting the chunk size");
    hid_t ds = check_id(H5Dcreate2(loc, name, type, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT),
                        "creating a dataset");
    H5Pclose(dcpl);
    H5Sclose(sp);
    return ds;
  }

  /** Grow @p ds to @p frames along its first axis. */
  void extend(hid_t ds, hsize_t frames_new) const {
    hid_t sp = H5Dget_space(ds);
    int const rank = H5Sget_simple_extent_ndims(sp);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
    H5Sclose(sp);
    dims[0] = frames_new;
    check(H5Dset_extent(ds, dims.data()), "extending a dataset");
  }

  hid_t xfer() const {
    hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
#if defined(MARBLE_HAVE_MPI) && defined(H5_HAVE_PARALLEL)
    if (mpio)
      check(H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE), "setting collective transfer");
#endif
    return dxpl;
  }

  /** Collective write of one frame's block [frame, 0.., 0..] from rank 0 only. */
  void write_root(hid_t ds, hid_t mem_type, void const *buf, std::vector<hsize_t> const &inner) const {
    hid_t fs = H5Dget_space(ds);
    std::vector<hsize_t> start(inner.size() + 1, 0), count{1};
    start[0] = static_cast<hsize_t>(frames);
    count.insert(count.end(), inner.begin(), inner.end());
    hsize_t n_mem = 1;
    for (auto d : inner)
      n_mem *= d;
    hid_t ms = H5Screate_simple(1, &n_mem, nullptr);
    if (comm.is_root()) {
      check(H5Sselect_hyperslab(fs, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
            "selecting");
    } else {
      H5Sselect_none(fs);
      H5Sselect_none(ms);
    }
    hid_t dxpl = xfer();
    herr_t rc = H5Dwrite(ds, mem_type, ms, fs, dxpl, buf);
    H5Pclose(dxpl);
    H5Sclose(ms);
    H5Sclose(fs);
    check(rc, "writing a dataset");
  }

  /** Collective write of this rank's rows of @p s, laid out by @p l: the
   * values, in the layout's row order, are in @p dbuf or @p ibuf (by the
   * series' memory type). */
  void write_rows(Series const &s, RowLayout const &l, std::vector<double> const &dbuf,
                  std::vector<int> const &ibuf) const {
    auto const &runs = l.runs;
    auto const n_rows = static_cast<hsize_t>(l.rows.size());
    double const dummy = 0.;
    void const *buf = l.rows.empty()                 ? static_cast<void const *>(&dummy)
                      : s.mem_type == H5T_NATIVE_DOUBLE ? static_cast<void const *>(dbuf.data())
                                                        : static_cast<void const *>(ibuf.data());
    hid_t fs = H5Dget_space(s.value);
    hsize_t const per_row = s.cols == 0 ? 1 : static_cast<hsize_t>(s.cols);
    hsize_t n_mem = std::max<hsize_t>(1, n_rows * per_row);
    hid_t ms = H5Screate_simple(1, &n_mem, nullptr);
    if (runs.empty()) {
      H5Sselect_none(fs);
      H5Sselect_none(ms);
    } else {
      H5Sselect_none(fs);
      for (auto const &r : runs) {
        std::array<hsize_t, 3> start{static_cast<hsize_t>(frames), r[0], 0};
        std::array<hsize_t, 3> count{1, r[1], per_row};
        check(H5Sselect_hyperslab(fs, H5S_SELECT_OR, start.data(), nullptr, count.data(), nullptr),
              "selecting rows");
      }
    }
    hid_t dxpl = xfer();
    herr_t rc = H5Dwrite(s.value, s.mem_type, ms, fs, dxpl, buf);
    H5Pclose(dxpl);
    H5Sclose(ms);
    H5Sclose(fs);
    check(rc, "writing a dataset");
  }

  /** A time series @p name (value [frames, n(, cols)]) in group @p parent, appended to @p into;
   * nothing if @p on is false or there are no rows. */
  void add_series(std::vector<Series> &into, hid_t parent, hsize_t n, bool on, char const *name, int cols,
                  hid_t file_type, hid_t mem_type) {
    if (!on || n == 0)
      return;
    Series s;
    s.name = name;
    s.cols = cols;
    s.file_type = file_type;
    s.mem_type = mem_type;
    s.group = group(parent, name);
    std::vector<hsize_t> inner{n};
    if (cols)
      inner.push_back(static_cast<hsize_t>(cols));
    s.value = dataset(s.group, "value", file_type, inner, 1);
    into.push_back(s);
  }

  void create_datasets(long n_particles, long n_srd_particles) {
    if (n_srd_particles > 0) {
      n_srd = n_srd_particles;
      srd = group(particles, "srd");
      srd_box = group(srd, "box");
      attr_ints(srd_box, "dimension", {3});
      std::vector<std::string> boundary;
      for (int d = 0; d < 3; ++d)
        boundary.push_back(box_periodic[d] ? "periodic" : "none");
      attr_strings(srd_box, "boundary", boundary);
      auto const Ns = static_cast<hsize_t>(n_srd_particles);
      auto add_srd = [&](bool on, char const *name, int cols, hid_t file_type, hid_t mem_type) {
        add_series(srd_series, srd, Ns, on, name, cols, file_type, mem_type);
      };
      add_srd(fields.position, "position", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
      add_srd(fields.velocity, "velocity", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
      add_srd(fields.species, "species", 0, H5T_STD_I32LE, H5T_NATIVE_INT);
      add_srd(fields.id, "id", 0, H5T_STD_I32LE, H5T_NATIVE_INT);
    }
    auto const N = static_cast<hsize_t>(n_particles);
    auto add = [&](bool on, char const *name, int cols, hid_t file_type, hid_t mem_type) {
      add_series(series, atoms, N, on, name, cols, file_type, mem_type);
    };
    add(fields.position, "position", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    add(fields.image, "image", 3, H5T_STD_I32LE, H5T_NATIVE_INT);
    add(fields.velocity, "velocity", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    add(fields.force, "force", 3, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    add(fields.species, "species", 0, H5T_STD_I32LE, H5T_NATIVE_INT);
    add(fields.mass, "mass", 0, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
    add(fields.id, "id", 0, H5T_STD_I32LE, H5T_NATIVE_INT);
    if (fields.box) {
      edges_group = group(box, "edges");
      edges = dataset(edges_group, "value", H5T_IEEE_F64LE, {3, 3}, chunk_frames);
    }
    if (srd_box >= 0 && edges_group >= 0) // the same box for the SRD group
      check(H5Lcreate_hard(box, "edges", srd_box, "edges", H5P_DEFAULT, H5P_DEFAULT), "linking the box");
    // step (always: H5MD requires it) and time, shared by every time series
    hid_t owner = !series.empty()       ? series.front().group
                  : edges_group >= 0    ? edges_group
                  : !srd_series.empty() ? srd_series.front().group
                                        : -1;
    if (owner < 0)
      return;
    step = dataset(owner, "step", H5T_STD_I64LE, {}, chunk_frames);
    if (fields.time)
      time = dataset(owner, "time", H5T_IEEE_F64LE, {}, chunk_frames);
    std::vector<hid_t> others;
    for (auto const &s : series)
      if (s.group != owner)
        others.push_back(s.group);
    if (edges_group >= 0 && edges_group != owner)
      others.push_back(edges_group);
    for (auto const &s : srd_series)
      if (s.group != owner)
        others.push_back(s.group);
    for (hid_t g : others) {
      check(H5Lcreate_hard(owner, "step", g, "step", H5P_DEFAULT, H5P_DEFAULT), "linking step");
      if (fields.time)
        check(H5Lcreate_hard(owner, "time", g, "time", H5P_DEFAULT, H5P_DEFAULT), "linking time");
    }
  }

  /** Open the datasets of a file written by Marble (append mode): fields,
   * number of particles and frames must be consistent. */
  void open_existing() {
    static std::array<std::pair<char const *, int>, 7> const names{
        {{"position", 3}, {"image", 3}, {"velocity", 3}, {"force", 3}, {"species", 0}, {"mass", 0}, {"id", 0}}};
    std::array<bool, 7> const wanted{fields.position, fields.image, fields.velocity, fields.force,
                                     fields.species,  fields.mass,  fields.id};
    auto exists = [&](hid_t loc, char const *name) { return H5Lexists(loc, name, H5P_DEFAULT) > 0; };
    std::string file_fields, want_fields;
    bool any = false, mismatch = false;
    for (std::size_t k = 0; k < names.size(); ++k) {
      bool const has = exists(atoms, names[k].first);
      any = any || has;
      mismatch = mismatch || has != wanted[k];
      if (has)
        file_fields += std::string(file_fields.empty() ? "" : ", ") + names[k].first;
      if (wanted[k])
        want_fields += std::string(want_fields.empty() ? "" : ", ") + names[k].first;
    }
    bool const has_edges = exists(box, "edges");
    any = any || has_edges;
    if (!any)
      return; // no frame written yet: datasets are created by the first write()
    mismatch = mismatch || has_edges != fields.box;
    for (std::size_t k = 0; k < names.size(); ++k) {
      if (!wanted[k])
        continue;
      Series s;
      s.name = names[k].first;
      s.cols = names[k].second;
      bool const is_int = s.name == "image" || s.name == "species" || s.name == "id";
      s.file_type = is_int ? H5T_STD_I32LE : H5T_IEEE_F64LE;
      s.mem_type = is_int ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE;
      if (!mismatch) {
        s.group = check_id(H5Gopen2(atoms, s.name.c_str(), H5P_DEFAULT), "opening a group");
        s.value = check_id(H5Dopen2(s.group, "value", H5P_DEFAULT), "opening a dataset");
        series.push_back(s);
      }
    }
    if (!mismatch && fields.box) {
      edges_group = check_id(H5Gopen2(box, "edges", H5P_DEFAULT), "opening a group");
      edges = check_id(H5Dopen2(edges_group, "value", H5P_DEFAULT), "opening a dataset");
    }
    hid_t const owner = !series.empty() ? series.front().group : edges_group;
    if (!mismatch && owner >= 0)
      mismatch = exists(owner, "time") != fields.time;
    if (mismatch) {
      if (has_edges)
        file_fields += std::string(file_fields.empty() ? "" : ", ") + "box";
      if (fields.box)
        want_fields += std::string(want_fields.empty() ? "" : ", ") + "box";
      throw Utils::RuntimeError("H5MD: cannot append to '" + path + "': it holds the fields [" +
                                file_fields + "] (time: " +
                                (owner >= 0 && exists(owner, "time") ? "yes" : "no") +
                                "), not the requested [" + want_fields + "] (time: " +
                                (fields.time ? "yes" : "no") + "); open it with the same fields");
    }
    step = check_id(H5Dopen2(owner, "step", H5P_DEFAULT), "opening the step dataset");
    if (fields.time)
      time = check_id(H5Dopen2(owner, "time", H5P_DEFAULT), "opening the time dataset");
    auto dims_of = [&](hid_t ds) {
      hid_t sp = H5Dget_space(ds);
      int const rank = H5Sget_simple_extent_ndims(sp);
      std::vector<hsize_t> d(static_cast<std::size_t>(std::max(rank, 0)));
      H5Sget_simple_extent_dims(sp, d.data(), nullptr);
      H5Sclose(sp);
      return d;
    };
    auto const sd = dims_of(step);
    long const nf = sd.empty() ? 0 : static_cast<long>(sd[0]);
    std::vector<hid_t> all{edges, time};
    for (auto const &s : series)
      all.push_back(s.value);
    for (hid_t ds : all) {
      if (ds < 0)
        continue;
      auto const d = dims_of(ds);
      if (d.empty() || static_cast<long>(d[0]) != nf)
        throw Utils::RuntimeError("H5MD: cannot append to '" + path +
                                  "': its time series have different numbers of frames "
                                  "(an interrupted write?)");
    }
    if (fields.srd && exists(particles, "srd")) { // SRD particles of a Marble file
      srd = check_id(H5Gopen2(particles, "srd", H5P_DEFAULT), "opening /particles/srd");
      static std::array<std::pair<char const *, int>, 4> const srd_names{
          {{"position", 3}, {"velocity", 3}, {"species", 0}, {"id", 0}}};
      for (auto const &[name, cols] : srd_names) {
        if (!exists(srd, name))
          continue;
        Series s;
        s.name = name, s.cols = cols;
        bool const is_int = s.name == "species" || s.name == "id";
        s.file_type = is_int ? H5T_STD_I32LE : H5T_IEEE_F64LE;
        s.mem_type = is_int ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE;
        s.group = check_id(H5Gopen2(srd, name, H5P_DEFAULT), "opening a group");
        s.value = check_id(H5Dopen2(s.group, "value", H5P_DEFAULT), "opening a dataset");
        auto const d = dims_of(s.value);
        if (d.size() < 2 || static_cast<long>(d[0]) != nf)
          throw Utils::RuntimeError("H5MD: cannot append to '" + path +
                                    "': its SRD time series have a different number of frames");
        n_srd = static_cast<long>(d[1]);
        srd_series.push_back(s);
      }
    }
    frames = nf;
    if (!series.empty()) {
      auto const d = dims_of(series.front().value);
      n = d.size() >= 2 ? static_cast<long>(d[1]) : -1;
    } else {
      n = -2; // box-only file: any number of particles
    }
  }

  void close_all() {
    for (auto &s : series) {
      H5Dclose(s.value);
      H5Gclose(s.group);
    }
    series.clear();
    for (auto &s : srd_series) {
      H5Dclose(s.value);
      H5Gclose(s.group);
    }
    srd_series.clear();
    for (hid_t *g : {&srd_box, &srd})
      if (*g >= 0)
        H5Gclose(*g), *g = -1;
    for (hid_t *d : {&edges, &step, &time})
      if (*d >= 0)
        H5Dclose(*d), *d = -1;
    for (hid_t *g : {&edges_group, &box, &atoms, &particles})
      if (*g >= 0)
        H5Gclose(*g), *g = -1;
    if (file >= 0) {
      H5Fclose(file);
      file = -1;
    }
  }
};

H5mdFile::H5mdFile(System const &system, std::string const &path, H5mdFields const &fields,
                   std::string const &author, bool append)
    : m(std::make_unique<Impl>()) {
  m->comm = system.comm();
  for (int d = 0; d < 3; ++d)
    m->box_periodic[d] = system.box().periodic(d);
  m->path = path;
  m->fields = fields;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // errors are reported as exceptions
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
#if defined(MARBLE_HAVE_MPI) && defined(H5_HAVE_PARALLEL)
  int mpi_on = 0;
  MPI_Initialized(&mpi_on);
  if (mpi_on) { // the Python module always initialises MPI; C++ tests may not
    m->check(H5Pset_fapl_mpio(fapl, m->comm.comm(), MPI_INFO_NULL), "selecting the MPI-IO driver");
    m->mpio = true;
  }
#endif
  struct stat st {};
  errno = 0;
  bool const exists = ::stat(path.c_str(), &st) == 0;
  // Refuse devices, directories, pipes before HDF5 sees them: a failed
  // H5Fcreate on e.g. /dev/full leaves a half-open file in HDF5 1.10 that
  // crashes the process at exit (doc/reliability.md).
  if (exists && !S_ISREG(st.st_mode)) {
    H5Pclose(fapl);
    throw Utils::RuntimeError("H5MD: cannot " + std::string(append ? "append to" : "create") +
                              " '" + path + "': not a regular file (a directory or a device)");
  }
  if (append && exists) {
    m->file = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl);
    int const err = errno;
    H5Pclose(fapl);
    if (m->file < 0)
      throw Utils::RuntimeError("H5MD: cannot open '" + path + "' to append (" +
                                (S_ISREG(st.st_mode) ? "not an HDF5 file, or not writable: "
                                                     : "not a regular file: ") +
                                errno_text(err) + ")");
    try {
      if (H5Lexists(m->file, "h5md", H5P_DEFAULT) <= 0 ||
          H5Lexists(m->file, "particles", H5P_DEFAULT) <= 0)
        throw Utils::RuntimeError("H5MD: cannot append to '" + path +
                                  "': not an H5MD file (no /h5md or /particles group)");
      m->particles = m->check_id(H5Gopen2(m->file, "particles", H5P_DEFAULT), "opening /particles");
      if (H5Lexists(m->particles, "atoms", H5P_DEFAULT) <= 0)
        throw Utils::RuntimeError("H5MD: cannot append to '" + path +
                                  "': it has no /particles/atoms group (not written by Marble)");
      m->atoms = m->check_id(H5Gopen2(m->particles, "atoms", H5P_DEFAULT), "opening /particles/atoms");
      m->box = m->check_id(H5Gopen2(m->atoms, "box", H5P_DEFAULT), "opening the box group");
      m->open_existing();
    } catch (...) {
      m->close_all();
      throw;
    }
    return;
  }
  m->file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  int const err = errno;
  H5Pclose(fapl);
  if (m->file < 0)
    throw Utils::RuntimeError("H5MD: cannot create file '" + path + "' (" + errno_text(err) +
                              "; does the directory exist and is it writable?)");
  try {
    hid_t h5md = m->group(m->file, "h5md");
    m->attr_ints(h5md, "version", {1, 1});
    hid_t a = m->group(h5md, "author");
    m->attr_string(a, "name", author.empty() ? std::string("unknown") : author);
    H5Gclose(a);
    hid_t c = m->group(h5md, "creator");
    m->attr_string(c, "name", "Marble");
    m->attr_string(c, "version", "0.1.0");
    H5Gclose(c);
    H5Gclose(h5md);
    m->particles = m->group(m->file, "particles");
    m->atoms = m->group(m->particles, "atoms");
    m->box = m->group(m->atoms, "box");
    m->attr_ints(m->box, "dimension", {3});
    std::vector<std::string> boundary;
    for (int d = 0; d < 3; ++d)
      boundary.push_back(system.box().periodic(d) ? "periodic" : "none");
    m->attr_strings(m->box, "boundary", boundary);
  } catch (...) {
    m->close_all();
    throw;
  }
}

H5mdFile::~H5mdFile() {
  if (m)
    m->close_all();
}

bool H5mdFile::is_open() const { return m->file >= 0; }
long H5mdFile::n_frames() const { return m->frames; }
long H5mdFile::n_particles() const { return m->n; }
std::string const &H5mdFile::path() const { return m->path; }

void H5mdFile::write(System const &system) {
  errno = 0;
  if (m->file < 0)
    throw Utils::RuntimeError("H5MD: the file '" + m->path + "' is closed");
  try {
    write_frame(system);
  } catch (Utils::RuntimeError const &e) {
    std::string const what = e.what();
    if (what.find("number of particles") != std::string::npos ||
        what.find("no particles") != std::string::npos)
      throw;
    throw Utils::RuntimeError(what + " while writing frame " + std::to_string(m->frames) +
                              " (is the disk full, or the file size limited?); the file keeps " +
                              std::to_string(m->frames) + " complete frame(s)");
  }
}

void H5mdFile::write_frame(System const &system) {
  auto const &ps = system.particles();
  int const n_local = ps.n_local();
  std::vector<int> local_ids(ps.id.begin(), ps.id.begin() + n_local);
  auto all_ids = m->comm.allgatherv(local_ids);
  long const N = static_cast<long>(all_ids.size());
  long n_srd = 0;
#ifdef SRD
  if (m->fields.srd && system.srd)
    n_srd = system.srd->global_size(system);
#endif
  if (m->n == -2) { // appending to a file with the box only
    if (N == 0)
      throw Utils::RuntimeError("H5MD: the system has no particles: nothing to write");
  } else if (m->n < 0) {
    if (N == 0 && n_srd == 0)
      throw Utils::RuntimeError("H5MD: the system has no particles: nothing to write");
    m->create_datasets(N, n_srd);
    m->n = N;
  } else if (N != m->n) {
    throw Utils::RuntimeError("H5MD: the number of particles changed from " + std::to_string(m->n) +
                              " to " + std::to_string(N) + " since the first frame of '" + m->path +
                              "'; an H5MD file holds a fixed number of particles: close it and "
                              "write to a new file");
  }
  std::sort(all_ids.begin(), all_ids.end());
  auto const layout = row_layout(all_ids, local_ids.data(), n_local);
  if (m->n_srd >= 0 && n_srd != m->n_srd)
    throw Utils::RuntimeError("H5MD: the number of SRD particles changed from " + std::to_string(m->n_srd) +
                              " to " + std::to_string(n_srd) + " since the first frame of '" + m->path +
                              "'; an H5MD file holds a fixed number of particles: close it and "
                              "write to a new file");
  hsize_t const frames_new = static_cast<hsize_t>(m->frames + 1);
  for (auto const &s : m->series)
    m->extend(s.value, frames_new);
  for (auto const &s : m->srd_series)
    m->extend(s.value, frames_new);
  for (hid_t d : {m->edges, m->step, m->time})
    if (d >= 0)
      m->extend(d, frames_new);

  auto const &box = system.box();
  std::vector<double> dbuf;
  std::vector<int> ibuf;
  for (auto const &s : m->series) {
    dbuf.clear();
    ibuf.clear();
    for (auto const &[r, i] : layout.rows) {
      (void)r;
      if (s.name == "position" || s.name == "image") {
        Utils::Vector3d p = ps.pos[i];
        Utils::Vector3i img = ps.image[i];
        box.fold(p, img);
        for (int d = 0; d < 3; ++d) {
          if (s.name == "position")
            dbuf.push_back(p[d]);
          else
            ibuf.push_back(img[d]);
        }
      } else if (s.name == "velocity" || s.name == "force") {
        // velocity: Lees-Edwards frame of the folded position (ps.v otherwise)
        Utils::Vector3d const x = s.name == "velocity" ? system.folded_velocity(i) : ps.f[i];
        for (int d = 0; d < 3; ++d)
          dbuf.push_back(x[d]);
      } else if (s.name == "species") {
        ibuf.push_back(ps.type[i]);
      } else if (s.name == "mass") {
        dbuf.push_back(ps.get_mass(i));
      } else if (s.name == "id") {
        ibuf.push_back(ps.id[i]);
      }
    }
    m->write_rows(s, layout, dbuf, ibuf);
  }
#ifdef SRD
  if (!m->srd_series.empty())
    write_srd_frame(system);
#endif
  if (m->edges >= 0) {
    std::array<double, 9> e{};
    for (int d = 0; d < 3; ++d)
      e[d * 3 + d] = box.length()[d];
    m->write_root(m->edges, H5T_NATIVE_DOUBLE, e.data(), {3, 3});
  }
  if (m->step >= 0) {
    auto const st = static_cast<std::int64_t>(system.step());
    m->write_root(m->step, H5T_NATIVE_INT64, &st, {});
  }
  if (m->time >= 0) {
    double const t = system.time();
    m->write_root(m->time, H5T_NATIVE_DOUBLE, &t, {});
  }
  ++m->frames;
}

#ifdef SRD
// The SRD particles: rows by increasing SRD id, each rank writes its own.
void H5mdFile::write_srd_frame(System const &system) {
  auto const &f = *system.srd;
  auto all_ids = m->comm.allgatherv(f.id);
  std::sort(all_ids.begin(), all_ids.end());
  auto const layout = row_layout(all_ids, f.id.data(), f.size());
  std::vector<double> dbuf;
  std::vector<int> ibuf;
  for (auto const &s : m->srd_series) {
    dbuf.clear();
    ibuf.clear();
    for (auto const &[r, i] : layout.rows) {
      (void)r;
      if (s.name == "position" || s.name == "velocity") {
        auto const &x = s.name == "position" ? f.pos[i] : f.v[i];
        for (int d = 0; d < 3; ++d)
          dbuf.push_back(x[d]);
      } else if (s.name == "species") {
        ibuf.push_back(f.type[i]);
      } else if (s.name == "id") {
        ibuf.push_back(f.id[i]);
      }
    }
    m->write_rows(s, layout, dbuf, ibuf);
  }
}
#endif

void H5mdFile::flush() {
  errno = 0;
  if (m->file >= 0 && H5Fflush(m->file, H5F_SCOPE_GLOBAL) < 0)
    throw Utils::RuntimeError("H5MD: flushing '" + m->path + "' failed (" + errno_text(errno) +
                              ")");
}

void H5mdFile::close() {
  if (m->file < 0)
    return;
  // flush first: a full disk or a vanished file shows up here, as an error
  errno = 0;
  herr_t const rc = H5Fflush(m->file, H5F_SCOPE_GLOBAL);
  int const err = errno;
  m->close_all();
  if (rc < 0)
    throw Utils::RuntimeError("H5MD: writing '" + m->path + "' failed while closing it (" +
                              errno_text(err) + "); the file is closed and may be incomplete");
}

} // namespace Marble::IO
