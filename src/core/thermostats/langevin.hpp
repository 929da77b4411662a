#pragma once
// Langevin thermostat (single-particle friction + noise), added to the forces
// at every force evaluation of an MD step (doc/thermostats.md):
//   F_i   += -gamma_i v_i + sqrt(24 kT gamma_i / dt) xi_i,
//   tau_i += -gamma_rot_i omega_i + sqrt(24 kT gamma_rot_i / dt) xi'_i  (ROTATION, rotating particles)
// xi uniform on (-1/2, 1/2] per component (variance 1/12, so the noise has the
// variance 2 kT gamma / dt of the continuum form), keyed by (seed, salt
// langevin, step counter, particle id, 0 translation / 1 rotation): the same
// numbers on any number of ranks and in any loop order. In velocity Verlet the
// force is evaluated after the drift, so the friction acts on the half-step
// velocity v(t + dt/2); for a free particle the on-step velocities v(t) then
// have exactly <m v^2> = kT for every gamma dt / m < 2 (the half-step ones are
// hot by 1 / (1 - gamma dt / (2 m))).
#include "particles/ParticleStore.hpp"
#include "thermostats/Thermostat.hpp"
#include "utils/noise.hpp"

#include <cmath>
#include <string>

namespace Marble {

/** The particle's friction: its own value if set (>= 0), else the global one. */
inline double particle_gamma(double own, double global) { return own >= 0. ? own : global; }

/** Add the Langevin friction and noise to the forces (and torques) of the local particles. */
inline void add_langevin_forces(ParticleStore &ps, SingleParticleThermostat const &th, double dt) {
  double const pref = std::sqrt(24. * th.kT / dt);
  for (int i = 0; i < ps.n_local(); ++i) {
    auto const pid = static_cast<std::uint64_t>(ps.id[i]);
    double const g = particle_gamma(ps.gamma[i], th.gamma);
    if (g > 0.) {
      auto const xi = Utils::noise_uniform(th.seed, Utils::RNGSalt::langevin, th.philox_counter, pid, 0);
      ps.f[i] += (-g) * ps.v[i] + (pref * std::sqrt(g)) * xi;
    }
#ifdef ROTATION
    if (ps.rotation[i]) {
      double const gr = particle_gamma(ps.gamma_rot[i], th.gamma_rotation);
      if (gr > 0.) {
        auto const xi = Utils::noise_uniform(th.seed, Utils::RNGSalt::langevin, th.philox_counter, pid, 1);
        ps.torque[i] += (-gr) * ps.omega[i] + (pref * std::sqrt(gr)) * xi;
      }
    }
#endif
  }
}

/** Largest gamma dt / m (and gamma_rot dt / I) of the local particles; the
 * explicit friction of velocity Verlet is unstable at >= 2. @p who gets the
 * particle id. */
inline double langevin_max_friction(ParticleStore const &ps, SingleParticleThermostat const &th,
                                    double dt, int &who) {
  double worst = 0.;
  who = -1;
  for (int i = 0; i < ps.n_local(); ++i) {
    double a = particle_gamma(ps.gamma[i], th.gamma) * dt / ps.get_mass(i);
#ifdef ROTATION
    if (ps.rotation[i])
      a = std::max(a, particle_gamma(ps.gamma_rot[i], th.gamma_rotation) * dt / ps.rinertia[i]);
#endif
    if (a > worst) {
      worst = a;
      who = ps.id[i];
    }
  }
  return worst;
}

} // namespace Marble
