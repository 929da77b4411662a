// Dissipative contribution to the pressure tensor (doc/dpd.md, "Stress"):
//   P^DPD_ab = (1/V) sum_{pairs i<j} d_a F_b,   d = r_i - r_j,  F = force on i of
// every pair-dissipative kernel (the DPD pair thermostat, squeeze lubrication)
// and of the stick friction (surface_friction),
// the same (virial, pressure-sign) convention as the conservative part of
// System::pressure_tensor(). It uses the current velocities and the noise of
// the current Philox counter, i.e. exactly the DPD force of the last force
// evaluation when the velocities are those it saw. Friction (-gamma w^2 v) and
// noise (s w xi) are returned separately; their sum is the total.
#include "system/System.hpp"
#include "forces/pair_traversal.hpp"
#include "nonbonded/surface_friction_apply.hpp"

#include <cmath>

namespace Marble {

DPDStress System::dpd_stress() {
  DPDStress out;
#ifdef DPD
  if (!m_thermo.dpd.active)
    return out;
  ensure_lists();
  double const V = m_box.volume();
  NoiseContext const noise = noise_context(true);
  Utils::Vector3d const zero{};
  // every pair-dissipative kernel of the pair loop (DPD, lubrication, ...),
  // in registry order, with the noise the force loop draws for it
  for_each_pair(m_ps, m_cells.pairs(), m_ia, [&](int i, int j) {
    IAParams const &ip = m_ia.get(m_ps.type[i], m_ps.type[j]);
    Utils::Vector3d const d = m_ps.pos[i] - m_ps.pos[j];
    double const r2 = d.norm2();
    if (r2 == 0.)
      return;
    double const r = std::sqrt(r2);
    for_each_kernel<PairLoopKernels>([&]<class K>() {
      if constexpr (K::role == KernelRole::pair_dissipative) {
        auto const &p = ip.template get<K>();
        if (!p.active)
          return;
        // the noise of the force loop (forces/pair_traversal.hpp)
        Utils::Vector3d const xi = pair_noise(noise, K::salt, m_ps.id[i], m_ps.id[j]);
        double const mfac = pair_mass_factor(m_ps, i, j);
        Utils::Vector3d const f_fric = K::force(p, d, r, m_ps.v[i] - m_ps.v[j], zero, mfac);
        Utils::Vector3d const f_noise = K::force(p, d, r, zero, xi, mfac);
        for (int x = 0; x < 3; ++x)
          for (int y = 0; y < 3; ++y) {
            out.friction[3 * x + y] += d[x] * f_fric[y] / V;
            out.noise[3 * x + y] += d[x] * f_noise[y] / V;
          }
      }
    });
  });
#ifdef TRANS_DPD
  // the stick friction (nonbonded/surface_friction.hpp), with the same convention
  if (m_ia.any_active<SurfaceFriction>())
    surface_friction_virial(m_ps, m_cells, m_ia, noise, V, m_comm.parallel(), out.friction, out.noise);
#endif
  m_comm.sum_inplace(out.friction.data(), 9);
  m_comm.sum_inplace(out.noise.data(), 9);
#endif
  return out;
}

} // namespace Marble
