// Philox4x32-10 for a block of pairs, one pair per SIMD lane (structure of
// arrays). Two code paths, chosen once at run time by the CPU (doc/benchmarks.md):
// - AVX2 intrinsics: 8 pairs per register, 4 registers interleaved (32 pairs)
//   to hide the multiply latency; a 32 x 32 -> 64-bit product is two
//   vpmuludq (even and odd lanes) and two blends;
// - portable C++ (the baseline x86-64 or any other CPU): the lanes of a chunk
//   as four word arrays, which the compiler vectorises with what it has (SSE2).
// Integer arithmetic and one exact int -> double conversion: every path gives
// the same bits as the scalar Utils::pair_uniform3 (testsuite/core/philox4x32_test.cpp).
#include "forces/pair_noise.hpp"
#include "utils/cpu.hpp"

#include <algorithm>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define MARBLE_PAIR_NOISE_AVX2 1
#include <immintrin.h>
#endif

namespace Marble {

namespace {
constexpr int kLanes = 32; // pairs per chunk (a multiple of every vector width)
constexpr int kPairNoiseChunk = 128;

void pair_noise_portable(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                         std::uint32_t const *hi, double const *sign, double *x, double *y, double *z) {
  using std::uint32_t;
  using std::uint64_t;
  for (int s0 = 0; s0 < n; s0 += kLanes) {
    int const m = std::min(kLanes, n - s0);
    alignas(64) uint32_t c0[kLanes], c1[kLanes], c2[kLanes], c3[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      c0[l] = l < m ? lo[s0 + l] : 0u;
      c1[l] = l < m ? hi[s0 + l] : 0u;
      c2[l] = k.c2;
      c3[l] = k.c3;
    }
    uint32_t k0 = k.key[0], k1 = k.key[1];
    for (int rnd = 0; rnd < 10; ++rnd) {
      for (int l = 0; l < kLanes; ++l) {
        uint64_t const p0 = uint64_t{Utils::kPhiloxM0} * c0[l];
        uint64_t const p1 = uint64_t{Utils::kPhiloxM1} * c2[l];
        uint32_t const n0 = static_cast<uint32_t>(p1 >> 32) ^ c1[l] ^ k0;
        uint32_t const n2 = static_cast<uint32_t>(p0 >> 32) ^ c3[l] ^ k1;
        c0[l] = n0;
        c1[l] = static_cast<uint32_t>(p1);
        c2[l] = n2;
        c3[l] = static_cast<uint32_t>(p0);
      }
      k0 += Utils::kPhiloxW0;
      k1 += Utils::kPhiloxW1;
    }
    if (m == kLanes) {
      for (int l = 0; l < kLanes; ++l) {
        double const sg = sign[s0 + l];
        x[s0 + l] = sg * Utils::u32_to_centered_uniform(c0[l]);
        y[s0 + l] = sg * Utils::u32_to_centered_uniform(c1[l]);
        z[s0 + l] = sg * Utils::u32_to_centered_uniform(c2[l]);
      }
    } else {
      for (int l = 0; l < m; ++l) {
        double const sg = sign[s0 + l];
        x[s0 + l] = sg * Utils::u32_to_centered_uniform(c0[l]);
        y[s0 + l] = sg * Utils::u32_to_centered_uniform(c1[l]);
        z[s0 + l] = sg * Utils::u32_to_centered_uniform(c2[l]);
      }
    }
  }
}

#ifdef MARBLE_PAIR_NOISE_AVX2
__attribute__((target("avx2"))) static inline void out8(__m256i c, double *dst, __m256d sg0, __m256d sg1) {
  __m256i const f = _mm256_xor_si256(c, _mm256_set1_epi32(static_cast<int>(0x80000000u)));
  __m256d const half = _mm256_set1_pd(0.5), scale = _mm256_set1_pd(1.0 / 4294967296.0);
  __m256d const a = _mm256_cvtepi32_pd(_mm256_castsi256_si128(f));
  __m256d const b = _mm256_cvtepi32_pd(_mm256_extracti128_si256(f, 1));
  _mm256_storeu_pd(dst, _mm256_mul_pd(sg0, _mm256_mul_pd(_mm256_add_pd(a, half), scale)));
  _mm256_storeu_pd(dst + 4, _mm256_mul_pd(sg1, _mm256_mul_pd(_mm256_add_pd(b, half), scale)));
}
template <int G>
__attribute__((target("avx2"), always_inline)) static inline void groups(Utils::PairNoiseKey const &k, int s0, std::uint32_t const *lo,
                          std::uint32_t const *hi, double const *sign, double *x, double *y, double *z) {
  __m256i const m0 = _mm256_set1_epi64x(Utils::kPhiloxM0), m1 = _mm256_set1_epi64x(Utils::kPhiloxM1);
  __m256i c0[G], c1[G], c2[G], c3[G];
#pragma GCC unroll 4
  for (int g = 0; g < G; ++g) {
    c0[g] = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(lo + s0 + 8 * g));
    c1[g] = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(hi + s0 + 8 * g));
    c2[g] = _mm256_set1_epi32(static_cast<int>(k.c2));
    c3[g] = _mm256_set1_epi32(static_cast<int>(k.c3));
  }
  std::uint32_t k0 = k.key[0], k1 = k.key[1];
#pragma GCC unroll 10
  for (int rnd = 0; rnd < 10; ++rnd) {
    __m256i const kk0 = _mm256_set1_epi32(static_cast<int>(k0)), kk1 = _mm256_set1_epi32(static_cast<int>(k1));
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g) {
      __m256i const p0e = _mm256_mul_epu32(c0[g], m0), p0o = _mm256_mul_epu32(_mm256_srli_epi64(c0[g], 32), m0);
      __m256i const p1e = _mm256_mul_epu32(c2[g], m1), p1o = _mm256_mul_epu32(_mm256_srli_epi64(c2[g], 32), m1);
      __m256i const lo0 = _mm256_blend_epi32(p0e, _mm256_slli_epi64(p0o, 32), 0xAA);
      __m256i const hi0 = _mm256_blend_epi32(_mm256_srli_epi64(p0e, 32), p0o, 0xAA);
      __m256i const lo1 = _mm256_blend_epi32(p1e, _mm256_slli_epi64(p1o, 32), 0xAA);
      __m256i const hi1 = _mm256_blend_epi32(_mm256_srli_epi64(p1e, 32), p1o, 0xAA);
      c0[g] = _mm256_xor_si256(_mm256_xor_si256(hi1, c1[g]), kk0);
      c1[g] = lo1;
      c2[g] = _mm256_xor_si256(_mm256_xor_si256(hi0, c3[g]), kk1);
      c3[g] = lo0;
    }
    k0 += Utils::kPhiloxW0;
    k1 += Utils::kPhiloxW1;
  }
