// Brownian dynamics (overdamped Langevin, Ermak-McCammon with a diagonal,
// position-independent mobility 1/gamma; doc/thermostats.md). One step:
//   x(t + dt) = x(t) + F(t) dt / gamma + sqrt(2 kT dt / gamma) N(0, 1)
//   v         = F(t) / gamma + sqrt(kT / m) N'(0, 1)        (as ESPResSo: drift
//               velocity plus a Maxwell velocity, for kinetic observables)
//   omega     = tau(t) / gamma_rot + sqrt(kT / I) N''(0, 1)  (ROTATION, rotating
//               particles; Marble has no orientation state to propagate)
// N, N', N'' Gaussian, keyed by (seed, salt brownian, step counter, particle id,
// 0 / 1 / 2). Forces exclude every thermostat (the Brownian thermostat is the
// only one allowed with this integrator: System::check_thermostats_before_run).
#include "system/System.hpp"
#include "thermostats/langevin.hpp"
#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <cmath>
#include <string>

namespace Marble {

using Utils::Vector3d;

int System::run_bd(int n_steps) {
  if (m_time_step <= 0.)
    throw Utils::RuntimeError("time_step is not set: set system.time_step > 0 before running");
  auto &th = m_thermo.brownian;
  double const dt = m_time_step;
  // every particle needs gamma > 0 (the mobility is 1 / gamma)
  {
    std::string msg;
    for (int i = 0; i < m_ps.n_local() && msg.empty(); ++i) {
      bool bad = !(particle_gamma(m_ps.gamma[i], th.gamma) > 0.);
#ifdef ROTATION
      bad = bad || (m_ps.rotation[i] && !(particle_gamma(m_ps.gamma_rot[i], th.gamma_rotation) > 0.));
#endif
      if (bad)
        msg = "cannot integrate: Brownian dynamics needs gamma > 0 (and gamma_rotation > 0 for "
              "rotating particles), particle " + std::to_string(m_ps.id[i]) +
              " has 0: set thermostat.set_brownian(gamma=...) or the particle's gamma/gamma_rot";
    }
    m_comm.throw_if_any(msg);
  }
  if (!m_forces_valid || n_steps == 0)
    compute_forces_checked(false);
  double const max2 = m_cells.skin() * m_cells.skin();
  for (int s = 0; s < n_steps; ++s) {
    std::uint64_t const c = th.philox_counter;
    auto dx_of = [&](int i) {
      double const g = particle_gamma(m_ps.gamma[i], th.gamma);
      auto const xi = Utils::noise_gaussian(th.seed, Utils::RNGSalt::brownian, c,
                                            static_cast<std::uint64_t>(m_ps.id[i]), 0);
      Vector3d dx = (dt / g) * m_ps.f[i] + std::sqrt(2. * th.kT * dt / g) * xi;
      for (int d = 0; d < 3; ++d)
        if (m_ps.is_fixed(i, d))
          dx[d] = 0.;
      return dx;
    };
    // Check first (on every rank), then move: a refused step changes nothing.
    // Only the force-driven drift F dt / gamma is limited (by the skin: a
    // larger one means a time step too large for the forces); the random part
    // has Gaussian tails and may exceed the skin: the Verlet list is rebuilt
    // before the next force evaluation anyway (displacement > skin / 2).
    int bad = -1;
    double bad_disp2 = 0.;
    for (int i = 0; i < m_ps.n_local(); ++i) {
      double const g = particle_gamma(m_ps.gamma[i], th.gamma);
      double const d2 = ((dt / g) * m_ps.f[i]).norm2();
      if (!(d2 <= max2) || !Utils::isfinite(dx_of(i))) {
        bad = i;
        bad_disp2 = d2;
        break;
      }
    }
    if (m_comm.any(bad >= 0)) {
      m_forces_valid = false;
      m_cells.invalidate();
      std::string msg;
      if (bad >= 0)
        msg = "integration stopped at step " + std::to_string(m_step + 1) + ": particle " +
              std::to_string(m_ps.id[bad]) + " would drift " + Utils::to_str(std::sqrt(bad_disp2)) +
              " (F dt / gamma) in one Brownian step, more than the skin (" +
              Utils::to_str(m_cells.skin()) + ") or non-finite: likely cause: time step too large "
              "for the forces, or overlapping particles; reduce time_step or remove overlaps "
              "with integrator.set_steepest_descent()";
      m_comm.throw_if_any(msg);
    }
    for (int i = 0; i < m_ps.n_local(); ++i) {
      auto const pid = static_cast<std::uint64_t>(m_ps.id[i]);
      double const g = particle_gamma(m_ps.gamma[i], th.gamma);
      Vector3d const dx = dx_of(i);
      m_ps.pos[i] += dx;
      auto const xv = Utils::noise_gaussian(th.seed, Utils::RNGSalt::brownian, c, pid, 1);
      Vector3d v = (1. / g) * m_ps.f[i] + std::sqrt(th.kT / m_ps.get_mass(i)) * xv;
      for (int d = 0; d < 3; ++d)
        if (m_ps.is_fixed(i, d))
          v[d] = 0.;
      m_ps.v[i] = v;
#ifdef ROTATION
      if (m_ps.rotation[i]) {
        double const gr = particle_gamma(m_ps.gamma_rot[i], th.gamma_rotation);
        auto const xo = Utils::noise_gaussian(th.seed, Utils::RNGSalt::brownian, c, pid, 2);
        m_ps.omega[i] = (1. / gr) * m_ps.torque[i] + std::sqrt(th.kT / m_ps.rinertia[i]) * xo;
      }
#endif
    }
    ++m_step;
    m_time += dt;
    ++th.philox_counter;
#ifdef DPD
    ++m_thermo.dpd.philox_counter; // keeps the DPD stream in step with the step counter
#endif
    ++m_thermo.langevin.philox_counter;
    compute_forces_checked(false); // (m_forces_valid false if it throws)
    for (auto const &acc : m_auto_update)
      if (acc->delta_N > 0 && m_step % static_cast<std::uint64_t>(acc->delta_N) == 0)
        acc->update(*this);
  }
  return n_steps;
}

} // namespace Marble
