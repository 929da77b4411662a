// Script interface of the non-bonded interactions, one named kind per kernel:
// set_params validates every key (ValueError naming the parameter and range),
// get_params returns what is stored, deactivate switches the kernel off.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::IAParams;
using Marble::System;

namespace {

double get_num(py::dict const &kw, char const *key, double dflt) {
  return kw.contains(key) ? to_double(key, kw[key]) : dflt;
}
void require(py::dict const &kw, std::string const &what, std::vector<char const *> const &keys) {
  for (auto k : keys)
    if (!kw.contains(k))
      value_error("parameter '" + std::string(k) + "' is required for " + what);
}

void check_types(int i, int j) {
  for (int t : {i, j})
    if (t < 0 || t >= Marble::InteractionTable::max_type)
      value_error("particle type must be an integer in [0, " +
                  std::to_string(Marble::InteractionTable::max_type) + "), got " + std::to_string(t));
}

#ifdef LENNARD_JONES
void set_lj(IAParams &p, py::dict const &kw) {
  check_keys("lennard_jones", kw, {"epsilon", "sigma", "cutoff", "shift", "offset", "min"});
  require(kw, "lennard_jones", {"epsilon", "sigma", "cutoff"});
  Marble::LennardJonesParams lj;
  lj.epsilon = check_double("epsilon", get_num(kw, "epsilon", 0.), 0., INFINITY);
  lj.sigma = check_double("sigma", get_num(kw, "sigma", 0.), 0., INFINITY, true);
  lj.cutoff = check_double("cutoff", get_num(kw, "cutoff", 0.), 0., INFINITY, true);
  lj.offset = check_double("offset", get_num(kw, "offset", 0.), 0., INFINITY);
  lj.min = check_double("min", get_num(kw, "min", 0.), 0., lj.cutoff, false, true);
  if (kw.contains("shift") && py::isinstance<py::str>(kw["shift"])) {
    if (kw["shift"].cast<std::string>() != "auto")
      value_error("parameter 'shift' must be a number or \"auto\"");
    lj.shift = Marble::LennardJonesParams::auto_shift(lj.sigma, lj.cutoff);
  } else {
    lj.shift = check_double("shift", get_num(kw, "shift", 0.));
  }
  lj.active = lj.epsilon > 0.;
  p.lj = lj;
}
py::dict get_lj(IAParams const &p) {
  return py::dict("epsilon"_a = p.lj.epsilon, "sigma"_a = p.lj.sigma, "cutoff"_a = p.lj.cutoff,
                  "shift"_a = p.lj.shift, "offset"_a = p.lj.offset, "min"_a = p.lj.min);
}
#endif

#ifdef HAT
void set_hat(IAParams &p, py::dict const &kw) {
  check_keys("hat", kw, {"F_max", "cutoff"});
  require(kw, "hat", {"F_max", "cutoff"});
  Marble::HatParams h;
  h.F_max = check_double("F_max", get_num(kw, "F_max", 0.), 0., INFINITY);
  h.cutoff = check_double("cutoff", get_num(kw, "cutoff", 0.), 0., INFINITY, true);
  h.active = h.F_max > 0.;
  p.hat = h;
}
py::dict get_hat(IAParams const &p) { return py::dict("F_max"_a = p.hat.F_max, "cutoff"_a = p.hat.cutoff); }
#endif

#ifdef DPD
Marble::DPDWeight read_weight(py::dict const &kw, std::string const &prefix) {
  Marble::DPDWeight w;
  auto key = [&](char const *k) { return prefix + k; };
  auto wf = key("weight_function");
  if (kw.contains(wf.c_str())) {
    long long const v = to_int(wf, kw[wf.c_str()]);
    if (v != 0 && v != 1)
      value_error("parameter '" + wf + "' must be 0 (w = 1) or 1 (w = 1 - (r/r_cut)^k), got " +
                  std::to_string(v));
    w.weight_function = static_cast<int>(v);
  }
  w.gamma = check_double(key("gamma"), get_num(kw, key("gamma").c_str(), 0.), 0., INFINITY);
  w.r_cut = check_double(key("r_cut"), get_num(kw, key("r_cut").c_str(), 0.), 0., INFINITY);
  w.k = check_double(key("k"), get_num(kw, key("k").c_str(), 1.), 0., INFINITY, true);
  return w;
}
void set_dpd(IAParams &p, py::dict const &kw) {
  check_keys("dpd", kw, {"weight_function", "gamma", "k", "r_cut", "trans_weight_function",
                         "trans_gamma", "trans_r_cut"});
  Marble::DPDParams d;
  d.radial = read_weight(kw, "");
#ifdef TRANS_DPD
  d.trans = read_weight(kw, "trans_");
  d.trans.k = d.radial.k; // espressomd: one exponent k for both weights
  d.active = (d.radial.gamma > 0. && d.radial.r_cut > 0.) || (d.trans.gamma > 0. && d.trans.r_cut > 0.);
#else
  for (auto k : {"trans_weight_function", "trans_gamma", "trans_r_cut"})
    if (kw.contains(k) && to_double(k, kw[k]) != 0.)
      throw Utils::FeaturesError("TRANS_DPD", std::string("dpd parameter '") + k + "'");
  d.active = d.radial.gamma > 0. && d.radial.r_cut > 0.;
#endif
  p.dpd = d;
}
py::dict get_dpd(IAParams const &p) {
  py::dict d("weight_function"_a = p.dpd.radial.weight_function, "gamma"_a = p.dpd.radial.gamma,
             "k"_a = p.dpd.radial.k, "r_cut"_a = p.dpd.radial.r_cut);
#ifdef TRANS_DPD
  d["trans_weight_function"] = p.dpd.trans.weight_function;
  d["trans_gamma"] = p.dpd.trans.gamma;
  d["trans_r_cut"] = p.dpd.trans.r_cut;
#else
  d["trans_weight_function"] = 0;
  d["trans_gamma"] = 0.;
  d["trans_r_cut"] = 0.;
#endif
  return d;
}
#endif

[[noreturn]] void unknown_kind(std::string const &kind) {
  if (kind == "lennard_jones")
    throw Utils::FeaturesError("LENNARD_JONES", "lennard_jones");
  if (kind == "hat")
    throw Utils::FeaturesError("HAT", "hat");
  if (kind == "dpd")
    throw Utils::FeaturesError("DPD", "dpd");
  value_error("unknown non-bonded interaction '" + kind + "'");
}

} // namespace

