// Script interface of constraints (marble.constraints): walls. Their
// tunable-slip friction is a kernel (non_bonded_inter[wall, fluid].tunable_slip).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;
using Utils::Vector3d;

void bind_constraints(py::class_<System> &cls) {
  cls.def("add_wall", [](System &s, py::object normal, py::object dist, py::object type, py::object velocity) {
    Marble::Wall w;
    Vector3d n = to_vec3("normal", normal);
    double const len = n.norm();
    if (!(len > 0.))
      value_error("parameter 'normal' must be a non-zero vector");
    w.normal = n / len;
    w.dist = check_double("dist", to_double("dist", dist));
    long long const t = to_int("particle_type", type);
    if (t < 0 || t >= Marble::InteractionTable::max_type)
      value_error("parameter 'particle_type' must be an integer in [0, 256), got " + std::to_string(t));
    w.type = static_cast<int>(t);
    w.velocity = velocity.is_none() ? Vector3d{} : to_vec3("velocity", velocity);
    if (std::abs(w.velocity * w.normal) > 1e-12 * (1. + w.velocity.norm()))
      value_error("parameter 'velocity' must be tangential to the wall (velocity . normal = 0); "
                  "moving walls along their normal are not supported");
    int const id = s.constraints().add_wall(w);
    s.on_constraints_change();
    return id;
  });
  cls.def("remove_constraint", [](System &s, int id) {
    if (!s.constraints().find(id))
      value_error("no constraint with id " + std::to_string(id));
    s.constraints().remove(id);
    s.on_constraints_change();
  });
  cls.def("clear_constraints", [](System &s) {
    s.constraints().clear();
    s.on_constraints_change();
  });
  cls.def("constraint_state", [](System &s, int id) {
    auto const *w = s.constraints().find(id);
    if (!w)
      value_error("no constraint with id " + std::to_string(id));
    py::dict d;
    auto arr = [](Vector3d const &v) { return std::vector<double>{v[0], v[1], v[2]}; };
    d["normal"] = arr(w->normal);
    d["dist"] = w->dist;
    d["particle_type"] = w->type;
    d["velocity"] = arr(w->velocity);
    d["total_force"] = arr(w->total_force);
    return d;
  });
}

} // namespace ScriptInterface
