// Checkpoint blobs of the core state (see checkpoint.hpp, doc/io.md).
#include "io/checkpoint.hpp"

#include "analysis/correlator.hpp"
#include "config/features.hpp"
#include "utils/errors.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace Marble {

namespace {

constexpr std::size_t header_size = 8 + 4 + 8 + 4;
constexpr char system_magic[9] = "MRBLSYS\x01";
constexpr char accumulator_magic[9] = "MRBLACC\x01";

[[noreturn]] void corrupt(std::string const &what) {
  throw Utils::RuntimeError("invalid Marble checkpoint data: " + what);
}

class Out {
public:
  std::vector<char> buf;
  template <typename T> void pod(T const &x) {
    static_assert(std::is_trivially_copyable_v<T>);
    auto const *p = reinterpret_cast<char const *>(&x);
    buf.insert(buf.end(), p, p + sizeof(T));
  }
  template <typename T> void vec(T const *data, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(static_cast<std::uint64_t>(n));
    auto const *p = reinterpret_cast<char const *>(data);
    buf.insert(buf.end(), p, p + n * sizeof(T));
  }
  template <typename T> void vec(std::vector<T> const &v) { vec(v.data(), v.size()); }
  /** First @p n elements of @p v. */
  template <typename T> void head(std::vector<T> const &v, std::size_t n) { vec(v.data(), n); }
  void str(std::string const &s) { vec(s.data(), s.size()); }
  /** Fields of a struct, one by one (no padding bytes in the blob). */
  template <typename... T> void operator()(T const &...xs) { (field(xs), ...); }
  template <typename T> void field(T const &x) {
    if constexpr (std::is_same_v<T, bool>)
      pod(static_cast<std::uint8_t>(x ? 1 : 0));
    else if constexpr (std::is_enum_v<T>)
      pod(static_cast<std::int32_t>(x));
    else
      pod(x);
  }
  /** A vector of structs written field by field by @p fn(Out &, T const &). */
  template <typename T, typename F> void structs(std::vector<T> const &v, F &&fn) {
    pod(static_cast<std::uint64_t>(v.size()));
    for (auto const &x : v)
      fn(*this, x);
  }
};

class In {
public:
  In(char const *p, std::size_t n) : m_p(p), m_n(n) {}
  template <typename T> T pod() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T x;
    std::memcpy(&x, m_p + m_pos, sizeof(T));
    m_pos += sizeof(T);
    return x;
  }
  template <typename T> std::vector<T> vec() {
    static_assert(std::is_trivially_copyable_v<T>);
    auto const n = pod<std::uint64_t>();
    if (n > (m_n - m_pos) / std::max<std::size_t>(sizeof(T), 1))
      corrupt("an array is longer than the data left (truncated or corrupt)");
    std::vector<T> v(static_cast<std::size_t>(n));
    if (n)
      std::memcpy(v.data(), m_p + m_pos, n * sizeof(T));
    m_pos += n * sizeof(T);
    return v;
  }
  std::string str() {
    auto const v = vec<char>();
    return {v.begin(), v.end()};
  }
  bool done() const { return m_pos == m_n; }
  template <typename... T> void operator()(T &...xs) { (field(xs), ...); }
  template <typename T> void field(T &x) {
    if constexpr (std::is_same_v<T, bool>)
      x = pod<std::uint8_t>() != 0;
    else if constexpr (std::is_enum_v<T>)
      x = static_cast<T>(pod<std::int32_t>());
    else
      x = pod<T>();
  }
  template <typename T, typename F> std::vector<T> structs(F &&fn) {
    auto const n = pod<std::uint64_t>();
    if (n > m_n - m_pos) // every struct takes at least one byte
      corrupt("an array is longer than the data left (truncated or corrupt)");
    std::vector<T> v(static_cast<std::size_t>(n));
    for (auto &x : v)
      fn(*this, x);
    return v;
  }

private:
  void need(std::size_t k) const {
    if (k > m_n - m_pos)
      corrupt("the data ends early (truncated or corrupt)");
  }
  char const *m_p;
  std::size_t m_n, m_pos = 0;
};

std::vector<char> wrap(char const *magic, std::vector<char> const &payload) {
  Out o;
  o.buf.insert(o.buf.end(), magic, magic + 8);
  o.pod(Checkpoint::format_version);
  o.pod(static_cast<std::uint64_t>(payload.size()));
  o.pod(Checkpoint::crc32(payload.data(), payload.size()));
  o.buf.insert(o.buf.end(), payload.begin(), payload.end());
  return o.buf;
}

/** Check the envelope; returns the payload's reader (and the format version
 * in @p version_out when given). */