#pragma GCC unroll 4
  for (int g = 0; g < G; ++g) {
    int const o = s0 + 8 * g;
    __m256d const sg0 = _mm256_loadu_pd(sign + o), sg1 = _mm256_loadu_pd(sign + o + 4);
    out8(c0[g], x + o, sg0, sg1);
    out8(c1[g], y + o, sg0, sg1);
    out8(c2[g], z + o, sg0, sg1);
  }
}

__attribute__((target("avx2")))
void pair_noise_avx2(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                          std::uint32_t const *hi, double const *sign, double *x, double *y, double *z) {
  int s0 = 0;
  for (; s0 + 8 * 4 <= n; s0 += 8 * 4)
    groups<4>(k, s0, lo, hi, sign, x, y, z);
  for (; s0 + 8 <= n; s0 += 8)
    groups<1>(k, s0, lo, hi, sign, x, y, z);
  for (; s0 < n; ++s0) {
    auto const u = Utils::pair_uniform3(k, lo[s0], hi[s0]);
    x[s0] = sign[s0] * u[0], y[s0] = sign[s0] * u[1], z[s0] = sign[s0] * u[2];
  }
}

/** groups<G> with AVX-512 VL instructions on the same 256-bit registers
 * (no 512-bit ones: on Intel those lower the core's clock, and a 16-lane
 * form measured ~5 % slower on the whole step): the high and low words of
 * the even and odd products recombined by one masked dword shuffle each
 * instead of a shift and a blend, and the two xors of a word by one
 * ternary-logic op. The same integer results, so the same bits. */
template <int G>
__attribute__((target("avx512f,avx512vl,avx2"), always_inline)) static inline void
groups_vl(Utils::PairNoiseKey const &k, int s0, std::uint32_t const *lo, std::uint32_t const *hi, double const *sign,
          double *x, double *y, double *z) {
  __m256i const m0 = _mm256_set1_epi64x(Utils::kPhiloxM0), m1 = _mm256_set1_epi64x(Utils::kPhiloxM1);
  __m256i c0[G], c1[G], c2[G], c3[G];
#pragma GCC unroll 4
  for (int g = 0; g < G; ++g) {
    c0[g] = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(lo + s0 + 8 * g));
    c1[g] = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(hi + s0 + 8 * g));
    c2[g] = _mm256_set1_epi32(static_cast<int>(k.c2));
    c3[g] = _mm256_set1_epi32(static_cast<int>(k.c3));
  }
  std::uint32_t k0 = k.key[0], k1 = k.key[1];
  constexpr __mmask8 odd = 0xAA, even = 0x55;
