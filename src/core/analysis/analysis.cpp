// Observables of the current state: energies, pressure tensor, momentum,
// centre of mass, distances.
#include "forces/pair_traversal.hpp"
#include "system/System.hpp"
#include "utils/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace Marble {

using Utils::Vector3d;

namespace {
} // namespace

Energies System::energies() {
  ensure_lists();
  Energies e;
  int const nt = std::max(1, m_ia.n_types());
  e.non_bonded_pairs.assign(static_cast<std::size_t>(nt) * nt, 0.);
  for (int i = 0; i < m_ps.n_local(); ++i) {
    e.kinetic += 0.5 * m_ps.get_mass(i) * folded_velocity(i).norm2(); // Lees-Edwards: frame of the folded position
#ifdef ROTATION
    if (m_ps.rotation[i])
      e.kinetic_rot += 0.5 * m_ps.rinertia[i] * m_ps.omega[i].norm2();
#endif
  }
  e.kinetic += e.kinetic_rot;
  for_each_pair(m_ps, m_cells.pairs(), m_ia, [&](int i, int j) {
    int const ti = m_ps.type[i], tj = m_ps.type[j];
    double const r2 = (m_ps.pos[i] - m_ps.pos[j]).norm2();
    double const u = conservative_pair(m_ia.get(ti, tj), std::sqrt(r2)).energy;
    e.non_bonded += u;
    e.non_bonded_pairs[std::min(ti, tj) * nt + std::max(ti, tj)] += u;
  });
  e.non_bonded += m_constraints.energy(m_ps, m_box, m_ia);
#ifdef MARBLE
  {
    std::vector<double> eu(e.non_bonded_pairs.size(), 0.);
    std::array<double, 9> vir{};
    m_colloids.conservative(m_ps, m_ia, eu, vir);
    for (std::size_t k = 0; k < eu.size(); ++k) {
      e.non_bonded_pairs[k] += eu[k];
      e.non_bonded += eu[k];
    }
  }
#endif
  if (m_comm.parallel()) { // every pair is on one rank: sum the parts
    double sc[3] = {e.kinetic, e.kinetic_rot, e.non_bonded};
    m_comm.sum_inplace(sc, 3);
    e.kinetic = sc[0], e.kinetic_rot = sc[1], e.non_bonded = sc[2];
    m_comm.sum_inplace(e.non_bonded_pairs.data(), static_cast<int>(e.non_bonded_pairs.size()));
  }
  return e;
}

PressureTensor System::pressure_tensor() {
  ensure_lists();
  PressureTensor p;
  double const V = m_box.volume();
  for (int i = 0; i < m_ps.n_local(); ++i) {
    double const m = m_ps.get_mass(i);
    Vector3d const v = folded_velocity(i); // Lees-Edwards: frame of the folded position
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        p.kinetic[3 * a + b] += m * v[a] * v[b] / V;
  }
  for_each_pair(m_ps, m_cells.pairs(), m_ia, [&](int i, int j) {
    Vector3d const d = m_ps.pos[i] - m_ps.pos[j];
    double const fac = conservative_pair(m_ia.get(m_ps.type[i], m_ps.type[j]), std::sqrt(d.norm2())).force_over_r;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        p.non_bonded[3 * a + b] += fac * d[a] * d[b] / V;
  });
#ifdef MARBLE
  {
    std::vector<double> eu(static_cast<std::size_t>(m_ia.n_types()) * m_ia.n_types(), 0.);
    std::array<double, 9> vir{};
    m_colloids.conservative(m_ps, m_ia, eu, vir);
    for (int k = 0; k < 9; ++k)
      p.non_bonded[k] += vir[k] / V;
  }
#endif
#ifdef MARBLE
  {
    std::array<double, 9> dpd{}, marble{};
    m_colloids.dissipative_virial(m_ps, m_ia, noise_context(true), dpd, marble);
    for (int k = 0; k < 9; ++k) {
      p.dpd[k] += dpd[k] / V;
      p.marble[k] += marble[k] / V;
    }
  }
#endif
  m_comm.sum_inplace(p.kinetic.data(), 9);
  m_comm.sum_inplace(p.non_bonded.data(), 9);
  m_comm.sum_inplace(p.dpd.data(), 9);
  m_comm.sum_inplace(p.marble.data(), 9);
#ifdef DPD
  auto const st = dpd_stress(); // main list, already summed over ranks
  for (int k = 0; k < 9; ++k)
    p.dpd[k] += st.friction[k] + st.noise[k];
#endif
  return p;
}

Vector3d System::linear_momentum() const {
  Vector3d m{};
  for (int i = 0; i < m_ps.n_local(); ++i)
    m += m_ps.get_mass(i) * m_ps.v[i];
  m_comm.sum_inplace(m.data(), 3);
  return m;
}

Vector3d System::angular_momentum_spin() const {
  Vector3d l{};
#ifdef ROTATION
  for (int i = 0; i < m_ps.n_local(); ++i)
    if (m_ps.rotation[i])
      l += m_ps.rinertia[i] * m_ps.omega[i];
#endif
  m_comm.sum_inplace(l.data(), 3);
  return l;
}

double System::total_mass() const {
  double m = 0.;
  for (int i = 0; i < m_ps.n_local(); ++i)
    m += m_ps.get_mass(i);
  return m_comm.sum(m);
}

Vector3d System::center_of_mass() const {
  Vector3d c{};
  double const M = total_mass();
  if (M <= 0.)
    return c;
  for (int i = 0; i < m_ps.n_local(); ++i)
    c += m_ps.get_mass(i) * m_box.unfolded(m_ps.pos[i], m_ps.image[i]);
  m_comm.sum_inplace(c.data(), 3);
  return c / M;
}

double System::min_dist(std::vector<int> const &t1, std::vector<int> const &t2) {
  auto in = [](std::vector<int> const &set, int t) {
    return set.empty() || std::find(set.begin(), set.end(), t) != set.end();
  };
  auto match = [&](int ta, int tb) { return (in(t1, ta) && in(t2, tb)) || (in(t1, tb) && in(t2, ta)); };
  // every rank looks at all particles (gathered)
  std::vector<Vector3d> pos(m_ps.pos.begin(), m_ps.pos.begin() + m_ps.n_local());
  std::vector<int> type(m_ps.type.begin(), m_ps.type.begin() + m_ps.n_local());
  if (m_comm.parallel()) {
    pos = m_comm.allgatherv(pos);
    type = m_comm.allgatherv(type);
  }
  int const n = static_cast<int>(pos.size());
  // O(N^2) over minimum images: exact for any distance and any box.
  double best2 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (!match(type[i], type[j]))
        continue;
      best2 = std::min(best2, m_box.get_mi_vector(pos[i], pos[j]).norm2());
    }
  return std::sqrt(best2);
}

} // namespace Marble
