#pragma once
// Counter-based random numbers for SRD (Philox, utils/noise.hpp).
#include "utils/Vector.hpp"
#include "utils/noise.hpp"
#include "utils/philox4x32.hpp"

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

/** A uniform number in (-1/2, 1/2) from 52 bits of two 32-bit words (the
 * top 20 bits of @p a, all of @p b): ((x + 1/2) 2^-52 - 1/2, x < 2^52), exact
 * integer-to-double conversions only, so it vectorises and gives the same
 * bits in every code path. */
inline double u52_centered(std::uint32_t a, std::uint32_t b) {
  double const hi = static_cast<double>(static_cast<std::int32_t>(a >> 12));
  double const lo = static_cast<double>(static_cast<std::int32_t>(b ^ 0x80000000u)) + 2147483648.;
  return ((hi * 4294967296. + lo) + 0.5) * 2.220446049250313e-16 - 0.5;
}

/** cos and sin of 2 pi u, u in [-1/2, 1/2]: reduced to quarter turns
 * (r in [-pi/4, pi/4]) and Taylor series to r^17 / r^18 (truncation below
 * 1e-19), basic IEEE operations only (no libm): the same bits scalar and
 * vectorised, one vector lane per cell. */
inline void cos_sin_2pi(double u, double &co, double &si) {
  constexpr double kM = 6755399441055744.; // 1.5 2^52: round to nearest
  double const t = 4. * u;
  double const q = (t + kM) - kM;
  double const r = (t - q) * 1.5707963267948966;
  double const r2 = r * r;
  double const sr =
      r + r * r2 *
              (-1. / 6. +
               r2 * (1. / 120. +
                     r2 * (-1. / 5040. +
                           r2 * (1. / 362880. +
                                 r2 * (-1. / 39916800. +
                                       r2 * (1. / 6227020800. +
                                             r2 * (-1. / 1307674368000. + r2 * (1. / 355687428096000.))))))));
  double const cr =
      1. + r2 * (-0.5 +
                 r2 * (1. / 24. +
                       r2 * (-1. / 720. +
                             r2 * (1. / 40320. +
                                   r2 * (-1. / 3628800. +
                                         r2 * (1. / 479001600. +
                                               r2 * (-1. / 87178291200. +
                                                     r2 * (1. / 20922789888000. +
                                                           r2 * (-1. / 6402373705728000.)))))))));
  int const k = static_cast<int>(q) & 3; // quarter turns mod 4
  co = k == 0 ? cr : (k == 1 ? -sr : (k == 2 ? -cr : sr));
  si = k == 0 ? sr : (k == 1 ? cr : (k == 2 ? -sr : -cr));
}

/** Rotation axis of collision cell @p cell at collision @p c: a unit vector
 * uniform on the sphere (z uniform in (-1, 1), phi uniform), from one
 * Philox4x32-10 draw keyed by (seed, collision, global cell index, salt
 * srd_axis) (utils/philox4x32.hpp; 52 bits each for z and phi). Only
 * 32 x 32 bit products and basic IEEE operations: collide.cpp evaluates it
 * for a block of cells in SIMD lanes, with the same bits as this scalar form. */
/* The two parts: z and (cos phi, sin phi) (no libm: vectorises), then
 * x, y = sqrt(1 - z^2) (cos phi, sin phi) (|z| < 1). */
inline void cell_axis_z_phi(Utils::PairNoiseKey const &key, std::uint32_t cell, double &co, double &si,
                            double &z) {
  auto const r = Utils::philox4x32_10({cell, 0u, key.c2, key.c3}, key.key);
  z = 2. * u52_centered(r[0], r[1]);
  cos_sin_2pi(u52_centered(r[2], r[3]), co, si);
}
inline void cell_axis_xy(double &x, double &y, double z) {
  double const s = std::sqrt(1. - z * z);
  x *= s, y *= s;
}
inline void cell_axis(Utils::PairNoiseKey const &key, std::uint32_t cell, double &x, double &y, double &z) {
  cell_axis_z_phi(key, cell, x, y, z);
  cell_axis_xy(x, y, z);
}
inline Utils::PairNoiseKey axis_key(std::uint64_t seed, std::uint64_t c) {
  return {seed, static_cast<std::uint64_t>(Utils::RNGSalt::srd_axis), c};
}

} // namespace Marble::Srd
