// Script interface of the SRD solvent (marble.srd, doc/srd.md).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#ifdef SRD
#include "srd/Fluid.hpp"
#endif

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>

namespace ScriptInterface {

using Marble::System;

#ifdef SRD
namespace {
using Marble::Srd::Fluid;

Fluid &fluid(System &s) {
  if (!s.srd)
    throw Utils::RuntimeError("no SRD fluid: set system.srd = marble.srd.SRDFluid(...) first");
  return *s.srd;
}

void check_type(std::string const &name, long long t) {
  if (t < 0 || t >= Marble::InteractionTable::max_type)
    value_error("parameter '" + name + "' must be an integer in [0, 256), got " + std::to_string(t));
}

// An SRD type takes part in no pair interaction (they would be ignored).
void check_no_pair_interaction(System &s, int t) {
  auto &ia = s.interactions();
  if (t >= ia.n_types())
    return;
  for (int u = 0; u < ia.n_types(); ++u)
    if (ia.get(t, u).max_cut > 0.)
      value_error("SRD type " + std::to_string(t) + " has a pair interaction with type " +
                  std::to_string(u) + " (cutoff " + Utils::to_str(ia.get(t, u).max_cut) +
                  "): SRD particles take part in no pair interaction; deactivate it first");
}

void check_no_md_particles(System &s, int t) {
  auto const &ps = s.particles();
  int bad = 0;
  for (int i = 0; i < ps.n_local(); ++i)
    bad = bad || ps.type[i] == t;
  if (s.comm().any(bad))
    value_error("type " + std::to_string(t) + " is used by MD particles; an SRD type must not be");
}

// On several ranks the reads gather every rank's SRD particles in rank order
// (the order is arbitrary: use srd_ids), the writes take this rank's slice
// of the same order. Collective.
template <typename T> std::vector<T> gather(System &s, std::vector<T> const &x) {
  return s.comm().parallel() ? s.comm().allgatherv(x) : x;
}
std::pair<std::size_t, std::size_t> my_slice(System &s, std::size_t n_local) {
  auto const counts = s.comm().allgather(static_cast<int>(n_local));
  std::size_t off = 0, total = 0;
  for (int r = 0; r < static_cast<int>(counts.size()); ++r) {
    if (r < s.comm().rank())
      off += counts[r];
    total += counts[r];
  }
  return {off, total};
}

py::array_t<double> to_array(std::vector<Utils::Vector3d> const &x) {
  py::array_t<double> a({static_cast<py::ssize_t>(x.size()), py::ssize_t{3}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < x.size(); ++i)
    for (int d = 0; d < 3; ++d)
      r(i, d) = x[i][d];
  return a;
}

void from_array(std::string const &name, py::array_t<double> const &a, std::vector<Utils::Vector3d> &x) {
  if (a.ndim() != 2 || a.shape(1) != 3 || a.shape(0) != static_cast<py::ssize_t>(x.size()))
    value_error("parameter '" + name + "' must have shape (" + std::to_string(x.size()) + ", 3)");
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (int d = 0; d < 3; ++d)
      if (!std::isfinite(r(i, d)))
        value_error("parameter '" + name + "' must be finite");
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (int d = 0; d < 3; ++d)
      x[i][d] = r(i, d);
}

bool to_bool(std::string const &name, py::handle h) {
  if (!py::isinstance<py::bool_>(h))
    value_error("parameter '" + name + "' must be True or False");
  return h.cast<bool>();
}
} // namespace
#endif

void bind_srd(py::class_<System> &cls) {
#ifdef SRD
  cls.def("srd_create", [](System &s, py::dict kw) {
    check_keys("SRDFluid", kw, {"types", "cell_size", "tau", "angle", "kT", "mass", "seed", "shift",
                                "rule", "thermostat", "conserve_angular", "wall_axis", "wall_rule",
                                "wall_velocity_lo", "wall_velocity_hi", "wall_positions"});
    for (auto key : {"tau", "seed"})
      if (!kw.contains(key))
        value_error(std::string("parameter '") + key + "' is required for SRDFluid");
    Marble::Srd::Params p;
    if (kw.contains("cell_size"))
      p.cell_size = check_double("cell_size", to_double("cell_size", kw["cell_size"]), 0., INFINITY, true);
    p.tau = check_double("tau", to_double("tau", kw["tau"]), 0., INFINITY, true);
    double const deg = kw.contains("angle") ? check_double("angle", to_double("angle", kw["angle"]), 0., 180.) : 90.;
    p.angle = deg * M_PI / 180.;
    if (kw.contains("kT"))
      p.kT = check_double("kT", to_double("kT", kw["kT"]), 0., INFINITY);
    if (kw.contains("mass"))
      p.mass = check_double("mass", to_double("mass", kw["mass"]), 0., INFINITY, true);
    long long const seed = to_int("seed", kw["seed"]);
    if (seed < 0)
      value_error("parameter 'seed' must be an integer >= 0, got " + std::to_string(seed));
    p.seed = static_cast<std::uint64_t>(seed);
    if (kw.contains("shift"))
      p.shift = to_bool("shift", kw["shift"]);
    if (kw.contains("thermostat")) {
      if (!py::isinstance<py::str>(kw["thermostat"]))
        value_error("parameter 'thermostat' must be one of 'none', 'mbs'");
      auto const t = kw["thermostat"].cast<std::string>();
      if (t != "none" && t != "mbs")
        value_error("parameter 'thermostat' must be one of 'none', 'mbs', got '" + t + "'");
      p.thermostat = t == "mbs";
    }
    if (kw.contains("rule")) {
      if (!py::isinstance<py::str>(kw["rule"]))
        value_error("parameter 'rule' must be one of 'srd', 'at'");
      auto const r = kw["rule"].cast<std::string>();
      if (r == "srd")
        p.rule = Marble::Srd::CollisionRule::srd;
      else if (r == "at")
        p.rule = Marble::Srd::CollisionRule::at;
      else
        value_error("parameter 'rule' must be one of 'srd', 'at', got '" + r + "'");
    }
    if (kw.contains("conserve_angular")) {
      p.conserve_angular = to_bool("conserve_angular", kw["conserve_angular"]);
      if (p.conserve_angular && p.rule != Marble::Srd::CollisionRule::at)
        value_error("parameter 'conserve_angular' needs rule='at' (AT+a)");
    }
    if (kw.contains("wall_axis") && !kw["wall_axis"].is_none()) {
      long long const a = to_int("wall_axis", kw["wall_axis"]);
      if (a < 0 || a > 2)
        value_error("parameter 'wall_axis' must be 0, 1, 2 or None, got " + std::to_string(a));
      p.wall_axis = static_cast<int>(a);
      std::string rule = "stochastic";
      if (kw.contains("wall_rule")) {
        if (!py::isinstance<py::str>(kw["wall_rule"]))
          value_error("parameter 'wall_rule' must be one of 'stochastic', 'bounce_back', 'slip'");
        rule = kw["wall_rule"].cast<std::string>();
      }
      if (rule == "stochastic")
        p.wall_rule = static_cast<int>(Marble::Srd::BoundaryRule::stochastic);
      else if (rule == "bounce_back")
        p.wall_rule = static_cast<int>(Marble::Srd::BoundaryRule::bounce_back);
      else if (rule == "slip")
        p.wall_rule = static_cast<int>(Marble::Srd::BoundaryRule::slip);
      else
        value_error("parameter 'wall_rule' must be one of 'stochastic', 'bounce_back', 'slip', got '" + rule + "'");
      for (auto key : {"wall_velocity_lo", "wall_velocity_hi"}) {
        if (!kw.contains(key))
          continue;
        auto const u = to_vec3(key, kw[key]);
        for (int d = 0; d < 3; ++d)
          check_double(key, u[d]);
        if (u[p.wall_axis] != 0.)
          value_error(std::string("parameter '") + key + "' must be tangential to the wall (component " +
                      std::to_string(p.wall_axis) + " = 0)");
        (std::string(key) == "wall_velocity_lo" ? p.wall_v_lo : p.wall_v_hi) = u;
      }
      if (kw.contains("wall_positions") && !kw["wall_positions"].is_none()) {
        double const La = s.box().length()[p.wall_axis];
        std::vector<double> z;
        try {
          z = kw["wall_positions"].cast<std::vector<double>>();
        } catch (py::cast_error const &) {
        }
        if (z.size() != 2 || !std::isfinite(z[0]) || !std::isfinite(z[1]) || !(z[0] >= 0.) ||
            !(z[1] <= La) || !(z[1] - z[0] >= p.cell_size))
          value_error("parameter 'wall_positions' must be two numbers lo, hi with 0 <= lo, hi <= " +
                      Utils::to_str(La) + " (the box length along wall_axis) and hi - lo >= cell_size");
        p.wall_lo = z[0], p.wall_hi = z[1];
      }
    } else if (kw.contains("wall_rule") || kw.contains("wall_velocity_lo") || kw.contains("wall_velocity_hi") ||
               kw.contains("wall_positions")) {
      value_error("parameters 'wall_rule', 'wall_velocity_lo/hi', 'wall_positions' need 'wall_axis'");
    }
    auto f = std::make_shared<Fluid>(p);
    f->check_geometry(s.box(), s.time_step()); // ValueError: cell/box, tau/dt
    if (kw.contains("types"))
      for (auto h : py::list(kw["types"])) {
        long long const t = to_int("types", h);
        check_type("types", t);
        check_no_pair_interaction(s, static_cast<int>(t));
        check_no_md_particles(s, static_cast<int>(t));
      }
    // keep the particles of an existing fluid (the boundaries are kernels of
    // the interaction table: non_bonded_inter[c, s].srd_boundary)
    if (s.srd)
      f->pos = s.srd->pos, f->v = s.srd->v, f->id = s.srd->id, f->type = s.srd->type;
    s.srd = f;
  });
  cls.def("srd_remove", [](System &s) { s.srd.reset(); });
  cls.def("srd_active", [](System &s) { return static_cast<bool>(s.srd); });
  cls.def("srd_get_params", [](System &s) {
    auto const &p = fluid(s).params();
    py::dict d;
    d["cell_size"] = p.cell_size, d["tau"] = p.tau, d["angle"] = p.angle * 180. / M_PI;
    d["kT"] = p.kT, d["mass"] = p.mass, d["seed"] = p.seed, d["shift"] = p.shift;
    d["rule"] = p.rule == Marble::Srd::CollisionRule::srd ? "srd" : "at";
    d["thermostat"] = p.thermostat ? "mbs" : "none";
    d["conserve_angular"] = p.conserve_angular;
    if (p.wall_axis >= 0) {
      static char const *names[] = {"stochastic", "bounce_back", "slip", "rough"};
      d["wall_axis"] = p.wall_axis, d["wall_rule"] = names[p.wall_rule];
      d["wall_velocity_lo"] = vec_to_array(p.wall_v_lo), d["wall_velocity_hi"] = vec_to_array(p.wall_v_hi);
      d["wall_positions"] = py::make_tuple(p.wall_lo, fluid(s).wall_hi(s.box().length()[p.wall_axis]));
    }
    return d;
  });
  cls.def("srd_add_particles", [](System &s, py::handle n_, py::handle t_, py::handle kT_, py::handle seed_) {
    auto &f = fluid(s);
    long long const n = to_int("n", n_);
    if (n < 0 || n > 2000000000)
      value_error("parameter 'n' must be an integer in [0, 2e9], got " + std::to_string(n));
    long long const t = to_int("type", t_);
    check_type("type", t);
    check_no_pair_interaction(s, static_cast<int>(t));
    check_no_md_particles(s, static_cast<int>(t));
    double const kT = check_double("kT", to_double("kT", kT_), 0., INFINITY);
    long long const seed = to_int("seed", seed_);
    if (seed < 0)
      value_error("parameter 'seed' must be an integer >= 0, got " + std::to_string(seed));
    f.add_particles(s, static_cast<int>(n), static_cast<int>(t), kT, static_cast<std::uint64_t>(seed));
  });
  cls.def("srd_n", [](System &s) { return s.srd ? s.srd->global_size(s) : 0LL; });
  cls.def("srd_pos", [](System &s) { return to_array(gather(s, fluid(s).pos)); });
  cls.def("srd_v", [](System &s) { return to_array(gather(s, fluid(s).v)); });
  cls.def("srd_ids", [](System &s) { return gather(s, fluid(s).id); });
  cls.def("srd_types", [](System &s) { return gather(s, fluid(s).type); });
  cls.def("srd_set_v", [](System &s, py::array_t<double> a) {
    auto &f = fluid(s);
    auto const [off, total] = my_slice(s, f.v.size());
    std::vector<Utils::Vector3d> x(total);
    from_array("v", a, x);
    std::copy(x.begin() + static_cast<long>(off), x.begin() + static_cast<long>(off + f.v.size()), f.v.begin());
    f.invalidate_index();
  });
  cls.def("srd_set_pos", [](System &s, py::array_t<double> a) {
    auto &f = fluid(s);
    auto const [off, total] = my_slice(s, f.pos.size());
    std::vector<Utils::Vector3d> x(total);
    from_array("pos", a, x);
    auto const &L = s.box().length();
    for (auto &p : x)
      for (int d = 0; d < 3; ++d)
        p[d] -= L[d] * std::floor(p[d] / L[d]);
    std::copy(x.begin() + static_cast<long>(off), x.begin() + static_cast<long>(off + f.pos.size()), f.pos.begin());
    f.invalidate_index();
  });
  cls.def("srd_collide", [](System &s) {
    auto &f = fluid(s);
    f.check_geometry(s.box(), -1.);
    f.collide(s);
  });
  // checkpoint: the whole SRD state, particles in their stored order (the
  // order of the sums in a cell), counters, boundaries and drive
  cls.def("srd_get_state", [](System &s) {
    auto &f = fluid(s);
    py::dict d;
    d["pos"] = to_array(gather(s, f.pos)), d["v"] = to_array(gather(s, f.v));
    d["id"] = gather(s, f.id), d["type"] = gather(s, f.type);
    // the rank holding each particle: on the same number of ranks a restore
    // puts every particle back where it was (bit-exact continuation)
    d["rank"] = gather(s, std::vector<int>(f.id.size(), s.comm().rank()));
    d["n_ranks"] = s.comm().size();
    Utils::Vector3d mlo = f.momentum_to_wall_lo, mhi = f.momentum_to_wall_hi;
    s.comm().sum_inplace(&mlo[0], 3);
    s.comm().sum_inplace(&mhi[0], 3);
    d["n_collisions"] = f.n_collisions(), d["n_streams"] = f.n_streams();
    d["drive"] = py::make_tuple(f.drive.on, f.drive.flow_dir, f.drive.grad_dir, f.drive.g,
                                vec_to_array(f.drive.accel));
    d["momentum_to_colloids"] = vec_to_array(f.momentum_to_colloids);
    d["momentum_to_walls"] = py::make_tuple(vec_to_array(mlo), vec_to_array(mhi));
    return d;
  });
  cls.def("srd_set_state", [](System &s, py::dict d) {
    auto &f = fluid(s);
    auto const ids = d["id"].cast<std::vector<int>>();
    auto const types = d["type"].cast<std::vector<int>>();
    std::vector<Utils::Vector3d> x(ids.size()), u(ids.size());
    from_array("pos", d["pos"].cast<py::array_t<double>>(), x);
    from_array("v", d["v"].cast<py::array_t<double>>(), u);
    if (types.size() != ids.size())
      throw Utils::RuntimeError("SRD checkpoint state is inconsistent");
    // keep this rank's particles: those it held at the save on the same
    // number of ranks, else those in its domain (in the stored order)
    std::vector<int> where;
    if (d.contains("rank") && d["n_ranks"].cast<int>() == s.comm().size())
      where = d["rank"].cast<std::vector<int>>();
    if (where.size() != ids.size()) {
      where.resize(ids.size());
      for (std::size_t i = 0; i < ids.size(); ++i)
        where[i] = s.cells().owner_rank(x[i], s.box());
    }
    f.pos.clear(), f.v.clear(), f.id.clear(), f.type.clear();
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (where[i] == s.comm().rank())
        f.pos.push_back(x[i]), f.v.push_back(u[i]), f.id.push_back(ids[i]), f.type.push_back(types[i]);
    f.set_counters(d["n_collisions"].cast<std::uint64_t>(), d["n_streams"].cast<std::uint64_t>());
    f.invalidate_index();
    auto dr = d["drive"].cast<py::tuple>();
    f.drive.on = dr[0].cast<bool>(), f.drive.flow_dir = dr[1].cast<int>();
    f.drive.grad_dir = dr[2].cast<int>(), f.drive.g = dr[3].cast<double>();
    f.drive.accel = to_vec3("accel", dr[4]);
    f.momentum_to_colloids = to_vec3("momentum_to_colloids", d["momentum_to_colloids"]);
    auto mw = d["momentum_to_walls"].cast<py::tuple>();
    f.momentum_to_wall_lo = to_vec3("momentum_to_walls", mw[0]);
    f.momentum_to_wall_hi = to_vec3("momentum_to_walls", mw[1]);
    if (!s.comm().is_root()) // the totals are kept by rank 0
      f.momentum_to_wall_lo = f.momentum_to_wall_hi = Utils::Vector3d{};
  });
  cls.def("srd_move_out", [](System &s) { return fluid(s).move_out(s); });
  cls.def("srd_n_collisions", [](System &s) { return fluid(s).n_collisions(); });
  cls.def("srd_momentum_to_colloids", [](System &s) { return vec_to_array(fluid(s).momentum_to_colloids); });
  cls.def("srd_set_drive", [](System &s, int flow, int grad, double g) {
    auto &f = fluid(s);
    if (flow < 0 || flow > 2 || grad < 0 || grad > 2 || flow == grad)
      value_error("parameters 'flow_dir' and 'grad_dir' must be different axes in {0, 1, 2}");
    check_double("g", g);
    f.drive.on = g != 0., f.drive.flow_dir = flow, f.drive.grad_dir = grad, f.drive.g = g;
  });
  cls.def("srd_wall_momentum", [](System &s) {
    auto &f = fluid(s);
    Utils::Vector3d lo = f.momentum_to_wall_lo, hi = f.momentum_to_wall_hi;
    s.comm().sum_inplace(&lo[0], 3);
    s.comm().sum_inplace(&hi[0], 3);
    return py::make_tuple(vec_to_array(lo), vec_to_array(hi));
  });
  cls.def("srd_set_acceleration", [](System &s, py::handle a) {
    auto &f = fluid(s);
    auto const x = to_vec3("acceleration", a);
    for (int d = 0; d < 3; ++d)
      check_double("acceleration", x[d]);
    f.drive.accel = x;
  });
  cls.def("srd_profile", [](System &s, int flow, int grad, int n_bins) {
    auto &f = fluid(s);
    if (n_bins < 1)
      value_error("parameter 'n_bins' must be >= 1");
    std::vector<double> vs(n_bins, 0.), cnt(n_bins, 0.);
    double const L = s.box().length()[grad];
    for (int i = 0; i < f.size(); ++i) {
      int b = static_cast<int>(f.pos[i][grad] / L * n_bins);
      b = std::min(std::max(b, 0), n_bins - 1);
      vs[b] += f.v[i][flow];
      cnt[b] += 1.;
    }
    s.comm().sum_inplace(vs.data(), n_bins);
    s.comm().sum_inplace(cnt.data(), n_bins);
    return py::make_tuple(vs, cnt);
  });
#else
  cls.def("srd_create", [](System &, py::dict) { throw Utils::FeaturesError("SRD", "SRDFluid"); });
  cls.def("srd_active", [](System &) { return false; });
#endif
}

} // namespace ScriptInterface
