// The pair forces of a block in SIMD lanes (forces/pair_simd.hpp): one loop
// over the pairs of the block with no data-dependent branch (the cutoffs are
// blends), so the compiler vectorises it; built by GCC's target_clones for
// AVX2 and for the baseline x86-64 (SSE2), chosen at load time by the CPU
// (doc/benchmarks.md). Compiled without FMA contraction (src/core/CMakeLists.txt):
// both paths do the same IEEE operations, so a trajectory has the same bits on
// every x86-64 CPU. The arithmetic is that of Hat::force_over_r and
// DPDPair::force (pair_force.hpp) up to rounding (1/r once per pair instead
// of the divisions): the same to ~1e-15 relative.
#include "forces/pair_simd.hpp"

#include "nonbonded/registry.hpp"

#include <cmath>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MARBLE_PAIR_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MARBLE_PAIR_SIMD_CLONES
#endif

namespace Marble {

bool simd_pair_params(IAParams const &ia, unsigned mask, SimdPairParams &out) {
  out = {};
  unsigned handled = 0;
  if constexpr (compiled<Hat>) {
    handled |= pair_loop_bit<Hat>;
    auto const &h = ia.get<Hat>();
    if ((mask & pair_loop_bit<Hat>) && h.active) {
      out.hat = true;
      out.hat_fmax = h.F_max, out.hat_cut = h.cutoff, out.hat_off = h.offset;
    }
  }
  if constexpr (compiled<DPDPair>) {
    handled |= pair_loop_bit<DPDPair>;
    auto const &d = ia.get<DPDPair>();
    if ((mask & pair_loop_bit<DPDPair>) && d.active) {
      auto ok = [](DPDWeight const &w) { return w.weight_function == 0 || (w.weight_function == 1 && w.k == 1.); };
      if (!ok(d.radial))
        return false;
      out.dpd = true;
      out.dpd_off = d.offset;
      out.wf = d.radial.weight_function, out.gamma = d.radial.gamma, out.rc = d.radial.r_cut;
      out.pref = d.radial.pref_noise;
#ifdef TRANS_DPD
      if (d.trans.gamma > 0.) {
        if (!ok(d.trans))
          return false;
        out.trans = true;
        out.twf = d.trans.weight_function, out.tgamma = d.trans.gamma, out.trc = d.trans.r_cut;
        out.tpref = d.trans.pref_noise;
      }
#endif
    }
  }
  // any other kernel of the mask active for this pair: no SIMD form
  bool other = false;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if ((mask & pair_loop_bit<K>) && !(handled & pair_loop_bit<K>) && ia.get<K>().active)
      other = true;
  });
  return !other;
}

MARBLE_PAIR_SIMD_CLONES
void pair_block_forces(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
  bool const hat = p.hat, dpd = p.dpd, trans = p.trans;
  double const fmax = p.hat_fmax, hcut = p.hat_cut, hoff = p.hat_off;
  double const doff = p.dpd_off, gamma = p.gamma, rc = p.rc, pref = p.pref;
  double const tgamma = p.tgamma, trc = p.trc, tpref = p.tpref;
  bool const wf1 = p.wf == 1, twf1 = p.twf == 1;
  for (int s = 0; s < n; ++s) {
    double const dx = b.dx[s], dy = b.dy[s], dz = b.dz[s];
    double const r = std::sqrt(dx * dx + dy * dy + dz * dz);
    double const rinv = r != 0. ? 1. / r : 0.; // a NaN distance stays NaN (the force check)
    double fac = 0.;
    if (hat) {
      double const x = r - hoff;
      fac = !(x >= hcut) ? fmax * (1. - x / hcut) * rinv : 0.;
    }
    double fx = fac * dx, fy = fac * dy, fz = fac * dz;
    if (dpd) {
      double const ex = dx * rinv, ey = dy * rinv, ez = dz * rinv;
      double const vx = b.vx[s], vy = b.vy[s], vz = b.vz[s];
      double const xx = b.xx[s], xy = b.xy[s], xz = b.xz[s];
      double const ev = ex * vx + ey * vy + ez * vz;
      double const exi = ex * xx + ey * xy + ez * xz;
      double const mf = mass ? b.m[s] : 1.;
      double const sq_m = mass ? std::sqrt(mf) : 1.;
      double const x = std::max(r - doff, 0.);
      double const w = !(x >= rc) ? (wf1 ? 1. - x / rc : 1.) : 0.;
      double const mag = -gamma * mf * w * w * ev + pref * sq_m * w * exi;
      fx += mag * ex, fy += mag * ey, fz += mag * ez;
      if (trans) {
        double const wt = !(x >= trc) ? (twf1 ? 1. - x / trc : 1.) : 0.;
        double const a = -tgamma * mf * wt * wt, c = tpref * sq_m * wt;
        fx += a * (vx - ev * ex) + c * (xx - exi * ex);
        fy += a * (vy - ev * ey) + c * (xy - exi * ey);
        fz += a * (vz - ev * ez) + c * (xz - exi * ez);
      }
    }
    b.fx[s] = fx, b.fy[s] = fy, b.fz[s] = fz;
  }
}

} // namespace Marble
