// The pair forces of a block in SIMD lanes (forces/pair_simd.hpp): one loop
// over the pairs of the block with no data-dependent branch (the cutoffs are
// blends), so the compiler vectorises it; built by GCC's target_clones for
// AVX2 and for the baseline x86-64 (SSE2), chosen at load time by the CPU
// (doc/benchmarks.md). Compiled without FMA contraction (src/core/CMakeLists.txt):
// both paths do the same IEEE operations, so a trajectory has the same bits on
// every x86-64 CPU. The arithmetic is that of Hat::force_over_r and
// DPDPair::force (pair_force.hpp) up to rounding (1/r once per pair instead
// of the divisions): the same to ~1e-15 relative. LennardJones::force_over_r
// with an offset is the scalar kernel's arithmetic; without one the force is
// computed from 1/r^2 (one division, no root: LAMMPS-style), the same to
// ~1e-15 relative.
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
  unsigned const hat_bit = pair_loop_bit_if_compiled<Hat>(), dpd_bit = pair_loop_bit_if_compiled<DPDPair>();
  unsigned const lj_bit = pair_loop_bit_if_compiled<LennardJones>();
  unsigned const handled = hat_bit | dpd_bit | lj_bit;
  auto const &l = ia.get<LennardJones>(); // reads as off where LENNARD_JONES is not compiled in
  if ((mask & lj_bit) && l.active) {
    out.lj = l.offset == 0. ? 1 : 2;
    out.lj_eps48 = 48. * l.epsilon, out.lj_sig2 = l.sigma * l.sigma;
    out.lj_cut = l.cutoff, out.lj_off = l.offset, out.lj_min = l.min;
  }
  auto const &h = ia.get<Hat>(); // reads as off where HAT is not compiled in
  if ((mask & hat_bit) && h.active) {
    out.hat = true;
    out.hat_fmax = h.F_max, out.hat_cut = h.cutoff, out.hat_off = h.offset;
  }
  auto const &d = ia.get<DPDPair>();
  if ((mask & dpd_bit) && d.active) {
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
  // any other kernel of the mask active for this pair: no SIMD form
  bool other = false;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if ((mask & pair_loop_bit<K>) && !(handled & pair_loop_bit<K>) && ia.get<K>().active)
      other = true;
  });
  return !other;
}

bool simd_scene_params(InteractionTable const &ia, unsigned mask, SimdPairParams &out) {
  int const nt = ia.n_types();
  bool found = false;
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < nt; ++b) {
      IAParams const &p = ia.get(a, b);
      if (!(p.max_cut2 > 0.))
        continue; // never selected from the list
      SimdPairParams q;
      if (!simd_pair_params(p, mask, q))
        return false;
      if (found && !(q == out))
        return false;
      out = q;
      found = true;
    }
  return found;
}

