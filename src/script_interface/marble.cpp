// Script interface of the marble colloid coupling:
// non_bonded_inter[c, s].marble.set_params(radius=, gamma=, r_cut=, weight_function=, k=, coupling=)
#include <climits>
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;

void bind_marble(py::class_<System> &cls) {
  cls.def("set_marble", [](System &s, int c, int sv, py::dict kw) {
#ifdef MARBLE
    check_keys("marble", kw, {"radius", "gamma", "r_cut", "weight_function", "k", "coupling"});
    for (auto key : {"radius", "gamma"})
      if (!kw.contains(key))
        value_error(std::string("parameter '") + key + "' is required for marble");
    for (int t : {c, sv})
      if (t < 0 || t >= Marble::InteractionTable::max_type)
        value_error("particle type must be an integer in [0, 256), got " + std::to_string(t));
    if (c == sv)
      value_error("marble: the colloid type and the solvent type must differ (got " +
                  std::to_string(c) + " for both)");
    Marble::MarbleParams p;
    p.radius = check_double("radius", to_double("radius", kw["radius"]), 0., 1e6, true);
    p.gamma = check_double("gamma", to_double("gamma", kw["gamma"]), 0., INFINITY);
    p.r_cut = kw.contains("r_cut") ? check_double("r_cut", to_double("r_cut", kw["r_cut"]), 0., 1e6, true) : 1.;
    if (kw.contains("weight_function")) {
      long long const wf = to_int("weight_function", kw["weight_function"]);
      if (wf != 0 && wf != 1)
        value_error("parameter 'weight_function' must be 0 (w = 1) or 1 (w = 1 - (h/r_cut)^k), got " +
                    std::to_string(wf));
      p.weight_function = static_cast<int>(wf);
    }
    p.k = kw.contains("k") ? check_double("k", to_double("k", kw["k"]), 0., INFINITY, true) : 1.;
    std::string coupling = "tunable_slip";
    if (kw.contains("coupling")) {
      if (!py::isinstance<py::str>(kw["coupling"]))
        value_error("parameter 'coupling' must be one of 'tunable_slip', 'transverse', 'dpd'");
      coupling = kw["coupling"].cast<std::string>();
    }
    if (coupling == "tunable_slip")
      p.coupling = Marble::MarbleCoupling::tunable_slip;
    else if (coupling == "transverse")
      p.coupling = Marble::MarbleCoupling::transverse;
    else if (coupling == "dpd")
      p.coupling = Marble::MarbleCoupling::dpd;
    else
      value_error("parameter 'coupling' must be one of 'tunable_slip', 'transverse', 'dpd', got '" +
                  coupling + "'");
    p.active = true;
    auto const &col = s.colloids();
    if (col.is_colloid_type(sv))
      value_error("marble: type " + std::to_string(sv) +
                  " is already a colloid type; it cannot also be the solvent of a coupling");
    if (col.is_solvent_type(c))
      value_error("marble: type " + std::to_string(c) +
                  " is already the solvent of a coupling; it cannot also be a colloid type");
    // A coupling that exerts torque needs rotating colloids.
    if (p.transmits_torque()) {
      auto const &ps = s.particles();
      int bad = INT_MAX;
      for (int i = 0; i < ps.n_local(); ++i)
        if (ps.type[i] == c && !ps.rotation[i])
          bad = std::min(bad, ps.id[i]);
      bad = s.comm().min(bad);
      if (bad != INT_MAX)
        value_error("marble: particle " + std::to_string(bad) + " of colloid type " +
                    std::to_string(c) + " does not rotate, but coupling '" + coupling +
                    "' exerts torque: add it with rotation=True (or use coupling='dpd')");
    }
    s.set_marble(c, sv, p);
#else
    (void)s, (void)c, (void)sv, (void)kw;
    throw Utils::FeaturesError("MARBLE", "marble");
#endif
  });
  cls.def("get_marble", [](System &s, int c, int sv) {
    py::dict d;
#ifdef MARBLE
    auto const &p = s.colloids().get(c, sv);
    if (!p.active)
      return d;
    static char const *names[] = {"dpd", "transverse", "tunable_slip"};
    d["radius"] = p.radius;
    d["gamma"] = p.gamma;
    d["r_cut"] = p.r_cut;
    d["weight_function"] = p.weight_function;
    d["k"] = p.k;
    d["coupling"] = names[static_cast<int>(p.coupling)];
#else
    (void)s, (void)c, (void)sv;
    throw Utils::FeaturesError("MARBLE", "marble");
#endif
    return d;
  });
  cls.def("deactivate_marble", [](System &s, int c, int sv) {
#ifdef MARBLE
    if (c < 0 || sv < 0 || c >= Marble::InteractionTable::max_type || sv >= Marble::InteractionTable::max_type)
      value_error("particle type must be an integer in [0, 256)");
    s.set_marble(c, sv, Marble::MarbleParams{});
#else
    (void)s, (void)c, (void)sv;
    throw Utils::FeaturesError("MARBLE", "marble");
#endif
  });
  cls.def("n_colloid_pairs", [](System &s) -> std::size_t {
#ifdef MARBLE
    s.ensure_lists();
    return s.colloids().n_pairs();
#else
    (void)s;
    return 0;
#endif
  });
}

} // namespace ScriptInterface