In unwrap(char const *magic, std::vector<char> const &blob, char const *what,
          std::uint32_t *version_out = nullptr) {
  if (blob.size() < header_size)
    corrupt(std::string("only ") + std::to_string(blob.size()) + " bytes, too short for a " +
            what + " (truncated)");
  if (std::memcmp(blob.data(), magic, 8) != 0)
    corrupt(std::string("bad magic: this is not a Marble ") + what);
  In h(blob.data() + 8, header_size - 8);
  auto const version = h.pod<std::uint32_t>();
  auto const size = h.pod<std::uint64_t>();
  auto const crc = h.pod<std::uint32_t>();
  if (version < Checkpoint::oldest_readable_version || version > Checkpoint::format_version)
    corrupt("format version " + std::to_string(version) + ", this build reads versions " +
            std::to_string(Checkpoint::oldest_readable_version) + " to " +
            std::to_string(Checkpoint::format_version) +
            " (written by another Marble version; restart it with the version that wrote it)");
  if (size != blob.size() - header_size)
    corrupt("the header announces " + std::to_string(size) + " bytes of data, found " +
            std::to_string(blob.size() - header_size) + " (truncated or corrupt)");
  if (version_out)
    *version_out = version;
  char const *payload = blob.data() + header_size;
  if (Checkpoint::crc32(payload, blob.size() - header_size) != crc)
    corrupt("checksum mismatch (the data is corrupt)");
  return In(payload, blob.size() - header_size);
}

std::string layout_signature() {
  std::string s = "Thermostat=" + std::to_string(sizeof(Thermostat)) +
                  " Wall=" + std::to_string(sizeof(Wall)) +
                  " BoxGeometry=" + std::to_string(sizeof(BoxGeometry)) +
                  " SteepestDescentParams=" + std::to_string(sizeof(SteepestDescentParams));
  // the kernels and their fields, as the interaction table is written
  for_each_kernel<CompiledKernels>([&]<class K>() {
    s += std::string(" ") + K::name + "(";
    for (auto const &f : K::fields())
      if (!f.missing_feature)
        s += std::string(f.key) + ",";
    s += ")";
  });
  return s;
}

// The interaction table, kernel by kernel through the kernels' field lists
// (every number as a double: integer and choice fields are exact); derived
// values (cutoffs, noise prefactors) are recomputed on restore.
void write_ia(Out &o, IAParams const &p) {
  for_each_kernel<CompiledKernels>([&]<class K>() {
    auto const &kp = p.template get<K>();
    o.field(kp.active);
    for (auto const &f : K::fields())
      if (!f.missing_feature)
        o.pod(f.get(kp));
  });
}
void read_ia(In &in, IAParams &p) {
  for_each_kernel<CompiledKernels>([&]<class K>() {
    auto &kp = p.template get<K>();
    in.field(kp.active);
    for (auto const &f : K::fields())
      if (!f.missing_feature)
        f.set(kp, in.pod<double>());
    if constexpr (requires { K::finish(kp); })
      if (kp.active) // derived values (e.g. Morse's energy shift)
        K::finish(kp);
  });
  p.update_cutoff();
}

// Field lists of the other parameter structs (A: Out with const, In with
// mutable references). A new member must be added here; the layout signature
// above makes a blob of a build with other struct sizes fail loudly.
template <typename A, typename P> void thermostat_fields([[maybe_unused]] A &a, [[maybe_unused]] P &t) {
#ifdef DPD
  a(t.dpd.active, t.dpd.seeded, t.dpd.kT, t.dpd.seed, t.dpd.philox_counter);
#endif
  for (auto *sp : {&t.langevin, &t.brownian})
    a(sp->active, sp->seeded, sp->kT, sp->gamma, sp->gamma_rotation, sp->seed, sp->philox_counter);
}
template <typename A, typename P> void wall_fields(A &a, P &w) {
  a(w.normal, w.dist, w.type, w.velocity, w.id, w.total_force, w.energy);
}
template <typename A, typename P> void sd_fields(A &a, P &p) { a(p.f_max, p.gamma, p.max_displacement); }

/** Every local-particle array, in ParticleStore order. */
struct ParticleBlock {
  std::vector<int> id, type;
  std::vector<Utils::Vector3d> pos, v, f;
  std::vector<double> mass;
  std::vector<Utils::Vector3d> omega, torque;
  std::vector<double> rinertia;
  std::vector<std::uint8_t> rotation;
  std::vector<Utils::Vector3i> image;
  std::vector<Utils::Vector3d> pos_at_rebuild, ext_force, ext_torque;
  std::vector<std::uint8_t> fix;
  std::vector<double> gamma, gamma_rot;
};

} // namespace