namespace {

/** The loop body for one set of switches (hoisted out of the loop so that
 * it has no branch left and vectorises). */
template <int Lj, bool Hat, bool Dpd, bool Trans, bool Mass>
[[gnu::always_inline]] inline void block_forces(SimdPairParams const &p, int n, PairBlockSoA &b) {
  double const eps48 = p.lj_eps48, sig2 = p.lj_sig2, lcut = p.lj_cut, loff = p.lj_off, lmin = p.lj_min;
  double const lcut2 = lcut * lcut, lmin2 = lmin * lmin;
  double const fmax = p.hat_fmax, hcut = p.hat_cut, hoff = p.hat_off;
  double const doff = p.dpd_off, gamma = p.gamma, rc = p.rc, pref = p.pref;
  double const tgamma = p.tgamma, trc = p.trc, tpref = p.tpref;
  bool const wf1 = p.wf == 1, twf1 = p.twf == 1;
  // wf 0: w = 1 - 0 (x / 1); a zero r_cut divides by 1 (its w is 0 anyway)
  double const rc_div = wf1 && rc > 0. ? rc : 1., trc_div = twf1 && trc > 0. ? trc : 1.;
  double const wsel = wf1 ? 1. : 0., twsel = twf1 ? 1. : 0.;
  double *__restrict const fxo = b.fx, *__restrict const fyo = b.fy, *__restrict const fzo = b.fz;
  double const *__restrict const dxs = b.dx, *__restrict const dys = b.dy, *__restrict const dzs = b.dz;
  double const *__restrict const vxs = b.vx, *__restrict const vys = b.vy, *__restrict const vzs = b.vz;
  double const *__restrict const xxs = b.xx, *__restrict const xys = b.xy, *__restrict const xzs = b.xz;
  double const *__restrict const ms = b.m;
  for (int s = 0; s < n; ++s) {
    double const dx = dxs[s], dy = dys[s], dz = dzs[s];
    double const r2 = dx * dx + dy * dy + dz * dz;
    constexpr bool need_r = Hat || Dpd || Lj == 2;
    double const r = need_r ? std::sqrt(r2) : 0.;
    // 1/r, 0 at r = 0; a NaN distance stays NaN (the force check reports it).
    // Selects between constants and always-safe divisions: no branch is left.
    double const nz = r != 0. ? 1. : 0.;
    double const rinv = (Hat || Dpd) ? nz / (r + (1. - nz)) : 0.;
    double fac = 0.; // the conservative kernels' force / r, in kernel-list order (LJ, hat)
    if constexpr (Lj == 1) {
      // LennardJones::force_over_r at offset 0 from r^2: inside min < r < cutoff
      // (a NaN distance is inside: it stays NaN), 1/r^2 of 1 outside
      bool const in = !(r2 >= lcut2) && !(r2 <= lmin2);
      double const r2inv = 1. / (in ? r2 : 1.);
      double const q2 = sig2 * r2inv;
      double const q6 = q2 * q2 * q2;
      fac = in ? eps48 * q6 * (q6 - 0.5) * r2inv : 0.;
    } else if constexpr (Lj == 2) {
      // the scalar kernel's operations, roff = r - offset and roff * r of 1 outside
      double const roff = r - loff;
      bool const in = !(roff >= lcut) && !(roff <= lmin);
      double const rs = in ? roff : 1.;
      double const q2 = sig2 / (rs * rs);
      double const q6 = q2 * q2 * q2;
      fac = in ? eps48 * q6 * (q6 - 0.5) / (rs * r) : 0.;
    }
    if constexpr (Hat) {
      double const x = r - hoff;
      double const in = !(x >= hcut) ? 1. : 0.;
      double const fh = in * (fmax * (1. - x / hcut) * rinv);
      fac = Lj != 0 ? fac + fh : fh;
    }
    double fx = 0., fy = 0., fz = 0.;
    if constexpr (Lj != 0 || Hat)
      fx = fac * dx, fy = fac * dy, fz = fac * dz;
    if constexpr (Dpd) {
      double const ex = dx * rinv, ey = dy * rinv, ez = dz * rinv;
      double const vx = vxs[s], vy = vys[s], vz = vzs[s];
      double const xx = xxs[s], xy = xys[s], xz = xzs[s];
      double const ev = ex * vx + ey * vy + ez * vz;
      double const exi = ex * xx + ey * xy + ez * xz;
      double const mf = Mass ? ms[s] : 1.;
      double const sq_m = Mass ? std::sqrt(mf) : 1.;
      double const x = std::max(r - doff, 0.);
      double const w = (!(x >= rc) ? 1. : 0.) * (1. - wsel * (x / rc_div));
      double const mag = -gamma * mf * w * w * ev + pref * sq_m * w * exi;
      fx += mag * ex, fy += mag * ey, fz += mag * ez;
      if constexpr (Trans) {
        double const wt = (!(x >= trc) ? 1. : 0.) * (1. - twsel * (x / trc_div));
        double const a = -tgamma * mf * wt * wt, c = tpref * sq_m * wt;
        fx += a * (vx - ev * ex) + c * (xx - exi * ex);
        fy += a * (vy - ev * ey) + c * (xy - exi * ey);
        fz += a * (vz - ev * ez) + c * (xz - exi * ez);
      }
    }
    fxo[s] = fx, fyo[s] = fy, fzo[s] = fz;
  }
}

} // namespace

// one case per set of switches: LJ (0, 1, 2) x hat x {none, DPD, +TRANS} (x mass)
#define MARBLE_BLOCK_CASE(L, H, D, T, M)                                                             \
  case 16u * (L) + 1u * (H) + 2u * (D) + 4u * (T) + 8u * (M):                                      \
    return block_forces<L, H, D, T, M>(p, n, b);
#define MARBLE_BLOCK_CASES_DPD(L, H, M)                                                              \
  MARBLE_BLOCK_CASE(L, H, true, false, M)                                                            \
  MARBLE_BLOCK_CASE(L, H, true, true, M)
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
#define MARBLE_BLOCK_CASES(L, H)                                                                     \
  MARBLE_BLOCK_CASES_DPD(L, H, false)                                                                \
  MARBLE_BLOCK_CASES_DPD(L, H, true)
#else
#define MARBLE_BLOCK_CASES(L, H) MARBLE_BLOCK_CASES_DPD(L, H, false)
#endif

MARBLE_PAIR_SIMD_CLONES
void pair_block_forces(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
  unsigned const sw = 16u * static_cast<unsigned>(p.lj) | (p.hat ? 1u : 0u) | (p.dpd ? 2u : 0u) |
                      (p.dpd && p.trans ? 4u : 0u) | (p.dpd && mass ? 8u : 0u);
  switch (sw) {
    MARBLE_BLOCK_CASE(0, true, false, false, false)
    MARBLE_BLOCK_CASE(1, false, false, false, false)
    MARBLE_BLOCK_CASE(1, true, false, false, false)
    MARBLE_BLOCK_CASE(2, false, false, false, false)
    MARBLE_BLOCK_CASE(2, true, false, false, false)
    MARBLE_BLOCK_CASES(0, false)
    MARBLE_BLOCK_CASES(0, true)
    MARBLE_BLOCK_CASES(1, false)
    MARBLE_BLOCK_CASES(1, true)
    MARBLE_BLOCK_CASES(2, false)
    MARBLE_BLOCK_CASES(2, true)
  default:
    for (int s = 0; s < n; ++s)
      b.fx[s] = b.fy[s] = b.fz[s] = 0.;
  }
}
#undef MARBLE_BLOCK_CASES
#undef MARBLE_BLOCK_CASES_DPD
#undef MARBLE_BLOCK_CASE

} // namespace Marble
