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
