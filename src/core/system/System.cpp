#include "system/System.hpp"
#include "nonbonded/surface_friction_apply.hpp"
#include "utils/errors.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace Marble {

System::System(Utils::Vector3d const &box_l) {
  m_cells.set_comm(&m_comm);
  set_box_l(box_l);
  reset_balance_clock(); // (balance_domains by time measures from here at first)
}

void System::set_box_l(Utils::Vector3d const &l) {
  m_box.set_length(l);
  on_particle_change();
}

void System::set_time_step(double dt) {
  m_time_step = dt;
  update_thermostat_prefactors();
  on_change();
}

void System::set_skin(double s) {
  m_cells.set_skin(s);
  on_particle_change();
}

void System::add_particle(ParticleProperties p) {
  m_ps.clear_ghosts();
  m_box.fold(p.pos, p.image);
  m_ia.ensure_type(p.type);
  // every rank is told about every particle; the one whose domain holds it keeps it
  if (m_cells.owner_rank(p.pos, m_box) == m_comm.rank())
    m_ps.add(p);
  on_particle_change();
}

void System::remove_particle(int pid) {
  m_ps.clear_ghosts();
  if (m_ps.exists(pid))
    m_ps.remove(pid);
  on_particle_change();
}

void System::clear_particles() {
  m_ps.clear();
  m_cells.invalidate();
  on_particle_change();
}

void System::on_interactions_change() {
  refresh_large_types();
  update_thermostat_prefactors();
  on_particle_change(); // the cutoff may have changed
}

void System::update_thermostat_prefactors() {
#ifdef DPD
  m_ia.refresh_prefactors(m_thermo.dpd.kT, m_time_step);
#endif
}

void System::refresh_large_types() {
  int const n = m_ia.n_types();
  auto large = m_constraints.wall_types(n);
#ifdef MARBLE
  m_colloids.set_types(m_ia.colloid_types());
  auto const &col = m_colloids.colloid_types();
  for (int t = 0; t < n && t < static_cast<int>(col.size()); ++t)
    large[t] = large[t] || col[t];
#endif
  m_ia.set_large_types(large);
#ifdef MARBLE
  m_cells.set_replicated_types(m_colloids.colloid_types());
#endif
}

void System::on_constraints_change() {
  for (auto const &w : m_constraints.walls())
    m_ia.ensure_type(w.type);
  refresh_large_types();
  update_thermostat_prefactors();
  on_particle_change();
}

void System::set_lees_edwards(int shear_direction, int shear_plane_normal, LeesEdwardsProtocol const &protocol) {
  m_le_protocol = protocol;
  bool const on = protocol.kind != LeesEdwardsProtocol::Off;
  m_le_direction = on ? shear_direction : -1;
  m_le_normal = on ? shear_plane_normal : -1;
  update_lees_edwards();
  on_particle_change(); // new images: rebuild the lists
}

void System::update_lees_edwards() {
  LeesEdwardsBC le;
  if (m_le_protocol.kind != LeesEdwardsProtocol::Off) {
    le.shear_direction = m_le_direction;
    le.shear_plane_normal = m_le_normal;
    le.pos_offset = m_le_protocol.pos_offset(m_time);
    le.shear_velocity = m_le_protocol.velocity(m_time);
  }
  m_box.set_lees_edwards(le);
  m_cells.set_lees_edwards(le);
}

void System::set_periodic(int d, bool p) {
  m_box.set_periodic(d, p);
  on_particle_change();
}

void System::add_extra_forces([[maybe_unused]] bool with_thermostat) {
#ifdef TRANS_DPD
  // the rotational pair kernel (stick friction) on the main list's pairs: its
  // own pass (spins and torques), explicit unless Shardlow updates it
  if (with_thermostat && m_thermo.dpd.active && !shardlow_sweep_active() &&
      m_ia.any_active<SurfaceFriction>())
    add_surface_friction_forces(m_ps, m_cells, m_ia, noise_context(true), m_comm.parallel());
#endif
#ifdef MARBLE
  if (m_colloids.any()) {
    // RESPA's slow forces leave the colloid pairs' conservative kernels out;
    // under Shardlow its sweep updates the marble coupling (integrators/shardlow.cpp)
    m_colloids.add_forces(m_ps, m_ia, noise_context(with_thermostat), !m_exclude_fast,
                          /*with_marble=*/!shardlow_sweep_active());
  }
#endif
  if (!m_constraints.empty())
    m_constraints.add_forces(m_ps, m_box, m_ia, noise_context(with_thermostat), m_step);
}

