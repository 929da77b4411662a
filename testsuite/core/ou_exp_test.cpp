// The OU-factor exp of the Shardlow sweep (integrators/ou_exp.hpp): within
// 1 ulp of a long-double reference (expl) on x in [-746, 0] and on the special
// values, and every code path (scalar, AVX2 where the CPU has it) gives the
// bits of the scalar exp_neg, for blocks of any length (tails included).
#include "integrators/ou_exp.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

using Marble::exp_neg;

std::uint64_t bits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

/** |y - exp(x)| in units of the last place of the double nearest exp(x)
 * (2^-1074 in the subnormal range and below). */
long double ulp_error(double x, double y) {
  long double const ref = std::exp(static_cast<long double>(x)); // expl
  int e = 0;
  std::frexp(ref, &e); // ref = m 2^e, m in [0.5, 1)
  long double ulp = std::ldexp(1.0L, e - 53);
  long double const tiny = std::ldexp(1.0L, -1074);
  if (ulp < tiny)
    ulp = tiny;
  return std::fabs(static_cast<long double>(y) - ref) / ulp;
}

/** The arguments: uniform on [-746, 0], log-uniform |x| in [1e-20, 746],
 * dense on the OU rates' range [-2, 0], next to the reduction boundaries
 * (k + 1/2) ln2 and in the subnormal range. Fixed seed. */
std::vector<double> arguments() {
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> full(-746., 0.), small(-2., 0.), lg(-20., std::log10(746.)),
      sub(-746., -708.);
  std::vector<double> x;
  for (int i = 0; i < 400000; ++i) {
    x.push_back(full(rng));
    x.push_back(small(rng));
    x.push_back(-std::pow(10., lg(rng)));
    x.push_back(sub(rng));
  }
  double const ln2 = std::log(2.);
  for (int k = 0; k <= 1076; ++k) {
    double const b = -(k + 0.5) * ln2;
    double lo = b, hi = b;
    for (int j = 0; j < 8; ++j) {
      lo = std::nextafter(lo, -1000.), hi = std::nextafter(hi, 0.);
      x.push_back(lo), x.push_back(hi);
    }
    x.push_back(-k * ln2);
  }
  return x;
}

std::vector<double> special_values() {
  double const inf = std::numeric_limits<double>::infinity();
  return {0.,     -0.,    -std::numeric_limits<double>::denorm_min(), -1e-300, -1e-17, -1.1102230246251565e-16,
          -0.5,   -1.,    -708.39641853226408, -708.4, -709.,         -744.4,  -745.1, -745.13321910194111,
          -745.2, -746.,  -1000., -1e300, -inf};
}

/** A list of code paths: "scalar" first, then "avx2" exactly where the CPU has it. */
template <class Paths> void expect_scalar_then_avx2(Paths const &paths) {
  ASSERT_GE(paths.size(), 1u);
  EXPECT_STREQ(paths[0].first, "scalar");
#if defined(__x86_64__) && defined(__GNUC__)
  EXPECT_EQ(paths.size(), __builtin_cpu_supports("avx2") ? 2u : 1u);
#endif
}

TEST(OuExp, WithinOneUlpOfExpl) {
  auto x = arguments();
  auto const sv = special_values();
  x.insert(x.end(), sv.begin(), sv.end());
  // the normal results and the subnormal ones (x < ln(2^-1022) = -708.396...)
  long double worst[2] = {0., 0.};
  double worst_x[2] = {0., 0.};
  for (double const xi : x) {
    long double const err = ulp_error(xi, exp_neg(xi));
    int const sub = xi < -708.39641853226408 ? 1 : 0;
    if (err > worst[sub])
      worst[sub] = err, worst_x[sub] = xi;
  }
  std::printf("max error %.4Lf ulp at x = %.17g (normal results), %.4Lf ulp at x = %.17g (subnormal); "
              "%zu arguments\n",
              worst[0], worst_x[0], worst[1], worst_x[1], x.size());
  EXPECT_LE(worst[0], 1.0L) << "at x = " << worst_x[0];
  EXPECT_LE(worst[1], 1.0L) << "at x = " << worst_x[1];
}

