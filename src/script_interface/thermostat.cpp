// Script interface of the thermostat (marble.thermostat): the DPD thermostat
// (kT, seed, Philox counter) and the single-particle Langevin and Brownian
// thermostats (kT, gamma, gamma_rotation, seed, Philox counter).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;
using Utils::Vector3d;

namespace {
Marble::SingleParticleThermostat &single(System &s, std::string const &which) {
  if (which == "langevin")
    return s.thermostat().langevin;
  if (which == "brownian")
    return s.thermostat().brownian;
  value_error("unknown thermostat '" + which + "'");
  return s.thermostat().langevin; // not reached
}
} // namespace

void bind_thermostat(py::class_<System> &cls) {
  // set_langevin / set_brownian (which = "langevin" / "brownian"); every
  // parameter is validated before anything changes.
  cls.def("set_single_particle_thermostat", [](System &s, std::string const &which, py::object kT,
                                               py::object gamma, py::object gamma_rotation,
                                               py::object seed) {
    auto &th = single(s, which);
    bool const bd = which == "brownian";
    double const t = check_double("kT", to_double("kT", kT), 0., INFINITY);
    // Brownian dynamics divides by gamma: it must be > 0
    double const g = check_double("gamma", to_double("gamma", gamma), 0., INFINITY, bd);
    double const gr = gamma_rotation.is_none()
                          ? g
                          : check_double("gamma_rotation", to_double("gamma_rotation", gamma_rotation),
                                         0., INFINITY, bd);
    std::uint64_t sd = th.seed;
    if (seed.is_none()) {
      if (!th.seeded)
        value_error("parameter 'seed' is required the first time the " +
                    std::string(bd ? "Brownian" : "Langevin") + " thermostat is activated");
    } else {
      long long const v = to_int("seed", seed);
      if (v < 0)
        value_error("parameter 'seed' must be an integer >= 0, got " + std::to_string(v));
      sd = static_cast<std::uint64_t>(v);
    }
    th.kT = t;
    th.gamma = g;
    th.gamma_rotation = gr;
    th.seed = sd;
    th.seeded = true;
    th.active = true;
    s.on_change();
  }, "which"_a, "kT"_a, "gamma"_a, "gamma_rotation"_a = py::none(), "seed"_a = py::none());
  cls.def("single_particle_thermostat_state", [](System &s, std::string const &which) {
    auto const &th = single(s, which);
    py::dict d;
    d["active"] = th.active;
    d["kT"] = th.kT;
    d["gamma"] = th.gamma;
    d["gamma_rotation"] = th.gamma_rotation;
    d["seed"] = th.seeded ? py::object(py::int_(th.seed)) : py::object(py::none());
    d["philox_counter"] = th.philox_counter;
    return d;
  });
  cls.def("set_single_particle_philox_counter", [](System &s, std::string const &which, py::object c) {
    auto &th = single(s, which);
    long long const v = to_int("philox_counter", c);
    if (v < 0)
      value_error("parameter 'philox_counter' must be an integer >= 0");
    th.philox_counter = static_cast<std::uint64_t>(v);
    s.on_change();
  });
  cls.def("set_dpd", [](System &s, py::object kT, py::object seed) {
#ifdef DPD
    auto &th = s.thermostat().dpd;
    double const t = check_double("kT", to_double("kT", kT), 0., INFINITY);
    if (seed.is_none()) {
      if (!th.seeded)
        value_error("parameter 'seed' is required the first time the DPD thermostat is activated");
    } else {
      long long const sd = to_int("seed", seed);
      if (sd < 0)
        value_error("parameter 'seed' must be an integer >= 0, got " + std::to_string(sd));
      th.seed = static_cast<std::uint64_t>(sd);
      th.seeded = true;
    }
    th.kT = t;
    th.active = true;
    s.update_thermostat_prefactors();
    s.on_change();
#else
    (void)s, (void)kT, (void)seed;
    throw Utils::FeaturesError("DPD", "thermostat.set_dpd");
#endif
  }, "kT"_a, "seed"_a = py::none());
  cls.def("thermostat_turn_off", [](System &s) {
    for (auto *th : {&s.thermostat().langevin, &s.thermostat().brownian}) {
      th->active = false; // seed and counter stay: a later set_* may omit the seed
      th->kT = 0.;
    }
#ifdef DPD
    s.thermostat().dpd.active = false;
    s.thermostat().dpd.kT = 0.;
    s.update_thermostat_prefactors();
#endif
    s.on_change();
  });
  cls.def("dpd_state", [](System &s) {
    py::dict d;
#ifdef DPD
    auto const &th = s.thermostat().dpd;
    d["active"] = th.active;
    d["kT"] = th.kT;
    d["seed"] = th.seeded ? py::object(py::int_(th.seed)) : py::object(py::none());
    d["philox_counter"] = th.philox_counter;
#else
    (void)s;
#endif
    return d;
  });
  cls.def("set_dpd_philox_counter", [](System &s, py::object c) {
#ifdef DPD
    long long const v = to_int("philox_counter", c);
    if (v < 0)
      value_error("parameter 'philox_counter' must be an integer >= 0");
    s.thermostat().dpd.philox_counter = static_cast<std::uint64_t>(v);
    s.on_change();
#else
    (void)s, (void)c;
    throw Utils::FeaturesError("DPD", "thermostat.dpd.philox_counter");
#endif
  });
}

} // namespace ScriptInterface