struct CheckpointAccess {
  /** Everything but the particles, identical on every rank. */
  struct Global {
    BoxGeometry box;
    double skin = 0., time_step = 0., time = 0., cut_at_rebuild = 0.;
    std::uint64_t step = 0;
    std::int32_t integrator = 0;
    SteepestDescentParams sd;
    std::uint8_t forces_valid = 0, dpd_in_pair_loop = 1, cells_valid = 0;
    Thermostat thermo;
    std::int32_t n_types = 0;
    std::vector<IAParams> ia;
    std::vector<char> large;
    std::vector<Wall> walls;
    std::int32_t wall_next_id = 0;
    // cell_system.large_range_types as requested (System::set_large_range_mode):
    // -1 auto (also for blobs of format version 3, which lack it), 0 off, 1 the flagged types
    std::int32_t large_range_mode = -1;
    std::vector<char> large_range_types;
    std::int32_t substeps = 1; // RESPA substeps (format version 5; 1 before)
    // the domain planes as fractions of the box (format version 6; none before:
    // equal domains): CellSystem::set_domain_fractions
    std::array<std::vector<double>, 3> domain_fractions;
    // the automatic load balance (cell_system.set_load_balance) and the number
    // of balances that moved the planes (format version 7; none before: no
    // automatic balance)
    System::BalanceSettings balance;
    std::int64_t n_balances = 0;
    // when a Verlet list is rebuilt (cell_system.list_check; format version
    // 8; before: at half the skin, the only test the writing build had)
    System::ListCheck list_check = System::ListCheck::HalfSkin;
    // Lees-Edwards (an optional tail of the global block, written only when
    // it is on: blobs without it are unchanged)
    LeesEdwardsProtocol le;
    std::int32_t le_direction = -1, le_normal = -1;
  };

  static void write_global(Out &o, System const &s) {
    o.pod(s.m_box.length());
    for (int d = 0; d < 3; ++d)
      o.field(s.m_box.periodic(d));
    o.pod(s.m_cells.skin());
    o.pod(s.m_time_step);
    o.pod(s.m_time);
    o.pod(s.m_cut_at_rebuild);
    o.pod(s.m_step);
    o.pod(static_cast<std::int32_t>(s.m_integrator));
    sd_fields(o, s.m_sd);
    o.pod(static_cast<std::uint8_t>(s.m_forces_valid));
    o.pod(static_cast<std::uint8_t>(s.m_dpd_in_pair_loop));
    o.pod(static_cast<std::uint8_t>(s.m_cells.valid()));
    thermostat_fields(o, s.m_thermo);
    int const n = s.m_ia.n_types();
    o.pod(static_cast<std::int32_t>(n));
    o.structs(s.m_ia.all(), [](Out &a, IAParams const &p) { write_ia(a, p); });
    std::vector<char> large(static_cast<std::size_t>(n));
    for (int t = 0; t < n; ++t)
      large[t] = s.m_ia.is_large(t) ? 1 : 0;
    o.vec(large);
    o.structs(s.m_constraints.m_walls, [](Out &a, Wall const &w) { wall_fields(a, w); });
    o.pod(static_cast<std::int32_t>(s.m_constraints.m_next_id));
    o.pod(static_cast<std::int32_t>(s.m_large_range_mode)); // format version 4
    o.vec(s.m_large_range_types);
    o.pod(static_cast<std::int32_t>(s.m_substeps)); // format version 5
    for (auto const &f : s.m_cells.domain_fractions()) // format version 6
      o.vec(f);
    o.pod(static_cast<std::int32_t>(s.m_balance.every)); // format version 7
    o.pod(static_cast<std::int32_t>(s.m_balance.by));
    o.pod(s.m_balance.damping);
    o.pod(s.m_balance.threshold);
    o.pod(static_cast<std::int64_t>(s.m_n_balances));
    o.pod(static_cast<std::int32_t>(s.m_list_check)); // format version 8
    if (s.m_le_protocol.kind != LeesEdwardsProtocol::Off) { // Lees-Edwards tail
      auto const &p = s.m_le_protocol;
      o.pod(static_cast<std::int32_t>(p.kind));
      o.pod(static_cast<std::int32_t>(s.m_le_direction));
      o.pod(static_cast<std::int32_t>(s.m_le_normal));
      for (double x : {p.initial_pos_offset, p.shear_velocity, p.amplitude, p.omega, p.time_0})
        o.pod(x);
    }
  }

