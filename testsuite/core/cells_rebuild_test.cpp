// The cheaper Verlet rebuild (doc/benchmarks.md, session 8) must not change
// what it builds: the candidate scan's code paths (scalar/SSE2, AVX2,
// AVX-512) give the same pair list, entry for entry, and permute_locals'
// shortcuts (an array of identical elements is left alone; pos_at_rebuild
// skipped on request) leave every particle's data under its id.
#include "box/BoxGeometry.hpp"
#include "cells/CellSystem.hpp"
#include "config/features.hpp"
#include "particles/ParticleStore.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

using Marble::BoxGeometry;
using Marble::CellSystem;
using Marble::ParticleProperties;
using Marble::ParticleStore;
using Utils::Vector3d;

namespace {

struct ScanCase {
  Vector3d box;
  int n;
  double cut, skin;
  bool periodic_z;
};

struct Built {
  std::vector<int> row_start, j, ids, inner_row_start, inner_j;
  std::vector<std::array<int, 2>> extra;
  std::vector<Vector3d> pos;
};

Built build_with_path(ScanCase const &c, int path) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0., 1.);
  ParticleStore ps;
  for (int k = 0; k < c.n; ++k) {
    ParticleProperties p;
    p.id = k;
    // a few outside the box (folded by the rebuild), one exactly on a face
    p.pos = {u(rng) * c.box[0] * 1.2 - 0.1 * c.box[0], u(rng) * c.box[1], u(rng) * c.box[2]};
    if (k == 3)
      p.pos[1] = c.box[1];
    ps.add(p);
  }
  BoxGeometry box;
  box.set_length(c.box);
  box.set_periodic(2, c.periodic_z);
  CellSystem cs;
  cs.set_skin(c.skin);
  cs.set_inner_list(true);
  CellSystem::set_scan_path(path);
  // two rebuilds: the second starts from cell-sorted locals
  cs.rebuild(ps, box, c.cut);
  for (int i = 0; i < ps.n_local(); ++i)
    ps.pos[i] += Vector3d{0.13 * (u(rng) - 0.5), 0.13 * (u(rng) - 0.5), 0.13 * (u(rng) - 0.5)};
  cs.rebuild(ps, box, c.cut);
  CellSystem::set_scan_path(-1);
  Built b;
  auto const &l = cs.pairs();
  b.row_start = l.row_start;
  b.j = l.j;
  b.extra = l.extra;
  b.ids.assign(ps.id.begin(), ps.id.end());
  b.pos.assign(ps.pos.begin(), ps.pos.end());
  EXPECT_TRUE(cs.inner_fresh());
  b.inner_row_start = cs.select_pairs().row_start;
  b.inner_j = cs.select_pairs().j;
  return b;
}

} // namespace

TEST(CellsRebuild, ScanPathsGiveTheSameList) {
  ScanCase const cases[] = {
      {{8., 8., 8.}, 1536, 1.0, 0.4, true},   // the DPD solvent's density and range
      {{6., 7., 5.}, 2000, 1.0, 0.3, false},  // denser, one open axis
      {{2.5, 3., 2.8}, 150, 1.0, 0.4, true},  // box below twice the range: images of images
      {{10., 10., 10.}, 3000, 0.35, 0.1, true}, // small cells, few candidates a range
  };
  int const best = [] {
    CellSystem::set_scan_path(2);
    int const b = CellSystem::scan_path();
    CellSystem::set_scan_path(-1);
    return b;
  }();
  std::printf("scan paths on this CPU: 0..%d\n", best);
  for (auto const &c : cases) {
    Built const ref = build_with_path(c, 0);
    ASSERT_GT(ref.j.size(), 4u);
    for (int path = 1; path <= best; ++path) {
      Built const b = build_with_path(c, path);
      EXPECT_EQ(b.ids, ref.ids) << "path " << path;
      EXPECT_EQ(b.pos, ref.pos) << "path " << path;
      EXPECT_EQ(b.row_start, ref.row_start) << "path " << path;
      EXPECT_EQ(b.j, ref.j) << "path " << path;
      EXPECT_EQ(b.extra, ref.extra) << "path " << path;
      EXPECT_EQ(b.inner_row_start, ref.inner_row_start) << "path " << path;
      EXPECT_EQ(b.inner_j, ref.inner_j) << "path " << path;
    }
  }
}

