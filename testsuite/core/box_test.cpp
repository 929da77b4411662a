// BoxGeometry: minimum image and folding with image counts, for positions
// inside the box, on its faces, negative and many box lengths away.
#include "box/BoxGeometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using Marble::BoxGeometry;
using Utils::Vector3d;
using Utils::Vector3i;

namespace {
BoxGeometry make_box(Vector3d const &l) {
  BoxGeometry b;
  b.set_length(l);
  return b;
}
} // namespace

TEST(BoxGeometry, MinimumImageSimpleCases) {
  auto const box = make_box({10., 20., 30.});
  // inside half a box: unchanged
  auto d = box.get_mi_vector({1., 2., 3.}, {4., 5., 6.});
  EXPECT_DOUBLE_EQ(d[0], -3.);
  EXPECT_DOUBLE_EQ(d[1], -3.);
  EXPECT_DOUBLE_EQ(d[2], -3.);
  // across the faces: the short way round
  d = box.get_mi_vector({9.5, 19., 1.}, {0.5, 1., 29.});
  EXPECT_NEAR(d[0], -1., 1e-12);
  EXPECT_NEAR(d[1], -2., 1e-12);
  EXPECT_NEAR(d[2], 2., 1e-12);
  // positions many boxes away (unfolded) give the same vector
  d = box.get_mi_vector({9.5 + 70., 19. - 200., 1. + 3000.}, {0.5 - 40., 1. + 20., 29. - 90.});
  EXPECT_NEAR(d[0], -1., 1e-9);
  EXPECT_NEAR(d[1], -2., 1e-9);
  EXPECT_NEAR(d[2], 2., 1e-9);
}

TEST(BoxGeometry, MinimumImageIsShortestImage) {
  // Against a brute-force search over images, for random (also far) points.
  auto const box = make_box({3., 5., 7.});
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-50., 50.);
  for (int t = 0; t < 2000; ++t) {
    Vector3d const a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    auto const d = box.get_mi_vector(a, b);
    for (int k = 0; k < 3; ++k) {
      double const L = box.length()[k];
      // |d| <= L/2 and d - (a - b) is a whole number of box lengths
      EXPECT_LE(std::abs(d[k]), 0.5 * L + 1e-9);
      double const n = (a[k] - b[k] - d[k]) / L;
      EXPECT_NEAR(n, std::round(n), 1e-9);
      double best = INFINITY;
      for (int m = -40; m <= 40; ++m)
        best = std::min(best, std::abs(a[k] - b[k] - m * L));
      EXPECT_NEAR(std::abs(d[k]), best, 1e-9);
    }
    // antisymmetric
    auto const e = box.get_mi_vector(b, a);
    for (int k = 0; k < 3; ++k)
      if (std::abs(std::abs(d[k]) - 0.5 * box.length()[k]) > 1e-9) { // ties may go either way
        EXPECT_NEAR(e[k], -d[k], 1e-9);
      }
  }
}

TEST(BoxGeometry, MinimumImageNonPeriodicAxis) {
  auto box = make_box({10., 10., 10.});
  box.set_periodic(2, false);
  auto const d = box.get_mi_vector({9., 9., 9.}, {1., 1., 1.});
  EXPECT_NEAR(d[0], -2., 1e-12);
  EXPECT_NEAR(d[1], -2., 1e-12);
  EXPECT_NEAR(d[2], 8., 1e-12);
}

TEST(BoxGeometry, FoldCountsImages) {
  auto const box = make_box({10., 20., 30.});
  Vector3d p{25., -5., -61.};
  Vector3i img{};
  box.fold(p, img);
  EXPECT_NEAR(p[0], 5., 1e-12);
  EXPECT_NEAR(p[1], 15., 1e-12);
  EXPECT_NEAR(p[2], 29., 1e-12);
  EXPECT_EQ(img, (Vector3i{2, -1, -3}));
  // image counts accumulate
  Vector3d q{-0.5, 40., 30.};
  Vector3i img2{1, 1, 1};
  box.fold(q, img2);
  EXPECT_NEAR(q[0], 9.5, 1e-12);
  EXPECT_NEAR(q[1], 0., 1e-12);
  EXPECT_NEAR(q[2], 0., 1e-12);
  EXPECT_EQ(img2, (Vector3i{0, 3, 2}));
}

TEST(BoxGeometry, FoldFacesAndRoundoff) {
  auto const box = make_box({1., 1., 1.});
  // exactly L and -L go to 0; a tiny negative number must not stay at L
  Vector3d p{1., -1., -1e-18};
  Vector3i img{};
  box.fold(p, img);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(p[k], 0.);
    EXPECT_LT(p[k], 1.);
  }
  EXPECT_EQ(p[0], 0.);
  EXPECT_EQ(p[1], 0.);
  EXPECT_EQ(img[0], 1);
  EXPECT_EQ(img[1], -1);
  // the unfolded position is conserved up to round-off
  EXPECT_NEAR(box.unfolded(p, img)[2], -1e-18, 1e-15);
}

TEST(BoxGeometry, FoldRandomRoundTrip) {
  auto const box = make_box({2.5, 3.25, 7.});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1000., 1000.);
  for (int t = 0; t < 10000; ++t) {
    Vector3d const x{u(rng), u(rng), u(rng)};
    Vector3d p = x;
    Vector3i img{};
    box.fold(p, img);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(p[k], 0.);
      EXPECT_LT(p[k], box.length()[k]);
      EXPECT_EQ(img[k], static_cast<int>(std::floor(x[k] / box.length()[k]))) << "x = " << x[k];
    }
    auto const back = box.unfolded(p, img);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back[k], x[k], 1e-10);
    // folding twice changes nothing
    Vector3d p2 = p;
    Vector3i img2 = img;
    box.fold(p2, img2);
    EXPECT_EQ(p2, p);
    EXPECT_EQ(img2, img);
  }
}

TEST(BoxGeometry, FoldSkipsNonPeriodicAxis) {
  auto box = make_box({10., 10., 10.});
  box.set_periodic(1, false);
  Vector3d p{-1., -1., 11.};
  Vector3i img{};
  box.fold(p, img);
  EXPECT_NEAR(p[0], 9., 1e-12);
  EXPECT_EQ(p[1], -1.);
  EXPECT_NEAR(p[2], 1., 1e-12);
  EXPECT_EQ(img, (Vector3i{-1, 0, 1}));
}

TEST(BoxGeometry, Volume) {
  auto const box = make_box({2., 3., 4.});
  EXPECT_DOUBLE_EQ(box.volume(), 24.);
}