NoiseContext System::noise_context([[maybe_unused]] bool with_thermostat) const {
  NoiseContext n;
#ifdef DPD
  n.on = with_thermostat && m_thermo.dpd.active;
  n.seed = m_thermo.dpd.seed;
  n.counter = m_thermo.dpd.philox_counter;
#endif
  return n;
}

void System::check_scene_before_run() const {
  std::string msg;
#ifdef MARBLE
  msg = m_colloids.check_rotation(m_ps, m_ia);
  if (!msg.empty())
    msg = "cannot integrate: " + msg;
#endif
  m_comm.throw_if_any(msg);
  if (m_box.lees_edwards().active()) {
    std::string why;
    int const n = m_le_normal, sd = m_le_direction;
#ifdef SRD
    if (srd)
      why = "an SRD solvent is not supported (its streaming and cell grid ignore the offset)";
#endif
#ifdef MARBLE
    if (why.empty() && m_colloids.any())
      why = "marble colloids are not supported (their neighbour search uses plain periodic images)";
#endif
    if (why.empty() && m_integrator == IntegratorKind::BrownianDynamics)
      why = "Brownian dynamics is not supported; use a velocity Verlet integrator";
    if (why.empty() && (!m_box.periodic(n) || !m_box.periodic(sd)))
      why = "the shear direction and the shear-plane normal must be periodic axes";
    if (!why.empty())
      throw Utils::RuntimeError("cannot integrate with Lees-Edwards boundary conditions: " + why +
                                " (doc/lees-edwards.md)");
  }
  if (m_substeps > 1) {
    std::string why;
    if (m_integrator != IntegratorKind::VelocityVerlet && m_integrator != IntegratorKind::Shardlow)
      why = "only velocity Verlet and Shardlow have them";
    else if (m_le_protocol.kind != LeesEdwardsProtocol::Off)
      why = "Lees-Edwards boundary conditions are not supported";
#ifdef SRD
    else if (srd)
      why = "an SRD solvent is not supported";
#endif
    if (!why.empty())
      throw Utils::RuntimeError("cannot integrate with substeps = " + std::to_string(m_substeps) +
                                " (RESPA for the colloid pairs' conservative forces): " + why +
                                "; use substeps=1 (doc/speed-accuracy.md)");
  }
  // (Shardlow on several ranks: the domain width its rounds need is checked
  // when the lists are built, run_md / run_md_respa)
}

void System::ensure_lists() {
  double cut = m_ia.max_cutoff();
#ifdef MARBLE
  // The colloid search needs a cell grid even if the solvent has no pair interaction.
  if (cut <= 0. && m_colloids.any())
    cut = 1.;
#endif
  // the drift sweep of run_md has already compared the positions with those
  // of the last build (same test, same positions) and voted over the ranks
  int const hint = m_displacement_hint;
  m_displacement_hint = -1;
  bool stale = !m_cells.valid() || cut != m_cut_at_rebuild;
  if (!stale && (hint >= 0 ? hint != 0 : m_cells.displacement_exceeds_half_skin(m_ps))) {
    // past half a skin: the pair test may keep the list (doc/benchmarks.md)
    float const *const disp2 = hint >= 0 && m_disp2_fresh ? m_disp2.data() : nullptr;
    stale = !pair_test_applies() || m_cells.pairs_may_be_missing(m_ps, disp2, colloid_reach());
  }
  m_disp2_fresh = false;
  if (stale) {
    // the inner list pays where lists live ~2 steps (Shardlow at its large dt; doc/benchmarks.md, session 15)
    m_cells.set_inner_list(m_integrator == IntegratorKind::Shardlow);
    m_cells.rebuild(m_ps, m_box, configure_large_range(cut));
    m_cut_at_rebuild = cut;
#ifdef MARBLE
    m_colloids.rebuild(m_ps, m_box, m_cells, m_ia);
#endif
  } else {
    m_cells.update_ghosts(m_ps);
  }
}

double System::colloid_reach() const {
#ifdef MARBLE
  if (!m_colloids.any())
    return -1.;
  // the colloid pair list's own test (SubstepTally::colloid_list_stale): the
  // largest displacement of a local colloid since the build, exact
  double d2 = 0.;
  for (int i = 0; i < m_ps.n_local(); ++i)
    if (m_colloids.is_colloid_type(m_ps.type[i]))
      d2 = std::max(d2, (m_ps.pos[i] - m_ps.pos_at_rebuild[i]).norm2());
  return std::sqrt(d2);
#else
  return -1.;
#endif
}