// The inner list of a rebuild (CellSystem::select_pairs, session 15): per
// row, exactly the listed partners within the largest cutoff (to a relative
// 1e-12), in list order, so the force loop's and the Shardlow sweep's
// select gives the same pairs and the same d from it as from the whole list;
// it ends with the positions of the build (update_ghosts, forget_inner).
TEST(CellsRebuild, InnerListIsTheListWithinTheCutoff) {
  ScanCase const cases[] = {
      {{8., 8., 8.}, 1536, 1.0, 0.4, true},
      {{6., 7., 5.}, 2000, 1.0, 0.6, false},
      {{2.5, 3., 2.8}, 150, 1.0, 0.4, true},
  };
  int const best = [] {
    CellSystem::set_scan_path(2);
    int const b = CellSystem::scan_path();
    CellSystem::set_scan_path(-1);
    return b;
  }();
  for (auto const &c : cases)
    for (int path = 0; path <= best; ++path) {
      std::mt19937_64 rng(5);
      std::uniform_real_distribution<double> u(0., 1.);
      ParticleStore ps;
      for (int k = 0; k < c.n; ++k) {
        ParticleProperties p;
        p.id = k;
        p.pos = {u(rng) * c.box[0], u(rng) * c.box[1], u(rng) * c.box[2]};
        ps.add(p);
      }
      // a partner at exactly the cutoff (r^2 == cut^2 is out of range: not in the inner list)
      ps.pos[1] = ps.pos[0] + Vector3d{c.cut, 0., 0.};
      BoxGeometry box;
      box.set_length(c.box);
      box.set_periodic(2, c.periodic_z);
      CellSystem cs;
      cs.set_skin(c.skin);
      CellSystem::set_scan_path(path);
      cs.rebuild(ps, box, c.cut); // not asked for: the whole list
      EXPECT_FALSE(cs.inner_fresh());
      EXPECT_EQ(&cs.select_pairs(), &cs.pairs());
      std::vector<int> const j_without = cs.pairs().j;
      cs.set_inner_list(true);
      cs.rebuild(ps, box, c.cut);
      CellSystem::set_scan_path(-1);
      ASSERT_TRUE(cs.inner_fresh());
      EXPECT_EQ(cs.pairs().j, j_without); // the list itself is the same either way
      auto const &all = cs.pairs();
      auto const &in = cs.select_pairs();
      ASSERT_NE(&all, &in);
      ASSERT_EQ(in.row_start.size(), all.row_start.size());
      double const cut2 = c.cut * c.cut;
      std::size_t n_in = 0, n_all_within = 0;
      for (int i = 0; i + 1 < static_cast<int>(all.row_start.size()); ++i) {
        std::vector<int> want;
        for (int k = all.row_start[i]; k < all.row_start[i + 1]; ++k) {
          int const j = all.j[k];
          if ((ps.pos[i] - ps.pos[j]).norm2() < cut2 * (1. + 1e-12))
            want.push_back(j);
        }
        std::vector<int> const got(in.j.begin() + in.row_start[i], in.j.begin() + in.row_start[i + 1]);
        EXPECT_EQ(got, want) << "row " << i << " path " << path;
        n_in += got.size();
        n_all_within += want.size();
      }
      EXPECT_EQ(n_in, n_all_within);
      EXPECT_GT(n_in, 0u);
      EXPECT_LT(n_in, all.n_row_pairs()); // the skin's pairs are left out
      EXPECT_EQ(in.j.size(), n_in + 8);   // padded like the list
      cs.update_ghosts(ps);               // the positions may have changed: the whole list again
      EXPECT_FALSE(cs.inner_fresh());
      EXPECT_EQ(&cs.select_pairs(), &cs.pairs());
      cs.rebuild(ps, box, c.cut);
      EXPECT_TRUE(cs.inner_fresh());
      cs.forget_inner();
      EXPECT_EQ(&cs.select_pairs(), &cs.pairs());
      cs.rebuild(ps, box, c.cut);
      cs.invalidate();
      EXPECT_FALSE(cs.inner_fresh());
    }
}

