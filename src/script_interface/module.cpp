// The compiled part of the Python package: marble._marble.
#include "script_interface/bindings.hpp"

#include "comm/Communicator.hpp"
#include "config/features.hpp"
#include "utils/errors.hpp"

#include <pybind11/stl.h>

#include <sstream>
#include <string>
#include <vector>

namespace {
std::vector<std::string> split(std::string const &s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;)
    out.push_back(w);
  return out;
}
} // namespace

PYBIND11_MODULE(_marble, m) {
  namespace py = pybind11;
  m.doc() = "Marble core (C++), wrapped by the marble package";
  static py::exception<Utils::FeaturesError> features_error(m, "FeaturesError", PyExc_Exception);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p)
        std::rethrow_exception(p);
    } catch (Utils::FeaturesError const &e) {
      features_error(e.what());
    } catch (Utils::RuntimeError const &e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  // SPMD: every rank runs the script; MPI is set up on import (a plain
  // `python script.py` is a one-rank run) and finalised at interpreter exit.
  Marble::mpi_init_once();
  py::module_::import("atexit").attr("register")(py::cpp_function([] { Marble::mpi_finalize_once(); }));
  m.def("mpi_rank", [] { return Marble::Communicator().rank(); });
  m.def("mpi_size", [] { return Marble::Communicator().size(); });
  m.def("mpi_abort", [](int code) { Marble::mpi_abort(code); });
  m.def("features", [] { return split(MARBLE_FEATURES_ACTIVE); });
  // optional libraries compiled in (not physics features)
  m.def("build_options", [] {
    std::vector<std::string> o;
#ifdef MARBLE_HAVE_MPI
    o.emplace_back("MPI");
#endif
#ifdef MARBLE_HAVE_HDF5
    o.emplace_back("HDF5");
#endif
#ifdef MARBLE_HAVE_FFTW
    o.emplace_back("FFTW");
#endif
    return o;
  });
  m.def("all_features", [] { return split(MARBLE_FEATURES_ALL); });

  py::class_<Marble::System> cls(m, "System");
  ScriptInterface::bind_system(cls);
  ScriptInterface::bind_cell_system(cls);
  ScriptInterface::bind_particle_data(cls);
  ScriptInterface::bind_interactions(cls);
  ScriptInterface::bind_colloids(cls);
  ScriptInterface::bind_constraints(cls);
  ScriptInterface::bind_thermostat(cls);
  ScriptInterface::bind_integrate(cls);
  ScriptInterface::bind_analysis(cls);
  ScriptInterface::bind_accumulators(m, cls);
  ScriptInterface::bind_io(m, cls);
  ScriptInterface::bind_srd(cls);
  ScriptInterface::bind_lees_edwards(cls);
}
