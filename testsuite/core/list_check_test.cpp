// The Verlet list's pair test (CellSystem::pairs_may_be_missing, doc/benchmarks.md
// "The Verlet list's life"): after a build, particles are moved, and the test's
// answer is compared with brute force. A pair is missing if its particles are
// now closer than the cutoff (minimum image) but the list does not hold them
// at a distance below the cutoff. The test must find every missing pair, and,
// below its cost cap and before the fastest particle has moved a whole skin,
// report nothing else.
#include "box/BoxGeometry.hpp"
#include "cells/CellSystem.hpp"
#include "particles/ParticleStore.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace {

using Marble::BoxGeometry;
using Marble::CellSystem;
using Marble::ParticleStore;
using Utils::Vector3d;

constexpr double cut = 1.0, skin = 0.4;

struct Scene {
  BoxGeometry box;
  ParticleStore ps;
  CellSystem cs;
  std::vector<Vector3d> x0; // the positions at the build, by local index
};

void build(Scene &s, Vector3d const &L, bool periodic_z, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0., 1.);
  s.box.set_length(L);
  s.box.set_periodic(2, periodic_z);
  for (int k = 0; k < n; ++k) {
    Marble::ParticleProperties p;
    p.id = k;
    p.pos = {u(rng) * L[0], u(rng) * L[1], u(rng) * L[2]};
    s.ps.add(p);
  }
  s.cs.set_skin(skin);
  s.cs.rebuild(s.ps, s.box, cut);
  s.x0.assign(s.ps.pos.begin(), s.ps.pos.begin() + s.ps.n_local());
}

double mi_dist2(BoxGeometry const &box, Vector3d const &a, Vector3d const &b) {
  double r2 = 0.;
  for (int d = 0; d < 3; ++d) {
    double x = a[d] - b[d];
    if (box.periodic(d))
      x -= box.length()[d] * std::round(x / box.length()[d]);
    r2 += x * x;
  }
  return r2;
}

// brute force: some pair of ids within the cutoff now that the list does not
// hold within the cutoff (the list's distances from its own entries, ghosts
// refreshed)
bool missing_brute(Scene &s) {
  s.cs.update_ghosts(s.ps);
  int const n = s.ps.n_local();
  std::set<std::pair<int, int>> listed;
  for (auto const &pr : s.cs.pairs()) {
    int const a = s.ps.id[pr[0]], b = s.ps.id[pr[1]];
    if ((s.ps.pos[pr[0]] - s.ps.pos[pr[1]]).norm2() < cut * cut)
      listed.insert({std::min(a, b), std::max(a, b)});
  }
  // every pair within the cutoff, by a grid of cells at least the cutoff
  // wide over the current positions (at least 3 per axis in these boxes)
  int nc[3];
  for (int d = 0; d < 3; ++d)
    nc[d] = static_cast<int>(s.box.length()[d] / cut);
  auto cell_of = [&](Vector3d const &x, int d) {
    double const L = s.box.length()[d];
    double const v = s.box.periodic(d) ? x[d] - L * std::floor(x[d] / L) : x[d];
    return std::clamp(static_cast<int>(v / L * nc[d]), 0, nc[d] - 1);
  };
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(nc[0] * nc[1] * nc[2]));
  for (int i = 0; i < n; ++i)
    cells[(cell_of(s.ps.pos[i], 2) * nc[1] + cell_of(s.ps.pos[i], 1)) * nc[0] + cell_of(s.ps.pos[i], 0)]
        .push_back(i);
  for (int i = 0; i < n; ++i) {
    int const c[3] = {cell_of(s.ps.pos[i], 0), cell_of(s.ps.pos[i], 1), cell_of(s.ps.pos[i], 2)};
    for (int oz = -1; oz <= 1; ++oz)
      for (int oy = -1; oy <= 1; ++oy)
        for (int ox = -1; ox <= 1; ++ox) {
          int t[3] = {c[0] + ox, c[1] + oy, c[2] + oz};
          bool skip = false;
          for (int d = 0; d < 3; ++d)
            if (t[d] < 0 || t[d] >= nc[d]) {
              skip = skip || !s.box.periodic(d);
              t[d] = (t[d] + nc[d]) % nc[d];
            }
          if (skip)
            continue;
          for (int j : cells[(t[2] * nc[1] + t[1]) * nc[0] + t[0]])
            if (j > i && mi_dist2(s.box, s.ps.pos[i], s.ps.pos[j]) < cut * cut) {
              int const a = s.ps.id[i], b = s.ps.id[j];
              if (!listed.count({std::min(a, b), std::max(a, b)}))
                return true;
            }
        }
  }
  return false;
}

