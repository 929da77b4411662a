// exp(x) for x <= 0: the OU factors of the Shardlow pair sweep, 4 lanes at a
// time with AVX2 (chosen at run time), else one at a time; both paths perform
// the same IEEE operations in the same order (no FMA: this file is compiled
// with -ffp-contract=off, and the AVX2 path is target("avx2") only), so they
// give the same bits (testsuite/core/ou_exp_test.cpp).
//
// The method is the classical one (W. J. Cody and W. Waite, "Software Manual
// for the Elementary Functions", 1980; J.-M. Muller, "Elementary Functions:
// Algorithms and Implementation", ch. on range reduction):
// 1. range reduction x = k ln2 + r, k = round(x / ln2), |r| <= ln2/2 (plus
//    round-off): k by adding and subtracting 1.5 * 2^52 (round to nearest),
//    r = (x - k ln2_hi) - k ln2_lo with ln2 split in two (Cody-Waite):
//    ln2_hi has 42 significant bits, so k ln2_hi is exact for |k| < 2^11, and
//    x - k ln2_hi is exact (Sterbenz: x and k ln2_hi within a factor 2);
// 2. exp(r) = 1 + r + r^2 Q(r), Q a degree-10 polynomial fitted to
//    (e^r - 1 - r) / r^2 on |r| <= ln2/2 (Chebyshev interpolation, 50 digits,
//    coefficients rounded to double; rel. error of 1 + r + r^2 Q < 0.01 ulp);
//    the sum is 1 + hi done exactly as s + e (Fast2Sum, |hi| < 1), then
//    s + (e + (r^2 Q - lo)): one rounding of size 0.5 ulp dominates;
// 3. the scaling by 2^k in two steps through the exponent bits,
//    (p 2^(k+64)) 2^-64: the first product is exact (a normal number for
//    every k >= -1077), the second rounds only where the result is subnormal
//    (x < -708.4), and is 0 below x = -745.13 (x is clamped to [-746, 0]
//    first, which also takes -inf to 0).
// Measured error against expl (ou_exp_test, 1.6 million arguments): at most
// 0.68 ulp for normal results, 0.77 ulp for subnormal ones (two roundings).
#include "integrators/ou_exp.hpp"
#include "utils/cpu.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#define MARBLE_OU_EXP_AVX2 1
#include <immintrin.h>
#endif

namespace Marble {

namespace {

constexpr double kLog2e = 0x1.71547652b82fep+0; // 1 / ln2
constexpr double kShift = 0x1.8p52;             // 1.5 * 2^52: x + kShift - kShift rounds x to an integer
constexpr double kLn2Hi = 0x1.62e42fefa3800p-1; // ln2 to 42 bits
constexpr double kLn2Lo = 0x1.ef35793c76730p-45; // ln2 - kLn2Hi
constexpr double kLow = -746.;                   // below ln(2^-1075): the result rounds to 0
constexpr double kTwoM64 = 0x1p-64;
constexpr std::uint64_t kBias = 1023 + 64; // 2^(k+64): exponent field k + 64 + 1023
// Q(r) ~ (e^r - 1 - r) / r^2, |r| <= ln2/2: Q = c0 + c1 r + ... + c10 r^10
constexpr double c0 = 0x1.0000000000000p-1;
constexpr double c1 = 0x1.5555555555557p-3;
constexpr double c2 = 0x1.5555555555556p-5;
constexpr double c3 = 0x1.11111111100dfp-7;
constexpr double c4 = 0x1.6c16c16c162d6p-10;
constexpr double c5 = 0x1.a01a01abe6327p-13;
constexpr double c6 = 0x1.a01a01a6d7833p-16;
constexpr double c7 = 0x1.71de0237479e4p-19;
constexpr double c8 = 0x1.27e4db67abc75p-22;
constexpr double c9 = 0x1.af4ddda32bea9p-26;
constexpr double c10 = 0x1.1f72fc848c527p-29;

inline std::uint64_t bits_of(double d) {
  std::uint64_t i;
  std::memcpy(&i, &d, sizeof i);
  return i;
}
inline double from_bits(std::uint64_t i) {
  double d;
  std::memcpy(&d, &i, sizeof d);
  return d;
}

/** One lane: the operations of exp4_avx2 in the same order. */
inline double exp_neg_one(double x) {
  double xc = x > kLow ? x : kLow; // _mm256_max_pd(x, kLow): NaN -> kLow (fixed below)
  xc = xc < 0. ? xc : 0.;          // _mm256_min_pd(xc, 0)
  double const t = xc * kLog2e + kShift;
  double const kd = t - kShift; // k, exactly
  double const hi = xc - kd * kLn2Hi; // exact
  double const lo = kd * kLn2Lo;
  double const r = hi - lo;
  double q = c10;
  q = q * r + c9;
  q = q * r + c8;
  q = q * r + c7;
  q = q * r + c6;
  q = q * r + c5;
  q = q * r + c4;
  q = q * r + c3;
  q = q * r + c2;
  q = q * r + c1;
  q = q * r + c0;
  q = (r * r) * q;
  double const s = 1. + hi;
  double const e = (1. - s) + hi; // 1 + hi = s + e exactly
  double const p = s + (e + (q - lo));
  double const scale = from_bits((bits_of(t) + kBias) << 52); // 2^(k+64)
  double const y = (p * scale) * kTwoM64;
  return x != x ? x : y;
}

void exp_neg_scalar(double const *x, double *out, int n) {
  for (int l = 0; l < n; ++l)
    out[l] = exp_neg_one(x[l]);
}

#ifdef MARBLE_OU_EXP_AVX2
__attribute__((target("avx2"), always_inline)) inline __m256d exp4_avx2(__m256d x) {
  __m256d xc = _mm256_max_pd(x, _mm256_set1_pd(kLow));
  xc = _mm256_min_pd(xc, _mm256_setzero_pd());
  __m256d const shift = _mm256_set1_pd(kShift);
  __m256d const t = _mm256_add_pd(_mm256_mul_pd(xc, _mm256_set1_pd(kLog2e)), shift);
  __m256d const kd = _mm256_sub_pd(t, shift);
  __m256d const hi = _mm256_sub_pd(xc, _mm256_mul_pd(kd, _mm256_set1_pd(kLn2Hi)));
  __m256d const lo = _mm256_mul_pd(kd, _mm256_set1_pd(kLn2Lo));
  __m256d const r = _mm256_sub_pd(hi, lo);
  __m256d q = _mm256_set1_pd(c10);
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c9));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c8));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c7));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c6));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c5));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c4));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c3));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c2));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c1));
  q = _mm256_add_pd(_mm256_mul_pd(q, r), _mm256_set1_pd(c0));
  q = _mm256_mul_pd(_mm256_mul_pd(r, r), q);
  __m256d const one = _mm256_set1_pd(1.);
  __m256d const s = _mm256_add_pd(one, hi);
  __m256d const e = _mm256_add_pd(_mm256_sub_pd(one, s), hi);
  __m256d const p = _mm256_add_pd(s, _mm256_add_pd(e, _mm256_sub_pd(q, lo)));
  __m256i const sb =
      _mm256_slli_epi64(_mm256_add_epi64(_mm256_castpd_si256(t), _mm256_set1_epi64x(static_cast<long long>(kBias))), 52);
  __m256d const y = _mm256_mul_pd(_mm256_mul_pd(p, _mm256_castsi256_pd(sb)), _mm256_set1_pd(kTwoM64));
  return _mm256_blendv_pd(y, x, _mm256_cmp_pd(x, x, _CMP_UNORD_Q));
}