  static Global read_global(In &in, std::uint32_t version) {
    Global g;
    g.box.set_length(in.pod<Utils::Vector3d>());
    for (int d = 0; d < 3; ++d) {
      bool p = true;
      in.field(p);
      g.box.set_periodic(d, p);
    }
    g.skin = in.pod<double>();
    g.time_step = in.pod<double>();
    g.time = in.pod<double>();
    g.cut_at_rebuild = in.pod<double>();
    g.step = in.pod<std::uint64_t>();
    g.integrator = in.pod<std::int32_t>();
    sd_fields(in, g.sd);
    g.forces_valid = in.pod<std::uint8_t>();
    g.dpd_in_pair_loop = in.pod<std::uint8_t>();
    g.cells_valid = in.pod<std::uint8_t>();
    thermostat_fields(in, g.thermo);
    g.n_types = in.pod<std::int32_t>();
    g.ia = in.structs<IAParams>([](In &a, IAParams &p) { read_ia(a, p); });
    g.large = in.vec<char>();
    g.walls = in.structs<Wall>([](In &a, Wall &w) { wall_fields(a, w); });
    g.wall_next_id = in.pod<std::int32_t>();
    if (version >= 4) {
      g.large_range_mode = in.pod<std::int32_t>();
      g.large_range_types = in.vec<char>();
      if (g.large_range_mode < -1 || g.large_range_mode > 1 ||
          g.large_range_types.size() > static_cast<std::size_t>(InteractionTable::max_type))
        corrupt("bad large-range types of the cell system");
    }
    if (version >= 5) {
      g.substeps = in.pod<std::int32_t>();
      if (g.substeps < 1 || g.substeps > System::max_substeps)
        corrupt("bad integrator substeps");
    }
    if (version >= 6)
      for (auto &f : g.domain_fractions) {
        f = in.vec<double>();
        bool ok = f.empty() || (f.size() >= 2 && f.size() <= 1u << 20 && f.front() == 0. && f.back() == 1.);
        for (std::size_t k = 1; ok && k < f.size(); ++k)
          ok = f[k] > f[k - 1];
        if (!ok)
          corrupt("bad domain planes of the cell system");
      }
    if (version >= 7) {
      auto const every = in.pod<std::int32_t>(), by = in.pod<std::int32_t>();
      g.balance.every = every;
      g.balance.by = static_cast<System::BalanceBy>(by);
      g.balance.damping = in.pod<double>();
      g.balance.threshold = in.pod<double>();
      g.n_balances = in.pod<std::int64_t>();
      // the ranges set_load_balance accepts (script interface)
      if (every < 0 || by < static_cast<int>(System::BalanceBy::Particles) ||
          by > static_cast<int>(System::BalanceBy::Pairs) || !(g.balance.damping > 0. && g.balance.damping <= 1.) ||
          !(g.balance.threshold >= 0.) || g.n_balances < 0)
        corrupt("bad load-balance settings of the cell system");
    }
    if (version >= 8) {
      auto const lc = in.pod<std::int32_t>();
      if (lc != static_cast<int>(System::ListCheck::Pairs) && lc != static_cast<int>(System::ListCheck::HalfSkin))
        corrupt("bad Verlet list check of the cell system");
      g.list_check = static_cast<System::ListCheck>(lc);
    }
    if (!in.done()) { // the Lees-Edwards tail
      g.le.kind = in.pod<std::int32_t>();
      g.le_direction = in.pod<std::int32_t>();
      g.le_normal = in.pod<std::int32_t>();
      g.le.initial_pos_offset = in.pod<double>();
      g.le.shear_velocity = in.pod<double>();
      g.le.amplitude = in.pod<double>();
      g.le.omega = in.pod<double>();
      g.le.time_0 = in.pod<double>();
      if (g.le.kind < LeesEdwardsProtocol::Linear || g.le.kind > LeesEdwardsProtocol::Oscillatory ||
          g.le_direction < 0 || g.le_direction > 2 || g.le_normal < 0 || g.le_normal > 2 ||
          g.le_direction == g.le_normal)
        corrupt("bad Lees-Edwards state");
    }
    auto square = [](std::int32_t n) { return static_cast<std::size_t>(n) * static_cast<std::size_t>(n); };
    if (g.n_types < 0 || g.n_types > InteractionTable::max_type || g.ia.size() != square(g.n_types) ||
        g.large.size() != static_cast<std::size_t>(g.n_types))
      corrupt("inconsistent interaction table");
    if (g.integrator < 0 || g.integrator > static_cast<int>(IntegratorKind::BrownianDynamics))
      corrupt("unknown integrator");
    for (int d = 0; d < 3; ++d)
      if (!(g.box.length()[d] > 0.))
        corrupt("box length <= 0");
    return g;
  }

