// The compiled part of the Python package: marble._marble.
#include "script_interface/bindings.hpp"

#include "config/features.hpp"
#include "utils/errors.hpp"

#include <pybind11/stl.h>

#include <sstream>
#include <string>
#include <vector>

namespace ScriptInterface {
void bind_dpd(pybind11::class_<Marble::System> &cls); // dpd.cpp
}

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
  m.def("features", [] { return split(MARBLE_FEATURES_ACTIVE); });
  m.def("all_features", [] { return split(MARBLE_FEATURES_ALL); });

  py::class_<Marble::System> cls(m, "System");
  ScriptInterface::bind_system(cls);
  ScriptInterface::bind_particles(cls);
  ScriptInterface::bind_interactions(cls);
  ScriptInterface::bind_marble(cls);
  ScriptInterface::bind_constraints(cls);
  ScriptInterface::bind_dpd(cls);
  ScriptInterface::bind_integrators(cls);
  ScriptInterface::bind_accumulators(m, cls);
}
