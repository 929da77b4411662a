#pragma once
// Counter-based noise (reference.md section 1): Philox4x64-10 from Random123.
// The numbers depend only on (seed, salt, step, id_a, id_b): the same for a
// pair whatever cell, thread or MPI rank evaluates it.
#include "utils/Vector.hpp"

#include <Random123/philox.h>

#include <cmath>
#include <cstdint>

namespace Utils {

/** Salts: one independent stream per noise source. */
enum class RNGSalt : std::uint64_t {
  // lower case: the upper-case names are feature macros
  dpd = 1,
  marble = 2,
  tunable_slip_wall = 3,
  langevin = 4,     // Langevin thermostat (seed, step, particle id, 0 transl. / 1 rot.)
  srd_shift = 5,    // SRD grid shift (seed, collision)
  srd_axis = 6,     // SRD rotation axis (seed, collision, cell)
  srd_thermo = 7,   // SRD cell thermostat (seed, collision, cell, block)
  srd_at = 8,       // SRD Andersen velocities (seed, collision, particle id)
  srd_wall = 9,     // SRD stochastic boundary (seed, MD step, particle id)
  srd_init = 10,    // SRD initial positions/velocities and relocation
  brownian = 11,    // Brownian dynamics (seed, step, particle id, 0 pos / 1 vel / 2 omega)
  lubrication = 16, // suspensions (nonbonded/lubrication.hpp)
  surface_friction = 20, // stick colloids (nonbonded/surface_friction.hpp)
};

/** Four raw 64-bit words for counter @p step and keys. */
inline r123::Philox4x64::ctr_type philox_4x64(std::uint64_t seed, RNGSalt salt,
                                              std::uint64_t step, std::uint64_t id_a,
                                              std::uint64_t id_b) {
  using rng = r123::Philox4x64;
  rng::ctr_type c{{step, id_a, id_b, static_cast<std::uint64_t>(salt)}};
  rng::key_type k{{seed, 0x6d61726231ull /* "marb1" */}};
  return rng{}(c, k);
}

/** Map a 64-bit word to the uniform distribution on (-1/2, 1/2]. */
inline double u64_to_centered_uniform(std::uint64_t x) {
  // 53 random bits -> (0, 1], then shift.
  constexpr double two_m53 = 1.0 / 9007199254740992.0;
  return (static_cast<double>(x >> 11) + 1.0) * two_m53 - 0.5;
}

/** Three independent uniform numbers in (-1/2, 1/2]; variance 1/12 each. */
inline Vector3d noise_uniform(std::uint64_t seed, RNGSalt salt, std::uint64_t step,
                              std::uint64_t id_a, std::uint64_t id_b) {
  auto const r = philox_4x64(seed, salt, step, id_a, id_b);
  return {u64_to_centered_uniform(r[0]), u64_to_centered_uniform(r[1]),
          u64_to_centered_uniform(r[2])};
}

/** Three independent standard normal numbers (Box-Muller on three of the
 * four Philox words, the fourth word giving the second angle). */
inline Vector3d noise_gaussian(std::uint64_t seed, RNGSalt salt, std::uint64_t step,
                               std::uint64_t id_a, std::uint64_t id_b) {
  auto const r = philox_4x64(seed, salt, step, id_a, id_b);
  constexpr double two_pi = 6.283185307179586;
  auto open01 = [](std::uint64_t x) { return u64_to_centered_uniform(x) + 0.5; }; // (0, 1]
  double const r1 = std::sqrt(-2. * std::log(open01(r[0])));
  double const r2 = std::sqrt(-2. * std::log(open01(r[2])));
  double const p1 = two_pi * open01(r[1]), p2 = two_pi * open01(r[3]);
  return {r1 * std::cos(p1), r1 * std::sin(p1), r2 * std::cos(p2)};
}

} // namespace Utils
