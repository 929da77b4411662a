// Script interface of the I/O (doc/io.md): checkpoint state of the System and
// of the accumulators as bytes (marble.checkpointing pickles them), the H5MD
// writer (marble.io.H5md) and the collective helpers the Python side needs.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include "comm/Communicator.hpp"
#include "io/checkpoint.hpp"
#ifdef MARBLE_HAVE_HDF5
#include "io/h5md.hpp"
#endif

#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

namespace ScriptInterface {

using Marble::AutoUpdate;
using Marble::System;

namespace {

std::vector<char> bytes_of(py::handle h, char const *name) {
  if (!py::isinstance<py::bytes>(h))
    value_error(std::string("parameter '") + name + "' must be bytes");
  auto const s = h.cast<std::string>();
  return {s.begin(), s.end()};
}

py::bytes to_bytes(std::vector<char> const &v) { return py::bytes(v.data(), v.size()); }

#ifdef MARBLE_HAVE_HDF5
Marble::IO::H5mdFields parse_fields(py::handle h) {
  static std::vector<std::string> const names{"position", "image", "velocity", "force", "species",
                                              "mass",     "id",    "box",      "time",  "step",
                                              "srd"};
  std::string allowed = "all";
  for (auto const &n : names)
    allowed += ", " + n;
  std::vector<std::string> list;
  if (py::isinstance<py::str>(h)) {
    auto const s = h.cast<std::string>();
    if (s == "all")
      return {};
    list.push_back(s);
  } else if (py::hasattr(h, "__iter__")) {
    for (auto item : h) {
      if (!py::isinstance<py::str>(item))
        value_error("parameter 'fields' must be 'all' or a list of names from: " + allowed);
      list.push_back(item.cast<std::string>());
    }
  } else {
    value_error("parameter 'fields' must be 'all' or a list of names from: " + allowed);
  }
  if (list.empty())
    value_error("parameter 'fields' must name at least one field (" + allowed + ")");
  Marble::IO::H5mdFields f;
  f.position = f.image = f.velocity = f.force = f.species = f.mass = f.id = f.box = f.time = f.srd = false;
  f.step = true; // H5MD requires step in every time series
  for (auto const &s : list) {
    if (s == "all")
      return {};
    bool *flag = s == "position" ? &f.position
                 : s == "image"  ? &f.image
                 : s == "velocity" ? &f.velocity
                 : s == "force"  ? &f.force
                 : s == "species" ? &f.species
                 : s == "mass"   ? &f.mass
                 : s == "id"     ? &f.id
                 : s == "box"    ? &f.box
                 : s == "time"   ? &f.time
                 : s == "step"   ? &f.step
                 : s == "srd"    ? &f.srd
                                 : nullptr;
    if (!flag)
      value_error("parameter 'fields': unknown field '" + s + "' (allowed: " + allowed + ")");
    *flag = true;
  }
  return f;
}
#endif

} // namespace

void bind_io(py::module_ &m, py::class_<System> &cls) {
  // --- checkpoints ---
  cls.def("get_checkpoint_state",
          [](System const &s) { return to_bytes(Marble::Checkpoint::save_system(s)); });
  cls.def("set_checkpoint_state", [](System &s, py::object blob) {
    auto const b = bytes_of(blob, "state");
    py::gil_scoped_release release;
    Marble::Checkpoint::load_system(s, b);
  });
  m.def("accumulator_get_state",
        [](AutoUpdate const &a) { return to_bytes(Marble::Checkpoint::save_accumulator(a)); });
  m.def("accumulator_set_state", [](AutoUpdate &a, py::object blob) {
    Marble::Checkpoint::load_accumulator(a, bytes_of(blob, "state"));
  });
  m.def("crc32", [](py::bytes b, std::uint32_t crc) {
    auto const s = b.cast<std::string_view>();
    return Marble::Checkpoint::crc32(s.data(), s.size(), crc);
  }, "data"_a, "crc"_a = 0);

  // --- collective helpers (SPMD) ---
  m.def("comm_barrier", [] { Marble::Communicator().barrier(); });
  m.def("comm_throw_if_any", [](std::string const &msg) { Marble::Communicator().throw_if_any(msg); });

  // --- H5MD ---
#ifdef MARBLE_HAVE_HDF5
  m.def("have_hdf5", [] { return true; });
  py::class_<Marble::IO::H5mdFile>(m, "H5mdFile")
      .def(py::init([](System const &s, std::string const &path, py::object fields,
                       std::string const &author, std::string const &mode) {
             if (path.empty())
               value_error("parameter 'file_path' must be a non-empty path");
             if (mode != "w" && mode != "append")
               value_error("parameter 'mode' must be 'w' (create or replace) or 'append', got '" +
                           mode + "'");
             auto const f = parse_fields(fields);
             return std::make_unique<Marble::IO::H5mdFile>(s, path, f, author, mode == "append");
           }),
           "system"_a, "file_path"_a, "fields"_a, "author"_a, "mode"_a = "w")
      .def("write", &Marble::IO::H5mdFile::write, py::call_guard<py::gil_scoped_release>())
      .def("flush", &Marble::IO::H5mdFile::flush)
      .def("close", &Marble::IO::H5mdFile::close)
      .def_property_readonly("is_open", &Marble::IO::H5mdFile::is_open)
      .def_property_readonly("n_frames", &Marble::IO::H5mdFile::n_frames)
      .def_property_readonly("n_particles", &Marble::IO::H5mdFile::n_particles)
      .def_property_readonly("file_path", &Marble::IO::H5mdFile::path);
#else
  m.def("have_hdf5", [] { return false; });
#endif
}

} // namespace ScriptInterface
