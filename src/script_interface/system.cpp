// Script interface of the System: geometry, time step, cell system, thermostat,
// integrator and analysis.
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
  cls.def_property(
      "skin", [](System const &s) { return s.skin(); },
      [](System &s, py::object v) {
        // > 0: a step that moves a particle farther than the skin is refused
        // as a blow-up (integrate.cpp), so a zero skin could never integrate.
        double const skin = check_double("skin", to_double("skin", v), 0., INFINITY, true);
        double const lmin = std::min({s.box().length()[0], s.box().length()[1], s.box().length()[2]});
        if (skin > 0.5 * lmin)
          value_error("parameter 'skin' must be in (0, box_l/2], got " + Utils::to_str(skin));
        s.set_skin(skin);
      });
  cls.def("n_rebuilds", [](System &s) { return s.cells().n_rebuilds(); });
  cls.def("node_grid", [](System &s) { return s.cells().node_grid(s.box()); });
  cls.def("local_domain", [](System &s) {
    auto const d = s.cells().local_domain(s.box());
    return std::make_pair(vec_to_array(d.first), vec_to_array(d.second));
  });
  // ids this rank owns (not collective; for tests and diagnostics)
  cls.def("local_ids", [](System &s) { return s.particles().ids_sorted(); });
  cls.def("n_cells", [](System &s) { return s.cells().n_cells(); });
  cls.def("max_cut", &System::max_cutoff);
  cls.def("verlet_pairs", [](System &s) {
    s.ensure_lists();
    auto const &ps = s.particles();
    std::vector<std::pair<int, int>> out;
    std::vector<std::array<int, 2>> loc;
    for (auto const &p : s.cells().pairs()) {
      int a = ps.id[p[0]], b = ps.id[p[1]];
      loc.push_back({std::min(a, b), std::max(a, b)});
    }
    for (auto const &p : s.comm().allgatherv(loc)) // every pair is listed on one rank
      out.emplace_back(p[0], p[1]);
    return out;
  });

  // --- thermostat ---
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

  // --- integrator ---
  cls.def("set_vv", &System::set_integrator_vv);
  cls.def("set_steepest_descent", [](System &s, py::object f_max, py::object gamma, py::object max_disp) {
    Marble::SteepestDescentParams p;
    p.f_max = check_double("f_max", to_double("f_max", f_max), 0., INFINITY);
    p.gamma = check_double("gamma", to_double("gamma", gamma), 0., INFINITY, true);
    p.max_displacement = check_double("max_displacement", to_double("max_displacement", max_disp), 0., INFINITY, true);
    s.set_integrator_sd(p);
  }, "f_max"_a, "gamma"_a, "max_displacement"_a);
  cls.def("integrator_state", [](System &s) {
    py::dict d;
    if (s.integrator() == Marble::IntegratorKind::VelocityVerlet) {
      d["name"] = "VelocityVerlet";
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
    return s.run(static_cast<int>(n), recalc_forces);
  }, "steps"_a, "recalc_forces"_a = false);

  // --- analysis ---
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
    return d;
  });
  cls.def("linear_momentum", [](System &s) { return vec_to_array(s.linear_momentum()); });
  cls.def("spin_angular_momentum", [](System &s) { return vec_to_array(s.angular_momentum_spin()); });
  cls.def("center_of_mass", [](System &s) { return vec_to_array(s.center_of_mass()); });
  cls.def("total_mass", &System::total_mass);
  cls.def("min_dist", &System::min_dist, "types1"_a, "types2"_a);
  cls.def("distance_vec", [](System &s, int a, int b) {
    try {
      return vec_to_array(s.distance_vec(a, b));
    } catch (std::out_of_range const &) {
      throw py::index_error("particle does not exist");
    }
  });
  cls.def("compute_forces", [](System &s) { s.compute_forces(true); });
}

} // namespace ScriptInterface