  static std::vector<char> particle_block(System const &s) {
    auto const &ps = s.m_ps;
    auto const n = static_cast<std::size_t>(ps.n_local());
    Out o;
    o.pod(static_cast<std::uint64_t>(n));
    o.head(ps.id, n);
    o.head(ps.type, n);
    o.head(ps.pos, n);
    o.head(ps.v, n);
    o.head(ps.f, n);
#ifdef MASS
    o.head(ps.mass, n);
#endif
#ifdef ROTATION
    o.head(ps.omega, n);
    o.head(ps.torque, n);
    o.head(ps.rinertia, n);
    o.head(ps.rotation, n);
#endif
    o.head(ps.image, n);
    o.head(ps.pos_at_rebuild, n);
#ifdef EXTERNAL_FORCE
    o.head(ps.ext_force, n);
    o.head(ps.ext_torque, n);
    o.head(ps.fix, n);
#endif
    o.head(ps.gamma, n);
    o.head(ps.gamma_rot, n);
    return o.buf;
  }

  static ParticleBlock read_particles(In &in, int n_types) {
    ParticleBlock b;
    auto const n = in.pod<std::uint64_t>();
    b.id = in.vec<int>();
    b.type = in.vec<int>();
    b.pos = in.vec<Utils::Vector3d>();
    b.v = in.vec<Utils::Vector3d>();
    b.f = in.vec<Utils::Vector3d>();
    bool ok = b.id.size() == n && b.type.size() == n && b.pos.size() == n && b.v.size() == n &&
              b.f.size() == n;
#ifdef MASS
    b.mass = in.vec<double>();
    ok = ok && b.mass.size() == n;
#endif
#ifdef ROTATION
    b.omega = in.vec<Utils::Vector3d>();
    b.torque = in.vec<Utils::Vector3d>();
    b.rinertia = in.vec<double>();
    b.rotation = in.vec<std::uint8_t>();
    ok = ok && b.omega.size() == n && b.torque.size() == n && b.rinertia.size() == n &&
         b.rotation.size() == n;
#endif
    b.image = in.vec<Utils::Vector3i>();
    b.pos_at_rebuild = in.vec<Utils::Vector3d>();
    ok = ok && b.image.size() == n && b.pos_at_rebuild.size() == n;
#ifdef EXTERNAL_FORCE
    b.ext_force = in.vec<Utils::Vector3d>();
    b.ext_torque = in.vec<Utils::Vector3d>();
    b.fix = in.vec<std::uint8_t>();
    ok = ok && b.ext_force.size() == n && b.ext_torque.size() == n && b.fix.size() == n;
#endif
    b.gamma = in.vec<double>();
    b.gamma_rot = in.vec<double>();
    ok = ok && b.gamma.size() == n && b.gamma_rot.size() == n;
    if (!ok || !in.done())
      corrupt("inconsistent particle block");
    std::vector<int> ids = b.id;
    std::sort(ids.begin(), ids.end());
    if (!ids.empty() && ids.front() < 0)
      corrupt("negative particle id");
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
      corrupt("duplicate particle id");
    for (int t : b.type)
      if (t < 0 || t >= std::max(n_types, 1))
        corrupt("particle type outside the interaction table");
    return b;
  }

  /** The particles of all @p blocks whose domain is this rank's (for a
   * checkpoint written by another number of ranks), in block order. */
  static ParticleBlock redistribute(System const &s, Global const &g,
                                    std::vector<std::vector<char>> const &blocks) {
    ParticleBlock out;
    std::vector<int> all_ids;
    int const me = s.m_comm.rank();
    for (auto const &blk : blocks) {
      In pin(blk.data(), blk.size());
      auto const b = read_particles(pin, g.n_types);
      all_ids.insert(all_ids.end(), b.id.begin(), b.id.end());
      for (std::size_t k = 0; k < b.id.size(); ++k) {
        Utils::Vector3d p = b.pos[k];
        Utils::Vector3i img{};
        g.box.fold(p, img);
        if (s.m_cells.owner_rank(p, g.box) != me)
          continue;
        auto take = [k](auto &dst, auto const &src) {
          if (!src.empty())
            dst.push_back(src[k]);
        };
        take(out.id, b.id);
        take(out.type, b.type);
        take(out.pos, b.pos);
        take(out.v, b.v);
        take(out.f, b.f);
        take(out.mass, b.mass);
        take(out.omega, b.omega);
        take(out.torque, b.torque);
        take(out.rinertia, b.rinertia);
        take(out.rotation, b.rotation);
        take(out.image, b.image);
        take(out.pos_at_rebuild, b.pos_at_rebuild);
        take(out.ext_force, b.ext_force);
        take(out.ext_torque, b.ext_torque);
        take(out.fix, b.fix);
        take(out.gamma, b.gamma);
        take(out.gamma_rot, b.gamma_rot);
      }
    }
    std::sort(all_ids.begin(), all_ids.end());
    if (std::adjacent_find(all_ids.begin(), all_ids.end()) != all_ids.end())
      corrupt("a particle id in two ranks' blocks");
    return out;
  }

