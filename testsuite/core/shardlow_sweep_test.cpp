// The Shardlow pair sweep (integrators/shardlow.cpp) against a plain
// one-pass reference: every selected pair of the Verlet list in list order,
// the DPD pair's exact OU update computed and applied at once (the sweep as it
// was before session 11 split it into a position-only pre-pass, exponentials
// and square roots in their own loops, cached masses and a velocity pass).
// The split must not change a bit: the velocities after one sweep are
// compared exactly, on a periodic scene with ghosts, two types, unequal masses,
// a weight exponent k != 1, a cutoff that is not a power of two, and (with
// TRANS_DPD) transverse friction alone and with the radial one. The OU
// factors a = exp(-lambda dt) by the sweep's own exp (integrators/ou_exp.hpp,
// within 1 ulp of std::exp; session 15), whose bits every path reproduces.
#include "config/features.hpp"
#include "forces/pair_traversal.hpp"
#include "integrators/dpd_integrators.hpp"
#include "integrators/ou_exp.hpp"
#include "system/System.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#ifdef DPD
using Marble::System;
using Utils::Vector3d;

namespace {

/** The one-pass sweep: the DPD part of shardlow_sweep as it stood at main 9859bfe,
 * on the velocity array @p v (by list index; ghosts map to their owners). */
void reference_sweep(System &sys, std::vector<Vector3d> &v) {
  auto &ps = sys.particles();
  auto const &ia = sys.interactions();
  double const dt = sys.time_step();
  Marble::NoiseContext const noise = sys.noise_context(true);
  double const kT = sys.thermostat().dpd.kT;
  auto owner = [&](int k) { return k < ps.n_local() ? k : ps.ghost_owner[k - ps.n_local()]; };
  std::array<Vector3d, Marble::kPairBlock> xi;
  Marble::for_each_pair_block(ps, sys.cells().pairs(), ia, [&](Marble::PairBlock const &b) {
    Marble::draw_block_noise<Marble::DPDPair>(b, ps, ia, noise, xi);
    for (int s = 0; s < b.size; ++s) {
      int const i = b.i[s], j = b.j[s];
      Vector3d const d = ps.pos[i] - ps.pos[j];
      double const r2 = d.norm2();
      if (!(r2 > 0.))
        continue;
      Marble::DPDParams const &p = ia.get(ps.type[i], ps.type[j]).get<Marble::DPDPair>();
      if (!p.active)
        continue;
      double const r = std::sqrt(r2);
      double const w = p.radial.weight(Marble::DPDPair::gap(p, r));
#ifdef TRANS_DPD
      double const wt = p.trans.weight(Marble::DPDPair::gap(p, r));
      if (w <= 0. && wt <= 0.)
        continue;
#else
      if (w <= 0.)
        continue;
#endif
      int const oi = owner(i), oj = owner(j);
      double const mi = ps.get_mass(oi), mj = ps.get_mass(oj);
      double const mu = mi * mj / (mi + mj);
      double const mfac = Marble::dpd_mass_factor(mi, mj);
      Vector3d const e = d / r;
      Vector3d const vij = v[oi] - v[oj];
      double const u = e * vij;
      Vector3d du{};
      if (w > 0. && p.radial.gamma > 0.) {
        double const a = Marble::exp_neg(-(p.radial.gamma * mfac * w * w * dt / mu));
        double const sd = std::sqrt(12. * (kT / mu) * (1. - a * a));
        du = ((a - 1.) * u + sd * (e * xi[s])) * e;
      }
#ifdef TRANS_DPD
      if (wt > 0. && p.trans.gamma > 0.) {
        double const a = Marble::exp_neg(-(p.trans.gamma * mfac * wt * wt * dt / mu));
        double const sd = std::sqrt(12. * (kT / mu) * (1. - a * a));
        Vector3d const u_perp = vij - u * e;
        Vector3d const xi_perp = xi[s] - (e * xi[s]) * e;
        du += (a - 1.) * u_perp + sd * xi_perp;
      }
#endif
      Vector3d const dp = mu * du;
      v[oi] += dp / mi;
      v[oj] -= dp / mj;
    }
  });
}

void scene(System &s, std::uint64_t seed, bool masses) {
  double const L = 5.;
  s.set_box_l({L, L, L});
  s.set_time_step(0.04);
  s.set_skin(0.3);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0., L);
  std::normal_distribution<double> g(0., 1.);
  for (int id = 0; id < 375; ++id) {
    Marble::ParticleProperties pp;
    pp.id = id;
    pp.type = id % 3 == 0 ? 1 : 0;
    pp.pos = {u(rng), u(rng), u(rng)};
    pp.v = {g(rng), g(rng), g(rng)};
#ifdef MASS
    if (masses && id % 4 == 1)
      pp.mass = 2.5;
    if (masses && id % 7 == 2)
      pp.mass = 4.;
#else
    (void)masses;
#endif
    s.add_particle(pp);
  }
  Marble::DPDParams p00, p01, p11;
  p00.active = true, p00.radial.weight_function = 1, p00.radial.gamma = 5., p00.radial.r_cut = 1.;
  p01.active = true, p01.radial.weight_function = 1, p01.radial.gamma = 3., p01.radial.r_cut = 1.2,
  p01.radial.k = 2.;
  p11.active = true, p11.radial.weight_function = 0, p11.radial.gamma = 2., p11.radial.r_cut = 0.9;
#ifdef TRANS_DPD
  p00.trans.weight_function = 1, p00.trans.gamma = 1.5, p00.trans.r_cut = 0.8;
  p01.trans.weight_function = 0, p01.trans.gamma = 1., p01.trans.r_cut = 0.7, p01.trans.k = 2.;
  p11.radial.gamma = 0., p11.trans.weight_function = 1, p11.trans.gamma = 2., p11.trans.r_cut = 0.9;
#endif
  s.set_kernel<Marble::DPDPair>(0, 0, p00);
  s.set_kernel<Marble::DPDPair>(0, 1, p01);
  s.set_kernel<Marble::DPDPair>(1, 1, p11);
  auto &th = s.thermostat().dpd;
  th.active = true, th.seeded = true, th.kT = 1., th.seed = seed, th.philox_counter = 7;
  s.update_thermostat_prefactors();
  s.set_integrator_shardlow();
  s.ensure_lists();
}

void check_bit_for_bit(std::uint64_t seed, bool masses) {
  System s({5., 5., 5.});
  scene(s, seed, masses);
  auto &ps = s.particles();
  ASSERT_GT(ps.size(), ps.n_local()); // ghosts: pairs across the boundary
  ASSERT_GT(s.cells().pairs().size(), 1000u);
  std::vector<Vector3d> v(ps.v.begin(), ps.v.begin() + ps.n_local());
  std::vector<Vector3d> const v0 = v;
  reference_sweep(s, v);
  Marble::shardlow_sweep(s);
  int changed = 0;
  for (int k = 0; k < ps.n_local(); ++k) {
    changed += v[k] == v0[k] ? 0 : 1;
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(ps.v[k][c], v[k][c]) << "particle " << ps.id[k] << " component " << c;
  }
  EXPECT_GT(changed, ps.n_local() / 2); // the sweep did act
}

} // namespace

TEST(ShardlowSweep, BitForBitWithOnePassReferenceUnitMasses) { check_bit_for_bit(3, false); }
TEST(ShardlowSweep, BitForBitWithOnePassReferenceMixedMasses) { check_bit_for_bit(4, true); }
#endif
