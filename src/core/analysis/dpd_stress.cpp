// DPD contribution to the pressure tensor (doc/dpd.md, "Stress"):
//   P^DPD_ab = (1/V) sum_{pairs i<j} d_a F_b,   d = r_i - r_j,  F = DPD force on i,
// the same (virial, pressure-sign) convention as the conservative part of
// System::pressure_tensor(). It uses the current velocities and the noise of
// the current Philox counter, i.e. exactly the DPD force of the last force
// evaluation when the velocities are those it saw. Friction (-gamma w^2 v) and
// noise (s w xi) are returned separately; their sum is the total.
#include "system/System.hpp"
#include "utils/noise.hpp"

#include <cmath>

namespace Marble {

DPDStress System::dpd_stress() {
  DPDStress out;
#ifdef DPD
  auto const &th = m_thermo.dpd;
  if (!th.active)
    return out;
  ensure_lists();
  double const V = m_box.volume();
  Utils::Vector3d const zero{};
  for (auto const &pr : m_cells.pairs()) {
    int const i = pr[0], j = pr[1];
    IAParams const &p = m_ia.get(m_ps.type[i], m_ps.type[j]);
    if (!p.dpd.active)
      continue;
    Utils::Vector3d const d = m_ps.pos[i] - m_ps.pos[j];
    double const r2 = d.norm2();
    if (r2 >= p.max_cut2 || r2 == 0.)
      continue;
    double const r = std::sqrt(r2);
    // Same noise and id-order sign as the force loop (forces/forces.cpp).
    int const a = m_ps.id[i], b = m_ps.id[j];
    auto const lo = static_cast<std::uint64_t>(a < b ? a : b);
    auto const hi = static_cast<std::uint64_t>(a < b ? b : a);
    Utils::Vector3d xi =
        Utils::noise_uniform(th.seed, Utils::RNGSalt::dpd, th.philox_counter, lo, hi);
    if (a > b)
      xi = -xi;
    double const mfac = dpd_mass_factor(m_ps.get_mass(i), m_ps.get_mass(j));
    Utils::Vector3d const f_fric = dpd_pair_force(p.dpd, d, r, m_ps.v[i] - m_ps.v[j], zero, mfac);
    Utils::Vector3d const f_noise = dpd_pair_force(p.dpd, d, r, zero, xi, mfac);
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y) {
        out.friction[3 * x + y] += d[x] * f_fric[y] / V;
        out.noise[3 * x + y] += d[x] * f_noise[y] / V;
      }
  }
  m_comm.sum_inplace(out.friction.data(), 9);
  m_comm.sum_inplace(out.noise.data(), 9);
#endif
  return out;
}

} // namespace Marble
