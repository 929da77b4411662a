#pragma once
// Thermostat state owned by the System. Only the DPD pair thermostat exists
// for now; its noise is keyed by (seed, salt, philox_counter, ids).
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

struct Thermostat {
#ifdef DPD
  DPDThermostat dpd;
#endif
  bool any_active() const {
#ifdef DPD
    return dpd.active;
#else
    return false;
#endif
  }
};

} // namespace Marble
