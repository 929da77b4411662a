// Script interface of the Lees-Edwards boundary conditions
// (marble.lees_edwards, box/LeesEdwards.hpp, doc/lees-edwards.md).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::LeesEdwardsProtocol;
using Marble::System;

void bind_lees_edwards(py::class_<System> &cls) {
  // kind 0 switches Lees-Edwards off (the other arguments are then ignored)
  cls.def("le_set", [](System &s, int shear_direction, int shear_plane_normal, int kind, py::object initial_pos_offset,
                       py::object shear_velocity, py::object amplitude, py::object omega, py::object time_0) {
    LeesEdwardsProtocol p;
    if (kind < LeesEdwardsProtocol::Off || kind > LeesEdwardsProtocol::Oscillatory)
      value_error("unknown Lees-Edwards protocol kind " + std::to_string(kind));
    p.kind = kind;
    if (kind != LeesEdwardsProtocol::Off) {
      if (shear_direction < 0 || shear_direction > 2)
        value_error("parameter 'shear_direction' must be 'x', 'y' or 'z' (0, 1, 2), got " +
                    std::to_string(shear_direction));
      if (shear_plane_normal < 0 || shear_plane_normal > 2)
        value_error("parameter 'shear_plane_normal' must be 'x', 'y' or 'z' (0, 1, 2), got " +
                    std::to_string(shear_plane_normal));
      if (shear_direction == shear_plane_normal)
        value_error("parameters 'shear_direction' and 'shear_plane_normal' must be different axes");
      if (!s.box().periodic(shear_direction) || !s.box().periodic(shear_plane_normal))
        value_error("Lees-Edwards boundary conditions need periodic shear direction and shear-plane normal");
      auto fin = [](char const *name, py::object const &o) {
        return check_double(name, to_double(name, o), -INFINITY, INFINITY, false);
      };
      p.initial_pos_offset = fin("initial_pos_offset", initial_pos_offset);
      p.time_0 = fin("time_0", time_0);
      if (kind == LeesEdwardsProtocol::Linear)
        p.shear_velocity = fin("shear_velocity", shear_velocity);
      if (kind == LeesEdwardsProtocol::Oscillatory) {
        p.amplitude = fin("amplitude", amplitude);
        p.omega = fin("omega", omega);
      }
    }
    s.set_lees_edwards(shear_direction, shear_plane_normal, p);
  });
  cls.def("le_state", [](System &s) {
    auto const &p = s.lees_edwards_protocol();
    auto const &le = s.box().lees_edwards();
    py::dict d;
    d["kind"] = p.kind;
    d["initial_pos_offset"] = p.initial_pos_offset;
    d["shear_velocity_param"] = p.shear_velocity;
    d["amplitude"] = p.amplitude;
    d["omega"] = p.omega;
    d["time_0"] = p.time_0;
    d["shear_direction"] = le.shear_direction;
    d["shear_plane_normal"] = le.shear_plane_normal;
    d["pos_offset"] = le.pos_offset;
    d["shear_velocity"] = le.shear_velocity;
    return d;
  });
}

} // namespace ScriptInterface
