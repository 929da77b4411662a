#include "system/System.hpp"
#include "utils/errors.hpp"

#include <cmath>

namespace Marble {

System::System(Utils::Vector3d const &box_l) { set_box_l(box_l); }

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
  m_ps.add(p);
  on_particle_change();
}

void System::remove_particle(int pid) {
  m_ps.clear_ghosts();
  m_ps.remove(pid);
  on_particle_change();
}

void System::clear_particles() {
  m_ps.clear();
  on_particle_change();
}

void System::set_interaction(int i, int j, IAParams const &p) {
  m_ia.set(i, j, p);
  update_thermostat_prefactors();
  on_particle_change(); // the cutoff may have changed
}

void System::update_thermostat_prefactors() {
#ifdef DPD
  double const kT = m_thermo.dpd.kT;
  double const dt = m_time_step;
  auto pref = [&](DPDWeight &w) {
    w.pref_noise = (dt > 0. && kT > 0. && w.gamma > 0.) ? std::sqrt(24. * kT * w.gamma / dt) : 0.;
  };
  for (auto &p : m_ia.all()) {
    pref(p.dpd.radial);
#ifdef TRANS_DPD
    pref(p.dpd.trans);
#endif
  }
#endif
}

void System::ensure_lists() {
  double const cut = m_ia.max_cutoff();
  if (!m_cells.valid() || cut != m_cut_at_rebuild || m_cells.displacement_exceeds_half_skin(m_ps)) {
    m_cells.rebuild(m_ps, m_box, cut);
    m_cut_at_rebuild = cut;
  } else {
    m_cells.update_ghosts(m_ps);
  }
}

Utils::Vector3d System::distance_vec(int pid1, int pid2) const {
  int const i = m_ps.index_of(pid1), j = m_ps.index_of(pid2);
  return m_box.get_mi_vector(m_ps.pos[j], m_ps.pos[i]);
}

} // namespace Marble