  static std::vector<char> save(System const &s) {
    Out o;
    o.str(MARBLE_FEATURES_ACTIVE);
    o.str(layout_signature());
    auto const &comm = s.m_comm;
    o.pod(static_cast<std::int32_t>(comm.size()));
    Out g;
    write_global(g, s);
    o.vec(g.buf);
    auto const block = particle_block(s);
    auto const sizes = comm.allgather(static_cast<int>(block.size()));
    auto const all = comm.allgatherv_bytes(block);
    std::size_t off = 0;
    for (int r = 0; r < comm.size(); ++r) {
      o.vec(all.data() + off, static_cast<std::size_t>(sizes[r]));
      off += static_cast<std::size_t>(sizes[r]);
    }
    return wrap(system_magic, o.buf);
  }

  static void load(System &s, std::vector<char> const &blob) {
    auto const &comm = s.m_comm;
    Global g;
    ParticleBlock b;
    std::string error;
    try {
      std::uint32_t version = 0;
      In in = unwrap(system_magic, blob, "system checkpoint", &version);
      auto const features = in.str();
      if (features != MARBLE_FEATURES_ACTIVE)
        throw Utils::RuntimeError("the checkpoint was written by a build with the features [" +
                                  features + "], this build has [" + MARBLE_FEATURES_ACTIVE +
                                  "]: load it with the same build");
      if (in.str() != layout_signature())
        throw Utils::RuntimeError("the checkpoint was written by a build with another data "
                                  "layout: load it with the same build");
      auto const n_ranks = in.pod<std::int32_t>();
      auto const gbuf = in.vec<char>();
      std::vector<std::vector<char>> blocks;
      for (int r = 0; r < n_ranks && r < 1 << 20; ++r)
        blocks.push_back(in.vec<char>());
      if (!in.done())
        corrupt("unexpected data after the particle blocks");
      if (n_ranks < 1 || static_cast<std::size_t>(n_ranks) != blocks.size())
        corrupt("bad number of particle blocks");
      In gin(gbuf.data(), gbuf.size());
      g = read_global(gin, version);
      if (!gin.done())
        corrupt("unexpected data after the global state");
      if (n_ranks == comm.size()) {
        auto const &mine = blocks[static_cast<std::size_t>(comm.rank())];
        In pin(mine.data(), mine.size());
        b = read_particles(pin, g.n_types);
      } else {
        // Another number of ranks: every rank reads every block and keeps the
        // particles its domain owns; the pair lists are rebuilt at the current
        // positions (not at the saved ones), so the continued run equals the
        // uninterrupted one to round-off, not bit for bit (doc/io.md).
        b = redistribute(s, g, blocks);
        g.cells_valid = 0;
      }
    } catch (std::exception const &e) {
      error = e.what();
    }
    // every rank validated its part: all go on, or all throw
    comm.throw_if_any(error);
    apply(s, g, b);
  }

  static void apply(System &s, Global &g, ParticleBlock const &b) {
    s.m_box = g.box;
    s.m_cells.set_skin(g.skin);
    s.m_cells.invalidate();
    s.m_time_step = g.time_step;
    s.m_time = g.time;
    s.m_step = g.step;
    s.m_le_protocol = g.le;
    s.m_le_direction = g.le_direction;
    s.m_le_normal = g.le_normal;
    s.update_lees_edwards();
    s.m_integrator = static_cast<IntegratorKind>(g.integrator);
    s.m_sd = g.sd;
    s.m_substeps = g.substeps;
    s.m_cells.set_domain_fractions(g.domain_fractions); // (after set_skin: invalidates the lists again)
    s.m_balance = g.balance;
    s.m_n_balances = static_cast<long>(g.n_balances);
    s.m_list_check = g.list_check;
    s.reset_balance_clock(); // a balance by time measures from the load on
    s.m_dpd_in_pair_loop = g.dpd_in_pair_loop != 0;
    s.m_thermo = g.thermo;
    s.m_ia.clear();
    if (g.n_types > 0)
      s.m_ia.ensure_type(g.n_types - 1);
    s.m_ia.all() = g.ia;
    s.m_ia.set_large_types(g.large);
    s.update_thermostat_prefactors();
    s.m_constraints.m_walls = g.walls;
    s.m_constraints.m_next_id = g.wall_next_id;
    s.m_large_range_mode = g.large_range_mode; // before the lists are rebuilt below
    s.m_large_range_types = g.large_range_types;
#ifdef MARBLE
    s.m_colloids.set_types(s.m_ia.colloid_types());
    // with MPI, every rank keeps a copy of each colloid (cells/CellSystem.cpp)
    s.m_cells.set_replicated_types(s.m_colloids.colloid_types());
#endif
    auto &ps = s.m_ps;
    ps.clear();
    for (std::size_t k = 0; k < b.id.size(); ++k) {
      ParticleProperties p;
      p.id = b.id[k];
      p.type = b.type[k];
      p.pos = b.pos[k];
      p.v = b.v[k];
      p.image = b.image[k];
#ifdef MASS
      p.mass = b.mass[k];
#endif
#ifdef ROTATION
      p.rotation = b.rotation[k] != 0;
      p.rinertia = b.rinertia[k];
      p.omega = b.omega[k];
#endif
#ifdef EXTERNAL_FORCE
      p.ext_force = b.ext_force[k];
      p.ext_torque = b.ext_torque[k];
      p.fix = b.fix[k];
#endif
      p.gamma = b.gamma[k];
      p.gamma_rot = b.gamma_rot[k];
      ps.add(p);
      ps.f[k] = b.f[k];
#ifdef ROTATION
      ps.rotation[k] = b.rotation[k]; // the raw byte
      ps.torque[k] = b.torque[k];
#endif
      ps.pos_at_rebuild[k] = b.pos_at_rebuild[k];
    }
    // The pair lists of the last rebuild: rebuilt at pos_at_rebuild in the
    // stored order (the counting sort by cell then keeps that order).
    s.m_cut_at_rebuild = g.cut_at_rebuild;
    if (g.cells_valid)
      s.rebuild_lists_at_saved_positions();
    s.m_cut_at_rebuild = g.cut_at_rebuild;
    s.m_forces_valid = g.forces_valid != 0;
  }