TEST(OuExp, SpecialValues) {
  double const inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(bits(exp_neg(0.)), bits(1.));
  EXPECT_EQ(bits(exp_neg(-0.)), bits(1.));
  EXPECT_EQ(exp_neg(-std::numeric_limits<double>::denorm_min()), 1.);
  EXPECT_EQ(exp_neg(-1e-300), 1.);
  EXPECT_EQ(exp_neg(-1e-17), 1.);
  // subnormal results, and 0 below ln(2^-1075) = -745.1332191...
  EXPECT_GT(exp_neg(-708.4), 0.);
  EXPECT_LT(exp_neg(-708.4), std::numeric_limits<double>::min());
  EXPECT_EQ(exp_neg(-745.1), std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(bits(exp_neg(-745.2)), bits(0.));
  EXPECT_EQ(bits(exp_neg(-746.)), bits(0.));
  EXPECT_EQ(bits(exp_neg(-1000.)), bits(0.));
  EXPECT_EQ(bits(exp_neg(-inf)), bits(0.));
  EXPECT_TRUE(std::isnan(exp_neg(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_TRUE(std::isnan(exp_neg(-std::numeric_limits<double>::quiet_NaN())));
  // exp(-1) and exp(-0.5) rounded correctly
  EXPECT_EQ(exp_neg(-1.), static_cast<double>(std::exp(-1.0L)));
  EXPECT_EQ(exp_neg(-0.5), static_cast<double>(std::exp(-0.5L)));
}

TEST(OuExp, NonIncreasingOnSortedArguments) {
  // nice to have (not a requirement of the sweep): checked on a sorted sample
  auto x = arguments();
  std::sort(x.begin(), x.end());
  int violations = 0;
  for (std::size_t i = 1; i < x.size(); ++i)
    if (exp_neg(x[i]) < exp_neg(x[i - 1]))
      ++violations;
  std::printf("monotonicity violations: %d of %zu\n", violations, x.size() - 1);
  EXPECT_EQ(violations, 0);
}

TEST(OuExp, PathsGiveTheSameBits) {
  auto const paths = Marble::exp_neg_paths();
  expect_scalar_then_avx2(paths);
  auto x = arguments();
  auto const sv = special_values();
  x.insert(x.end(), sv.begin(), sv.end());
  x.push_back(std::numeric_limits<double>::quiet_NaN());
  x.push_back(-std::numeric_limits<double>::quiet_NaN());
  x.push_back(std::nan("0x123"));
  int const n = static_cast<int>(x.size());
  std::vector<double> ref(x.size());
  for (int l = 0; l < n; ++l)
    ref[l] = exp_neg(x[l]);
  // the dispatched block as well as each path
  std::vector<std::pair<char const *, Marble::ExpNegBlockFn>> fns = paths;
  fns.emplace_back("exp_neg_block", &Marble::exp_neg_block);
  for (auto const &[name, fn] : fns) {
    std::vector<double> out(x.size(), 42.);
    fn(x.data(), out.data(), n);
    int mismatches = 0;
    for (int l = 0; l < n; ++l)
      if (bits(out[l]) != bits(ref[l]) && ++mismatches <= 5)
        ADD_FAILURE() << name << ": x = " << x[l] << " gives " << out[l] << ", exp_neg " << ref[l];
    EXPECT_EQ(mismatches, 0) << name;
  }
}

TEST(OuExp, BlocksOfAnyLength) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3., 0.);
  double const sentinel = -123.5;
  for (auto const &[name, fn] : Marble::exp_neg_paths()) {
    for (int const n : {0, 1, 2, 3, 4, 5, 7, 8, 9, 251, 252}) {
      std::vector<double> x(static_cast<std::size_t>(n) + 8);
      for (auto &v : x)
        v = u(rng);
      std::vector<double> out(x.size(), sentinel);
      fn(x.data(), out.data(), n);
      for (int l = 0; l < n; ++l)
        EXPECT_EQ(bits(out[l]), bits(exp_neg(x[l]))) << name << " n = " << n << " lane " << l;
      for (std::size_t l = n; l < out.size(); ++l)
        EXPECT_EQ(out[l], sentinel) << name << " n = " << n << ": wrote past the end at " << l;
      // in place, at an odd offset (unaligned)
      std::vector<double> y(x);
      fn(y.data() + 1, y.data() + 1, n > 0 ? n - 1 : 0);
      EXPECT_EQ(y[0], x[0]);
      for (int l = 1; l < n; ++l)
        EXPECT_EQ(bits(y[l]), bits(exp_neg(x[l]))) << name << " in place, n = " << n << " lane " << l;
      for (std::size_t l = std::max(n, 1); l < y.size(); ++l)
        EXPECT_EQ(y[l], x[l]) << name << " in place, n = " << n;
    }
  }
}

} // namespace

// The sweep's OU amplitudes (ou_amplitude_block): every path gives the bits of
// the scalar expressions sqrt(12 kT/mu (1 - a^2)) and a - 1, for blocks of any
// length, in place (am1 = a) as the sweep calls it, and writes nothing past n.
TEST(OuAmplitude, PathsGiveTheScalarBits) {
  auto const paths = Marble::ou_amplitude_paths();
  expect_scalar_then_avx2(paths);
  std::vector<std::pair<char const *, Marble::OUAmplitudeBlockFn>> fns = paths;
  fns.emplace_back("ou_amplitude_block", &Marble::ou_amplitude_block);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> ua(0., 1.), uk(1e-3, 10.);
  double const sentinel = -7.25;
  for (auto const &[name, fn] : fns) {
    for (int const n : {0, 1, 2, 3, 4, 5, 7, 8, 9, 251, 252, 4000}) {
      std::vector<double> a(static_cast<std::size_t>(n) + 8), kT(a.size());
      for (std::size_t l = 0; l < a.size(); ++l) {
        a[l] = ua(rng), kT[l] = uk(rng);
        if (l % 97 == 3)
          a[l] = 1.; // no friction: sd = 0 exactly
      }
      std::vector<double> sd(a.size(), sentinel), am1 = a;
      std::fill(am1.begin() + n, am1.end(), sentinel);
      fn(am1.data(), kT.data(), n, sd.data(), am1.data());
      int mismatches = 0;
      for (int l = 0; l < n; ++l) {
        double const want_sd = std::sqrt(12. * kT[l] * (1. - a[l] * a[l]));
        double const want_am1 = a[l] - 1.;
        if ((bits(sd[l]) != bits(want_sd) || bits(am1[l]) != bits(want_am1)) && ++mismatches <= 5)
          ADD_FAILURE() << name << " n = " << n << " lane " << l << ": sd " << sd[l] << " (want " << want_sd
                        << "), a - 1 " << am1[l] << " (want " << want_am1 << ")";
      }
      EXPECT_EQ(mismatches, 0) << name << " n = " << n;
      for (std::size_t l = n; l < a.size(); ++l) {
        EXPECT_EQ(sd[l], sentinel) << name << " n = " << n << ": wrote past the end at " << l;
        EXPECT_EQ(am1[l], sentinel) << name << " n = " << n << ": wrote past the end at " << l;
      }
    }
  }
}
