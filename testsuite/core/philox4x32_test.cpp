// The pair-noise generator (utils/philox4x32.hpp, forces/pair_noise.cpp):
// Philox4x32-10 against the Random123 known-answer vectors and against
// Random123's own implementation, the SIMD block against the scalar form bit
// for bit, and the statistics of the uniforms: mean 0, variance 1/12, no
// correlation between the components of a draw, between neighbouring pair
// keys (id_hi + 1, id_lo + 1) or between consecutive steps.
#include "forces/pair_noise.hpp"
#include "utils/philox4x32.hpp"

#include <Random123/philox.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using Utils::philox4x32_10;

TEST(Philox4x32, KnownAnswerVectors) {
  // Random123 kat_vectors, philox4x32 10 rounds
  using A4 = std::array<std::uint32_t, 4>;
  EXPECT_EQ(philox4x32_10({0, 0, 0, 0}, {0, 0}), (A4{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}));
  EXPECT_EQ(philox4x32_10({0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff}, {0xffffffff, 0xffffffff}),
            (A4{0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd}));
  EXPECT_EQ(philox4x32_10({0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}, {0xa4093822, 0x299f31d0}),
            (A4{0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}));
  static_assert(philox4x32_10({0, 0, 0, 0}, {0, 0})[0] == 0x6627e8d5u);
}

TEST(Philox4x32, AgreesWithRandom123) {
  std::mt19937 g(5);
  r123::Philox4x32 ref;
  for (int t = 0; t < 10000; ++t) {
    auto u = [&] { return static_cast<std::uint32_t>(g()); };
    r123::Philox4x32::ctr_type c{{u(), u(), u(), u()}};
    r123::Philox4x32::key_type k{{u(), u()}};
    auto const r = ref(c, k);
    auto const m = philox4x32_10({c[0], c[1], c[2], c[3]}, {k[0], k[1]});
    for (int w = 0; w < 4; ++w)
      ASSERT_EQ(m[w], r[w]);
  }
}

TEST(Philox4x32, CenteredUniform) {
  EXPECT_EQ(Utils::u32_to_centered_uniform(0u), 0.5 / 4294967296.0 - 0.5);
  EXPECT_EQ(Utils::u32_to_centered_uniform(0xffffffffu), 0.5 - 0.5 / 4294967296.0);
  EXPECT_EQ(Utils::u32_to_centered_uniform(0x80000000u), 0.5 / 4294967296.0);
  EXPECT_EQ(Utils::u32_to_centered_uniform(0x7fffffffu), -0.5 / 4294967296.0);
  std::mt19937 g(3);
  for (int t = 0; t < 1000; ++t) {
    std::uint32_t const x = g();
    EXPECT_EQ(Utils::u32_to_centered_uniform(x), (x + 0.5) / 4294967296.0 - 0.5);
  }
}

TEST(Philox4x32, BlockEqualsScalar) {
  std::mt19937 g(11);
  for (int n : {0, 1, 7, 31, 32, 33, 100, 512}) {
    Utils::PairNoiseKey const k(0x123456789abcull + n, 1, 987654321012ull);
    std::vector<std::uint32_t> lo(n), hi(n);
    std::vector<double> sign(n);
    for (int s = 0; s < n; ++s) {
      lo[s] = g() >> 2;
      hi[s] = lo[s] + 1 + (g() >> 3);
      sign[s] = (g() & 1) ? 1. : -1.;
    }
    std::vector<Utils::Vector3d> xi(n);
    Marble::pair_noise_block(k, n, lo.data(), hi.data(), sign.data(), xi.data());
    for (int s = 0; s < n; ++s) {
      auto const u = Utils::pair_uniform3(k, lo[s], hi[s]);
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(xi[s][c], sign[s] * u[c]) << "n " << n << " pair " << s;
    }
    // every code path this CPU has (AVX-512 and AVX2 intrinsics, portable)
    for (auto const &[name, fn] : Marble::pair_noise_paths()) {
      std::vector<double> x(n), y(n), z(n);
      fn(k, n, lo.data(), hi.data(), sign.data(), x.data(), y.data(), z.data());
      for (int s = 0; s < n; ++s) {
        auto const u = Utils::pair_uniform3(k, lo[s], hi[s]);
        ASSERT_EQ(x[s], sign[s] * u[0]) << name << " n " << n << " pair " << s;
        ASSERT_EQ(y[s], sign[s] * u[1]) << name << " n " << n << " pair " << s;
        ASSERT_EQ(z[s], sign[s] * u[2]) << name << " n " << n << " pair " << s;
      }
    }
  }
  std::string const isa = Marble::pair_noise_isa();
  EXPECT_TRUE(isa == "avx512" || isa == "avx2" || isa == "default");
}

