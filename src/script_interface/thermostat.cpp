// Script interface of the thermostat (marble.thermostat): the DPD thermostat
// (kT, seed, Philox counter).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

namespace ScriptInterface {

using Marble::System;
using Utils::Vector3d;

void bind_thermostat(py::class_<System> &cls) {
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