#pragma GCC unroll 10
  for (int rnd = 0; rnd < 10; ++rnd) {
    __m256i const kk0 = _mm256_set1_epi32(static_cast<int>(k0)), kk1 = _mm256_set1_epi32(static_cast<int>(k1));
#pragma GCC unroll 4
    for (int g = 0; g < G; ++g) {
      __m256i const p0e = _mm256_mul_epu32(c0[g], m0), p0o = _mm256_mul_epu32(_mm256_srli_epi64(c0[g], 32), m0);
      __m256i const p1e = _mm256_mul_epu32(c2[g], m1), p1o = _mm256_mul_epu32(_mm256_srli_epi64(c2[g], 32), m1);
      // low words: even lanes from p_e (in place), odd lanes the low dword of p_o;
      // high words: odd lanes from p_o (in place), even lanes the high dword of p_e
      __m256i const lo0 = _mm256_mask_shuffle_epi32(p0e, odd, p0o, _MM_PERM_CCAA);
      __m256i const hi0 = _mm256_mask_shuffle_epi32(p0o, even, p0e, _MM_PERM_DDBB);
      __m256i const lo1 = _mm256_mask_shuffle_epi32(p1e, odd, p1o, _MM_PERM_CCAA);
      __m256i const hi1 = _mm256_mask_shuffle_epi32(p1o, even, p1e, _MM_PERM_DDBB);
      c0[g] = _mm256_ternarylogic_epi32(hi1, c1[g], kk0, 0x96); // hi1 ^ c1 ^ kk0
      c1[g] = lo1;
      c2[g] = _mm256_ternarylogic_epi32(hi0, c3[g], kk1, 0x96);
      c3[g] = lo0;
    }
    k0 += Utils::kPhiloxW0;
    k1 += Utils::kPhiloxW1;
  }
#pragma GCC unroll 4
  for (int g = 0; g < G; ++g) {
    int const o = s0 + 8 * g;
    __m256d const sg0 = _mm256_loadu_pd(sign + o), sg1 = _mm256_loadu_pd(sign + o + 4);
    out8(c0[g], x + o, sg0, sg1);
    out8(c1[g], y + o, sg0, sg1);
    out8(c2[g], z + o, sg0, sg1);
  }
}

/** pair_noise_avx2 with groups_vl (AVX-512 F + VL CPUs). */
__attribute__((target("avx512f,avx512vl,avx2")))
void pair_noise_avx512(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo, std::uint32_t const *hi,
                       double const *sign, double *x, double *y, double *z) {
  int s0 = 0;
  for (; s0 + 8 * 4 <= n; s0 += 8 * 4)
    groups_vl<4>(k, s0, lo, hi, sign, x, y, z);
  for (; s0 + 8 <= n; s0 += 8)
    groups_vl<1>(k, s0, lo, hi, sign, x, y, z);
  for (; s0 < n; ++s0) {
    auto const u = Utils::pair_uniform3(k, lo[s0], hi[s0]);
    x[s0] = sign[s0] * u[0], y[s0] = sign[s0] * u[1], z[s0] = sign[s0] * u[2];
  }
}

bool have_avx512() {
  static bool const has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                          __builtin_cpu_supports("avx2");
  return has;
}
#endif

using NoiseFn = PairNoiseFn;

bool have_avx2() {
#ifdef MARBLE_PAIR_NOISE_AVX2
  return Utils::cpu_has_avx2();
#else
  return false;
#endif
}

NoiseFn noise_fn() {
#ifdef MARBLE_PAIR_NOISE_AVX2
  if (have_avx512())
    return &pair_noise_avx512;
  if (have_avx2())
    return &pair_noise_avx2;
#endif
  return &pair_noise_portable;
}

NoiseFn const g_noise = noise_fn();

} // namespace

void pair_noise_block_soa(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                          std::uint32_t const *hi, double const *sign, double *x, double *y, double *z) {
  (g_noise ? g_noise : noise_fn())(k, n, lo, hi, sign, x, y, z);
}

void pair_noise_block(Utils::PairNoiseKey const &k, int n, std::uint32_t const *lo,
                      std::uint32_t const *hi, double const *sign, Utils::Vector3d *xi) {
  alignas(64) double x[kPairNoiseChunk], y[kPairNoiseChunk], z[kPairNoiseChunk];
  for (int s0 = 0; s0 < n; s0 += kPairNoiseChunk) {
    int const m = std::min(kPairNoiseChunk, n - s0);
    pair_noise_block_soa(k, m, lo + s0, hi + s0, sign + s0, x, y, z);
    for (int l = 0; l < m; ++l)
      xi[s0 + l] = {x[l], y[l], z[l]};
  }
}

char const *pair_noise_isa() {
#ifdef MARBLE_PAIR_NOISE_AVX2
  if (have_avx512())
    return "avx512";
#endif
  return have_avx2() ? "avx2" : "default";
}

std::vector<std::pair<char const *, PairNoiseFn>> pair_noise_paths() {
  std::vector<std::pair<char const *, PairNoiseFn>> out{{"default", &pair_noise_portable}};
#ifdef MARBLE_PAIR_NOISE_AVX2
  if (have_avx2())
    out.emplace_back("avx2", &pair_noise_avx2);
  if (have_avx512())
    out.emplace_back("avx512", &pair_noise_avx512);
#endif
  return out;
}

} // namespace Marble
