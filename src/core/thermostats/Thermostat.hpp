#pragma once
// Thermostat state owned by the System: the DPD pair thermostat (feature DPD)
// and the single-particle Langevin and Brownian thermostats (no feature: always
// compiled in). Each has its own seed and step counter; the noise is keyed by
// (seed, salt, philox_counter, particle ids) (utils/noise.hpp).
#include "config/features.hpp"

#include <cstdint>

namespace Marble {

struct DPDThermostat {
  bool active = false;
  bool seeded = false;
  double kT = 0.;
  std::uint64_t seed = 0;
  /** Advances once per integration step, before the force evaluation. */
  std::uint64_t philox_counter = 0;
};

/** Langevin (thermostats/langevin.hpp) or Brownian dynamics thermostat:
 * friction gamma (translation) and gamma_rotation (rotation, ROTATION only);
 * a particle's own gamma / gamma_rot (>= 0) replaces the global value. */
struct SingleParticleThermostat {
  bool active = false;
  bool seeded = false;
  double kT = 0.;
  double gamma = 0.;
  double gamma_rotation = 0.;
  std::uint64_t seed = 0;
  /** Advances once per integration step, before the force evaluation. */
  std::uint64_t philox_counter = 0;
};

struct Thermostat {
#ifdef DPD
  DPDThermostat dpd;
#endif
  SingleParticleThermostat langevin;
  SingleParticleThermostat brownian;
  bool any_active() const {
#ifdef DPD
    if (dpd.active)
      return true;
#endif
    return langevin.active || brownian.active;
  }
};

} // namespace Marble
