// The force driver: one pass over the Verlet list, with the set of kernels
// (LJ / hat / DPD) fixed at compile time for each instantiation of the loop,
// so a scene pays only for the kernels some type pair uses.
#include "system/System.hpp"
#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <cmath>

namespace Marble {

using Utils::Vector3d;

namespace {

struct ThermoContext {
  bool on = false;
  std::uint64_t seed = 0, counter = 0;
};

template <bool LJ_ON, bool HAT_ON, bool DPD_ON>
void pair_loop(ParticleStore &ps, std::vector<std::array<int, 2>> const &pairs,
               InteractionTable const &ia, ThermoContext const &th) {
  (void)th;
  auto *const pos = ps.pos.data();
  auto *const vel = ps.v.data();
  auto *const frc = ps.f.data();
  auto const *const typ = ps.type.data();
  [[maybe_unused]] auto const *const pid = ps.id.data();
  for (auto const &pr : pairs) {
    int const i = pr[0], j = pr[1];
    IAParams const &p = ia.get(typ[i], typ[j]);
    Vector3d const d = pos[i] - pos[j];
    double const r2 = d.norm2();
    if (r2 >= p.max_cut2)
      continue;
    double const r = std::sqrt(r2);
    double fac = 0.;
#ifdef LENNARD_JONES
    if constexpr (LJ_ON)
      if (p.lj.active)
        fac += p.lj.force_over_r(r);
#endif
#ifdef HAT
    if constexpr (HAT_ON)
      if (p.hat.active)
        fac += p.hat.force_over_r(r);
#endif
    Vector3d force = fac * d;
#ifdef DPD
    if constexpr (DPD_ON) {
      if (p.dpd.active && r > 0.) {
        // Noise of the unordered pair; the sign follows id order so F_j = -F_i.
        int const a = pid[i], b = pid[j];
        Vector3d xi = a < b ? Utils::noise_uniform(th.seed, Utils::RNGSalt::dpd, th.counter,
                                                   static_cast<std::uint64_t>(a),
                                                   static_cast<std::uint64_t>(b))
                            : -Utils::noise_uniform(th.seed, Utils::RNGSalt::dpd, th.counter,
                                                    static_cast<std::uint64_t>(b),
                                                    static_cast<std::uint64_t>(a));
        double mfac = 1.;
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
        mfac = dpd_mass_factor(ps.mass[i], ps.mass[j]);
#endif
        force += dpd_pair_force(p.dpd, d, r, vel[i] - vel[j], xi, mfac);
      }
    }
#endif
    frc[i] += force;
    frc[j] -= force;
  }
}

using LoopFn = void (*)(ParticleStore &, std::vector<std::array<int, 2>> const &,
                        InteractionTable const &, ThermoContext const &);

template <int Mask> constexpr LoopFn loop_for() {
  return &pair_loop<(Mask & 1) != 0, (Mask & 2) != 0, (Mask & 4) != 0>;
}

constexpr LoopFn loops[8] = {loop_for<0>(), loop_for<1>(), loop_for<2>(), loop_for<3>(),
                             loop_for<4>(), loop_for<5>(), loop_for<6>(), loop_for<7>()};

} // namespace

void System::compute_forces(bool with_thermostat) {
  ensure_lists();
  for (auto &f : m_ps.f)
    f = {};
#ifdef ROTATION
  for (auto &t : m_ps.torque)
    t = {};
#endif
  KernelMask const k = m_ia.kernels();
  ThermoContext th;
#ifdef DPD
  th.on = with_thermostat && m_thermo.dpd.active;
  th.seed = m_thermo.dpd.seed;
  th.counter = m_thermo.dpd.philox_counter;
#else
  (void)with_thermostat;
#endif
  int const mask = (k.lj ? 1 : 0) | (k.hat ? 2 : 0) | ((k.dpd && th.on) ? 4 : 0);
  loops[mask](m_ps, m_cells.pairs(), m_ia, th);
  m_cells.reduce_ghost_forces(m_ps);
#ifdef EXTERNAL_FORCE
  for (int i = 0; i < m_ps.n_local(); ++i) {
    m_ps.f[i] += m_ps.ext_force[i];
#ifdef ROTATION
    m_ps.torque[i] += m_ps.ext_torque[i];
#endif
  }
#endif
  m_forces_valid = true;
}

void System::check_forces_finite() const {
  for (int i = 0; i < m_ps.n_local(); ++i) {
    bool bad = !Utils::isfinite(m_ps.f[i]);
#ifdef ROTATION
    bad = bad || !Utils::isfinite(m_ps.torque[i]);
#endif
    if (bad)
      throw Utils::RuntimeError(
          "non-finite force on particle " + std::to_string(m_ps.id[i]) + " at step " +
          std::to_string(m_step) +
          ": likely cause: overlapping particles (a singular potential at r -> 0) or a "
          "time step too large for the interactions; remove overlaps with "
          "integrator.set_steepest_descent() or reduce time_step");
  }
}

} // namespace Marble
