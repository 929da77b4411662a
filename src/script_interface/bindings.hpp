#pragma once
#include "system/System.hpp"

#include <pybind11/pybind11.h>

namespace ScriptInterface {
namespace py = pybind11;
using namespace pybind11::literals;
void bind_particles(py::class_<Marble::System> &cls);
void bind_interactions(py::class_<Marble::System> &cls);
void bind_system(py::class_<Marble::System> &cls);
void bind_marble(py::class_<Marble::System> &cls);
void bind_constraints(py::class_<Marble::System> &cls);
void bind_integrators(py::class_<Marble::System> &cls); // integrators.cpp
void bind_accumulators(py::module_ &m, py::class_<Marble::System> &cls);
void bind_io(py::module_ &m, py::class_<Marble::System> &cls); // io.cpp
} // namespace ScriptInterface