void bind_interactions(py::class_<System> &cls) {
  cls.def("set_nonbonded", [](System &s, int i, int j, std::string const &kind, py::dict kw) {
    check_types(i, j);
    s.interactions().ensure_type(std::max(i, j));
    IAParams p = s.interactions().get(i, j);
    if (false) {
    }
#ifdef LENNARD_JONES
    else if (kind == "lennard_jones") set_lj(p, kw);
#endif
#ifdef HAT
    else if (kind == "hat") set_hat(p, kw);
#endif
#ifdef DPD
    else if (kind == "dpd") set_dpd(p, kw);
#endif
    else unknown_kind(kind);
    s.set_interaction(i, j, p);
  });
  cls.def("get_nonbonded", [](System &s, int i, int j, std::string const &kind) -> py::dict {
    check_types(i, j);
    s.interactions().ensure_type(std::max(i, j));
    IAParams const &p = s.interactions().get(i, j);
    if (false) {
    }
#ifdef LENNARD_JONES
    else if (kind == "lennard_jones") return p.lj.active ? get_lj(p) : py::dict();
#endif
#ifdef HAT
    else if (kind == "hat") return p.hat.active ? get_hat(p) : py::dict();
#endif
#ifdef DPD
    else if (kind == "dpd") return p.dpd.active ? get_dpd(p) : py::dict();
#endif
    unknown_kind(kind);
  });
  cls.def("deactivate_nonbonded", [](System &s, int i, int j, std::string const &kind) {
    check_types(i, j);
    s.interactions().ensure_type(std::max(i, j));
    IAParams p = s.interactions().get(i, j);
    if (false) {
    }
#ifdef LENNARD_JONES
    else if (kind == "lennard_jones") p.lj = {};
#endif
#ifdef HAT
    else if (kind == "hat") p.hat = {};
#endif
#ifdef DPD
    else if (kind == "dpd") p.dpd = {};
#endif
    else unknown_kind(kind);
    s.set_interaction(i, j, p);
  });
}

} // namespace ScriptInterface
