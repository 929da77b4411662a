// Velocity Verlet (with rotation of isotropic spheres) and steepest descent.
// One step (doc/architecture.md): half kick + drift, step counter += 1,
// Verlet list check, forces, half kick.
#include "integrators/stability.hpp"
#include "integrators/dpd_integrators.hpp"
#include "system/System.hpp"
#include "thermostats/langevin.hpp"
#include "utils/errors.hpp"
#ifdef SRD
#include "srd/Fluid.hpp" // SRD
#endif

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace Marble {

using Utils::Vector3d;

namespace {
// v += half_dt F/m (and omega += half_dt tau/I) of local i; returns half_dt/m.
// File-local so that the sweeps below inline it (a member function of the
// shared module is called through the PLT: -fPIC lets it be interposed).
inline double kick_particle(ParticleStore &ps, int i, double half_dt) {
  double const a = half_dt / ps.get_mass(i);
  auto &v = ps.v[i];
  auto const &f = ps.f[i];
  if (!ps.has_fixed(i)) {
    for (int d = 0; d < 3; ++d)
      v[d] = v[d] + a * f[d];
  } else {
    for (int d = 0; d < 3; ++d)
      v[d] = ps.is_fixed(i, d) ? 0. : v[d] + a * f[d];
  }
#ifdef ROTATION
  if (ps.rotation[i])
    ps.omega[i] += (half_dt / ps.rinertia[i]) * ps.torque[i];
#endif
  return a;
}

// The half kick a f and the drift h (v + a f) of local i, as changes dv, dx
// (fixed coordinates: v to 0, no drift); shared by the step and the RESPA
// substep so that both do the same arithmetic.
inline void kick_drift_of(ParticleStore const &ps, int i, double a, Vector3d const &f,
                          Vector3d const &v, double h, Vector3d &dv, Vector3d &dx) {
  if (!ps.has_fixed(i)) {
    for (int d = 0; d < 3; ++d) {
      dv[d] = a * f[d];
      dx[d] = h * (v[d] + dv[d]);
    }
    return;
  }
  for (int d = 0; d < 3; ++d) {
    bool const fx = ps.is_fixed(i, d);
    dv[d] = fx ? -v[d] : a * f[d];
    dx[d] = fx ? 0. : h * (v[d] + dv[d]);
  }
}

/** RESPA: the kick length of inner substep @p k of length @p h (the inner
 * half kicks of substeps k - 1 and k in one). */
inline double inner_kick_dt(int k, double h) { return k == 0 ? 0.5 * h : h; }

/** What a RESPA substep's check gathers over the locals given to it: the
 * first refusal (a displacement beyond the skin, or not finite), the main
 * list's half-skin test, and the largest displacements since the build of any
 * of them and of a colloid (the colloid list's staleness test). */
struct SubstepTally {
  double max2, lim2; // skin^2, (skin/2)^2
  int bad = -1;
  double bad_disp2 = 0.;
  bool moved = false;
  double dmax2 = 0., dcol2 = 0.;
  /** Local @p i at @p x moves by @p dx (@p x0: its position at the build);
   * false (and bad set) if that refuses the step. */
  bool add(int i, Vector3d const &x, Vector3d const &dx, Vector3d const &x0, bool colloid) {
    double const disp2 = dx.norm2();
    if (!(disp2 <= max2)) { // also catches NaN
      bad = i;
      bad_disp2 = disp2;
      return false;
    }
    double const dd2 = (x + dx - x0).norm2();
    moved |= dd2 > lim2;
    dmax2 = std::max(dmax2, dd2);
    if (colloid)
      dcol2 = std::max(dcol2, dd2);
    return true;
  }
  /** The colloid pair list holds the pairs within range + skin at the build:
   * it stays valid while no pair came closer by skin, |dx_j| + |dx_colloid| <
   * skin, which lets beads move up to ~skin (not skin/2, the main list's
   * criterion, checked at the end of the step). */
  bool colloid_list_stale(double skin) const { return std::sqrt(dmax2) + std::sqrt(dcol2) >= skin; }
};
} // namespace

namespace {
/** A RESPA substep's vote over the ranks (2: refuse, 1: the main list needs
 * a rebuild, 0), and on several ranks the largest displacements of @p t
 * replaced by those of all ranks in the same reduction: the colloid list's
 * staleness test is global (a colloid pairs with beads of other ranks), so
 * every rank takes the same decision. */
int substep_vote(Communicator const &comm, SubstepTally &t) {
  int const vote = t.bad >= 0 ? 2 : (t.moved ? 1 : 0);
  if (!comm.parallel())
    return vote;
  double r[3] = {static_cast<double>(vote), t.dmax2, t.dcol2};
  comm.max_inplace(r, 3);
  t.dmax2 = r[1];
  t.dcol2 = r[2];
  return static_cast<int>(r[0]);
}
} // namespace

double System::kick_one(int i, double half_dt) { return kick_particle(m_ps, i, half_dt); }

void System::kick(double half_dt) {
  for (int i = 0; i < m_ps.n_local(); ++i)
    kick_particle(m_ps, i, half_dt);
}

// Half kick + drift, refusing a step that moves a particle farther than the
// skin or makes it non-finite: the step is checked first (on every rank) and
// then done, so a refused step changes nothing. Two sweeps over the locals:
// (1) [the previous step's closing half kick, when run_md deferred it:
// kick_one], the check, and the Verlet-list displacement test on the new
// positions (the test ensure_lists would otherwise do in a third sweep),
// both voted on in one reduction over the ranks; (2) the half kick and drift.
void System::drift_checked(bool kick_first) {
  double const dt = m_time_step;
  double const half_dt = 0.5 * m_time_step;
  double const max2 = m_cells.skin() * m_cells.skin();
  int const n = m_ps.n_local();
  auto *const v = m_ps.v.data();
  auto *const x = m_ps.pos.data();
  auto const *const f = m_ps.f.data();
  // 0.5 dt / m of each local, computed once per step (the same value for the
  // kick, the check and the drift)
  m_half_dt_over_m.resize(static_cast<std::size_t>(n));
  double *const am = m_half_dt_over_m.data();
  auto step_of = [&](int i, Vector3d &dv, Vector3d &dx) {
    kick_drift_of(m_ps, i, am[i], f[i], v[i], dt, dv, dx);
  };
  int bad = -1;
  double bad_disp2 = 0.;
  // the list's displacement test (CellSystem::displacement_exceeds_half_skin)
  // on the new positions x + dx, voted on with the step check below
  double lim2 = 0.25 * m_cells.skin() * m_cells.skin();
  auto const *const x0 = m_ps.pos_at_rebuild.data();
  bool moved = false;
  if (m_box.lees_edwards().active()) {
    // Lees-Edwards: the images across the shear plane will have moved by the
    // offset change since the build: the particles get the rest of the skin
    double const b = m_cells.le_half_skin_budget(m_le_protocol.pos_offset(m_time + dt));
    moved = !(b > 0.);
    lim2 = b * b;
  }
  // the list's pair test (CellSystem::pairs_may_be_missing) reads the
  // displacements this sweep computes, as floats
  bool const keep_d2 = pair_test_applies();
  m_disp2.resize(keep_d2 ? static_cast<std::size_t>(n) : 0);
  float *const d2s = m_disp2.data();
  auto kick_sweep = [&](auto keep) {
    for (int i = 0; i < n; ++i) {
      am[i] = kick_particle(m_ps, i, half_dt);
      Vector3d dv, dx;
      step_of(i, dv, dx);
      double const disp2 = dx.norm2();
      if (!(disp2 <= max2) && bad < 0) { // also catches NaN
        bad = i;
        bad_disp2 = disp2;
      }
      double const m2 = (x[i] + dx - x0[i]).norm2();
      if constexpr (decltype(keep)::value)
        d2s[i] = static_cast<float>(m2);
      moved |= m2 > lim2;
    }
  };
  if (kick_first) {
    if (keep_d2)
      kick_sweep(std::true_type{});
    else
      kick_sweep(std::false_type{});
  } else {
    for (int i = 0; i < n; ++i)
      am[i] = 0.5 * dt / m_ps.get_mass(i);
    for (int i = 0; i < n; ++i) {
      Vector3d dv, dx;
      step_of(i, dv, dx);
      double const disp2 = dx.norm2();
      if (!(disp2 <= max2)) { // also catches NaN
        bad = i;
        bad_disp2 = disp2;
        break;
      }
      moved |= (x[i] + dx - x0[i]).norm2() > lim2;
    }
  }
  // one reduction for both: 2 = some rank refuses the step, 1 = some local
  // (on any rank) will have moved more than skin/2 (the list must be rebuilt)
  int const vote = m_comm.max(bad >= 0 ? 2 : (moved ? 1 : 0));
  if (vote == 2)
    refuse_step(bad, bad_disp2, dt, 1);
  for (int i = 0; i < n; ++i) {
    Vector3d dv, dx;
    step_of(i, dv, dx);
    v[i] += dv;
    x[i] += dx;
#ifdef ROTATION
    if (m_ps.rotation[i])
      m_ps.omega[i] += (0.5 * dt / m_ps.rinertia[i]) * m_ps.torque[i];
#endif
  }
  m_displacement_hint = vote; // already agreed by all ranks
  m_disp2_fresh = keep_d2 && kick_first;
}

// The refusal of a step (collective: every rank got vote 2): the message
// names the first bad local of the refusing rank and a time step to try.
// @p step_len is the length of the refused (sub)step, @p n_sub the RESPA
// substeps per time step (1: a plain step).
void System::refuse_step(int bad, double bad_disp2, double step_len, int n_sub) {
  double const dt = step_len * n_sub;
  m_forces_valid = false;
  m_cells.invalidate();
  // the friction limits (integrators/stability.cpp) name a likelier cause
  std::string where;
  double const frac = limit_fraction(*this, where); // collective
  std::string msg;
  if (bad >= 0) {
    double const disp2 = bad_disp2;
    std::string const friction =
        frac > 0.3 ? " (explicit friction at " + Utils::to_str(frac) +
                         " x its stability limit: " + where + ")"
                   : std::string();
    double const dt_sugg = std::isfinite(disp2) ? 0.5 * dt * m_cells.skin() / std::sqrt(disp2)
                                                : (frac > 0.3 ? 0.5 * dt / frac : 0.1 * dt);
    std::string const in_one = n_sub > 1 ? " in one of the " + std::to_string(n_sub) + " substeps"
                                         : std::string(" in one step");
    std::string const or_sub = n_sub > 1 ? " or raise the integrator's substeps" : std::string();
    std::string const what =
        std::isfinite(disp2)
            ? "moved " + Utils::to_str(std::sqrt(disp2)) + in_one + ", more than the skin (" +
                  Utils::to_str(m_cells.skin()) +
                  "): likely cause: time step too large for the forces/velocities" + friction +
                  " or overlapping particles; reduce time_step (suggested <= " +
                  Utils::to_str(dt_sugg) + ")" + or_sub + " or increase cell_system.skin"
            : "got a non-finite velocity or position: likely cause: time step too large" +
                  friction + " or a non-finite force/velocity set by the user; reduce time_step "
                  "(suggested <= " + Utils::to_str(dt_sugg) + ")" + or_sub;
    msg = "integration stopped at step " + std::to_string(m_step + 1) + ": particle " +
          std::to_string(m_ps.id[bad]) + " " + what;
  }
  m_comm.throw_if_any(msg);
  throw Utils::RuntimeError("integration stopped at step " + std::to_string(m_step + 1) +
                            " (refused on another rank)");
}

void System::check_thermostats_before_run() const {
  auto const &th = m_thermo;
#ifdef DPD
  bool const dpd_on = th.dpd.active;
#else
  bool const dpd_on = false;
#endif
  if (m_integrator == IntegratorKind::BrownianDynamics) {
    if (!th.brownian.active)
      throw Utils::RuntimeError(
          "The BD integrator requires the BD thermostat: call "
          "system.thermostat.set_brownian(kT=..., gamma=..., seed=...) before running");
    if (th.langevin.active || dpd_on)
      throw Utils::RuntimeError(
          std::string("The BD integrator cannot be combined with the ") +
          (dpd_on ? "DPD" : "Langevin") +
          " thermostat (Brownian dynamics has no velocities to damp; its solvent is implicit): "
          "switch it off (thermostat.turn_off() then set_brownian(...)) or use a velocity "
          "Verlet integrator");
#ifdef SRD
    if (srd)
      throw Utils::RuntimeError("The BD integrator cannot be combined with an SRD solvent: "
                                "use integrator.set_vv()");
#endif
    return;
  }
  if (th.brownian.active)
    throw Utils::RuntimeError(
        "The Brownian thermostat works only with integrator.set_brownian_dynamics(); with a "
        "velocity Verlet integrator use thermostat.set_langevin(...) (or turn the Brownian "
        "thermostat off with thermostat.turn_off())");
  if (th.langevin.active && m_time_step > 0.) {
    int who = -1;
    double const a = m_comm.max(langevin_max_friction(m_ps, th.langevin, m_time_step, who));
    if (a >= 2.) {
      who = m_comm.max(langevin_max_friction(m_ps, th.langevin, m_time_step, who) == a ? who : -1);
      throw Utils::RuntimeError(
          "cannot integrate: the Langevin friction gamma * time_step / mass (or gamma_rotation * "
          "time_step / rinertia) of particle " + std::to_string(who) + " is " + Utils::to_str(a) +
          ", >= 2, where velocity Verlet with explicit friction is unstable; reduce time_step "
          "below " + Utils::to_str(m_time_step / a) + " or gamma");
    }
  }
}

int System::run(int n_steps, bool recalc_forces) {
  check_scene_before_run();
  if (m_integrator == IntegratorKind::SteepestDescent)
    return run_sd(n_steps);
  check_thermostats_before_run();
  if (recalc_forces)
    m_forces_valid = false;
  if (m_integrator == IntegratorKind::BrownianDynamics)
    return run_bd(n_steps);
  if (m_le_protocol.kind != LeesEdwardsProtocol::Off)
    update_lees_edwards();
  if (n_steps > 0)
    check_stability_before_run(*this);
#ifdef SRD
  if (srd && n_steps > 0) // SRD: geometry checks, SRD particles inside colloids moved out
    srd->prepare(*this);
#endif
  if (m_substeps > 1)
    return run_md_respa(n_steps);
  return run_md(n_steps);
}

// One loop for the MD integrators: velocity Verlet, and the DPD integrators
// that change only what follows the second half kick (Shardlow S1: an exact
// pairwise thermostat sweep; DPD-VV: the friction of the half kick's velocity
// change added to the forces).
bool System::accumulator_due() const {
  for (auto const &acc : m_auto_update)
    if (acc->delta_N > 0 && m_step % static_cast<std::uint64_t>(acc->delta_N) == 0)
      return true;
  return false;
}

int System::run_md(int n_steps) {
  if (m_time_step <= 0.)
    throw Utils::RuntimeError("time_step is not set: set system.time_step > 0 before running");
  update_thermostat_prefactors();
  if (!m_forces_valid || n_steps == 0)
    compute_forces_checked(true);
#ifdef DPD
  if (shardlow_sweep_active() && n_steps > 0 && m_comm.parallel()) {
    ensure_lists(); // (the ranges of this run's lists, not of the last build)
    check_shardlow_decomposition(*this); // the domain width the sweep needs
  }
#endif
  [[maybe_unused]] std::vector<Vector3d> dv;
  // Plain velocity Verlet: a step's closing half kick is done by the next
  // step's first sweep (drift_checked(true)) unless something reads the
  // state in between (an accumulator due, the end of the run).
  bool kick_pending = false;
  for (int s = 0; s < n_steps; ++s) {
    try {
      drift_checked(kick_pending);
    } catch (...) {
      m_displacement_hint = -1;
      throw;
    }
    kick_pending = false;
    ++m_step;
    m_time += m_time_step;
    if (m_le_protocol.kind != LeesEdwardsProtocol::Off)
      update_lees_edwards(); // the offset of the new time (ghosts: ensure_lists)
#ifdef SRD
    m_displacement_hint = srd ? -1 : m_displacement_hint; // SRD may move the colloids
    if (srd) // SRD: stream (impulses to the colloids) and collide when due
      srd->md_step(*this);
#endif
#ifdef DPD
    ++m_thermo.dpd.philox_counter;
#endif
    ++m_thermo.langevin.philox_counter;
    compute_forces_checked(true); // (m_forces_valid false if it throws)
#ifdef DPD
    if (m_integrator == IntegratorKind::DPDVV) {
      int const n = m_ps.n_local();
      dv.assign(m_ps.v.begin(), m_ps.v.begin() + n);
      kick(0.5 * m_time_step);
      if (m_thermo.dpd.active) {
        for (int i = 0; i < n; ++i)
          dv[i] = m_ps.v[i] - dv[i];
        add_friction_of_dv(*this, dv);
      }
    } else if (shardlow_sweep_active()) {
      kick(0.5 * m_time_step);
      // the sweep sees x(t + dt), so the state returned is the one just thermalised
      shardlow_sweep(*this);
    } else if (s + 1 < n_steps && !accumulator_due()) {
      kick_pending = true;
    } else {
      kick(0.5 * m_time_step);
    }
#else
    if (s + 1 < n_steps && !accumulator_due())
      kick_pending = true;
    else
      kick(0.5 * m_time_step);
#endif
    for (auto const &acc : m_auto_update)
      if (acc->delta_N > 0 && m_step % static_cast<std::uint64_t>(acc->delta_N) == 0)
        acc->update(*this);
    maybe_balance(); // (new domain cuts: the next force computation migrates)
  }
  return n_steps;
}

// ---------------------------------------------------------------------------
// RESPA (Tuckerman, Berne & Martyna, J. Chem. Phys. 97, 1990 (1992)) for the
// stiff colloid pairs: the conservative pair kernels of the colloid pair list
// (marble/Colloids: e.g. a marble's LJ wall) are the fast forces F_f,
// integrated with n = substeps inner steps of h = dt/n; everything else
// (solvent pairs, walls, external and Langevin forces, the colloid pairs'
// DPD and, under velocity Verlet, marble-coupling friction and noise, with
// their counters of the outer step) is the slow part F_s at dt. One step:
//   v += dt/2 F_s/m;  n times { v += h/2 F_f/m; x += h v; F_f(x); v += h/2 F_f/m };
//   F_s(x);  v += dt/2 F_s/m;  [Shardlow: the pair sweep, marble coupling included]
// with the inner half kicks of consecutive substeps merged. Between steps
// particle.f holds F_s + F_f (as with substeps = 1); the step takes
// F_s = f - F_f again. Several MPI ranks (velocity Verlet or Shardlow, whose
// sweep sees every ghost updated by F_s): between substeps the other ranks' colloid copies get
// the new positions and the fast forces on them go back to their owners (a
// colloid pair's partner is a local; every ghost is updated at the step's end).

void System::kick_fast(double kick_dt) {
  auto *const v = m_ps.v.data();
  auto const *const f = m_f_fast.data();
  for_each_fast_member([&](int i) {
    double const a = kick_dt / m_ps.get_mass(i);
    if (!m_ps.has_fixed(i)) {
      for (int d = 0; d < 3; ++d)
        v[i][d] += a * f[i][d];
    } else {
      for (int d = 0; d < 3; ++d)
        v[i][d] = m_ps.is_fixed(i, d) ? 0. : v[i][d] + a * f[i][d];
    }
  });
}

bool System::drift_checked_substep(double kick_dt, double h) {
  double const skin = m_cells.skin();
  double const max2 = skin * skin;
  double const lim2 = 0.25 * skin * skin;
  int const n = m_ps.n_local();
  auto *const v = m_ps.v.data();
  auto *const x = m_ps.pos.data();
  auto const *const f = m_f_fast.data();
  auto const *const x0 = m_ps.pos_at_rebuild.data();
  m_half_dt_over_m.resize(static_cast<std::size_t>(n));
  double *const am = m_half_dt_over_m.data();
  for (int i = 0; i < n; ++i)
    am[i] = kick_dt / m_ps.get_mass(i);
  auto step_of = [&](int i, Vector3d &dv, Vector3d &dx) {
    kick_drift_of(m_ps, i, am[i], f[i], v[i], h, dv, dx);
  };
  SubstepTally t{max2, lim2};
  for (int i = 0; i < n; ++i) {
    Vector3d dv, dx;
    step_of(i, dv, dx);
#ifdef MARBLE
    bool const col = m_colloids.is_colloid_type(m_ps.type[i]);
#else
    bool const col = false;
#endif
    if (!t.add(i, x[i], dx, x0[i], col))
      break;
  }
  int const vote = substep_vote(m_comm, t);
  if (vote == 2)
    refuse_step(t.bad, t.bad_disp2, h, m_substeps);
  for (int i = 0; i < n; ++i) {
    Vector3d dv, dx;
    step_of(i, dv, dx);
    v[i] += dv;
    x[i] += dx;
  }
  m_displacement_hint = vote;
  return t.colloid_list_stale(skin);
}

// The substeps of one RESPA step, the particles outside the colloid pair list
// apart: their fast force is zero, so each substep is v += (kick_dt/m) 0,
// x += h v (kick_drift_of with f = 0) and nothing in the substeps depends on
// their positions (the fast forces act within the list), except the list's
// staleness test. Their n substeps are therefore checked in one sweep (the
// largest displacement since the build after each substep, for that test)
// and done in another, with the arithmetic of drift_checked_substep in the
// same order per particle: the same bits. The list's particles (a few
// hundred) go substep by substep between fast force evaluations, as before.
// If the list goes stale before the last substep the others are brought to
// that substep first, and the caller does the remaining substeps with the
// full sweeps (drift_checked_substep). Refused steps: a bad displacement of
// an outside particle in any substep refuses the step before any substep is
// done; one of a list particle, before its substep (as drift_checked_substep).
// Several ranks: the pairs' partners are locals, their colloids locals or
// other ranks' colloids, whose ghosts get each substep's positions (the
// outside particles' ghosts lag until the step's end, unused in between).
int System::respa_member_substeps(double h) {
#ifdef MARBLE
  int const n_sub = m_substeps;
  constexpr int kMaxSub = 100; // the substeps set_vv / set_shardlow accept
  if (!m_colloids.any() || n_sub > kMaxSub)
    return 0;
  auto const &members = m_colloids.pair_members();
  int const n = m_ps.n_local();
  double const skin = m_cells.skin();
  double const max2 = skin * skin;
  double const lim2 = 0.25 * skin * skin;
  auto *const v = m_ps.v.data();
  auto *const x = m_ps.pos.data();
  auto const *const f = m_f_fast.data();
  auto const *const x0 = m_ps.pos_at_rebuild.data();
  Vector3d const zero{};
  // An outside particle's kick factor a = kick_dt / m multiplies a zero
  // force: a * 0 = +0 for any finite a > 0, so for any mass whose a cannot
  // overflow 1 does as well as the division (the same bits, no divider)
  auto a_out = [&](double m, int k) { return m >= 1e-290 ? 1. : inner_kick_dt(k, h) / m; };
  // the outside particles: i in [lo, hi) between members
  auto for_each_outside = [&](auto &&fn) {
    int lo = 0;
    for (std::size_t q = 0; q <= members.size(); ++q) {
      int const hi = q < members.size() ? std::min(members[q], n) : n;
      for (int i = lo; i < hi; ++i)
        fn(i);
      lo = std::max(lo, hi + 1);
    }
  };
  // (1) check: per substep the outside particles' tally (the largest
  // displacements since the build, the half-skin test)
  std::array<SubstepTally, kMaxSub> out;
  out.fill(SubstepTally{max2, lim2});
  int bad_k = -1; // the substep of the first refusal
  // An outside particle without fixed coordinates whose a is 1 (almost all)
  // drifts by the same dx = h (v + 0) in every substep (v + 0 + 0 = v + 0):
  // its one displacement test stands for all substeps (the first refuses),
  // and its position after the substeps is kept for the sweep (2) that does
  // them (the same bits as doing them one by one).
  auto plain = [&](int i, double m) { return m >= 1e-290 && !m_ps.has_fixed(i); };
  m_respa_end_pos.resize(static_cast<std::size_t>(n));
  Vector3d *const x_end = m_respa_end_pos.data();
  for_each_outside([&](int i) {
    if (bad_k >= 0)
      return;
    double const m = m_ps.get_mass(i);
    bool const col = m_colloids.is_colloid_type(m_ps.type[i]);
    if (plain(i, m)) {
      Vector3d const dx{h * (v[i][0] + 0.), h * (v[i][1] + 0.), h * (v[i][2] + 0.)};
      double const disp2 = dx.norm2();
      if (!(disp2 <= max2)) { // (SubstepTally::add, substep 0)
        out[0].bad = i, out[0].bad_disp2 = disp2;
        bad_k = 0;
        return;
      }
      Vector3d y = x[i];
      for (int k = 0; k < n_sub; ++k) {
        y += dx;
        double const dd2 = (y - x0[i]).norm2();
        SubstepTally &t = out[k];
        t.moved |= dd2 > lim2;
        t.dmax2 = std::max(t.dmax2, dd2);
        if (col)
          t.dcol2 = std::max(t.dcol2, dd2);
      }
      x_end[i] = y;
      return;
    }
    Vector3d vi = v[i], xi = x[i];
    for (int k = 0; k < n_sub; ++k) {
      Vector3d dv, dx;
      kick_drift_of(m_ps, i, a_out(m, k), zero, vi, h, dv, dx);
      if (!out[k].add(i, xi, dx, x0[i], col)) {
        bad_k = k;
        return;
      }
      vi += dv;
      xi += dx;
    }
  });
  if (m_comm.max(bad_k >= 0 ? 2 : 0) == 2) // (bad_k < 0: refused on another rank)
    refuse_step(bad_k >= 0 ? out[bad_k].bad : -1, bad_k >= 0 ? out[bad_k].bad_disp2 : 0., h, n_sub);
  // the outside particles' substeps [k0, k1)
  // (all n_sub of them: the plain particles from the end positions of (1))
  auto advance_outside = [&](int k0, int k1) {
    bool const all = k0 == 0 && k1 == n_sub;
    for_each_outside([&](int i) {
      double const m = m_ps.get_mass(i);
      if (all && plain(i, m)) {
        v[i] += zero; // (v + 0 + 0 = v + 0)
        x[i] = x_end[i];
        return;
      }
      for (int k = k0; k < k1; ++k) {
        Vector3d dv, dx;
        kick_drift_of(m_ps, i, a_out(m, k), zero, v[i], h, dv, dx);
        v[i] += dv;
        x[i] += dx;
      }
    });
  };
  // (2) the list's particles, substep by substep
  for (int k = 0; k < n_sub; ++k) {
    double const kick_dt = inner_kick_dt(k, h);
    // this substep's tally over all locals: the outside particles' and the list's
    // (a half-skin vote before the last substep only decides nothing: the last one's stays)
    SubstepTally t = out[k];
    for (int i : members) {
      if (i >= n)
        break;
      Vector3d dv, dx;
      kick_drift_of(m_ps, i, kick_dt / m_ps.get_mass(i), f[i], v[i], h, dv, dx);
      if (!t.add(i, x[i], dx, x0[i], m_colloids.is_colloid_type(m_ps.type[i])))
        break;
    }
    bool const last = k + 1 == n_sub;
    int const vote = substep_vote(m_comm, t);
    if (vote == 2) {
      advance_outside(0, k); // the substeps before the refused one stay done
      refuse_step(t.bad, t.bad_disp2, h, n_sub);
    }
    for (int i : members) {
      if (i >= n)
        break;
      Vector3d dv, dx;
      kick_drift_of(m_ps, i, kick_dt / m_ps.get_mass(i), f[i], v[i], h, dv, dx);
      v[i] += dv;
      x[i] += dx;
    }
    m_displacement_hint = vote;
    if (last)
      break;
    if (t.colloid_list_stale(skin)) {
      advance_outside(0, k + 1);
      m_displacement_hint = 1;
      ensure_lists(); // rebuild (the pairs of the colloid list too)
      compute_fast_forces();
      return k + 1;
    }
    if (m_comm.parallel()) // the other ranks' colloids at this substep (the partners are locals;
      m_cells.update_replicated_ghosts(m_ps); // every other ghost lags until the step's end: unused)
    compute_fast_forces();
  }
  advance_outside(0, n_sub);
  return n_sub;
#else
  (void)h;
  return 0;
#endif
}

int System::run_md_respa(int n_steps) {
  if (m_time_step <= 0.)
    throw Utils::RuntimeError("time_step is not set: set system.time_step > 0 before running");
  update_thermostat_prefactors();
  // compute_forces without the fast forces (restored on every exit)
  struct ExcludeFast {
    bool &flag;
    explicit ExcludeFast(bool &f) : flag(f) { flag = true; }
    ~ExcludeFast() { flag = false; }
  };
  if (!m_forces_valid || n_steps == 0)
    compute_forces_checked(true); // all forces: F_s + F_f
  if (n_steps == 0)
    return 0;
  int const n_sub = m_substeps;
  double const dt = m_time_step;
  double const h = dt / n_sub;
#ifdef MARBLE
  bool const have_fast = m_colloids.any();
#else
  bool const have_fast = false;
#endif
  ensure_lists(); // (a rebuild keeps f with its particle)
#ifdef DPD
  if (shardlow_sweep_active() && m_comm.parallel())
    check_shardlow_decomposition(*this); // the domain width the sweep needs
#endif
  compute_fast_forces();
  for (int s = 0; s < n_steps; ++s) {
    try {
      // the outer half kick with F_s = f - F_f (and the slow torques)
      for_each_fast_member([&](int i) { m_ps.f[i] -= m_f_fast[i]; }); // (F_fast is 0 elsewhere)
      kick(0.5 * dt);
      int k = have_fast ? respa_member_substeps(h) : 0; // (all n_sub, or up to a mid-step rebuild)
      for (; k < n_sub; ++k) {
        // the inner half kicks of substeps k - 1 and k in one
        bool const colloid_list_stale = drift_checked_substep(inner_kick_dt(k, h), h);
        // (without fast forces nothing is evaluated between the substeps: the
        // list is checked at the end, as with substeps = 1)
        if (k + 1 < n_sub && have_fast) {
          if (colloid_list_stale) {
            m_displacement_hint = 1;
            ensure_lists(); // rebuild (the pairs of the colloid list too)
          } else if (m_comm.parallel()) {
            // the colloid pairs' ghosts (other ranks' colloids: the partners are
            // locals) at the substep's positions; the others lag until the step's end
            m_cells.update_replicated_ghosts(m_ps);
          }
          compute_fast_forces();
        }
      }
    } catch (...) {
      m_displacement_hint = -1;
      m_forces_valid = false;
      throw;
    }
    ++m_step;
    m_time += dt;
#ifdef DPD
    ++m_thermo.dpd.philox_counter;
#endif
    ++m_thermo.langevin.philox_counter;
    {
      ExcludeFast const guard(m_exclude_fast);
      compute_forces_checked(true); // F_s (ensure_lists may rebuild: before F_f)
    }
    try {
      compute_fast_forces();
    } catch (...) {
      m_forces_valid = false;
      throw;
    }
    kick_fast(0.5 * h);
    kick(0.5 * dt);
#ifdef DPD
    if (shardlow_sweep_active())
      shardlow_sweep(*this);
#endif
    // particle.f: all forces, as with substeps = 1
    for_each_fast_member([&](int i) { m_ps.f[i] += m_f_fast[i]; });
    for (auto const &acc : m_auto_update)
      if (acc->delta_N > 0 && m_step % static_cast<std::uint64_t>(acc->delta_N) == 0)
        acc->update(*this);
    maybe_balance(); // (new domain cuts: the next force computation migrates)
  }
  return n_steps;
}

int System::run_sd(int n_steps) {
  auto const &p = m_sd;
  int done = 0;
  for (; done < n_steps; ++done) {
    compute_forces_checked(false);
    double fmax2 = 0.;
    for (int i = 0; i < m_ps.n_local(); ++i) {
      Vector3d f = m_ps.f[i];
      for (int d = 0; d < 3; ++d)
        if (m_ps.is_fixed(i, d))
          f[d] = 0.;
      fmax2 = std::max(fmax2, f.norm2());
    }
    fmax2 = m_comm.max(fmax2);
    if (fmax2 < p.f_max * p.f_max)
      break;
    for (int i = 0; i < m_ps.n_local(); ++i)
      for (int d = 0; d < 3; ++d)
        if (!m_ps.is_fixed(i, d))
          m_ps.pos[i][d] += std::clamp(p.gamma * m_ps.f[i][d], -p.max_displacement, p.max_displacement);
    m_forces_valid = false;
  }
  // Forces from SD exclude the thermostat: recompute them before the next MD run.
  m_forces_valid = false;
  return done;
}

} // namespace Marble
