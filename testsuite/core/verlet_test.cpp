// Verlet lists (cells + ghost layer) against brute force over all periodic
// images: the set of interacting (i, j, image) triples, and, for the
// conservative potentials, forces and energies. Includes boxes smaller than
// twice the interaction range, where a particle interacts with several images
// of another particle and with its own images.
#include "config/features.hpp"
#include "system/System.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

using Marble::IAParams;
using Marble::System;
using Utils::Vector3d;
using Utils::Vector3i;

namespace {

// (id_a, id_b, image n): the pair x_a - x_b - n L (folded positions), a <= b,
// and for a == b (self images) n is lexicographically positive.
using Triple = std::tuple<int, int, int, int, int>;

bool positive(Vector3i const &n) {
  for (int d = 0; d < 3; ++d) {
    if (n[d] != 0)
      return n[d] > 0;
  }
  return false;
}

Triple canonical(int a, int b, Vector3i n) {
  if (a > b || (a == b && !positive(n))) {
    std::swap(a, b);
    n = {-n[0], -n[1], -n[2]};
  }
  return {a, b, n[0], n[1], n[2]};
}

/** Give every type pair an interaction of range @p cut (whatever kernel this build has). */
void set_range(System &s, int n_types, double cut) {
  for (int i = 0; i < n_types; ++i)
    for (int j = i; j < n_types; ++j) {
#if defined(LENNARD_JONES)
      Marble::LennardJones::Params p;
      p.active = true;
      p.epsilon = 1.;
      p.sigma = 0.3;
      p.cutoff = cut;
      p.shift = Marble::LennardJones::auto_shift(p.sigma, p.cutoff);
      s.set_kernel<Marble::LennardJones>(i, j, p);
#elif defined(HAT)
      Marble::Hat::Params p;
      p.active = true;
      p.F_max = 1.;
      p.cutoff = cut;
      s.set_kernel<Marble::Hat>(i, j, p);
#elif defined(DPD)
      Marble::DPDParams p;
      p.active = true;
      p.radial.gamma = 1.;
      p.radial.r_cut = cut;
      s.set_kernel<Marble::DPDPair>(i, j, p);
#endif
    }
}

Vector3d random_pos(std::mt19937_64 &rng, Vector3d const &L) {
  std::uniform_real_distribution<double> u(0., 1.);
  return {u(rng) * L[0], u(rng) * L[1], u(rng) * L[2]};
}

/** Triples within @p cut as found through the Verlet list. */
std::set<Triple> list_triples(System &s, double cut) {
  auto const &ps = s.particles();
  auto const &L = s.box().length();
  int const nl = ps.n_local();
  std::set<Triple> out;
  for (auto const &pr : s.cells().pairs()) {
    int const i = pr[0], j = pr[1];
    EXPECT_LT(i, nl); // the first index is always a local particle
    Vector3d const d = ps.pos[i] - ps.pos[j];
    if (d.norm2() >= cut * cut)
      continue;
    // image of the partner relative to the folded positions of the owners
    Vector3i n{};
    int owner = j;
    if (j >= nl) {
      owner = ps.ghost_owner[j - nl];
      auto const &sh = ps.ghost_shift[j - nl];
      for (int k = 0; k < 3; ++k)
        n[k] = static_cast<int>(std::lround(sh[k] / L[k]));
    }
    auto const t = canonical(ps.id[i], ps.id[owner], n);
    EXPECT_TRUE(out.insert(t).second)
        << "pair found twice: " << std::get<0>(t) << " " << std::get<1>(t);
  }
  return out;
}

/** Triples within @p cut by brute force over all images (positions as stored). */
std::set<Triple> brute_triples(System &s, double cut) {
  auto const &ps = s.particles();
  auto const &L = s.box().length();
  int const nl = ps.n_local();
  int nmax[3];
  for (int k = 0; k < 3; ++k)
    nmax[k] = s.box().periodic(k) ? static_cast<int>(std::ceil(cut / L[k])) + 1 : 0;
  std::set<Triple> out;
  for (int i = 0; i < nl; ++i)
    for (int j = i; j < nl; ++j)
      for (int a = -nmax[0]; a <= nmax[0]; ++a)
        for (int b = -nmax[1]; b <= nmax[1]; ++b)
          for (int c = -nmax[2]; c <= nmax[2]; ++c) {
            Vector3i const n{a, b, c};
            if (i == j && !positive(n))
              continue;
            Vector3d const d = ps.pos[i] - ps.pos[j] - Vector3d{a * L[0], b * L[1], c * L[2]};
            if (d.norm2() < cut * cut)
              out.insert(canonical(ps.id[i], ps.id[j], n));
          }
  return out;
}

struct Case {
  Vector3d box;
  int n;
  double cut, skin;
  std::array<bool, 3> periodic{true, true, true};
};

System make_system(Case const &c) {
  System s(c.box);
  for (int d = 0; d < 3; ++d)
    s.set_periodic(d, c.periodic[d]);
  s.set_skin(c.skin);
  return s;
}

class VerletVsBrute : public ::testing::TestWithParam<Case> {};

TEST_P(VerletVsBrute, SameInteractingImages) {
#if !defined(LENNARD_JONES) && !defined(HAT) && !defined(DPD)
  GTEST_SKIP() << "no pair interaction compiled into this build";
#endif
  auto const c = GetParam();
  std::mt19937_64 rng(1234 + c.n);
  System s = make_system(c);
  set_range(s, 2, c.cut);
  for (int k = 0; k < c.n; ++k) {
    Marble::ParticleProperties p;
    p.id = 3 * k + 1; // sparse ids
    p.type = k % 2;
    p.pos = random_pos(rng, c.box);
    s.add_particle(p);
  }
  s.ensure_lists();
  auto const brute = brute_triples(s, c.cut);
  auto const list = list_triples(s, c.cut);
  EXPECT_GT(brute.size(), 0u);
  EXPECT_EQ(list, brute);
  // The small boxes must really exercise several images of one partner and
  // the images of a particle itself.
  std::map<std::pair<int, int>, int> n_images;
  int n_self = 0;
  for (auto const &t : brute) {
    ++n_images[{std::get<0>(t), std::get<1>(t)}];
    n_self += std::get<0>(t) == std::get<1>(t);
  }
  int max_images = 0;
  for (auto const &kv : n_images)
    max_images = std::max(max_images, kv.second);
  double lmin = INFINITY; // smallest periodic length
  for (int d = 0; d < 3; ++d)
    if (c.periodic[d])
      lmin = std::min(lmin, c.box[d]);
  if (lmin < 2. * c.cut) {
    EXPECT_GE(max_images, 2);
  }
  if (lmin < c.cut) {
    EXPECT_GT(n_self, 0);
  }
  // Move every particle by less than skin/2: the list is kept (no rebuild)
  // and must still contain every pair now within the cutoff.
  long const rebuilds = s.cells().n_rebuilds();
  std::normal_distribution<double> g(0., 1.);
  auto &ps = s.particles();
  for (int i = 0; i < ps.n_local(); ++i) {
    Vector3d dir{g(rng), g(rng), g(rng)};
    ps.pos[i] += (0.49 * c.skin / dir.norm()) * dir;
  }
  s.ensure_lists();
  EXPECT_EQ(s.cells().n_rebuilds(), rebuilds);
  EXPECT_EQ(list_triples(s, c.cut), brute_triples(s, c.cut));
  // one more move beyond skin/2: the pair test (the default, where it
  // applies) rebuilds only if a pair may be missing, the half-skin rule
  // always; either way the list holds every pair now within the cutoff
  ps.pos[0] = ps.pos_at_rebuild[0] + Vector3d{0.51 * c.skin, 0., 0.};
  s.ensure_lists();
  if (!s.pair_test_applies()) {
    EXPECT_EQ(s.cells().n_rebuilds(), rebuilds + 1);
  }
  EXPECT_EQ(list_triples(s, c.cut), brute_triples(s, c.cut));
  s.set_list_check(System::ListCheck::HalfSkin);
  long const r = s.cells().n_rebuilds();
  ps.pos[0] = ps.pos_at_rebuild[0] + Vector3d{0.51 * c.skin, 0., 0.};
  s.ensure_lists();
  EXPECT_EQ(s.cells().n_rebuilds(), r + 1);
  EXPECT_EQ(list_triples(s, c.cut), brute_triples(s, c.cut));
}

INSTANTIATE_TEST_SUITE_P(
    Boxes, VerletVsBrute,
    ::testing::Values(Case{{8., 8., 8.}, 300, 1.2, 0.4}, // many cells
                      Case{{5., 6., 7.}, 200, 1.5, 0.3}, // anisotropic
                      Case{{3., 3., 3.}, 40, 1.4, 0.2},  // L < 2 range: 1 cell
                      Case{{2., 2.5, 3.}, 12, 1.8, 0.3}, // several images of each partner
                      Case{{1., 1., 1.}, 3, 1.3, 0.1},   // self images, range > L
                      Case{{1.2, 4., 9.}, 30, 1.1, 0.4}, // thin slab
                      // non-periodic axes (walls): no images along them
                      Case{{6., 6., 6.}, 150, 1.3, 0.3, {true, true, false}},
                      Case{{2., 3., 4.}, 20, 1.5, 0.2, {false, true, false}},
                      Case{{5., 5., 5.}, 80, 1.2, 0.3, {false, false, false}}));

#if defined(LENNARD_JONES) || defined(HAT)
// Forces and energy through the engine vs a brute-force sum over images.
struct Sums {
  std::map<int, Vector3d> f;
  double energy = 0.;
  std::array<double, 9> virial{}; // sum over pairs of d (x) F
};

Sums brute_forces(System &s, double cut) {
  auto const &ps = s.particles();
  auto const &L = s.box().length();
  int const nl = ps.n_local();
  int nmax[3];
  for (int k = 0; k < 3; ++k)
    nmax[k] = s.box().periodic(k) ? static_cast<int>(std::ceil(cut / L[k])) + 1 : 0;
  Sums out;
  for (int i = 0; i < nl; ++i)
    out.f[ps.id[i]] = {};
  for (int i = 0; i < nl; ++i)
    for (int j = i; j < nl; ++j) {
      auto const &p = s.interactions().get(ps.type[i], ps.type[j]);
      for (int a = -nmax[0]; a <= nmax[0]; ++a)
        for (int b = -nmax[1]; b <= nmax[1]; ++b)
          for (int c = -nmax[2]; c <= nmax[2]; ++c) {
            if (i == j && !positive(Vector3i{a, b, c}))
              continue;
            Vector3d const d = ps.pos[i] - ps.pos[j] - Vector3d{a * L[0], b * L[1], c * L[2]};
            double const r = d.norm();
            if (r >= p.max_cut)
              continue;
            double fac = 0., u = 0.;
#ifdef LENNARD_JONES
            if (p.get<Marble::LennardJones>().active)
              fac += Marble::LennardJones::force_over_r(p.get<Marble::LennardJones>(), r),
                  u += Marble::LennardJones::energy(p.get<Marble::LennardJones>(), r);
#endif
#ifdef HAT
            if (p.get<Marble::Hat>().active)
              fac += Marble::Hat::force_over_r(p.get<Marble::Hat>(), r),
                  u += Marble::Hat::energy(p.get<Marble::Hat>(), r);
#endif
            out.f[ps.id[i]] += fac * d;
            out.f[ps.id[j]] -= fac * d;
            out.energy += u;
            for (int x = 0; x < 3; ++x)
              for (int y = 0; y < 3; ++y)
                out.virial[3 * x + y] += fac * d[x] * d[y];
          }
    }
  return out;
}

class ForcesVsBrute : public ::testing::TestWithParam<Case> {};

TEST_P(ForcesVsBrute, ForcesAndEnergy) {
#if !defined(LENNARD_JONES) && !defined(HAT) && !defined(DPD)
  GTEST_SKIP() << "no pair interaction compiled into this build";
#endif
  auto const c = GetParam();
  std::mt19937_64 rng(99 + c.n);
  System s = make_system(c);
  // Two types with different potentials and cutoffs; the range is the largest.
  for (int i = 0; i < 2; ++i)
    for (int j = i; j < 2; ++j) {
#ifdef LENNARD_JONES
      Marble::LennardJones::Params lj;
      lj.active = true;
      lj.epsilon = 0.5 + i + j;
      lj.sigma = 0.25;
      lj.cutoff = (i + j == 1) ? c.cut : 0.8 * c.cut;
      lj.shift = 0.01 * (1 + i + j);
      s.set_kernel<Marble::LennardJones>(i, j, lj);
#endif
#ifdef HAT
      Marble::Hat::Params hat;
      hat.active = true;
      hat.F_max = 2. + i + j;
      hat.cutoff = (i == j) ? c.cut : 0.6 * c.cut;
      s.set_kernel<Marble::Hat>(i, j, hat);
#endif
    }
  for (int k = 0; k < c.n; ++k) {
    Marble::ParticleProperties p;
    p.id = k;
    p.type = (k * 7) % 2;
    p.pos = random_pos(rng, c.box);
    s.add_particle(p);
  }
  // Keep particles apart so that LJ forces stay moderate: drop near overlaps.
  for (int k = c.n - 1; k >= 0; --k) {
    auto const &ps = s.particles();
    int const i = ps.index_of(k);
    bool close = false;
    for (int m = 0; m < ps.n_local() && !close; ++m)
      close = m != i && s.box().get_mi_vector(ps.pos[i], ps.pos[m]).norm() < 0.2;
    if (close)
      s.remove_particle(k);
  }
  ASSERT_GE(s.particles().n_local(), 2);
  s.compute_forces(false);
  auto const e = s.energies();
  auto const ref = brute_forces(s, c.cut);
  auto const &ps = s.particles();
  double fscale = 0.;
  for (auto const &kv : ref.f)
    fscale = std::max(fscale, kv.second.norm());
  ASSERT_GT(fscale, 0.);
  for (int i = 0; i < ps.n_local(); ++i) {
    auto const &fr = ref.f.at(ps.id[i]);
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(ps.f[i][d], fr[d], 1e-10 * fscale) << "particle " << ps.id[i];
  }
  EXPECT_NEAR(e.non_bonded, ref.energy, 1e-10 * (1. + std::abs(ref.energy)));
  // pressure tensor: virial / V, with each self-image pair counted once
  auto const pt = s.pressure_tensor();
  double const V = c.box[0] * c.box[1] * c.box[2];
  double vscale = 0.;
  for (double w : ref.virial)
    vscale = std::max(vscale, std::abs(w));
  for (int k = 0; k < 9; ++k)
    EXPECT_NEAR(pt.non_bonded[k] * V, ref.virial[k], 1e-10 * (1. + vscale)) << "component " << k;
  // Newton's third law: total force zero
  Vector3d tot{};
  for (int i = 0; i < ps.n_local(); ++i)
    tot += ps.f[i];
  EXPECT_LT(tot.norm(), 1e-10 * fscale * ps.n_local());
}

INSTANTIATE_TEST_SUITE_P(Boxes, ForcesVsBrute,
                         ::testing::Values(Case{{7., 7., 7.}, 250, 1.5, 0.4},
                                           Case{{3., 3.5, 4.}, 40, 1.9, 0.2},
                                           Case{{1.5, 1.5, 1.5}, 6, 2.0, 0.3},
                                           Case{{1., 2., 3.}, 8, 1.6, 0.1},
                                           Case{{2., 2.5, 5.}, 12, 1.7, 0.2, {true, false, true}}));
#endif

} // namespace