TEST(CellsRebuild, PermuteKeepsUniformAndVaryingArrays) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0., 1.);
  ParticleStore ps;
  int const n = 200;
  for (int k = 0; k < n; ++k) {
    ParticleProperties p;
    p.id = k;
    p.type = 2;                                  // uniform
    p.pos = {u(rng), u(rng), u(rng)};            // varying
    p.v = {0., 0., 0.};                          // uniform ...
    if (k == n - 1)
      p.v[1] = -0.;                              // ... but for the sign bit of the last one
    p.image = {0, 0, 0};
    p.mass = 1.;
    p.gamma = k == 0 ? 2. : -1.;                 // differs only in the first
    ps.add(p);
  }
  for (int k = 0; k < n; ++k)
    ps.pos_at_rebuild[k] = ps.pos[k] * 2.;
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  auto const before_par = ps.pos_at_rebuild;
  ps.permute_locals(order, /*skip_pos_at_rebuild=*/true);
  EXPECT_EQ(ps.pos_at_rebuild, before_par); // left as it was
  for (int k = 0; k < n; ++k) {
    int const pid = ps.id[k];
    EXPECT_EQ(ps.index_of(pid), k);
    EXPECT_EQ(ps.type[k], 2);
    EXPECT_EQ(ps.pos[k], before_par[static_cast<std::size_t>(pid)] * 0.5);
    double const vy = ps.v[k][1];
    EXPECT_EQ(std::signbit(vy), pid == n - 1) << "id " << pid;
    EXPECT_EQ(ps.gamma[k], pid == 0 ? 2. : -1.);
#ifdef MASS
    EXPECT_EQ(ps.mass[k], 1.);
#endif
  }
  // and the full permutation (pos_at_rebuild follows its particle)
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<int> ids_before(ps.id.begin(), ps.id.end());
  std::vector<Vector3d> par_before(ps.pos_at_rebuild.begin(), ps.pos_at_rebuild.end());
  ps.permute_locals(order);
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(ps.id[k], ids_before[static_cast<std::size_t>(order[k])]);
    EXPECT_EQ(ps.pos_at_rebuild[k], par_before[static_cast<std::size_t>(order[k])]);
  }
}

TEST(CellsRebuild, GridCoordAsByDivision) {
  // Grid::coord multiplies by 1 / size where that cannot change the floor:
  // it must give floor((x - lo) / size) + 1 (clamped) for every x, faces
  // and their neighbouring doubles included.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  struct G {
    Vector3d lo, len;
    double range;
  };
  G const grids[] = {{{0., 0., 0.}, {20., 20., 20.}, 1.4},
                     {{10., -3., 0.1}, {10., 7.3, 3.3}, 1.0 / 3.0},
                     {{0., 0., 0.}, {1e-3, 5e4, 7.}, 1e-5}};
  long n_checked = 0;
  for (auto const &gg : grids) {
    CellSystem::Grid const g(gg.lo, gg.len, gg.range);
    for (int d = 0; d < 3; ++d) {
      auto by_division = [&](double x) {
        double const c = std::floor((x - g.lo[d]) / g.size[d]) + 1.;
        return static_cast<int>(std::clamp(c, 0., static_cast<double>(g.ext[d] - 1)));
      };
      std::vector<double> xs;
      for (int k = 0; k < 20000; ++k)
        xs.push_back(g.lo[d] + u(rng) * gg.len[d]);
      for (int k = -1; k <= g.n[d] + 1; ++k) { // the faces and the doubles around them
        double x = g.lo[d] + k * g.size[d];
        for (int s = 0; s < 4; ++s)
          x = std::nextafter(x, -1e300);
        for (int s = 0; s < 9; ++s, x = std::nextafter(x, 1e300))
          xs.push_back(x);
      }
      for (double x : xs) {
        ASSERT_EQ(g.coord(x, d), by_division(x)) << "x = " << x << " axis " << d;
        ++n_checked;
      }
    }
  }
  EXPECT_GT(n_checked, 180000);
}
