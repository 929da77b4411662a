// Script interface of the analysis (marble.analysis): energies, pressure
// tensor, DPD stress (doc/dpd.md), momentum, distances, the scene check.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"
#include "utils/errors.hpp"
#include "analysis/scene_check.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>

namespace ScriptInterface {

using Marble::System;

void bind_analysis(py::class_<System> &cls) {
  cls.def("energy", [](System &s) {
    auto const e = s.energies();
    py::dict d;
    d["total"] = e.total();
    d["kinetic"] = e.kinetic;
    d["kinetic_rotational"] = e.kinetic_rot;
    d["non_bonded"] = e.non_bonded;
    int const nt = s.interactions().n_types();
    for (int i = 0; i < nt; ++i)
      for (int j = i; j < nt; ++j)
        d[py::make_tuple("non_bonded", i, j)] = e.non_bonded_pairs[i * nt + j];
    return d;
  });
  cls.def("pressure_tensor", [](System &s) {
    auto const p = s.pressure_tensor();
    std::array<double, 9> tot{};
    for (int k = 0; k < 9; ++k)
      tot[k] = p.kinetic[k] + p.non_bonded[k];
    py::dict d;
    d["total"] = mat_to_array(tot);
    d["kinetic"] = mat_to_array(p.kinetic);
    d["non_bonded"] = mat_to_array(p.non_bonded);
    // dissipative parts: separate, not in "total" (ESPResSo's total has none;
    // the full mechanical stress is total + dpd + marble)
    d["dpd"] = mat_to_array(p.dpd);
    d["marble"] = mat_to_array(p.marble);
    return d;
  });
  cls.def("linear_momentum", [](System &s) { return vec_to_array(s.linear_momentum()); });
  cls.def("spin_angular_momentum", [](System &s) { return vec_to_array(s.angular_momentum_spin()); });
  cls.def("center_of_mass", [](System &s) { return vec_to_array(s.center_of_mass()); });
  cls.def("total_mass", &System::total_mass);
  cls.def("min_dist", &System::min_dist, "types1"_a, "types2"_a);
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
  cls.def("dpd_stress", [](Marble::System &s) {
#ifdef DPD
    auto const st = s.dpd_stress();
    std::array<double, 9> tot{};
    for (int k = 0; k < 9; ++k)
      tot[k] = st.friction[k] + st.noise[k];
    py::dict d;
    d["total"] = mat_to_array(tot);
    d["friction"] = mat_to_array(st.friction);
    d["noise"] = mat_to_array(st.noise);
    return d;
#else
    (void)s;
    throw Utils::FeaturesError("DPD", "analysis.dpd_stress");
#endif
  });
}

} // namespace ScriptInterface