  // --- accumulators ---
  enum Kind : std::uint8_t { CorrelatorKind = 1, TimeSeriesKind = 2, MeanVarianceKind = 3 };

  static void write_tau(Out &o, Accumulators::MultipleTau const &t) {
    o.pod(static_cast<std::uint64_t>(t.m_dim_a));
    o.pod(static_cast<std::uint64_t>(t.m_dim_b));
    o.pod(static_cast<std::uint64_t>(t.m_dim_corr));
    o.pod(static_cast<std::int32_t>(t.m_tau_lin));
    o.pod(static_cast<std::int32_t>(t.m_op));
    o.pod(static_cast<std::int32_t>(t.m_ca));
    o.pod(static_cast<std::int32_t>(t.m_cb));
    o.pod(static_cast<std::uint64_t>(t.m_levels.size()));
    for (auto const &l : t.m_levels) {
      o.vec(l.a);
      o.vec(l.b);
      o.pod(static_cast<std::int64_t>(l.n));
      o.vec(l.pend_a);
      o.vec(l.pend_b);
      o.pod(static_cast<std::uint8_t>(l.pending));
    }
    o.vec(t.m_lags);
    o.vec(t.m_count);
    o.vec(t.m_sum);
    o.pod(static_cast<std::int64_t>(t.m_n_samples));
  }

  /** Read into a copy of @p t (the constructed one), checking the fixed parts. */
  static Accumulators::MultipleTau read_tau(In &in, Accumulators::MultipleTau const &t) {
    auto const mismatch = [] {
      throw Utils::RuntimeError("the saved correlator has other parameters than this one "
                                "(tau_lin, tau_max, observables, operation or compression)");
    };
    Accumulators::MultipleTau out = t;
    if (in.pod<std::uint64_t>() != t.m_dim_a || in.pod<std::uint64_t>() != t.m_dim_b ||
        in.pod<std::uint64_t>() != t.m_dim_corr || in.pod<std::int32_t>() != t.m_tau_lin ||
        in.pod<std::int32_t>() != static_cast<std::int32_t>(t.m_op) ||
        in.pod<std::int32_t>() != static_cast<std::int32_t>(t.m_ca) ||
        in.pod<std::int32_t>() != static_cast<std::int32_t>(t.m_cb) ||
        in.pod<std::uint64_t>() != t.m_levels.size())
      mismatch();
    for (auto &l : out.m_levels) {
      auto a = in.vec<double>(), b = in.vec<double>();
      auto const n = in.pod<std::int64_t>();
      auto pa = in.vec<double>(), pb = in.vec<double>();
      auto const pending = in.pod<std::uint8_t>();
      if (a.size() != l.a.size() || b.size() != l.b.size() || n < 0 ||
          (pending && (pa.size() != t.m_dim_a || pb.size() != t.m_dim_b)))
        corrupt("inconsistent correlator level");
      l.a = std::move(a);
      l.b = std::move(b);
      l.n = n;
      l.pend_a = std::move(pa);
      l.pend_b = std::move(pb);
      l.pending = pending != 0;
    }
    auto lags = in.vec<long long>();
    auto count = in.vec<long long>();
    auto sum = in.vec<double>();
    if (lags != t.m_lags)
      mismatch();
    if (count.size() != t.m_count.size() || sum.size() != t.m_sum.size())
      corrupt("inconsistent correlator sums");
    out.m_count = std::move(count);
    out.m_sum = std::move(sum);
    out.m_n_samples = in.pod<std::int64_t>();
    return out;
  }

