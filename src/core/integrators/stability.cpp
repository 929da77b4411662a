// Stability checks before a run (doc/stability.md). Explicit friction
// integrated by velocity Verlet multiplies a velocity by (1 - nu) per step
// (nu = friction rate * dt, one body): unstable beyond nu = 2, and the kinetic
// temperature is already far off before. For the many-body DPD friction the
// largest eigenvalue of the friction matrix exceeds the mean rate: the limit
// of the mean-field estimate below was measured (kNuDpd).
#include <climits>
#include "integrators/stability.hpp"
#include "system/System.hpp"
#include "utils/errors.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace Marble {

namespace {

// int_0^rc w(r)^2 4 pi (r + R)^2 dr (R = 0 for pairs), midpoint rule.
// int_0^rc w(r)^2 4 pi (r + R)^power dr (midpoint rule, 200 intervals);
// power 2: the shell's volume weight, 4: with the lever arm squared.
template <typename W> double weight_integral(W const &w, double rc, double R, int power = 2) {
  int const n = 200;
  double s = 0.;
  for (int k = 0; k < n; ++k) {
    double const r = (k + 0.5) * rc / n;
    double const x = w(r);
    double term = x * x * 4. * M_PI;
    for (int e = 0; e < power; ++e)
      term *= r + R;
    s += term;
  }
  return s * rc / n;
}

struct TypeStats {
  std::vector<double> count, m_min, rinertia_min;
  std::vector<int> lightest; // id of the lightest particle of each type
};

[[maybe_unused]] TypeStats type_stats(System &sys) {
  auto const &ps = sys.particles();
  int const nt = sys.interactions().n_types();
  TypeStats t;
  t.count.assign(nt, 0.);
  t.m_min.assign(nt, INFINITY);
  t.rinertia_min.assign(nt, INFINITY);
  t.lightest.assign(nt, -1);
  for (int i = 0; i < ps.n_local(); ++i) {
    int const a = ps.type[i];
    if (a >= nt)
      continue;
    t.count[a] += 1.;
    if (ps.get_mass(i) < t.m_min[a] || t.lightest[a] < 0)
      t.lightest[a] = ps.id[i];
    t.m_min[a] = std::min(t.m_min[a], ps.get_mass(i));
#ifdef ROTATION
    if (ps.rotation[i])
      t.rinertia_min[a] = std::min(t.rinertia_min[a], ps.rinertia[i]);
#endif
  }
  // over all ranks
  auto const &comm = sys.comm();
  if (comm.parallel()) {
    comm.sum_inplace(t.count.data(), nt);
    for (int a = 0; a < nt; ++a) {
      double const m_loc = t.m_min[a];
      t.m_min[a] = comm.min(m_loc);
      t.rinertia_min[a] = comm.min(t.rinertia_min[a]);
      int const cand = (t.lightest[a] >= 0 && m_loc == t.m_min[a]) ? t.lightest[a] : INT_MAX;
      int const best = comm.min(cand);
      t.lightest[a] = best == INT_MAX ? -1 : best;
    }
  }
  return t;
}

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

} // namespace