__attribute__((target("avx2"))) void exp_neg_avx2(double const *x, double *out, int n) {
  int l = 0;
  for (; l + 4 <= n; l += 4)
    _mm256_storeu_pd(out + l, exp4_avx2(_mm256_loadu_pd(x + l)));
  for (; l < n; ++l)
    out[l] = exp_neg_one(x[l]);
}
#endif

void ou_amplitude_scalar(double const *a, double const *kT_mu, int n, double *sd, double *am1) {
  for (int l = 0; l < n; ++l) {
    double const al = a[l];
    sd[l] = std::sqrt(12. * kT_mu[l] * (1. - al * al));
    am1[l] = al - 1.;
  }
}

#ifdef MARBLE_OU_EXP_AVX2
__attribute__((target("avx2"))) void ou_amplitude_avx2(double const *a, double const *kT_mu, int n, double *sd,
                                                        double *am1) {
  int l = 0;
  __m256d const one = _mm256_set1_pd(1.), twelve = _mm256_set1_pd(12.);
  for (; l + 4 <= n; l += 4) {
    __m256d const al = _mm256_loadu_pd(a + l);
    __m256d const v = _mm256_mul_pd(_mm256_mul_pd(twelve, _mm256_loadu_pd(kT_mu + l)),
                                    _mm256_sub_pd(one, _mm256_mul_pd(al, al)));
    _mm256_storeu_pd(sd + l, _mm256_sqrt_pd(v));
    _mm256_storeu_pd(am1 + l, _mm256_sub_pd(al, one));
  }
  ou_amplitude_scalar(a + l, kT_mu + l, n - l, sd + l, am1 + l);
}
#endif

} // namespace

void ou_amplitude_block(double const *a, double const *kT_mu, int n, double *sd, double *am1) {
#ifdef MARBLE_OU_EXP_AVX2
  if (Utils::cpu_has_avx2()) {
    ou_amplitude_avx2(a, kT_mu, n, sd, am1);
    return;
  }
#endif
  ou_amplitude_scalar(a, kT_mu, n, sd, am1);
}

std::vector<std::pair<char const *, OUAmplitudeBlockFn>> ou_amplitude_paths() {
  std::vector<std::pair<char const *, OUAmplitudeBlockFn>> out{{"scalar", &ou_amplitude_scalar}};
#ifdef MARBLE_OU_EXP_AVX2
  if (Utils::cpu_has_avx2())
    out.emplace_back("avx2", &ou_amplitude_avx2);
#endif
  return out;
}

double exp_neg(double x) { return exp_neg_one(x); }

void exp_neg_block(double const *x, double *out, int n) {
#ifdef MARBLE_OU_EXP_AVX2
  if (Utils::cpu_has_avx2()) {
    exp_neg_avx2(x, out, n);
    return;
  }
#endif
  exp_neg_scalar(x, out, n);
}

std::vector<std::pair<char const *, ExpNegBlockFn>> exp_neg_paths() {
  std::vector<std::pair<char const *, ExpNegBlockFn>> out{{"scalar", &exp_neg_scalar}};
#ifdef MARBLE_OU_EXP_AVX2
  if (Utils::cpu_has_avx2())
    out.emplace_back("avx2", &exp_neg_avx2);
#endif
  return out;
}

} // namespace Marble