TEST(Philox4x32, SaltsAndStepsAreDistinctStreams) {
  auto const a = Utils::pair_uniform3(Utils::PairNoiseKey(7, 1, 5), 3, 8);
  auto const b = Utils::pair_uniform3(Utils::PairNoiseKey(7, 16, 5), 3, 8);
  auto const c = Utils::pair_uniform3(Utils::PairNoiseKey(7, 1, 5 + (1ull << 32)), 3, 8);
  auto const d = Utils::pair_uniform3(Utils::PairNoiseKey(7 + (1ull << 32), 1, 5), 3, 8);
  EXPECT_NE(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(a, d);
}

namespace {
// n samples of a quantity with |x| <= bound: 5 sigma of the mean
double tol(double sigma, int n) { return 5. * sigma / std::sqrt(double(n)); }
} // namespace

TEST(Philox4x32, Statistics) {
  // 4e6 draws: pairs (i, i + 1 + i % 5) at steps 0..9, their neighbouring keys and steps
  int const n_pairs = 400000, n_steps = 10;
  int const n = n_pairs * n_steps;
  double m[3] = {}, v[3] = {}, cc[3] = {}, c_next_hi[3] = {}, c_next_lo[3] = {}, c_step[3] = {};
  for (int t = 0; t < n_steps; ++t) {
    Utils::PairNoiseKey const k(42, 1, t), k1(42, 1, t + 1);
    for (int i = 0; i < n_pairs; ++i) {
      std::uint32_t const lo = i, hi = i + 1 + i % 5;
      auto const u = Utils::pair_uniform3(k, lo, hi);
      auto const uh = Utils::pair_uniform3(k, lo, hi + 1);
      auto const ul = Utils::pair_uniform3(k, lo + 1, hi + 1);
      auto const us = Utils::pair_uniform3(k1, lo, hi);
      for (int c = 0; c < 3; ++c) {
        m[c] += u[c];
        v[c] += u[c] * u[c];
        cc[c] += u[c] * u[(c + 1) % 3];
        c_next_hi[c] += u[c] * uh[c];
        c_next_lo[c] += u[c] * ul[c];
        c_step[c] += u[c] * us[c];
      }
    }
  }
  // sigma of u: 1/sqrt(12); of u^2: sqrt(1/80 - 1/144); of u u': 1/12
  double const s_u = std::sqrt(1. / 12.), s_u2 = std::sqrt(1. / 80. - 1. / 144.), s_uu = 1. / 12.;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(m[c] / n, 0., tol(s_u, n)) << "component " << c;
    EXPECT_NEAR(v[c] / n, 1. / 12., tol(s_u2, n)) << "component " << c;
    EXPECT_NEAR(cc[c] / n, 0., tol(s_uu, n)) << "component " << c;
    EXPECT_NEAR(c_next_hi[c] / n, 0., tol(s_uu, n)) << "component " << c;
    EXPECT_NEAR(c_next_lo[c] / n, 0., tol(s_uu, n)) << "component " << c;
    EXPECT_NEAR(c_step[c] / n, 0., tol(s_uu, n)) << "component " << c;
  }
}

TEST(Philox4x32, UniformHistogram) {
  // chi^2 of 64 bins over 640 000 draws (all three components): 63 dof,
  // mean 63, sigma 11.2; 63 + 5 sigma = 119
  int const nb = 64, n = 640000 / 3;
  std::vector<double> h(nb, 0.);
  Utils::PairNoiseKey const k(1, 1, 99);
  for (int i = 0; i < n; ++i) {
    auto const u = Utils::pair_uniform3(k, i, i + 3);
    for (double x : u)
      h[static_cast<int>((x + 0.5) * nb)] += 1.;
  }
  double const e = 3. * n / nb;
  double chi2 = 0.;
  for (double x : h)
    chi2 += (x - e) * (x - e) / e;
  EXPECT_LT(chi2, 119.);
}
