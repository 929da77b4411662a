#pragma once
// Counter-based random numbers for SRD (Philox, utils/noise.hpp).
#include "utils/Vector.hpp"
#include "utils/noise.hpp"

#include <array>
#include <cmath>
#include <cstdint>

namespace Marble::Srd {

/** Uniform on (0, 1]. */
inline double unit_open0(std::uint64_t x) { return Utils::u64_to_centered_uniform(x) + 0.5; }

/** Four standard normal numbers (Box-Muller on the four Philox words). */
inline std::array<double, 4> gauss4(std::uint64_t seed, Utils::RNGSalt salt, std::uint64_t c,
                                    std::uint64_t a, std::uint64_t b) {
  auto const r = Utils::philox_4x64(seed, salt, c, a, b);
  constexpr double two_pi = 6.283185307179586;
  double const r1 = std::sqrt(-2. * std::log(unit_open0(r[0])));
  double const r2 = std::sqrt(-2. * std::log(unit_open0(r[2])));
  double const p1 = two_pi * unit_open0(r[1]), p2 = two_pi * unit_open0(r[3]);
  return {r1 * std::cos(p1), r1 * std::sin(p1), r2 * std::cos(p2), r2 * std::sin(p2)};
}

/** Unit vector uniform on the sphere (z uniform in [-1, 1], phi uniform). */
inline Utils::Vector3d random_axis(std::uint64_t seed, std::uint64_t c, std::uint64_t cell) {
  auto const r = Utils::philox_4x64(seed, Utils::RNGSalt::srd_axis, c, cell, 0);
  double const z = 2. * Utils::u64_to_centered_uniform(r[0]);
  double const phi = 6.283185307179586 * Utils::u64_to_centered_uniform(r[1]);
  double const s = std::sqrt(std::max(0., 1. - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

} // namespace Marble::Srd
