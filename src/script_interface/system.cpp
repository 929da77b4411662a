// Script interface of the System (marble.system): geometry, periodicity, time
// step, time, step counter, force evaluation.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;
using Utils::Vector3d;

namespace {

Vector3d check_box(py::handle h) {
  Vector3d const l = to_vec3("box_l", h);
  for (int d = 0; d < 3; ++d)
    check_double("box_l", l[d], 0., 1e9, true);
  return l;
}

} // namespace

void bind_system(py::class_<System> &cls) {
  cls.def(py::init([](py::object box_l) { return std::make_unique<System>(check_box(box_l)); }),
          "box_l"_a);
  cls.def_property(
      "box_l", [](System const &s) { return vec_to_array(s.box().length()); },
      [](System &s, py::object l) {
        if (s.n_particles() > 0)
          value_error("box_l cannot be changed while particles exist (rescaling is not "
                      "implemented); clear the particles first");
        s.set_box_l(check_box(l));
      });
  cls.def_property(
      "time_step", [](System const &s) { return s.time_step(); },
      [](System &s, py::object dt) { s.set_time_step(check_double("time_step", to_double("time_step", dt), 0., INFINITY, true)); });
  cls.def_property(
      "time", [](System const &s) { return s.time(); },
      [](System &s, py::object t) { s.set_time(check_double("time", to_double("time", t), 0.)); });
  cls.def_property_readonly("step", [](System const &s) { return s.step(); });
  cls.def("distance_vec", [](System &s, int a, int b) {
    try {
      return vec_to_array(s.distance_vec(a, b));
    } catch (std::out_of_range const &) {
      throw py::index_error("particle does not exist");
    }
  });
  cls.def("compute_forces", [](System &s) { s.compute_forces(true); });
  cls.def("set_periodicity", [](System &s, std::vector<bool> const &p) {
    if (p.size() != 3)
      value_error("parameter 'periodicity' must be 3 bools");
    for (int d = 0; d < 3; ++d)
      s.set_periodic(d, p[d]);
  });
  cls.def("get_periodicity", [](System &s) {
    return std::vector<bool>{s.box().periodic(0), s.box().periodic(1), s.box().periodic(2)};
  });
}

} // namespace ScriptInterface