FrictionRates friction_rates(System &sys,
                             [[maybe_unused]] bool include_pair_dpd) {
  FrictionRates out;
#ifdef DPD
  auto const &ia = sys.interactions();
  auto const &th = sys.thermostat().dpd;
  if (!th.active)
    return out;
  int const nt = ia.n_types();
  auto const st = type_stats(sys);
  auto const &L = sys.box().length();
  double const V = L[0] * L[1] * L[2];
  std::vector<double> bead(nt, 0.),
      one(nt, 0.); // per type: DPD and one-body rates
  std::vector<std::string> bead_what(nt);
  // names one more friction term acting on beads of type t
  auto const note_bead = [&](int t, std::string const &what) {
    bead_what[t] += (bead_what[t].empty() ? "" : " + ") + what;
  };
  for (int a = 0; a < nt; ++a) {
    if (st.count[a] == 0.)
      continue;
    if (th.kT > 0.)
      out.v_thermal = std::max(out.v_thermal, std::sqrt(th.kT / st.m_min[a]));
    if (!include_pair_dpd || ia.is_large(a))
      continue;
    for (int b = 0; b < nt; ++b) {
      auto const &p = ia.get(a, b).get<DPDPair>();
      if (!p.active || st.count[b] == 0. || ia.is_large(b))
        continue;
      double const ma = st.m_min[a], mb = st.m_min[b];
      double const M = dpd_mass_factor(ma, mb);
      // with an offset (seed-004 colloid-solvent DPD) the weights act on the
      // gap, over the shell offset < r < offset + r_cut (the core holds no beads)
      double g = p.radial.gamma *
                 weight_integral([&](double r) { return p.radial.weight(r); },
                                 p.radial.r_cut, p.offset);
#ifdef TRANS_DPD
      g += p.trans.gamma *
           weight_integral([&](double r) { return p.trans.weight(r); },
                           p.trans.r_cut, p.offset);
#endif
      double const rate = g * M * (1. / ma + 1. / mb) * st.count[b] / V;
      bead[a] += rate;
      note_bead(a, std::string("DPD of types ") + std::to_string(a) + "-" +
                      std::to_string(b) + " (gamma " + fmt(p.radial.gamma) +
                      ")");
      if (bead[a] > out.dpd) {
        out.dpd = bead[a];
        out.dpd_where = bead_what[a];
      }
    }
  }
#ifdef MARBLE
  auto const &col = sys.colloids();
  // the marble coupling: explicit under velocity Verlet; under Shardlow it is
  // part of the exact pair update (marble/Colloids.cpp) and sets no limit
  for (int c = 0; include_pair_dpd && c < nt; ++c) {
    if (!col.is_colloid_type(c) || st.count[c] == 0.)
      continue;
    double trans = 0., rot = 0.;
    double R = 0.;
    for (int s = 0; s < nt; ++s) {
      auto const &m = ia.get(c, s).get<MarbleSurface>();
      if (!m.active || st.count[s] == 0.)
        continue;
      R = std::max(R, m.radius);
      // bead side: one-body friction gamma w^2 / m with w <= 1
      one[s] += m.gamma / st.m_min[s];
      note_bead(s, std::string("marble coupling ") + std::to_string(c) +
                      "-" + std::to_string(s) + " (gamma " + fmt(m.gamma) + ")");
      // colloid side: sum over the shell of gamma w^2, with the solvent density
      // outside the colloids ~ count / V
      double const shell =
          m.gamma *
          weight_integral([&](double h) { return m.weight(h); }, m.r_cut,
                          m.radius) *
          st.count[s] / V;
      double const f_trans = m.coupling == MarbleCoupling::dpd ? 1. / 3. : 1.;
      trans += f_trans * shell / st.m_min[c];
      if (m.transmits_torque() && std::isfinite(st.rinertia_min[c]))
        rot += (2. / 3.) * m.radius * m.radius * shell / st.rinertia_min[c];
    }
    double const r = std::max(trans, rot);
    if (r > out.colloid) {
      out.colloid = r;
      out.colloid_where =
          "marble colloid type " + std::to_string(c) + " (particle " +
          std::to_string(st.lightest[c]) + ", radius " + fmt(R) + ", mass " +
          fmt(st.m_min[c]) +
          "): " + (rot > trans ? "rotational" : "translational") +
          " friction from its solvent shell";
    }
  }
#endif
#ifdef TRANS_DPD
  // the stick friction (nonbonded/surface_friction.hpp) with explicit
  // integration (under Shardlow it is part of the exact pair update): gamma w^2
  // on the tangential contact velocity, w <= 1. A point partner (radius 0) of
  // a surface feels at most gamma / m, one-body-like; the surface's particle
  // sums its shell: translation (2/3) gamma n int w^2 4 pi r^2 dr / M
  // (tangential: two of three directions), rotation with the lever r,
  // (2/3) gamma n int w^2 4 pi r^4 dr / I (r = a + h on the gap h).
  if (include_pair_dpd) {
    for (int a = 0; a < nt; ++a) {
      for (int b = 0; b < nt; ++b) {
        auto const &p = ia.get(a, b).get<SurfaceFriction>();
        if (!p.active || st.count[a] == 0. || st.count[b] == 0.)
          continue;
        // the partner b of the surface a: one-body bound gamma / m_b (each
        // ordered pair once: (b, a) adds a's)
        one[b] += p.gamma / st.m_min[b];
        note_bead(b, std::string("surface_friction of types ") +
                        std::to_string(a) + "-" + std::to_string(b) +
                        " (gamma " + fmt(p.gamma) + ")");
        if (!(p.a1 > 0.) || p.a2 > 0.)
          continue; // the shell sum for a sphere with point partners only
        double const n = st.count[b] / V;
        auto const w = [&](double h) {
          return h < p.r_cut ? 1. - h / p.r_cut : 0.;
        };
        double const shell2 =
            p.gamma * n * weight_integral(w, p.r_cut, p.a1);
        double const shell4 =
            p.gamma * n * weight_integral(w, p.r_cut, p.a1, 4);
        double const trans = (2. / 3.) * shell2 / st.m_min[a];
        double const rot = std::isfinite(st.rinertia_min[a])
                               ? (2. / 3.) * shell4 / st.rinertia_min[a]
                               : 0.;
        double const r = std::max(trans, rot);
        if (r > out.colloid) {
          out.colloid = r;
          out.colloid_where =
              "surface_friction sphere type " + std::to_string(a) +
              " (particle " + std::to_string(st.lightest[a]) + ", radius " +
              fmt(p.a1) + ", mass " + fmt(st.m_min[a]) +
              "): " + (rot > trans ? "rotational" : "translational") +
              " stick friction (gamma " + fmt(p.gamma) +
              ") from its shell of type " + std::to_string(b);
        }
      }
    }
  }
#endif
  for (auto const &w : sys.constraints().walls()) {
    for (int s = 0; s < nt; ++s) {
      if (w.type >= nt || st.count[s] == 0.)
        continue;
      auto const &p = std::as_const(sys.interactions()).get(w.type, s).get<TunableSlip>();
      if (!p.active || p.gamma <= 0.)
        continue;
      one[s] += p.gamma / st.m_min[s];
      note_bead(s, std::string("tunable-slip wall type ") +
                      std::to_string(w.type) + " (gamma_L " + fmt(p.gamma) +
                      ")");
      break;
    }
  }
  for (int a = 0; a < nt; ++a) {
    out.one_body = std::max(out.one_body, one[a]);
    double const frac = bead[a] / kNuDpd + one[a] / kNuOneBody;
    if (frac > out.bead) {
      out.bead = frac;
      out.bead_where = "particles of type " + std::to_string(a) +
                       " (e.g. particle " + std::to_string(st.lightest[a]) +
                       "): " + bead_what[a];
    }
  }
#else
  (void)sys;
#endif
  return out;
}