  static std::vector<char> save_acc(AutoUpdate const &acc) {
    Out o;
    o.pod(static_cast<std::int32_t>(acc.delta_N));
    if (auto const *c = dynamic_cast<Accumulators::Correlator const *>(&acc)) {
      o.pod(CorrelatorKind);
      o.pod(c->m_time_step);
      o.pod(c->m_dt);
      o.pod(c->m_tau_max);
      o.pod(static_cast<std::int32_t>(c->m_op));
      o.pod(static_cast<std::uint8_t>(c->m_finalized));
      write_tau(o, c->m_data);
    } else if (auto const *t = dynamic_cast<Accumulators::TimeSeries const *>(&acc)) {
      o.pod(TimeSeriesKind);
      o.vec(t->m_data);
      o.pod(static_cast<std::uint64_t>(t->m_n));
    } else if (auto const *m = dynamic_cast<Accumulators::MeanVarianceCalculator const *>(&acc)) {
      o.pod(MeanVarianceKind);
      o.vec(m->m_mean);
      o.vec(m->m_m2);
      o.pod(static_cast<std::uint64_t>(m->m_n));
    } else {
      throw Utils::RuntimeError("this accumulator cannot be checkpointed");
    }
    return wrap(accumulator_magic, o.buf);
  }

  static void load_acc(AutoUpdate &acc, std::vector<char> const &blob) {
    In in = unwrap(accumulator_magic, blob, "accumulator checkpoint");
    auto const delta_N = in.pod<std::int32_t>();
    auto const kind = in.pod<std::uint8_t>();
    if (delta_N != acc.delta_N)
      throw Utils::RuntimeError("the saved accumulator has another delta_N");
    auto const wrong_kind = [] {
      throw Utils::RuntimeError("the saved accumulator is of another kind");
    };
    if (auto *c = dynamic_cast<Accumulators::Correlator *>(&acc)) {
      if (kind != CorrelatorKind)
        wrong_kind();
      auto const time_step = in.pod<double>(), dt = in.pod<double>(), tau_max = in.pod<double>();
      auto const op = in.pod<std::int32_t>();
      auto const finalized = in.pod<std::uint8_t>();
      if (op != static_cast<std::int32_t>(c->m_op))
        throw Utils::RuntimeError("the saved correlator has another corr_operation");
      auto data = read_tau(in, c->m_data);
      if (!in.done())
        corrupt("unexpected data after the correlator");
      c->m_time_step = time_step;
      c->m_dt = dt;
      c->m_tau_max = tau_max;
      c->m_finalized = finalized != 0;
      c->m_data = std::move(data);
    } else if (auto *t = dynamic_cast<Accumulators::TimeSeries *>(&acc)) {
      if (kind != TimeSeriesKind)
        wrong_kind();
      auto data = in.vec<double>();
      auto const n = in.pod<std::uint64_t>();
      if (!in.done() || data.size() != n * t->m_obs->n_values())
        corrupt("inconsistent time series");
      t->m_data = std::move(data);
      t->m_n = static_cast<std::size_t>(n);
    } else if (auto *m = dynamic_cast<Accumulators::MeanVarianceCalculator *>(&acc)) {
      if (kind != MeanVarianceKind)
        wrong_kind();
      auto mean = in.vec<double>(), m2 = in.vec<double>();
      auto const n = in.pod<std::uint64_t>();
      if (!in.done() || mean.size() != m->m_mean.size() || m2.size() != m->m_m2.size())
        corrupt("inconsistent mean/variance state");
      m->m_mean = std::move(mean);
      m->m_m2 = std::move(m2);
      m->m_n = static_cast<std::size_t>(n);
    } else {
      throw Utils::RuntimeError("this accumulator cannot be checkpointed");
    }
  }
};

namespace Checkpoint {

std::uint32_t crc32(char const *data, std::size_t n, std::uint32_t crc) {
  static auto const table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k)
        c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i)
    crc = table[(crc ^ static_cast<unsigned char>(data[i])) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::vector<char> save_system(System const &system) { return CheckpointAccess::save(system); }

void load_system(System &system, std::vector<char> const &blob) {
  CheckpointAccess::load(system, blob);
}

std::vector<char> save_accumulator(AutoUpdate const &acc) { return CheckpointAccess::save_acc(acc); }

void load_accumulator(AutoUpdate &acc, std::vector<char> const &blob) {
  CheckpointAccess::load_acc(acc, blob);
}

} // namespace Checkpoint
} // namespace Marble
