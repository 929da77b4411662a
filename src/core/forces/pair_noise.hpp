#pragma once
// The pair noise of a whole block of pairs at once (forces/pair_noise.cpp):
// Philox4x32-10 (utils/philox4x32.hpp) with one pair per SIMD lane.
#include "utils/Vector.hpp"
#include "utils/philox4x32.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace Marble {

/** xi[s] = sign[s] * (three uniforms of the pair (lo[s], hi[s]) at key @p k) for s < n;
 * the same numbers as Utils::pair_uniform3, bit for bit, whatever SIMD path runs. */
void pair_noise_block(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                      std::uint32_t const *hi, double const *sign, Utils::Vector3d *xi);

/** The same as structure of arrays: (x, y, z)[s] = sign[s] * the uniforms of pair s. */
void pair_noise_block_soa(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                          std::uint32_t const *hi, double const *sign, double *x, double *y, double *z);

/** Which code path pair_noise_block takes on this CPU ("avx2" or "default"). */
char const *pair_noise_isa();

using PairNoiseFn = void (*)(Utils::PairNoiseKey const &, int, std::uint32_t const *, std::uint32_t const *,
                             double const *, double *, double *, double *);
/** Every code path of pair_noise_block_soa this CPU can run, by name (tests, bench). */
std::vector<std::pair<char const *, PairNoiseFn>> pair_noise_paths();

} // namespace Marble