bool System::pair_test_applies() const {
  if (m_list_check != ListCheck::Pairs ||
      (m_integrator != IntegratorKind::VelocityVerlet && m_integrator != IntegratorKind::DPDVV &&
       m_integrator != IntegratorKind::Shardlow) ||
      m_box.lees_edwards().active())
    return false;
#ifdef SRD
  if (srd)
    return false;
#endif
  return m_cells.pair_test_applies();
}

double System::configure_large_range(double cut) {
  InteractionTable::RangeSplit split;
  if (m_large_range_mode < 0) {
    // (a scene of one range scale has no candidate: no split, and no pass
    // over the locals to count their types; the interaction table is the
    // same on every rank, so every rank skips the reduction alike)
    auto cand = m_ia.range_split_candidates();
    if (std::find(cand.begin(), cand.end(), char(1)) != cand.end()) {
      int const nt = m_ia.n_types();
      std::vector<double> count(static_cast<std::size_t>(nt), 0.);
      for (int i = 0; i < m_ps.n_local(); ++i)
        if (m_ps.type[i] >= 0 && m_ps.type[i] < nt)
          count[static_cast<std::size_t>(m_ps.type[i])] += 1.;
      if (nt > 0)
        m_comm.sum_inplace(count.data(), nt);
      split = m_ia.auto_range_split(std::move(cand), count);
    }
  } else if (m_large_range_mode > 0) {
    split = m_ia.range_split(m_large_range_types);
    if (!(split.cut_small > 0.))
      split = InteractionTable::RangeSplit{}; // nothing left for the solvent grid: no split
  }
  bool const any = std::find(split.large.begin(), split.large.end(), char(1)) != split.large.end();
  if (!any) {
    m_cells.set_large_range({}, 0., 0.);
    return cut;
  }
  m_cells.set_large_range(split.large, split.cut_ll, split.cut_ls);
  return split.cut_small;
}

void System::rebuild_lists_at_saved_positions() {
  int const n = m_ps.n_local();
  std::vector<Utils::Vector3d> current(m_ps.pos.begin(), m_ps.pos.begin() + n);
  std::vector<int> ids(m_ps.id.begin(), m_ps.id.begin() + n);
  for (int i = 0; i < n; ++i)
    m_ps.pos[i] = m_ps.pos_at_rebuild[i];
  m_cells.invalidate();
  ensure_lists();
  // the rebuild keeps the (cell-sorted) order; put the current positions back by id
  std::vector<Utils::Vector3d> by_id(static_cast<std::size_t>(m_ps.max_id() + 1));
  for (int i = 0; i < n; ++i)
    by_id[static_cast<std::size_t>(ids[i])] = current[i];
  for (int i = 0; i < m_ps.n_local(); ++i)
    m_ps.pos[i] = by_id[static_cast<std::size_t>(m_ps.id[i])];
  m_cells.forget_inner(); // (built at other positions)
  m_cells.update_ghosts(m_ps);
}

Utils::Vector3d System::distance_vec(int pid1, int pid2) const {
  auto const a = folded_position(pid1), b = folded_position(pid2);
  return m_box.get_mi_vector(b, a);
}

Utils::Vector3d System::folded_position(int pid) const {
  double buf[4] = {0., 0., 0., 0.};
  int const i = m_ps.index_of(pid);
  if (i >= 0) {
    for (int d = 0; d < 3; ++d)
      buf[d] = m_ps.pos[i][d];
    buf[3] = 1.;
  }
  m_comm.sum_inplace(buf, 4);
  if (buf[3] != 1.)
    throw std::out_of_range("particle " + std::to_string(pid) + " does not exist");
  return {buf[0], buf[1], buf[2]};
}

std::optional<int> System::first_missing_particle(std::vector<int> const &ids) const {
  std::vector<double> found(ids.size(), 0.);
  for (std::size_t k = 0; k < ids.size(); ++k)
    found[k] = m_ps.exists(ids[k]) ? 1. : 0.;
  m_comm.sum_inplace(found.data(), static_cast<int>(found.size()));
  for (std::size_t k = 0; k < ids.size(); ++k)
    if (found[k] != 1.)
      return ids[k];
  return std::nullopt;
}

int System::n_particles() const {
  return static_cast<int>(m_comm.sum(static_cast<long long>(m_ps.n_local())));
}

} // namespace Marble
