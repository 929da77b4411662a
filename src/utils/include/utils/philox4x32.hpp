#pragma once
// Philox4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy
// as 1, 2, 3", SC11), written from the paper's round function: the counter-based
// generator of the DPD pair noise (reference.md section 1). Only 32 x 32 -> 64
// bit products, so a compiler maps it onto SIMD lanes (one pair per lane,
// forces/pair_noise.cpp); the scalar form here is the definition and the one
// used where pairs come one at a time. Checked against the Random123
// known-answer vectors (testsuite/core/philox4x32_test.cpp).
#include <array>
#include <cstdint>

namespace Utils {

constexpr std::uint32_t kPhiloxM0 = 0xD2511F53u, kPhiloxM1 = 0xCD9E8D57u;
constexpr std::uint32_t kPhiloxW0 = 0x9E3779B9u, kPhiloxW1 = 0xBB67AE85u;

/** Philox4x32-10 of a 4-word counter and a 2-word key. */
constexpr std::array<std::uint32_t, 4> philox4x32_10(std::array<std::uint32_t, 4> c,
                                                     std::array<std::uint32_t, 2> k) {
  for (int rnd = 0; rnd < 10; ++rnd) {
    if (rnd) {
      k[0] += kPhiloxW0;
      k[1] += kPhiloxW1;
    }
    std::uint64_t const p0 = std::uint64_t{kPhiloxM0} * c[0];
    std::uint64_t const p1 = std::uint64_t{kPhiloxM1} * c[2];
    c = {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k[0], static_cast<std::uint32_t>(p1),
         static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k[1], static_cast<std::uint32_t>(p0)};
  }
  return c;
}

/** A 32-bit word to the uniform distribution on (-1/2, 1/2): (x + 1/2) 2^-32 - 1/2,
 * exact in double; mean 0, variance (1 - 2^-64)/12. Written as a signed
 * conversion of x ^ 2^31 (= x - 2^31) so that it vectorises. */
constexpr double u32_to_centered_uniform(std::uint32_t x) {
  return (static_cast<double>(static_cast<std::int32_t>(x ^ 0x80000000u)) + 0.5) *
         (1.0 / 4294967296.0);
}

/** The key words of a pair draw: (seed) as the Philox key; the counter is
 * (id_lo, id_hi, step low word, step high word + salt * 2^24), so salts stay
 * distinct for step < 2^56 and ids < 2^32. */
struct PairNoiseKey {
  std::array<std::uint32_t, 2> key;
  std::uint32_t c2, c3;
  constexpr PairNoiseKey(std::uint64_t seed, std::uint64_t salt, std::uint64_t step)
      : key{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
        c2{static_cast<std::uint32_t>(step)},
        c3{static_cast<std::uint32_t>(step >> 32) + (static_cast<std::uint32_t>(salt) << 24)} {}
};

/** The three uniforms of the unordered pair (id_lo < id_hi) at this key. */
constexpr std::array<double, 3> pair_uniform3(PairNoiseKey const &k, std::uint32_t id_lo,
                                              std::uint32_t id_hi) {
  auto const r = philox4x32_10({id_lo, id_hi, k.c2, k.c3}, k.key);
  return {u32_to_centered_uniform(r[0]), u32_to_centered_uniform(r[1]),
          u32_to_centered_uniform(r[2])};
}

} // namespace Utils
