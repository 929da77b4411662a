// The SIMD block forces (forces/pair_simd.cpp) of the Groot-Warren hat and
// the DPD pair thermostat (weight function 1) against the same arithmetic
// written out here with the divisions by the cutoffs, bit for bit: with a
// power-of-two cutoff (r_c = 1, 0.5, 2) the block multiplies by the exact
// reciprocal instead, which must give the division's bits; with another
// cutoff (0.7, 1.3) it divides.
#include "forces/pair_simd.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/** block_forces<Lj = 0, Hat, Dpd = true, Trans = false, Mass = false> with
 * divisions, pair @p s of @p b. */
void reference(Marble::SimdPairParams const &p, Marble::PairBlockSoA const &b, int s, double &fx, double &fy,
               double &fz) {
  double const dx = b.dx[s], dy = b.dy[s], dz = b.dz[s];
  double const r2 = dx * dx + dy * dy + dz * dz;
  double const r = std::sqrt(r2);
  double const nz = r != 0. ? 1. : 0.;
  double const rinv = nz / (r + (1. - nz));
  fx = fy = fz = 0.;
  if (p.hat) {
    double const x = r - p.hat_off;
    double const in = !(x >= p.hat_cut) ? 1. : 0.;
    double const fac = in * (p.hat_fmax * (1. - x / p.hat_cut) * rinv);
    fx = fac * dx, fy = fac * dy, fz = fac * dz;
  }
  double const ex = dx * rinv, ey = dy * rinv, ez = dz * rinv;
  double const ev = ex * b.vx[s] + ey * b.vy[s] + ez * b.vz[s];
  double const exi = ex * b.xx[s] + ey * b.xy[s] + ez * b.xz[s];
  double const mf = 1., sq_m = 1.;
  double const x = std::max(r - p.dpd_off, 0.);
  double const w = (!(x >= p.rc) ? 1. : 0.) * (1. - 1. * (x / p.rc));
  double const mag = -p.gamma * mf * w * w * ev + p.pref * sq_m * w * exi;
  fx += mag * ex, fy += mag * ey, fz += mag * ez;
}

} // namespace

TEST(PairForces, CutoffReciprocalKeepsBits) {
  std::mt19937_64 g(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5), n(-2., 2.);
  for (double rc : {1., 0.5, 2., 0.7, 1.3})
    for (bool hat : {false, true}) {
      Marble::SimdPairParams p;
      p.dpd = true, p.wf = 1, p.gamma = 4.5, p.rc = rc, p.pref = 3.7;
      if (hat)
        p.hat = true, p.hat_fmax = 25., p.hat_cut = rc, p.hat_off = 0.;
      auto B = std::make_unique<Marble::PairBlockSoA>();
      int const nb = 203;
      for (int s = 0; s < nb; ++s) {
        B->dx[s] = rc * u(g), B->dy[s] = rc * u(g), B->dz[s] = rc * u(g);
        B->vx[s] = n(g), B->vy[s] = n(g), B->vz[s] = n(g);
        B->xx[s] = n(g), B->xy[s] = n(g), B->xz[s] = n(g);
        B->m[s] = 1.;
      }
      B->dx[7] = B->dy[7] = B->dz[7] = 0.; // r = 0
      Marble::pair_block_forces(p, false, nb, *B);
      int inside = 0;
      for (int s = 0; s < nb; ++s) {
        double fx, fy, fz;
        reference(p, *B, s, fx, fy, fz);
        ASSERT_TRUE(same_bits(B->fx[s], fx) && same_bits(B->fy[s], fy) && same_bits(B->fz[s], fz))
            << "r_c " << rc << " hat " << hat << " pair " << s;
        inside += fx != 0. ? 1 : 0;
      }
      EXPECT_GT(inside, nb / 10); // the test sees pairs inside the cutoff
    }
}

// Every build of the block forces this CPU runs (baseline x86-64, AVX2,
// AVX-512 F) gives the baseline's bits, for every set of switches (LJ
// without and with an offset, hat, DPD with both weight functions, TRANS_DPD,
// the mass factor), with a power-of-two cutoff and another, at r = 0, with
// a NaN distance, and for block lengths that end inside a vector.
TEST(PairForces, BuildsAgreeBitForBit) {
  auto const paths = Marble::pair_block_forces_paths();
  ASSERT_GE(paths.size(), 1u);
  std::mt19937_64 g(17);
  std::uniform_real_distribution<double> u(-1.5, 1.5), n(-2., 2.), m(0.3, 3.);
  int checked = 0;
  for (double rc : {1., 1.3})
    for (int lj : {0, 1, 2})
      for (int hat = 0; hat < 2; ++hat)
        for (int dpd = 0; dpd < 3; ++dpd) // off, DPD, DPD + TRANS_DPD
          for (int mass = 0; mass < 2; ++mass) {
            Marble::SimdPairParams p;
            if (lj != 0)
              p.lj = lj, p.lj_eps48 = 48., p.lj_sig2 = 0.81, p.lj_cut = 1.2 * rc, p.lj_off = lj == 2 ? 0.1 : 0.,
              p.lj_min = lj == 2 ? 0.05 : 0.;
            if (hat)
              p.hat = true, p.hat_fmax = 25., p.hat_cut = rc, p.hat_off = 0.;
            if (dpd != 0) {
              p.dpd = true, p.wf = mass ? 0 : 1, p.gamma = 4.5, p.rc = rc, p.pref = 3.7;
              if (dpd == 2)
                p.trans = true, p.twf = 1, p.tgamma = 2., p.trc = 0.8 * rc, p.tpref = 1.9;
            }
            for (int nb : {1, 7, 203}) {
              auto A = std::make_unique<Marble::PairBlockSoA>();
              for (int s = 0; s < nb; ++s) {
                A->dx[s] = rc * u(g), A->dy[s] = rc * u(g), A->dz[s] = rc * u(g);
                A->vx[s] = n(g), A->vy[s] = n(g), A->vz[s] = n(g);
                A->xx[s] = n(g), A->xy[s] = n(g), A->xz[s] = n(g);
                A->m[s] = m(g);
              }
              if (nb > 10) {
                A->dx[7] = A->dy[7] = A->dz[7] = 0.;                      // r = 0
                A->dy[9] = std::numeric_limits<double>::quiet_NaN(); // kept by the select: stays NaN
              }
              auto ref = std::make_unique<Marble::PairBlockSoA>(*A);
              paths[0].forces(p, mass != 0, nb, *ref);
              for (auto const &path : paths) {
                auto B = std::make_unique<Marble::PairBlockSoA>(*A);
                path.forces(p, mass != 0, nb, *B);
                for (int s = 0; s < nb; ++s)
                  ASSERT_TRUE(same_bits(B->fx[s], ref->fx[s]) && same_bits(B->fy[s], ref->fy[s]) &&
                              same_bits(B->fz[s], ref->fz[s]))
                      << path.name << " lj " << lj << " hat " << hat << " dpd " << dpd << " mass " << mass
                      << " nb " << nb << " pair " << s;
              }
              ++checked;
            }
          }
  EXPECT_EQ(checked, 2 * 3 * 2 * 3 * 2 * 3);
}
