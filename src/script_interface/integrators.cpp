// Script interface of the DPD integrators (Shardlow S1, DPD-VV), the
// integrator state and the scene check (doc/stability.md).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include "analysis/scene_check.hpp"

#include <pybind11/stl.h>

namespace ScriptInterface {

using Marble::IntegratorKind;
using Marble::System;

void bind_integrators(py::class_<System> &cls) {
  cls.def("set_shardlow", [](System &s) {
#ifdef DPD
    s.set_integrator_shardlow();
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "integrator.set_shardlow");
#endif
  });
  cls.def("set_dpd_vv", [](System &s) {
#ifdef DPD
    s.set_integrator_dpd_vv();
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "integrator.set_dpd_vv");
#endif
  });
  cls.def("check_scene", [](System &s) {
    py::list out;
    for (auto const &w : Marble::check_scene(s)) {
      py::dict d;
      d["code"] = w.code;
      d["message"] = w.message;
      d["value"] = w.value;
      d["limit"] = w.limit;
      out.append(d);
    }
    return out;
  });
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
    }
    return "?";
  });
}

} // namespace ScriptInterface