double max_disp(Scene const &s) {
  double m = 0.;
  for (int i = 0; i < s.ps.n_local(); ++i)
    m = std::max(m, (s.ps.pos[i] - s.x0[i]).norm());
  return m;
}

// Random displacements (Gaussian, scale sigma) and, with @p pairs > 0, that
// many pairs at distance range..range + @p window at the build pushed
// towards each other until they are @p gap_left short of (or beyond) the
// cutoff (a narrow window: displacements that add up to just over the skin).
void displace(Scene &s, std::mt19937_64 &rng, double sigma, int pairs, double gap_left, double window) {
  std::normal_distribution<double> g(0., sigma);
  int const n = s.ps.n_local();
  for (int i = 0; i < n; ++i)
    s.ps.pos[i] = s.x0[i] + Vector3d{g(rng), g(rng), g(rng)};
  std::uniform_int_distribution<int> pick(0, n - 1);
  double const range = cut + skin;
  for (int done = 0, tries = 0; done < pairs && tries < 100000; ++tries) {
    int const i = pick(rng), j = pick(rng);
    if (i == j)
      continue;
    Vector3d d = s.box.get_mi_vector(s.x0[i], s.x0[j]);
    double const r = d.norm();
    if (!(r >= range && r < range + window))
      continue;
    // move each by half of (r - cut + gap_left) along the line, from the build
    double const h = 0.5 * (r - cut + gap_left);
    Vector3d const e = d / r;
    s.ps.pos[i] = s.x0[i] - h * e;
    s.ps.pos[j] = s.x0[j] + h * e;
    ++done;
  }
}

} // namespace

TEST(ListCheck, AgreesWithBruteForce) {
  struct Case {
    Vector3d L;
    bool periodic_z;
  };
  int n_true = 0, n_false = 0, n_exact = 0;
  for (auto const &c : {Case{{11., 11., 11.}, true}, Case{{12., 10.5, 9.}, false}}) {
    Scene s;
    int const n = static_cast<int>(3. * c.L[0] * c.L[1] * c.L[2]);
    build(s, c.L, c.periodic_z, n, 11);
    ASSERT_TRUE(s.cs.pair_test_applies());
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < 48; ++trial) {
      // sigma 0.02-0.065: the fastest particle from ~0.1 to ~0.3 (hot ones: 0 to many)
      double const sigma = 0.02 + 0.045 * (trial % 8) / 7.;
      int const pairs = (trial / 8) % 3;              // 0, 1, 2 pushed pairs
      double const gap = (trial / 24) ? -0.01 : 0.01; // short of the cutoff / within it
      double const window = trial % 2 ? 0.3 : 0.03;
      displace(s, rng, sigma, pairs, gap, window);
      bool const brute = missing_brute(s);
      bool const test = s.cs.pairs_may_be_missing(s.ps);
      double const dmax = max_disp(s);
      // never a missing pair unreported
      if (brute)
        EXPECT_TRUE(test) << "trial " << trial << ": a missing pair not found";
      // below half a skin: false; at a whole skin: true; between, exact unless
      // more than 1/128 of the particles moved more than skin/2 (then true)
      int hot = 0;
      for (int i = 0; i < n; ++i)
        hot += (s.ps.pos[i] - s.x0[i]).norm() > 0.5 * skin;
      if (dmax <= 0.5 * skin * (1. - 1e-6))
        EXPECT_FALSE(test) << "trial " << trial;
      else if (dmax >= skin)
        EXPECT_TRUE(test) << "trial " << trial;
      else if (128 * hot <= n) {
        EXPECT_EQ(test, brute) << "trial " << trial << " dmax " << dmax << " hot " << hot;
        ++n_exact;
      }
      (brute ? n_true : n_false) += 1;
    }
  }
  // the trials cover both answers, and the exact regime
  EXPECT_GE(n_true, 10);
  EXPECT_GE(n_false, 10);
  EXPECT_GE(n_exact, 20);
}

TEST(ListCheck, NotForSmallBoxes) {
  // a periodic box under 3 ranges (cut + skin) could hold a pair through a
  // second image: the test does not apply there
  Scene s;
  build(s, {4.0, 8.0, 8.0}, true, 600, 3);
  EXPECT_FALSE(s.cs.pair_test_applies());
  Scene t;
  build(t, {4.0, 8.0, 8.0}, true, 600, 3);
  t.box.set_periodic(0, false);
  t.cs.rebuild(t.ps, t.box, cut);
  EXPECT_TRUE(t.cs.pair_test_applies()); // (a non-periodic axis has no second image)
}
