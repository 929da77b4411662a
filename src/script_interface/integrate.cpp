// Script interface of the integrators (marble.integrate): velocity Verlet,
// steepest descent, the DPD integrators (Shardlow S1, DPD-VV; doc/stability.md)
// Brownian dynamics and run().
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/stl.h>

namespace ScriptInterface {

using Marble::IntegratorKind;
using Marble::System;

namespace {
/** RESPA substeps (System::substeps): an integer in [1, max_substeps]. */
int check_substeps(py::object const &v) {
  long long const n = to_int("substeps", v);
  if (n < 1 || n > System::max_substeps)
    value_error("parameter 'substeps' must be an integer in [1, " + std::to_string(System::max_substeps) +
                "], got " + std::to_string(n));
  return static_cast<int>(n);
}
} // namespace

void bind_integrate(py::class_<System> &cls) {
  cls.def("set_vv", [](System &s, py::object substeps) { s.set_integrator_vv(check_substeps(substeps)); },
          "substeps"_a = 1);
  cls.def("set_steepest_descent", [](System &s, py::object f_max, py::object gamma, py::object max_disp) {
    Marble::SteepestDescentParams p;
    p.f_max = check_double("f_max", to_double("f_max", f_max), 0., INFINITY);
    // gamma = 0 is allowed (as in ESPResSo): the descent then only evaluates forces
    p.gamma = check_double("gamma", to_double("gamma", gamma), 0., INFINITY);
    p.max_displacement = check_double("max_displacement", to_double("max_displacement", max_disp), 0., INFINITY, true);
    s.set_integrator_sd(p);
  }, "f_max"_a, "gamma"_a, "max_displacement"_a);
  cls.def("integrator_state", [](System &s) {
    py::dict d;
    if (s.integrator() == Marble::IntegratorKind::VelocityVerlet) {
      d["name"] = "VelocityVerlet";
      d["substeps"] = s.substeps();
    } else if (s.integrator() == Marble::IntegratorKind::Shardlow) {
      d["name"] = "Shardlow";
      d["substeps"] = s.substeps();
    } else {
      d["name"] = "SteepestDescent";
      d["f_max"] = s.sd_params().f_max;
      d["gamma"] = s.sd_params().gamma;
      d["max_displacement"] = s.sd_params().max_displacement;
    }
    return d;
  });
  cls.def("run", [](System &s, py::object steps, bool recalc_forces) {
    long long const n = to_int("steps", steps);
    if (n < 0 || n > 2000000000LL)
      value_error("parameter 'steps' must be an integer in [0, 2e9], got " + std::to_string(n));
    py::gil_scoped_release release;
    if (n == 0 && s.integrator() == IntegratorKind::SteepestDescent) {
      // run(0) evaluates the forces with every integrator (as in ESPResSo);
      // steepest descent's exclude the thermostat, so they are not kept for MD
      s.check_scene_before_run();
      s.compute_forces(false);
      s.on_change();
      return 0;
    }
    return s.run(static_cast<int>(n), recalc_forces);
  }, "steps"_a, "recalc_forces"_a = false);
  cls.def("set_shardlow", [](System &s, py::object substeps) {
#ifdef DPD
    s.set_integrator_shardlow(check_substeps(substeps));
#else
    (void)s;
    (void)substeps;
    throw Utils::FeaturesError("DPD", "integrator.set_shardlow");
#endif
  }, "substeps"_a = 1);
  cls.def("set_dpd_vv", [](System &s) {
#ifdef DPD
    s.set_integrator_dpd_vv();
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "integrator.set_dpd_vv");
#endif
  });
  cls.def("set_brownian_dynamics", &System::set_integrator_bd);
  cls.def("integrator_name", [](System &s) {
    switch (s.integrator()) {
    case IntegratorKind::VelocityVerlet:
      return "VelocityVerlet";
    case IntegratorKind::SteepestDescent:
      return "SteepestDescent";
    case IntegratorKind::Shardlow:
      return "Shardlow";
    case IntegratorKind::DPDVV:
      return "DPDVV";
    case IntegratorKind::BrownianDynamics:
      return "BrownianDynamics";
    }
    return "?";
  });
}

} // namespace ScriptInterface
