// system.analysis.check_scene(): rules for parameter choices known to be
// inaccurate, each quoting the measurement behind it (doc/stability.md).
#include "analysis/scene_check.hpp"
#include "integrators/stability.hpp"
#include "system/System.hpp"
#include "thermostats/langevin.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace Marble {

namespace {

[[maybe_unused]] std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// Time step at which the kinetic temperature is 1 % off (interpolated from
// the measured kT(dt) tables of doc/stability.md, L = 6, rho = 3).
struct DtRule {
  double dt_1pc;
  char const *what;
};

[[maybe_unused]] DtRule dt_rule(IntegratorKind kind, bool conservative) {
  switch (kind) {
  case IntegratorKind::Shardlow:
    return conservative ? DtRule{0.045, "Shardlow, a=25/gamma=4.5: kT = 1.0075 "
                                        "at dt 0.04, 1.0141 at 0.05"}
                        : DtRule{0.1, "Shardlow, a=0/gamma=5: kT = 0.998 at dt "
                                      "0.04 (exact pair updates)"};
  case IntegratorKind::DPDVV:
    return conservative ? DtRule{0.05, "DPD-VV, a=25/gamma=4.5: kT = 1.0051 at "
                                       "dt 0.04, 1.0091 at 0.05"}
                        : DtRule{0.05, "DPD-VV, a=0/gamma=5: kT = 0.997 at dt "
                                       "0.02, 0.992 at 0.04"};
  default:
    return conservative ? DtRule{0.022, "velocity Verlet, a=25/gamma=4.5 "
                                        "(reference.md): kT = 1.0083 at dt "
                                        "0.02, 1.0175 at 0.03, 1.0262 at 0.04"}
                        : DtRule{0.014, "velocity Verlet, a=0/gamma=5 "
                                        "(reference.md): kT ~1.007 at dt 0.01, "
                                        "1.014 at 0.02, 1.035 at 0.04"};
  }
}

} // namespace

