// Pair kernels: F = -dV/dr (central differences), cutoff/offset/min/shift
// conventions of reference.md (LJ with offset, Groot-Warren hat).
#include "config/features.hpp"
#include "nonbonded/hat.hpp"
#include "nonbonded/lennard_jones.hpp"

#include <gtest/gtest.h>

#include <cmath>

using Marble::Hat;
using HatParams = Marble::Hat::Params;
using Marble::LennardJones;
using LennardJonesParams = Marble::LennardJones::Params;

namespace {

template <typename K, typename P> double numeric_force(P const &p, double r, double h) {
  return -(K::energy(p, r + h) - K::energy(p, r - h)) / (2. * h);
}

template <typename K, typename P> void check_derivative(P const &p, double r_lo, double r_hi, double tol) {
  int const n = 400;
  for (int k = 0; k <= n; ++k) {
    double const r = r_lo + (r_hi - r_lo) * k / n;
    double const h = 1e-6 * r;
    double const f_num = numeric_force<K>(p, r, h);
    double const f = K::force_over_r(p, r) * r;
    EXPECT_NEAR(f, f_num, tol * (1. + std::abs(f))) << "r = " << r;
  }
}

LennardJonesParams lj(double eps, double sig, double cut, double shift, double offset = 0.,
                      double min = 0.) {
  LennardJonesParams p;
  p.active = true;
  p.epsilon = eps;
  p.sigma = sig;
  p.cutoff = cut;
  p.shift = shift;
  p.offset = offset;
  p.min = min;
  return p;
}

} // namespace

TEST(LennardJones, ForceIsMinusEnergyDerivative) {
  // plain, shifted, with offset and with min; stay away from the cutoff/min kinks
  check_derivative<LennardJones>(lj(1., 1., 2.5, 0.), 0.85, 2.49, 1e-6);
  check_derivative<LennardJones>(lj(1.7, 0.8, 2., 0.3), 0.7, 2.7 - 0.71, 1e-6);
  check_derivative<LennardJones>(lj(1., 1., std::pow(2., 1. / 6.), 0.25, 2.), 2.9, 3.12, 1e-6);
  check_derivative<LennardJones>(lj(0.5, 1.2, 3., -0.1, 0.5, 0.9), 1.41, 3.49, 1e-6);
}

TEST(LennardJones, KnownValues) {
  auto const p = lj(2., 1.5, 10., 0.);
  double const rmin = std::pow(2., 1. / 6.) * 1.5;
  // minimum at 2^(1/6) sigma with depth -eps; V(sigma) = 0
  EXPECT_NEAR(LennardJones::energy(p, rmin), -2., 1e-12);
  EXPECT_NEAR(LennardJones::force_over_r(p, rmin), 0., 1e-12);
  EXPECT_NEAR(LennardJones::energy(p, 1.5), 0., 1e-12);
  // F(sigma) = 24 eps / sigma (repulsive: positive along d)
  EXPECT_NEAR(LennardJones::force_over_r(p, 1.5) * 1.5, 24. * 2. / 1.5, 1e-10);
}

TEST(LennardJones, CutoffOffsetShift) {
  // WCA with offset (reference.md section 3): V = 0 and F = 0 at r0 + 2^(1/6) s
  double const rc = std::pow(2., 1. / 6.);
  auto const wca = lj(1., 1., rc, 0.25, 2.);
  EXPECT_NEAR(LennardJones::energy(wca, 2. + rc - 1e-12), 0., 1e-9);
  EXPECT_NEAR(LennardJones::range(wca), 2. + rc, 1e-15);
  EXPECT_EQ(LennardJones::energy(wca, 2. + rc), 0.);
  EXPECT_EQ(LennardJones::force_over_r(wca, 2. + rc + 1e-9), 0.);
  EXPECT_NEAR(LennardJones::energy(wca, 3.), 1., 1e-12); // r - r0 = sigma: 4 (1 - 1 + 1/4)
  // auto shift makes the energy continuous at the cutoff for any cutoff
  for (double cut : {1.5, 2.5, 3.}) {
    auto const p = lj(1., 1., cut, LennardJones::auto_shift(1., cut));
    EXPECT_NEAR(LennardJones::energy(p, cut * (1. - 1e-12)), 0., 1e-9);
  }
  EXPECT_NEAR(LennardJones::auto_shift(1., rc), 0.25, 1e-12);
  // nothing below min, nothing at the offset itself
  auto const m = lj(1., 1., 2.5, 0., 1., 0.8);
  EXPECT_EQ(LennardJones::energy(m, 1.79), 0.);
  EXPECT_EQ(LennardJones::force_over_r(m, 1.79), 0.);
  EXPECT_GT(LennardJones::energy(m, 1.81), 0.);
  EXPECT_EQ(LennardJones::force_over_r(wca, 2.), 0.);
  // inactive parameters have no range
  auto off = wca;
  off.active = false;
  EXPECT_EQ(LennardJones::range(off), 0.);
}

TEST(Hat, ForceIsMinusEnergyDerivative) {
  HatParams h;
  h.active = true;
  h.F_max = 25.;
  h.cutoff = 1.;
  check_derivative<Hat>(h, 0.01, 0.99, 1e-7);
  h.F_max = 3.;
  h.cutoff = 1.7;
  check_derivative<Hat>(h, 0.01, 1.69, 1e-7);
}

TEST(Hat, KnownValues) {
  HatParams h;
  h.active = true;
  h.F_max = 25.;
  h.cutoff = 2.;
  EXPECT_NEAR(Hat::force_over_r(h, 1.) * 1., 12.5, 1e-12); // F_max (1 - r/rc)
  EXPECT_NEAR(Hat::energy(h, 0.), 25., 1e-12);             // F_max rc / 2
  EXPECT_EQ(Hat::energy(h, 2.), 0.);
  EXPECT_EQ(Hat::force_over_r(h, 2.), 0.);
  EXPECT_EQ(Hat::force_over_r(h, 2.5), 0.);
  EXPECT_EQ(Hat::force_over_r(h, 0.), 0.); // no direction at r = 0
  EXPECT_EQ(Hat::range(h), 2.);
}