double limit_fraction(System &sys, std::string &where) {
  bool const pair_dpd = sys.integrator() != IntegratorKind::Shardlow;
  auto const r = friction_rates(sys, pair_dpd);
  double const dt = sys.time_step();
  double frac = r.bead * dt;
  where = r.bead_where;
  if (r.colloid * dt / kNuOneBody > frac) {
    frac = r.colloid * dt / kNuOneBody;
    where = r.colloid_where;
  }
  return frac;
}

void check_stability_before_run(System &sys) {
  double const dt = sys.time_step();
  if (!(dt > 0.))
    return; // the integrator reports the missing time step
  std::string where;
  double const frac = limit_fraction(sys, where);
  if (frac > 1.) {
    bool const shardlow = sys.integrator() == IntegratorKind::Shardlow;
    throw Utils::RuntimeError(
        "cannot integrate at step " + std::to_string(sys.step()) +
        ": explicit friction too stiff for time_step " + fmt(dt) + ": " +
        where + " use " + fmt(frac) +
        " x the measured stability limit (friction rate * dt <= " +
        fmt(kNuDpd) + " for solvent DPD pairs, " + fmt(kNuOneBody) +
        " for colloid/wall friction; doc/stability.md); likely result: "
        "exploding velocities. "
        "Reduce time_step to <= " +
        fmt(0.5 * dt / frac) + " (suggested)" +
        (shardlow
             ? std::string()
             : std::string(
                   ", or use integrator.set_shardlow() (exact, stable pair DPD "
                   "updates) if the solvent DPD dominates")));
  }
  auto const r = friction_rates(sys, false);
  double const disp = kSkinSpeeds * r.v_thermal * dt;
  if (disp > sys.skin())
    throw Utils::RuntimeError(
        "cannot integrate at step " + std::to_string(sys.step()) +
        ": thermal motion too fast for time_step " + fmt(dt) + ": " +
        fmt(kSkinSpeeds) + " thermal speeds sqrt(kT/m) = " +
        fmt(kSkinSpeeds * r.v_thermal) + " move " + fmt(disp) +
        " per step, more than the skin " + fmt(sys.skin()) +
        " (a particle would move beyond its Verlet list). Reduce time_step to "
        "<= " +
        fmt(0.5 * sys.skin() / (kSkinSpeeds * r.v_thermal)) +
        " or increase cell_system.skin");
}

} // namespace Marble