std::vector<SceneWarning> check_scene(System &sys) {
  std::vector<SceneWarning> out;
  double const dt = sys.time_step();
  auto const &ps = sys.particles();
  auto const &ia = sys.interactions();
  int const nt = ia.n_types();
  auto const &L = sys.box().length();
  [[maybe_unused]] double const V = L[0] * L[1] * L[2];
  std::vector<double> count(nt, 0.), m_min(nt, INFINITY);
  for (int i = 0; i < ps.n_local(); ++i)
    if (ps.type[i] < nt) {
      count[ps.type[i]] += 1.;
      m_min[ps.type[i]] = std::min(m_min[ps.type[i]], ps.get_mass(i));
    }
  sys.comm().sum_inplace(count.data(), nt);
  for (int a = 0; a < nt; ++a)
    m_min[a] = sys.comm().min(m_min[a]);
#ifdef DPD
  auto const &th = sys.thermostat().dpd;
  bool const dpd_on = th.active;
  // Solvent: types with a DPD self-interaction (and not colloids/walls).
  double n_solvent = 0.;
  bool conservative = false, any_dpd = false;
  for (int a = 0; a < nt; ++a) {
    if (ia.is_large(a) || count[a] == 0.)
      continue;
    for (int b = 0; b < nt; ++b) {
      auto const &p = ia.get(a, b);
      if (ia.is_large(b) || count[b] == 0. || !p.get<DPDPair>().active)
        continue;
      any_dpd = true;
      conservative = conservative || any_conservative(p);
    }
    if (ia.get(a, a).get<DPDPair>().active)
      n_solvent += count[a];
  }
  double V_free = V;
#ifdef MARBLE
  auto const &col = sys.colloids();
  double V_col = 0.;
  for (int i = 0; i < ps.n_local(); ++i) {
    int const c = ps.type[i];
    if (!col.is_colloid_type(c))
      continue;
    double R = 0.;
    for (int s = 0; s < nt; ++s)
      R = std::max(R, ia.get(c, s).get<MarbleSurface>().radius);
    V_col += 4. / 3. * M_PI * R * R * R;
  }
  V_free -= sys.comm().sum(V_col);
#endif
  // 1. time step vs the measured 1 % kT error of the integrator
  if (dpd_on && any_dpd && dt > 0.) {
    auto const r = dt_rule(sys.integrator(), conservative);
    if (dt > r.dt_1pc)
      out.push_back(
          {"dt_kT_error",
           "time_step " + fmt(dt) + " is above " + fmt(r.dt_1pc) +
               ", where the kinetic temperature is measured 1 % off (" +
               r.what + "; measured at gamma 4.5-5, rho 3). Reduce time_step" +
               (sys.integrator() == IntegratorKind::VelocityVerlet
                    ? std::string(" or use integrator.set_shardlow()")
                    : std::string()),
           dt, r.dt_1pc});
  }
  // 2. solvent density below the calibrated rho = 3
  if (n_solvent > 0. && V_free > 0.) {
    double const rho = n_solvent / V_free;
    if (rho < 2.95)
      out.push_back(
          {"solvent_density",
           "solvent number density " + fmt(rho) +
               " < 3: the marble paper's calibration (eta = 1.23 +/- 0.01, "
               "no-slip for "
               "marble gamma >~ 5, reference.md) and the kT(dt) tables of "
               "doc/stability.md are measured at rho = 3; at lower density the "
               "DPD fluid "
               "is more gas-like (larger D, lower eta, slip)",
           rho, 3.});
  }
#ifdef MARBLE
  // 3. box vs colloid size (Hasimoto), 4. marble gamma vs no-slip
  double const Lmin = std::min({L[0], L[1], L[2]});
  for (int c = 0; c < nt; ++c) {
    if (!col.is_colloid_type(c) || count[c] == 0.)
      continue;
    for (int s = 0; s < nt; ++s) {
      auto const &m = ia.get(c, s).get<MarbleSurface>();
      if (!m.active)
        continue;
      double const x = m.radius / Lmin;
      double const corr = 2.837297 * x - 4. * M_PI / 3. * x * x * x;
      if (corr > 0.4)
        out.push_back({"box_too_small",
                       "box length " + fmt(Lmin) + " for a colloid of radius " +
                           fmt(m.radius) + " (type " + std::to_string(c) +
                           "): the finite-box (Hasimoto) correction "
                           "reduces its diffusion coefficient by " +
                           fmt(100. * corr) +
                           " % (1 - D(L)/D(inf) = 2.837 R/L - (4 pi/3) "
                           "(R/L)^3, reference.md "
                           "section 5; > 40 % means L < ~6.9 R): use a larger "
                           "box or correct with "
                           "marble.theory.hasimoto_D",
                       corr, 0.4});
      if (m.coupling == MarbleCoupling::dpd)
        out.push_back({"marble_slip",
                       "marble coupling of types " + std::to_string(c) + "-" +
                           std::to_string(s) +
                           " is 'dpd' (central): it exerts no tangential "
                           "force, so the colloid "
                           "surface slips perfectly (D = kT/(4 pi eta R)); use "
                           "'tunable_slip' "
                           "with gamma >~ 5 for stick",
                       m.gamma, 5.});
      else if (m.gamma < 5.)
        out.push_back({"marble_slip",
                       "marble gamma " + fmt(m.gamma) + " (types " +
                           std::to_string(c) + "-" + std::to_string(s) +
                           ") is below ~5, where the marble paper (Fig. 4, "
                           "reference.md section 3) "
                           "finds the surface effectively no-slip: expect "
                           "partial slip (D between "
                           "the stick and slip values), not stick",
                       m.gamma, 5.});
    }
  }
#endif
  // 5. explicit friction near its stability limit (for one body, VV's full-step
  // velocities keep kT exact below it: doc/stability.md)
  if (dpd_on && dt > 0.) {
    std::string where;
    double const frac = limit_fraction(sys, where);
    if (frac > 0.5)
      out.push_back(
          {"friction_near_limit",
           "explicit friction at " + fmt(frac) +
               " x its measured stability limit (" + where +
               "; DPD pairs blow up at friction rate * dt ~3.3-3.5, colloid "
               "friction at ~2, doc/stability.md): reduce time_step to <= " +
               fmt(0.5 * dt / frac),
           frac, 0.5});
    auto const r = friction_rates(sys, false);
    // 6. skin vs thermal motion per step
    if (r.v_thermal > 0.) {
      double const disp = kSkinSpeeds * r.v_thermal * dt;
      if (disp > 0.5 * sys.skin())
        out.push_back({"skin_small",
                       "skin " + fmt(sys.skin()) + " vs time_step " + fmt(dt) +
                           ": " + fmt(kSkinSpeeds) + " thermal speeds move " +
                           fmt(disp) +
                           " per step, more than half the skin: the Verlet "
                           "lists are rebuilt "
                           "every few steps and a fast particle can outrun the "
                           "skin (a run is "
                           "refused above the full skin); increase "
                           "cell_system.skin to >= " +
                           fmt(2. * disp) + " or reduce time_step",
                       disp, 0.5 * sys.skin()});
    }
  }
#endif
  // 7. Langevin friction per step: velocity Verlet keeps the on-step kT exact
  // for gamma dt / m < 2 (run() refuses more), but the velocity relaxes by
  // (1 - a) per step instead of exp(-a): the relaxation rate -ln(1 - a)/a is
  // 5.4 % fast at a = 0.1 (doc/thermostats.md, test_langevin's lag table)
  if (sys.thermostat().langevin.active && sys.integrator() == IntegratorKind::VelocityVerlet &&
      dt > 0.) {
    int who = -1;
    double const a_loc = langevin_max_friction(ps, sys.thermostat().langevin, dt, who);
    double const a = sys.comm().max(a_loc);
    who = sys.comm().max(a_loc == a ? who : -1);
    constexpr double kLimit = 0.1;
    if (a > kLimit)
      out.push_back({"langevin_friction",
                     "Langevin friction gamma dt / m = " + fmt(a) + " (particle " + std::to_string(who) +
                         ") is above " + fmt(kLimit) +
                         ": the velocity relaxes by (1 - a) per step instead of exp(-a), so velocity "
                         "correlations decay " +
                         (a < 1. ? fmt(100. * (-std::log1p(-a) / a - 1.)) + " % too fast"
                                 : std::string("with alternating sign (a >= 1)")) +
                         " (static kT stays exact below 2, where run() refuses); reduce time_step "
                         "to <= " +
                         fmt(kLimit * dt / a) + " if dynamics matter",
                     a, kLimit});
  }
  (void)dt;
  return out;
}

} // namespace Marble
