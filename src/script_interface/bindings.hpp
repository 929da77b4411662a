#pragma once
#include "system/System.hpp"

#include <pybind11/pybind11.h>

namespace ScriptInterface {
namespace py = pybind11;
using namespace pybind11::literals;
// One file per Python module of the marble package (file name = module name).
void bind_system(py::class_<Marble::System> &cls);        // system.cpp
void bind_cell_system(py::class_<Marble::System> &cls);   // cell_system.cpp
void bind_particle_data(py::class_<Marble::System> &cls); // particle_data.cpp
void bind_interactions(py::class_<Marble::System> &cls);  // interactions.cpp
void bind_colloids(py::class_<Marble::System> &cls);      // colloids.cpp
void bind_constraints(py::class_<Marble::System> &cls);   // constraints.cpp
void bind_thermostat(py::class_<Marble::System> &cls);    // thermostat.cpp
void bind_integrate(py::class_<Marble::System> &cls);     // integrate.cpp
void bind_analysis(py::class_<Marble::System> &cls);      // analysis.cpp
void bind_accumulators(py::module_ &m, py::class_<Marble::System> &cls); // accumulators.cpp
void bind_io(py::module_ &m, py::class_<Marble::System> &cls);           // io.cpp
void bind_srd(py::class_<Marble::System> &cls);           // srd.cpp
void bind_lees_edwards(py::class_<Marble::System> &cls);  // lees_edwards.cpp
} // namespace ScriptInterface
