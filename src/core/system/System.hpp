#pragma once
// The System owns everything a simulation needs; there is no global state.
#include "box/BoxGeometry.hpp"
#include "cells/CellSystem.hpp"
#include "comm/Communicator.hpp"
#include "constraints/Constraints.hpp"
#include "nonbonded/InteractionTable.hpp"
#include "particles/ParticleStore.hpp"
#include "thermostats/Thermostat.hpp"
#ifdef MARBLE
#include "marble/Colloids.hpp"
#endif

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace Marble {

class System;
namespace Srd { class Fluid; } // SRD

/** Something updated automatically during integration (accumulators,
 * correlators): update() is called after every step whose number is a
 * multiple of delta_N. */
struct AutoUpdate {
  virtual ~AutoUpdate() = default;
  virtual void update(System &system) = 0;
  int delta_N = 1;
};

// Shardlow: S1 splitting, exact pairwise DPD updates + VV for the rest;
// DPDVV: velocity Verlet with the DPD friction recomputed from the full-step
// velocities (Besold et al.). See integrators/shardlow.cpp, doc/stability.md.
// BrownianDynamics: overdamped position update with the Brownian thermostat
// (integrators/brownian.cpp, doc/thermostats.md).
enum class IntegratorKind { VelocityVerlet, SteepestDescent, Shardlow, DPDVV, BrownianDynamics };

/** The Shardlow sweep's buffers on several ranks (integrators/shardlow.cpp),
 * kept between steps (no per-step allocation of these). Scratch, not state:
 * every step overwrites what it reads, except dq, which the rounds leave all
 * zero (dq_clean). */
struct ShardlowBuffers {
  std::vector<char> boundary;                     // per particle: another rank reads or writes its velocity
  std::vector<int> sent;                          // the locals sent to other ranks as ghosts
  std::vector<std::array<int, 2>> deferred;       // the step's boundary pairs, in list order
  std::vector<Utils::Vector3d> deferred_d;        // and their r_i - r_j (the select's)
  std::array<std::vector<int>, 3> side_pairs;     // face rounds: the deferred pairs (indices) at sides 1, 2, both
  std::array<std::vector<Utils::Vector3d>, 2> q0; // a round's ghost velocities (spins) before it
  std::array<std::vector<Utils::Vector3d>, 2> dq; // per particle: their changes (zero between rounds)
  std::array<bool, 2> dq_clean{true, true};       // dq[k] is all zero
  bool face = false; // this step's rounds are face rounds (CellSystem::boundary_axis() >= 0; the same on every rank)
};

struct SteepestDescentParams {
  double f_max = 0., gamma = 0., max_displacement = 0.;
};

/** Energies of the current configuration. */
struct Energies {
  double kinetic = 0., kinetic_rot = 0., non_bonded = 0.;
  std::vector<double> non_bonded_pairs; // n_types x n_types, upper triangle filled
  double total() const { return kinetic + non_bonded; }
};

/** Pressure tensor parts (already divided by the volume): kinetic,
 * conservative pair forces (non_bonded), and the dissipative ones with the
 * current velocities and noise: the DPD pair forces (main list and colloid
 * pairs, friction + noise) and the marble surface coupling. */
struct PressureTensor {
  std::array<double, 9> kinetic{}, non_bonded{}, dpd{}, marble{};
};

/** DPD pair-force contribution to the pressure tensor, split into friction
 * and noise (already divided by the volume; analysis/dpd_stress.cpp). */
struct DPDStress {
  std::array<double, 9> friction{}, noise{};
};

class System {
  friend struct CheckpointAccess; // io/checkpoint.cpp: the whole state, bit for bit

public:
  explicit System(Utils::Vector3d const &box_l);

  /** The ranks this system runs on (a group of one without MPI). */
  Communicator const &comm() const { return m_comm; }

  // --- geometry and parameters (validated by the script interface) ---
  BoxGeometry const &box() const { return m_box; }
  void set_box_l(Utils::Vector3d const &l);
  double time_step() const { return m_time_step; }
  void set_time_step(double dt);
  double time() const { return m_time; }
  void set_time(double t) {
    m_time = t;
    if (m_le_protocol.kind != LeesEdwardsProtocol::Off) {
      update_lees_edwards();
      m_cells.invalidate(); // the offset may have jumped
    }
  }

  // --- Lees-Edwards boundary conditions (box/LeesEdwards.hpp, doc/lees-edwards.md) ---
  /** Switch Lees-Edwards on with @p protocol (kind Off: switch it off).
   * Axes validated by the caller (distinct, in [0, 3)). */
  void set_lees_edwards(int shear_direction, int shear_plane_normal, LeesEdwardsProtocol const &protocol);
  LeesEdwardsProtocol const &lees_edwards_protocol() const { return m_le_protocol; }
  /** The box's Lees-Edwards state from the protocol at the current time. */
  void update_lees_edwards();
  /** Velocity of local @p i in the frame of its folded position: with
   * Lees-Edwards, a particle that crossed the shear plane since the last list
   * build (folded, with the velocity jump, at the next build) is reported
   * with the jump already applied; otherwise ps.v[i]. */
  Utils::Vector3d folded_velocity(int i) const {
    auto const &le = m_box.lees_edwards();
    if (!le.active())
      return m_ps.v[i];
    Utils::Vector3d p = m_ps.pos[i], v = m_ps.v[i];
    Utils::Vector3i img{};
    int const k = m_box.fold(p, img);
    v[le.shear_direction] -= k * le.shear_velocity;
    return v;
  }
  std::uint64_t step() const { return m_step; }
  void set_skin(double s);
  double skin() const { return m_cells.skin(); }
  /** When a Verlet list is rebuilt (doc/benchmarks.md "The Verlet list's
   * life"): HalfSkin as soon as some particle has moved more than skin/2;
   * Pairs (the default) then only if a pair may be missing from it
   * (CellSystem::pairs_may_be_missing), where that test applies
   * (pair_test_applies; elsewhere HalfSkin). Both give the same forces; the
   * list order, and so the trajectories' last bits, differ. */
  enum class ListCheck { Pairs, HalfSkin };
  ListCheck list_check() const { return m_list_check; }
  void set_list_check(ListCheck c) { m_list_check = c; }
  /** Whether ensure_lists() uses the pair test now (ListCheck::Pairs, VV,
   * DPD-VV or Shardlow, RESPA substeps and colloids included; no
   * Lees-Edwards, SRD or large-range types, and a box of at least 3 pair
   * ranges). With colloids the colloid pair list's own criterion is part of
   * the test (colloid_reach). */
  bool pair_test_applies() const;
  /** The largest displacement of a local colloid since the last build (< 0:
   * no colloid types): the colloid pair list, built with the Verlet list,
   * stays valid while d_max + this < skin (CellSystem::pairs_may_be_missing). */
  double colloid_reach() const;

  // --- particles ---
  ParticleStore &particles() { return m_ps; }
  ParticleStore const &particles() const { return m_ps; }
  void add_particle(ParticleProperties p);
  void remove_particle(int pid);
  void clear_particles();
  /** Call after any change of particle data or parameters. */
  void on_change() {
    m_forces_valid = false;
  }
  void on_particle_change() {
    m_forces_valid = false;
    m_cells.invalidate();
  }

  // --- interactions and thermostat ---
  InteractionTable &interactions() { return m_ia; }
  InteractionTable const &interactions() const { return m_ia; }
  /** Set kernel @p K of types (i, j) (validated by the caller). */
  template <class K> void set_kernel(int i, int j, typename K::Params const &p) {
    m_ia.set_kernel<K>(i, j, p);
    on_interactions_change();
  }
  /** Switch every kernel of every type pair off. */
  void reset_interactions() {
    m_ia.reset();
    on_interactions_change();
  }
  /** Call after a change of the interaction table: large types, colloid
   * types, noise prefactors and the lists follow. */
  void on_interactions_change();
  Thermostat &thermostat() { return m_thermo; }
  /** Recompute cached noise prefactors from kT, gamma, dt. */
  void update_thermostat_prefactors();

  // --- integration ---
  IntegratorKind integrator() const { return m_integrator; }
  void set_integrator_vv(int substeps = 1) {
    leave_bd();
    m_integrator = IntegratorKind::VelocityVerlet;
    set_pair_dpd_in_force_loop(true);
    m_substeps = substeps;
  }
  void set_integrator_shardlow(int substeps = 1) {
    leave_bd();
    m_integrator = IntegratorKind::Shardlow;
    set_pair_dpd_in_force_loop(false);
    m_substeps = substeps;
  }
  void set_integrator_dpd_vv() {
    leave_bd();
    m_integrator = IntegratorKind::DPDVV;
    set_pair_dpd_in_force_loop(true);
    m_substeps = 1;
  }
  /** RESPA inner substeps of the fast forces (velocity Verlet and Shardlow;
   * 1 = plain velocity Verlet, the default): the conservative pair kernels
   * of the colloid pair list are integrated with step time_step / substeps
   * (integrators/integrate.cpp, run_md_respa). */
  int substeps() const { return m_substeps; }
  static constexpr int max_substeps = 100;
  /** False with Shardlow: the main pair loop then leaves DPD out (the
   * integrator updates those pairs itself) and forces hold the rest. */
  bool pair_dpd_in_force_loop() const { return m_dpd_in_pair_loop; }
  /** True when the Shardlow sweep runs in a step (integrator Shardlow with the
   * DPD thermostat on): it then updates the DPD pairs, the stick friction and
   * the marble coupling exactly, and the force passes leave them out. */
  bool shardlow_sweep_active() const {
#ifdef DPD
    return m_integrator == IntegratorKind::Shardlow && m_thermo.dpd.active;
#else
    return false;
#endif
  }
  void set_integrator_sd(SteepestDescentParams const &p) {
    m_integrator = IntegratorKind::SteepestDescent;
    m_substeps = 1;
    m_sd = p;
  }
  SteepestDescentParams const &sd_params() const { return m_sd; }
  /** Brownian dynamics (needs the Brownian thermostat at run time). */
  void set_integrator_bd() {
    m_integrator = IntegratorKind::BrownianDynamics;
    m_substeps = 1;
    m_forces_valid = false; // BD forces exclude the thermostat
    set_pair_dpd_in_force_loop(true);
  }
  /** Integrate @p n_steps; returns the number of steps done. Throws Utils::RuntimeError. */
  int run(int n_steps, bool recalc_forces = false);

  /** Objects updated during run(): see AutoUpdate. */
  std::vector<std::shared_ptr<AutoUpdate>> &auto_update() { return m_auto_update; }

  // --- analysis ---
  CellSystem &cells() { return m_cells; }
  /** Make sure the Verlet list matches the current positions and interactions. */
  void ensure_lists();
  /** Rebuild the cell and pair lists exactly as they were at the last
   * rebuild (for checkpoint restart): the rebuild is done with every local at
   * its pos_at_rebuild, then the current positions are put back and the
   * ghosts refreshed. Locals must be in the stored order. Collective. */
  void rebuild_lists_at_saved_positions();
  Energies energies();
  PressureTensor pressure_tensor();
  /** DPD contribution sum d (x) F_DPD / V with the current velocities and noise. */
  DPDStress dpd_stress();
  Utils::Vector3d linear_momentum() const;
  Utils::Vector3d angular_momentum_spin() const;
  Utils::Vector3d center_of_mass() const;
  double total_mass() const;
  /** Minimum pair distance between particles of types in @p t1 and @p t2 (empty = all). */
  double min_dist(std::vector<int> const &t1, std::vector<int> const &t2);
  Utils::Vector3d distance_vec(int pid1, int pid2) const;
  /** Folded position of particle @p pid (collective; throws std::out_of_range). */
  Utils::Vector3d folded_position(int pid) const;
  /** Number of particles on all ranks (collective). */
  int n_particles() const;
  /** The first of @p ids that no rank holds, if any (collective). */
  std::optional<int> first_missing_particle(std::vector<int> const &ids) const;

#ifdef MARBLE
  Colloids const &colloids() const { return m_colloids; }
#endif
#ifdef SRD
  std::shared_ptr<Srd::Fluid> srd; // SRD: the SRD solvent (srd/Fluid.hpp), null if none
#endif
  Constraints &constraints() { return m_constraints; }
  /** Call after adding/removing walls: their types leave the main Verlet list. */
  void on_constraints_change();
  void set_periodic(int d, bool p);

  /** Forces beyond the main pair loop (colloid pairs, constraints); called
   * by compute_forces() after the pair loop. */
  void add_extra_forces(bool with_thermostat);
  /** The thermostat noise of this step for the force kernels (off without DPD
   * or when @p with_thermostat is false). */
  NoiseContext noise_context(bool with_thermostat) const;
  /** Throws Utils::RuntimeError if the scene cannot be integrated. */
  void check_scene_before_run() const;

  // --- force evaluation (used by the integrators and tests) ---
  void compute_forces(bool with_thermostat);
  /** RESPA: the fast forces (the conservative pair kernels of the colloid
   * pair list) at the current positions into m_f_fast (locals, then ghosts;
   * on several ranks the forces on the other ranks' colloid copies are added
   * to their owners, and stay in the copies' entries; every other ghost's is 0).
   * Does not touch the lists: they must be valid (run_md_respa). */
  void compute_fast_forces();
  /** The last compute_fast_forces' result (locals, in their order then; then the ghosts, as above). */
  std::vector<Utils::Vector3d> const &fast_forces() const { return m_f_fast; }
  bool forces_valid() const { return m_forces_valid; }
  double max_cutoff() const { return m_ia.max_cutoff(); }
  /** Large-range types of the pair list (cells/CellSystem.hpp): @p mode -1
   * automatic (InteractionTable::auto_range_split), 0 off, 1 the types
   * @p types. */
  void set_large_range_mode(int mode, std::vector<char> const &types) {
    m_large_range_mode = mode;
    m_large_range_types = types;
    m_cells.invalidate();
  }
  int large_range_mode() const { return m_large_range_mode; }
  std::vector<char> const &large_range_types_requested() const { return m_large_range_types; }
  /** The Shardlow sweep's buffers on several ranks (scratch). */
  ShardlowBuffers &shardlow_buffers() { return m_shardlow_buffers; }

  // --- load balance (system/balance.cpp; doc/parallel.md "Load balance") ---
  enum class BalanceBy { Particles = 0, Time = 1, Pairs = 2 };
  struct BalanceSettings {
    int every = 0;          ///< steps between automatic balances during run() (0: none)
    BalanceBy by = BalanceBy::Time;
    double damping = 1.;    ///< fraction of the way to the computed cuts, in (0, 1]
    double threshold = 0.05; ///< move only if max cost / mean cost exceeds 1 + threshold
  };
  struct BalanceResult {
    double imbalance = 1.; ///< max / mean of the ranks' cost before the call
    bool moved = false;    ///< whether the cuts were changed
  };
  /** Domain boundaries (cells/CellSystem.hpp set_domain_fractions): for each
   * axis node_grid[d] + 1 increasing positions from 0 to L, or empty (the
   * equal split). The caller checks them (the script interface). Identical on
   * every rank. Invalidates the lists (the next force computation migrates). */
  void set_domain_cuts(std::array<std::vector<double>, 3> const &cuts);
  /** Move the domain cuts along every split axis so that each slab of ranks
   * gets a share of the particles proportional to its measured speed
   * (particles per second of its own work since the last balance, the waits
   * inside MPI calls left out: @p by Time), an equal share (@p by
   * Particles), or an equal share of the particles weighted by 1 + their
   * listed pairs (@p by Pairs). Collective; on one rank nothing. */
  BalanceResult balance_domains(BalanceBy by, double damping, double threshold);
  void set_balance(BalanceSettings const &b) {
    m_balance = b;
    reset_balance_clock();
  }
  BalanceSettings const &balance_settings() const { return m_balance; }
  long n_balances() const { return m_n_balances; }
  /** Start the measurement of the ranks' work for the next balance. Not collective. */
  void reset_balance_clock();

private:
  /** compute_forces(@p with_thermostat), then a collective check that every
   * local force and torque is finite (a RuntimeError naming the particle and
   * the step; m_forces_valid false), tested inside compute_forces' last pass
   * over the locals (the external forces' addition), not in a pass of its own. */
  void compute_forces_checked(bool with_thermostat);
  /** compute_forces' body; @p first_bad (if given) gets the first local
   * whose force or torque is not finite (-1: none). */
  void compute_forces_pass(bool with_thermostat, int *first_bad);
  std::string non_finite_force_message(int i) const;
  int run_md(int n_steps); // VV, Shardlow, DPD-VV
  int run_md_respa(int n_steps); // VV, Shardlow with substeps > 1
  int run_sd(int n_steps);
  int run_bd(int n_steps); // integrators/brownian.cpp
  /** Throws Utils::RuntimeError if the thermostats do not fit the integrator. */
  void check_thermostats_before_run() const;
  void leave_bd() {
    if (m_integrator == IntegratorKind::BrownianDynamics)
      m_forces_valid = false; // BD forces exclude the thermostat
  }
  void set_pair_dpd_in_force_loop(bool on) {
    if (on != m_dpd_in_pair_loop)
      m_forces_valid = false;
    m_dpd_in_pair_loop = on;
  }
  void rebuild_if_needed();
  void kick(double half_dt);
  double kick_one(int i, double half_dt);
  /** Half kick + drift of one step, refused (nothing moved) if a particle
   * would move farther than the skin. @p kick_first: first do the previous
   * step's closing half kick (deferred by run_md) in the same sweep. */
  void drift_checked(bool kick_first = false);
  /** RESPA inner substep: v += kick_dt F_fast/m, x += h v (no rotation: the
   * fast forces are central), checked and refused as drift_checked (the
   * substeps before the refused one stay done). Returns whether the colloid
   * pair list must be rebuilt before fast forces at the new positions. */
  bool drift_checked_substep(double kick_dt, double h);
  /** v += kick_dt F_fast/m of the fast members (fixed components: v = 0;
   * the other locals' fixed components are zeroed by the kick that follows). */
  void kick_fast(double kick_dt);
  /** fn(i) for every local whose fast force may be non-zero: with colloids
   * the colloid pair list's members (every local colloid among them), on any
   * number of ranks; without, every local. */
  template <class Fn> void for_each_fast_member(Fn &&fn) const;
  /** RESPA's substeps with the particles outside the colloid pair list done
   * in two sweeps for all substeps (integrate.cpp); returns the number of
   * substeps done: all, or those up to a colloid list that went stale (the
   * caller does the rest with drift_checked_substep). */
  int respa_member_substeps(double h);
  /** The refusal of drift_checked: the collective message and throw. */
  [[noreturn]] void refuse_step(int bad, double bad_disp2, double step_len, int n_sub);
  /** Some auto-update accumulator updates at the current step. */
  bool accumulator_due() const;

  Communicator m_comm;
  BoxGeometry m_box;
  ParticleStore m_ps;
  CellSystem m_cells;
  InteractionTable m_ia;
  Thermostat m_thermo;
  IntegratorKind m_integrator = IntegratorKind::VelocityVerlet;
  SteepestDescentParams m_sd;
  int m_substeps = 1; // RESPA substeps of the fast forces (1: none)
  /** RESPA: compute_forces leaves the fast forces out (run_md_respa). */
  bool m_exclude_fast = false;
  std::vector<Utils::Vector3d> m_f_fast;
  long m_f_fast_rebuild = -1; // the list rebuild m_f_fast was zeroed at (compute_fast_forces)
  double m_time_step = -1.;
  double m_time = 0.;
  std::uint64_t m_step = 0;
  bool m_forces_valid = false;
  bool m_dpd_in_pair_loop = true;
  double m_cut_at_rebuild = -1.;
  /** Set by drift_checked: whether some local (on any rank: the vote is
   * already reduced) moved more than skin/2 since the last list build (-1:
   * not known); read and cleared by the next ensure_lists, which then skips
   * its own sweep and reduction. */
  int m_displacement_hint = -1;
  ListCheck m_list_check = ListCheck::Pairs;
  std::vector<float> m_disp2; // drift_checked: each local's squared displacement since the build
  bool m_disp2_fresh = false;  // m_disp2 holds the current positions' (set by drift_checked)
  std::vector<double> m_half_dt_over_m; // drift_checked's 0.5 dt / m per local
  std::vector<Utils::Vector3d> m_respa_end_pos; // respa_member_substeps: outside particles' positions after the substeps
  int m_large_range_mode = -1;
  std::vector<char> m_large_range_types;
  BalanceSettings m_balance;
  double m_balance_wall = 0.; // reset_balance_clock (from the constructor on): the wall clock and
  double m_balance_mpi = 0.;   // the wall time inside MPI calls then
  long m_n_balances = 0;
  /** run_md's hook: balance_domains when m_balance.every divides the step. */
  void maybe_balance() {
    if (m_balance.every > 0 && m_step % static_cast<std::uint64_t>(m_balance.every) == 0)
      balance_domains(m_balance.by, m_balance.damping, m_balance.threshold);
  }
  ShardlowBuffers m_shardlow_buffers;
  /** Configure the cell system's large-range types for a rebuild; returns
   * the range of the solvent grid (the small types' cutoff). Collective. */
  double configure_large_range(double cut);
  std::vector<std::shared_ptr<AutoUpdate>> m_auto_update;
  Constraints m_constraints;
  // Lees-Edwards: the protocol and axes (the current state lives in m_box)
  LeesEdwardsProtocol m_le_protocol;
  int m_le_direction = -1, m_le_normal = -1;
  void refresh_large_types();
#ifdef MARBLE
  Colloids m_colloids;
#endif
};

template <class Fn> void System::for_each_fast_member(Fn &&fn) const {
#ifdef MARBLE
  if (m_colloids.any()) { // (several ranks: every local colloid is a member)
    for (int i : m_colloids.pair_members())
      fn(i);
    return;
  }
#endif
  for (int i = 0; i < m_ps.n_local(); ++i)
    fn(i);
}

} // namespace Marble
