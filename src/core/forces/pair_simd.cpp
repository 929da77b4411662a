// The pair forces of a block in SIMD lanes (forces/pair_simd.hpp): one loop
// over the pairs of the block with no data-dependent branch (the cutoffs are
// blends), so the compiler vectorises it; built for AVX-512 F (zmm), AVX2
// and the baseline x86-64 (SSE2), chosen once by the CPU (Utils::cpu_prefers_zmm,
// cpu_has_avx2; doc/benchmarks.md). Compiled without FMA contraction
// (src/core/CMakeLists.txt): every path does the same IEEE operations, so a
// trajectory has the same bits on every x86-64 CPU. The arithmetic is that of Hat::force_over_r and
// DPDPair::force (pair_force.hpp) up to rounding (1/r once per pair instead
// of the divisions): the same to ~1e-15 relative. LennardJones::force_over_r
// with an offset is the scalar kernel's arithmetic; without one the force is
// computed from 1/r^2 (one division, no root: LAMMPS-style), the same to
// ~1e-15 relative.
#include "forces/pair_simd.hpp"

#include "nonbonded/registry.hpp"
#include "utils/cpu.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MARBLE_PAIR_SELECT_AVX2 1
#define MARBLE_PAIR_SIMD_TARGETS 1
#include <immintrin.h>
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
 * it has no branch left and vectorises). Pow2: the cutoffs the kernels
 * divide by (hat cutoff, DPD weight ranges) are powers of two (e.g. r_c = 1,
 * exact_reciprocal): each division by one is a multiplication by its exact
 * reciprocal, the same bits at a fraction of the cost (a vector division
 * takes the divider ~5 cycles, as long as the rest of a DPD pair). */
template <int Lj, bool Hat, bool Dpd, bool Trans, bool Mass, bool Pow2>
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
  // the reciprocals (used where Pow2: exact)
  double const rc_inv = 1. / rc_div, trc_inv = 1. / trc_div, hcut_inv = 1. / hcut;
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
      double const in = (!(r2 >= lcut2) ? 1. : 0.) * (!(r2 <= lmin2) ? 1. : 0.);
      double const r2inv = 1. / (in * r2 + (1. - in));
      double const q2 = sig2 * r2inv;
      double const q6 = q2 * q2 * q2;
      fac = in * (eps48 * q6 * (q6 - 0.5) * r2inv);
    } else if constexpr (Lj == 2) {
      // the scalar kernel's operations, roff = r - offset and roff * r of 1 outside
      double const roff = r - loff;
      double const in = (!(roff >= lcut) ? 1. : 0.) * (!(roff <= lmin) ? 1. : 0.);
      double const rs = in * roff + (1. - in), rr = in * r + (1. - in);
      double const q2 = sig2 / (rs * rs);
      double const q6 = q2 * q2 * q2;
      fac = in * (eps48 * q6 * (q6 - 0.5) / (rs * rr));
    }
    if constexpr (Hat) {
      double const x = r - hoff;
      double const in = !(x >= hcut) ? 1. : 0.;
      double const fh = in * (fmax * (1. - (Pow2 ? x * hcut_inv : x / hcut)) * rinv);
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
      double const w = (!(x >= rc) ? 1. : 0.) * (1. - wsel * (Pow2 ? x * rc_inv : x / rc_div));
      double const mag = -gamma * mf * w * w * ev + pref * sq_m * w * exi;
      fx += mag * ex, fy += mag * ey, fz += mag * ez;
      if constexpr (Trans) {
        double const wt = (!(x >= trc) ? 1. : 0.) * (1. - twsel * (Pow2 ? x * trc_inv : x / trc_div));
        double const a = -tgamma * mf * wt * wt, c = tpref * sq_m * wt;
        fx += a * (vx - ev * ex) + c * (xx - exi * ex);
        fy += a * (vy - ev * ey) + c * (xy - exi * ey);
        fz += a * (vz - ev * ez) + c * (xz - exi * ez);
      }
    }
    fxo[s] = fx, fyo[s] = fy, fzo[s] = fz;
  }
}

/** Listed pairs prefetched ahead of the select: the list (8 bytes a pair,
 * ~11-12 MB for 32 000 LJ atoms) streams from memory; 2 KB ahead gave ~5 % on
 * the LJ bench (doc/benchmarks.md), prefetching the j positions nothing. */
constexpr int kListAhead = 256;

/** Prefetch the listed pairs kListAhead after @p p. The address may lie past
 * the list: a prefetch does not fault, and it is formed as an integer (no
 * out-of-bounds pointer arithmetic). */
inline void prefetch_ahead(std::array<int, 2> const *p) {
  __builtin_prefetch(reinterpret_cast<void const *>(reinterpret_cast<std::uintptr_t>(p) +
                                                    kListAhead * sizeof(std::array<int, 2>)));
}

/** The scalar select (the reference for the AVX2 one): per listed pair the
 * pair and d are stored at slot n, which advances only for a pair in range.
 * The position of i is loaded once per run of its pairs (the list is built
 * per particle i). */
template <bool OneType>
int select_scalar(std::array<int, 2> const *__restrict blk, int q0, int nb, Utils::Vector3d const *__restrict pos,
                  int const *__restrict typ, double const *__restrict cut2_table, int nt,
                  std::array<int, 2> *__restrict bij, PairBlockSoA &B, int n) {
  double const cut2 = cut2_table[0];
  double *__restrict const dxs = B.dx, *__restrict const dys = B.dy, *__restrict const dzs = B.dz;
  int ci = -1;
  double xi = 0., yi = 0., zi = 0.;
  for (int q = q0; q < nb; ++q) {
    if ((q & 7) == 0)
      prefetch_ahead(blk + q);
    std::array<int, 2> const pr = blk[q];
    int const i = pr[0], j = pr[1];
    if (i != ci) // a new run of pairs of one i (predictable: runs are long)
      ci = i, xi = pos[i][0], yi = pos[i][1], zi = pos[i][2];
    double const dx = xi - pos[j][0], dy = yi - pos[j][1], dz = zi - pos[j][2];
    bij[n] = pr;
    dxs[n] = dx, dys[n] = dy, dzs[n] = dz;
    double const c2 = OneType ? cut2 : cut2_table[typ[i] * nt + typ[j]];
    n += !(dx * dx + dy * dy + dz * dz >= c2) ? 1 : 0;
  }
  return n;
}

int select_scalar_one_type(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, double cut2,
                           std::array<int, 2> *bij, PairBlockSoA &B) {
  double const cut2_table[1] = {cut2};
  return select_scalar<true>(blk, 0, nb, pos, nullptr, cut2_table, 1, bij, B, 0);
}

/** pair_block_gather_dpd, scalar, from pair @p s0 on. */
void gather_dpd_scalar_from(int s0, std::array<int, 2> const *__restrict bij, int n, Rec4 const *__restrict vel,
                            int const *__restrict pid, PairBlockSoA &B, std::uint32_t *__restrict lo,
                            std::uint32_t *__restrict hi, double *__restrict sign) {
  for (int s = s0; s < n; ++s) {
    int const i = bij[s][0], j = bij[s][1];
    double const *const vi = vel[i].v, *const vj = vel[j].v;
    B.vx[s] = vi[0] - vj[0], B.vy[s] = vi[1] - vj[1], B.vz[s] = vi[2] - vj[2];
    order_pair_ids(pid[i], pid[j], lo[s], hi[s], sign[s]);
  }
}

void gather_dpd_scalar(std::array<int, 2> const *bij, int n, Rec4 const *vel, int const *pid, PairBlockSoA &B,
                       std::uint32_t *lo, std::uint32_t *hi, double *sign) {
  gather_dpd_scalar_from(0, bij, n, vel, pid, B, lo, hi, sign);
}

/** pair_block_scatter, scalar (the reference for the AVX2 one). */
void scatter_scalar(std::array<int, 2> const *__restrict bij, int n, PairBlockSoA const &B, Force4 *__restrict f4) {
  for (int s = 0; s < n; ++s) {
    double *const fi = f4[bij[s][0]].v, *const fj = f4[bij[s][1]].v;
    double const fx = B.fx[s], fy = B.fy[s], fz = B.fz[s];
    fi[0] += fx, fi[1] += fy, fi[2] += fz;
    fj[0] -= fx, fj[1] -= fy, fj[2] -= fz;
  }
}

/** pair_rows_select, scalar (the reference for the AVX2 one). */
template <bool OneType>
int rows_select_scalar(int const *__restrict row_start, int const *__restrict pj, int n_rows, RowCursor &c,
                       int limit, Utils::Vector3d const *__restrict pos, int const *__restrict typ,
                       double const *__restrict cut2_table, int nt, std::array<int, 2> *__restrict bij,
                       PairBlockSoA &B) {
  double *__restrict const dxs = B.dx, *__restrict const dys = B.dy, *__restrict const dzs = B.dz;
  double const cut2_one = cut2_table[0];
  int n = 0, i = c.i, k = c.k;
  for (; i < n_rows; ++i) {
    int const k1 = row_start[i + 1];
    if (k >= k1)
      continue;
    double const xi = pos[i][0], yi = pos[i][1], zi = pos[i][2];
    double const *const c2row = OneType ? nullptr : cut2_table + typ[i] * nt;
    for (; k < k1; ++k) {
      if (n > limit) {
        c = {i, k};
        return n;
      }
      int const j = pj[k];
      double const dx = xi - pos[j][0], dy = yi - pos[j][1], dz = zi - pos[j][2];
      bij[n] = {i, j};
      dxs[n] = dx, dys[n] = dy, dzs[n] = dz;
      double const c2 = OneType ? cut2_one : c2row[typ[j]];
      n += !(dx * dx + dy * dy + dz * dz >= c2) ? 1 : 0;
    }
  }
  c = {i, k};
  return n;
}

int rows_select_scalar_one_type(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                                Utils::Vector3d const *pos, double cut2, std::array<int, 2> *bij,
                                PairBlockSoA &B) {
  double const cut2_table[1] = {cut2};
  return rows_select_scalar<true>(row_start, pj, n_rows, c, limit, pos, nullptr, cut2_table, 1, bij, B);
}

#ifdef MARBLE_PAIR_SELECT_AVX2
/** Lane permutation (as 32-bit words) that moves the selected 64-bit lanes of
 * a 4-bit mask to the front, in order. */
struct CompressTable {
  alignas(32) std::int32_t idx[16][8];
  constexpr CompressTable() : idx{} {
    for (int m = 0; m < 16; ++m) {
      int k = 0;
      for (int l = 0; l < 4; ++l)
        if (m & (1 << l))
          idx[m][2 * k] = 2 * l, idx[m][2 * k + 1] = 2 * l + 1, ++k;
      for (; k < 4; ++k)
        idx[m][2 * k] = 0, idx[m][2 * k + 1] = 1;
    }
  }
};
constexpr CompressTable kCompress{};

/** (x, y, z) of four particles as three vectors of their x, y and z. */
__attribute__((target("avx2"), always_inline)) inline void load4(Utils::Vector3d const *__restrict pos, int a,
                                                                  int b, int c, int d, __m256d &x, __m256d &y,
                                                                  __m256d &z) {
  double const *pa = pos[a].data(), *pb = pos[b].data(), *pc = pos[c].data(), *pd = pos[d].data();
  __m256d const ac = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pa)), _mm_loadu_pd(pc), 1);
  __m256d const bd = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(pb)), _mm_loadu_pd(pd), 1);
  x = _mm256_unpacklo_pd(ac, bd); // xa xb xc xd
  y = _mm256_unpackhi_pd(ac, bd);
  __m128d const zab = _mm_loadh_pd(_mm_load_sd(pa + 2), pb + 2);
  __m128d const zcd = _mm_loadh_pd(_mm_load_sd(pc + 2), pd + 2);
  z = _mm256_insertf128_pd(_mm256_castpd128_pd256(zab), zcd, 1);
}

/** select_scalar<OneType> four listed pairs at a time: d in lanes (the same
 * IEEE subtractions, products and sums, no FMA), the in-range mask, and the
 * selected lanes stored compressed (each store writes four lanes from slot
 * n; n <= q, so it stays inside the block's arrays). With several types
 * (!OneType) each lane's cut^2 comes from the table (typ[i] nt + typ[j]) by
 * four scalar loads: vpgather measured slower here (doc/benchmarks.md,
 * session 14). */
template <bool OneType>
__attribute__((target("avx2"))) int select_avx2(std::array<int, 2> const *__restrict blk, int nb,
                                                Utils::Vector3d const *__restrict pos, int const *__restrict typ,
                                                double const *__restrict cut2_table, int nt,
                                                std::array<int, 2> *__restrict bij, PairBlockSoA &B) {
  __m256d const c2one = _mm256_set1_pd(cut2_table[0]);
  int n = 0, q = 0;
  for (; q + 4 <= nb; q += 4) {
    prefetch_ahead(blk + q);
    int const i0 = blk[q][0], i1 = blk[q + 1][0], i2 = blk[q + 2][0], i3 = blk[q + 3][0];
    __m256d xi, yi, zi, xj, yj, zj;
    if (i0 == i3 && i1 == i0 && i2 == i0) { // one run of i (the common case)
      xi = _mm256_broadcast_sd(&pos[i0][0]), yi = _mm256_broadcast_sd(&pos[i0][1]);
      zi = _mm256_broadcast_sd(&pos[i0][2]);
    } else {
      load4(pos, i0, i1, i2, i3, xi, yi, zi);
    }
    load4(pos, blk[q][1], blk[q + 1][1], blk[q + 2][1], blk[q + 3][1], xj, yj, zj);
    __m256d const dx = _mm256_sub_pd(xi, xj), dy = _mm256_sub_pd(yi, yj), dz = _mm256_sub_pd(zi, zj);
    __m256d const r2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    __m256d c2 = c2one;
    if constexpr (!OneType)
      c2 = _mm256_setr_pd(cut2_table[typ[i0] * nt + typ[blk[q][1]]], cut2_table[typ[i1] * nt + typ[blk[q + 1][1]]],
                          cut2_table[typ[i2] * nt + typ[blk[q + 2][1]]],
                          cut2_table[typ[i3] * nt + typ[blk[q + 3][1]]]);
    // !(r2 >= cut2), true for a NaN
    int const m = _mm256_movemask_pd(_mm256_cmp_pd(r2, c2, _CMP_NGE_UQ));
    __m256i const perm = _mm256_load_si256(reinterpret_cast<__m256i const *>(kCompress.idx[m]));
    __m256i const prs = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(blk + q));
    _mm256_storeu_si256(reinterpret_cast<__m256i *>(bij + n), _mm256_permutevar8x32_epi32(prs, perm));
    _mm256_storeu_pd(B.dx + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dx), perm)));
    _mm256_storeu_pd(B.dy + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dy), perm)));
    _mm256_storeu_pd(B.dz + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dz), perm)));
    n += std::popcount(static_cast<unsigned>(m));
  }
  return select_scalar<OneType>(blk, q, nb, pos, typ, cut2_table, nt, bij, B, n);
}

int select_avx2_one_type(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, double cut2,
                         std::array<int, 2> *bij, PairBlockSoA &B) {
  double const cut2_table[1] = {cut2};
  return select_avx2<true>(blk, nb, pos, nullptr, cut2_table, 1, bij, B);
}

/** rows_select_scalar<OneType> four listed pairs of a row at a time: r_i
 * broadcast once per row, the row's last group masked to its length (the
 * list is padded by valid indices, so the extra lanes read valid particles),
 * the same IEEE operations as the scalar select; with several types the
 * row's line of the cutoff table and the partners' types by scalar loads. */
template <bool OneType>
__attribute__((target("avx2"))) int rows_select_avx2(int const *__restrict row_start, int const *__restrict pj,
                                                     int n_rows, RowCursor &c, int limit,
                                                     Utils::Vector3d const *__restrict pos,
                                                     int const *__restrict typ, double const *__restrict cut2_table,
                                                     int nt, std::array<int, 2> *__restrict bij, PairBlockSoA &B) {
  __m256d const c2one = _mm256_set1_pd(cut2_table[0]);
  int n = 0, i = c.i, k = c.k;
  for (; i < n_rows; ++i) {
    int const k1 = row_start[i + 1];
    if (k >= k1)
      continue;
    __m256d const xi = _mm256_broadcast_sd(&pos[i][0]), yi = _mm256_broadcast_sd(&pos[i][1]),
                  zi = _mm256_broadcast_sd(&pos[i][2]);
    __m128i const iv = _mm_set1_epi32(i);
    double const *const c2row = OneType ? nullptr : cut2_table + typ[i] * nt;
    for (; k < k1; k += 4) {
      if (n > limit) {
        c = {i, k};
        return n;
      }
      if ((k & 15) == 0)
        __builtin_prefetch(pj + k + 256);
      __m256d xj, yj, zj;
      load4(pos, pj[k], pj[k + 1], pj[k + 2], pj[k + 3], xj, yj, zj);
      __m256d const dx = _mm256_sub_pd(xi, xj), dy = _mm256_sub_pd(yi, yj), dz = _mm256_sub_pd(zi, zj);
      __m256d const r2 =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      __m256d c2 = c2one;
      if constexpr (!OneType)
        c2 = _mm256_setr_pd(c2row[typ[pj[k]]], c2row[typ[pj[k + 1]]], c2row[typ[pj[k + 2]]], c2row[typ[pj[k + 3]]]);
      int const rem = k1 - k;
      // !(r2 >= cut2), true for a NaN; lanes past the row's end off
      int const m = _mm256_movemask_pd(_mm256_cmp_pd(r2, c2, _CMP_NGE_UQ)) & (rem >= 4 ? 15 : (1 << rem) - 1);
      __m256i const perm = _mm256_load_si256(reinterpret_cast<__m256i const *>(kCompress.idx[m]));
      __m128i const js = _mm_loadu_si128(reinterpret_cast<__m128i const *>(pj + k));
      __m256i const ij = _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_unpacklo_epi32(iv, js)),
                                                 _mm_unpackhi_epi32(iv, js), 1);
      _mm256_storeu_si256(reinterpret_cast<__m256i *>(bij + n), _mm256_permutevar8x32_epi32(ij, perm));
      _mm256_storeu_pd(B.dx + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dx), perm)));
      _mm256_storeu_pd(B.dy + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dy), perm)));
      _mm256_storeu_pd(B.dz + n, _mm256_castsi256_pd(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(dz), perm)));
      n += std::popcount(static_cast<unsigned>(m));
    }
    k = k1;
  }
  c = {i, k};
  return n;
}

/** The address 4 doubles before particle @p j's position, for a load whose
 * lanes 0-3 are masked off (they are not read and do not fault); formed as an
 * integer, so no out-of-bounds pointer arithmetic. */
inline double const *record_minus4(Utils::Vector3d const *pos, int j) {
  return reinterpret_cast<double const *>(reinterpret_cast<std::uintptr_t>(pos[j].data()) - 4 * sizeof(double));
}

/** rows_select_scalar<OneType> eight listed pairs of a row at a time in
 * AVX-512 lanes: the partners' positions by masked loads, transposed to x, y
 * and z; d and r^2 by the same IEEE operations as the scalar select (no
 * FMA); with several types (nt <= 8) each partner's cutoff from the row's
 * line of the table by its type; the in-range mask, and the pairs (i, j) and
 * d compressed in registers and stored from slot n (each store writes eight
 * lanes: @p limit <= kPairBlock - 8). The row's last group is masked to its
 * length. */
template <bool OneType>
__attribute__((target("avx512f,avx512vl,avx2,popcnt"))) int
rows_select_avx512(int const *__restrict row_start, int const *__restrict pj, int n_rows, RowCursor &c, int limit,
                   Utils::Vector3d const *__restrict pos, int const *__restrict typ,
                   double const *__restrict cut2_table, int nt, std::array<int, 2> *__restrict bij,
                   PairBlockSoA &B) {
  __m512d c2 = _mm512_set1_pd(cut2_table[0]);
  int n = 0, i = c.i, k = c.k;
  for (; i < n_rows; ++i) {
    int const k1 = row_start[i + 1];
    if (k >= k1)
      continue;
    // several types (nt <= 8): the row's line of the cutoff table in lanes
    __m512d c2row = c2;
    if constexpr (!OneType)
      c2row = _mm512_maskz_loadu_pd(static_cast<__mmask8>((1u << nt) - 1u), cut2_table + typ[i] * nt);
    __m512d const xi = _mm512_set1_pd(pos[i][0]), yi = _mm512_set1_pd(pos[i][1]), zi = _mm512_set1_pd(pos[i][2]);
    __m512i const iv = _mm512_set1_epi64(static_cast<long long>(static_cast<std::uint32_t>(i)));
    for (; k < k1; k += 8) {
      if (n > limit) {
        c = {i, k};
        return n;
      }
      __m256i const jv = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(pj + k));
      int const *const pk = pj + k;
      // a_q = (r_{j_q}, 0 | r_{j_{q+4}}, 0) by two masked loads (the upper one
      // addressed 4 doubles before its record: the masked-off lanes do not
      // fault), then transposed to x, y, z of the eight partners
      __m512d const a0 = _mm512_mask_loadu_pd(_mm512_maskz_loadu_pd(0x07, pos[pk[0]].data()), 0x70, record_minus4(pos, pk[4]));
      __m512d const a1 = _mm512_mask_loadu_pd(_mm512_maskz_loadu_pd(0x07, pos[pk[1]].data()), 0x70, record_minus4(pos, pk[5]));
      __m512d const a2 = _mm512_mask_loadu_pd(_mm512_maskz_loadu_pd(0x07, pos[pk[2]].data()), 0x70, record_minus4(pos, pk[6]));
      __m512d const a3 = _mm512_mask_loadu_pd(_mm512_maskz_loadu_pd(0x07, pos[pk[3]].data()), 0x70, record_minus4(pos, pk[7]));
      __m512d const t0 = _mm512_unpacklo_pd(a0, a1); // x0 x1 z0 z1 | x4 x5 z4 z5
      __m512d const t1 = _mm512_unpackhi_pd(a0, a1); // y0 y1 0 0 | y4 y5 0 0
      __m512d const t2 = _mm512_unpacklo_pd(a2, a3); // x2 x3 z2 z3 | x6 x7 z6 z7
      __m512d const t3 = _mm512_unpackhi_pd(a2, a3);
      __m512i const ix = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13), iz = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
      __m512d const dx = _mm512_sub_pd(xi, _mm512_permutex2var_pd(t0, ix, t2));
      __m512d const dy = _mm512_sub_pd(yi, _mm512_permutex2var_pd(t1, ix, t3));
      __m512d const dz = _mm512_sub_pd(zi, _mm512_permutex2var_pd(t0, iz, t2));
      __m512d const r2 = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)),
                                       _mm512_mul_pd(dz, dz));
      if constexpr (!OneType) // each partner's cutoff: the row's line at its type
        c2 = _mm512_permutexvar_pd(_mm512_cvtepu32_epi64(_mm256_i32gather_epi32(typ, jv, 4)), c2row);
      int const rem = k1 - k;
      // !(r2 >= cut2), true for a NaN; lanes past the row's end off
      __mmask8 const m = _mm512_mask_cmp_pd_mask(static_cast<__mmask8>(rem >= 8 ? 255u : (1u << rem) - 1u), r2, c2,
                                                 _CMP_NGE_UQ);
      __m512i const prs = _mm512_or_si512(iv, _mm512_slli_epi64(_mm512_cvtepu32_epi64(jv), 32));
      _mm512_storeu_si512(bij + n, _mm512_maskz_compress_epi64(m, prs));
      _mm512_storeu_pd(B.dx + n, _mm512_maskz_compress_pd(m, dx));
      _mm512_storeu_pd(B.dy + n, _mm512_maskz_compress_pd(m, dy));
      _mm512_storeu_pd(B.dz + n, _mm512_maskz_compress_pd(m, dz));
      n += std::popcount(static_cast<unsigned>(m));
    }
    k = k1;
  }
  c = {i, k};
  return n;
}

int rows_select_avx512_one_type(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                                Utils::Vector3d const *pos, double cut2, std::array<int, 2> *bij, PairBlockSoA &B) {
  double const cut2_table[1] = {cut2};
  return rows_select_avx512<true>(row_start, pj, n_rows, c, limit, pos, nullptr, cut2_table, 1, bij, B);
}

/** rows_select_avx512<false>, for nt <= 8 (the table's line in one register). */
int rows_select_avx512_typed(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                             Utils::Vector3d const *pos, int const *typ, double const *cut2_table, int nt,
                             std::array<int, 2> *bij, PairBlockSoA &B) {
  return rows_select_avx512<false>(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, B);
}

int rows_select_avx2_one_type(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                              Utils::Vector3d const *pos, double cut2, std::array<int, 2> *bij, PairBlockSoA &B) {
  double const cut2_table[1] = {cut2};
  return rows_select_avx2<true>(row_start, pj, n_rows, c, limit, pos, nullptr, cut2_table, 1, bij, B);
}

int select_avx2_typed(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, int const *typ,
                      double const *cut2_table, int nt, std::array<int, 2> *bij, PairBlockSoA &B) {
  return select_avx2<false>(blk, nb, pos, typ, cut2_table, nt, bij, B);
}

int rows_select_avx2_typed(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                           Utils::Vector3d const *pos, int const *typ, double const *cut2_table, int nt,
                           std::array<int, 2> *bij, PairBlockSoA &B) {
  return rows_select_avx2<false>(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, B);
}

/** gather_dpd_scalar four pairs at a time, with no branch: the records of
 * v_i and v_j (one aligned 256-bit load each), subtracted record by record
 * (lanes 0-2: the scalar subtractions), transposed into lanes; the ids
 * ordered by unsigned min/max and the sign +1 where id_i < id_j, else -1
 * (exact). */
__attribute__((target("avx2"))) void gather_dpd_avx2(std::array<int, 2> const *__restrict bij, int n,
                                                     Rec4 const *__restrict vel, int const *__restrict pid,
                                                     PairBlockSoA &B, std::uint32_t *__restrict lo,
                                                     std::uint32_t *__restrict hi, double *__restrict sign) {
  int s = 0;
  __m128i const one = _mm_set1_epi32(1), two = _mm_set1_epi32(2);
  for (; s + 4 <= n; s += 4) {
    int const i0 = bij[s][0], i1 = bij[s + 1][0], i2 = bij[s + 2][0], i3 = bij[s + 3][0];
    int const j0 = bij[s][1], j1 = bij[s + 1][1], j2 = bij[s + 2][1], j3 = bij[s + 3][1];
    __m256d const d0 = _mm256_sub_pd(_mm256_load_pd(vel[i0].v), _mm256_load_pd(vel[j0].v));
    __m256d const d1 = _mm256_sub_pd(_mm256_load_pd(vel[i1].v), _mm256_load_pd(vel[j1].v));
    __m256d const d2 = _mm256_sub_pd(_mm256_load_pd(vel[i2].v), _mm256_load_pd(vel[j2].v));
    __m256d const d3 = _mm256_sub_pd(_mm256_load_pd(vel[i3].v), _mm256_load_pd(vel[j3].v));
    __m256d const t0 = _mm256_unpacklo_pd(d0, d1), t1 = _mm256_unpackhi_pd(d0, d1); // x0 x1 z0 z1 / y0 y1 - -
    __m256d const t2 = _mm256_unpacklo_pd(d2, d3), t3 = _mm256_unpackhi_pd(d2, d3);
    _mm256_store_pd(B.vx + s, _mm256_permute2f128_pd(t0, t2, 0x20));
    _mm256_store_pd(B.vy + s, _mm256_permute2f128_pd(t1, t3, 0x20));
    _mm256_store_pd(B.vz + s, _mm256_permute2f128_pd(t0, t2, 0x31));
    __m128i const a = _mm_set_epi32(pid[i3], pid[i2], pid[i1], pid[i0]);
    __m128i const c = _mm_set_epi32(pid[j3], pid[j2], pid[j1], pid[j0]);
    __m128i const mn = _mm_min_epu32(a, c), mx = _mm_max_epu32(a, c);
    // a < c (unsigned): a is the minimum and differs from c
    __m128i const less = _mm_andnot_si128(_mm_cmpeq_epi32(a, c), _mm_cmpeq_epi32(mn, a));
    _mm_storeu_si128(reinterpret_cast<__m128i *>(lo + s), mn);
    _mm_storeu_si128(reinterpret_cast<__m128i *>(hi + s), mx);
    _mm256_storeu_pd(sign + s, _mm256_cvtepi32_pd(_mm_sub_epi32(_mm_and_si128(less, two), one)));
  }
  gather_dpd_scalar_from(s, bij, n, vel, pid, B, lo, hi, sign);
}

/** scatter_scalar four pairs at a time: the forces transposed into
 * (fx, fy, fz, 0) records, then per pair one 256-bit add to f_i and one
 * subtract from f4[j], in list order (lane by lane the scalar operations).
 * RegI = false: f_i through memory pair by pair, no branch (short runs of
 * one i, as in a DPD fluid: the branch on a run's end would be mispredicted
 * every ~6 pairs); RegI = true: f_i summed in a register over a run of one i
 * (long runs, as in LJ at r_c = 2.5: through memory, each addition waits on
 * the last one's store). The same additions in the same order either way (no
 * j of a run is its i). */
/** One pair of scatter_avx2 (its force @p f as an (x, y, z, 0) record). */
template <bool RegI>
__attribute__((target("avx2"), always_inline)) inline void scatter_one(std::array<int, 2> const *__restrict bij,
                                                                       int q, __m256d f, Force4 *__restrict f4,
                                                                       int &ci, __m256d &fi) {
  int const i = bij[q][0];
  if constexpr (RegI) {
    if (i != ci) {
      _mm256_store_pd(f4[ci].v, fi);
      ci = i, fi = _mm256_load_pd(f4[i].v);
    }
    fi = _mm256_add_pd(fi, f);
  } else {
    double *const pi = f4[i].v;
    _mm256_store_pd(pi, _mm256_add_pd(_mm256_load_pd(pi), f));
  }
  double *const pj = f4[bij[q][1]].v;
  _mm256_store_pd(pj, _mm256_sub_pd(_mm256_load_pd(pj), f));
}

template <bool RegI>
__attribute__((target("avx2"))) void scatter_avx2(std::array<int, 2> const *__restrict bij, int n,
                                                  PairBlockSoA const &B, Force4 *__restrict f4) {
  if (n == 0)
    return;
  int s = 0;
  __m256d const zero = _mm256_setzero_pd();
  int ci = bij[0][0];
  __m256d fi = RegI ? _mm256_load_pd(f4[ci].v) : zero;
  for (; s + 4 <= n; s += 4) {
    __m256d const fx = _mm256_load_pd(B.fx + s), fy = _mm256_load_pd(B.fy + s), fz = _mm256_load_pd(B.fz + s);
    __m256d const t0 = _mm256_unpacklo_pd(fx, fy), t1 = _mm256_unpackhi_pd(fx, fy); // x0 y0 x2 y2 / x1 y1 x3 y3
    __m256d const t2 = _mm256_unpacklo_pd(fz, zero), t3 = _mm256_unpackhi_pd(fz, zero); // z0 0 z2 0 / z1 0 z3 0
    scatter_one<RegI>(bij, s, _mm256_permute2f128_pd(t0, t2, 0x20), f4, ci, fi);
    scatter_one<RegI>(bij, s + 1, _mm256_permute2f128_pd(t1, t3, 0x20), f4, ci, fi);
    scatter_one<RegI>(bij, s + 2, _mm256_permute2f128_pd(t0, t2, 0x31), f4, ci, fi);
    scatter_one<RegI>(bij, s + 3, _mm256_permute2f128_pd(t1, t3, 0x31), f4, ci, fi);
  }
  for (; s < n; ++s)
    scatter_one<RegI>(bij, s, _mm256_set_pd(0., B.fz[s], B.fy[s], B.fx[s]), f4, ci, fi);
  if constexpr (RegI)
    _mm256_store_pd(f4[ci].v, fi);
}

void scatter_avx2_pairs(std::array<int, 2> const *bij, int n, PairBlockSoA const &B, Force4 *f4) {
  scatter_avx2<false>(bij, n, B, f4);
}
void scatter_avx2_runs(std::array<int, 2> const *bij, int n, PairBlockSoA const &B, Force4 *f4) {
  scatter_avx2<true>(bij, n, B, f4);
}
#endif

} // namespace

int pair_block_select(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, int const *typ,
                      double const *cut2_table, int nt, std::array<int, 2> *bij, PairBlockSoA &b) {
  if (nt == 1) {
#ifdef MARBLE_PAIR_SELECT_AVX2
    if (Utils::cpu_has_avx2())
      return select_avx2_one_type(blk, nb, pos, cut2_table[0], bij, b);
#endif
    return select_scalar<true>(blk, 0, nb, pos, typ, cut2_table, nt, bij, b, 0);
  }
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    return select_avx2_typed(blk, nb, pos, typ, cut2_table, nt, bij, b);
#endif
  return select_scalar<false>(blk, 0, nb, pos, typ, cut2_table, nt, bij, b, 0);
}

void pair_block_gather_dpd(std::array<int, 2> const *bij, int n, Rec4 const *vel, int const *pid,
                           PairBlockSoA &b, std::uint32_t *lo, std::uint32_t *hi, double *sign) {
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    return gather_dpd_avx2(bij, n, vel, pid, b, lo, hi, sign);
#endif
  gather_dpd_scalar(bij, n, vel, pid, b, lo, hi, sign);
}

int pair_rows_select(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                     Utils::Vector3d const *pos, int const *typ, double const *cut2_table, int nt,
                     std::array<int, 2> *bij, PairBlockSoA &b) {
  if (nt == 1) {
#ifdef MARBLE_PAIR_SELECT_AVX2
    if (Utils::cpu_prefers_zmm())
      return rows_select_avx512_one_type(row_start, pj, n_rows, c, limit, pos, cut2_table[0], bij, b);
    if (Utils::cpu_has_avx2())
      return rows_select_avx2_one_type(row_start, pj, n_rows, c, limit, pos, cut2_table[0], bij, b);
#endif
    return rows_select_scalar<true>(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, b);
  }
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_prefers_zmm() && nt <= 8)
    return rows_select_avx512_typed(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, b);
  if (Utils::cpu_has_avx2())
    return rows_select_avx2_typed(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, b);
#endif
  return rows_select_scalar<false>(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, b);
}

void pair_block_scatter(std::array<int, 2> const *bij, int n, PairBlockSoA const &b, Force4 *f4, bool long_runs) {
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    return long_runs ? scatter_avx2_runs(bij, n, b, f4) : scatter_avx2_pairs(bij, n, b, f4);
#else
  (void)long_runs;
#endif
  scatter_scalar(bij, n, b, f4);
}

std::vector<PairScatterPath> pair_scatter_paths() {
  std::vector<PairScatterPath> out{{"scalar", &scatter_scalar}};
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    out.push_back({"avx2", &scatter_avx2_pairs}), out.push_back({"avx2_runs", &scatter_avx2_runs});
#endif
  return out;
}

namespace {
int select_scalar_typed(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, int const *typ,
                        double const *cut2_table, int nt, std::array<int, 2> *bij, PairBlockSoA &B) {
  return select_scalar<false>(blk, 0, nb, pos, typ, cut2_table, nt, bij, B, 0);
}
int rows_select_scalar_typed(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                             Utils::Vector3d const *pos, int const *typ, double const *cut2_table, int nt,
                             std::array<int, 2> *bij, PairBlockSoA &B) {
  return rows_select_scalar<false>(row_start, pj, n_rows, c, limit, pos, typ, cut2_table, nt, bij, B);
}
} // namespace

std::vector<PairTypedSelectPath> pair_typed_select_paths() {
  std::vector<PairTypedSelectPath> out{{"scalar", &select_scalar_typed, &rows_select_scalar_typed}};
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    out.push_back({"avx2", &select_avx2_typed, &rows_select_avx2_typed});
  // (the block select has no AVX-512 form; the AVX-512 rows take nt <= 8)
  if (Utils::cpu_prefers_zmm())
    out.push_back({"avx512", &select_avx2_typed, &rows_select_avx512_typed});
#endif
  return out;
}

std::vector<PairRowsSelectPath> pair_rows_select_paths() {
  std::vector<PairRowsSelectPath> out{{"scalar", &rows_select_scalar_one_type}};
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    out.push_back({"avx2", &rows_select_avx2_one_type});
  if (Utils::cpu_prefers_zmm())
    out.push_back({"avx512", &rows_select_avx512_one_type});
#endif
  return out;
}

std::vector<PairSelectPath> pair_select_paths() {
  std::vector<PairSelectPath> out{{"scalar", &select_scalar_one_type, &gather_dpd_scalar}};
#ifdef MARBLE_PAIR_SELECT_AVX2
  if (Utils::cpu_has_avx2())
    out.push_back({"avx2", &select_avx2_one_type, &gather_dpd_avx2});
#endif
  return out;
}

// one case per set of switches: LJ (0, 1, 2) x hat x {none, DPD, +TRANS} (x mass)
#define MARBLE_BLOCK_CASE(L, H, D, T, M)                                                             \
  case 16u * (L) + 1u * (H) + 2u * (D) + 4u * (T) + 8u * (M):                                      \
    return pow2 ? block_forces<L, H, D, T, M, true>(p, n, b) : block_forces<L, H, D, T, M, false>(p, n, b);
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

namespace {
[[gnu::always_inline]] inline void block_forces_switch(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
  unsigned const sw = 16u * static_cast<unsigned>(p.lj) | (p.hat ? 1u : 0u) | (p.dpd ? 2u : 0u) |
                      (p.dpd && p.trans ? 4u : 0u) | (p.dpd && mass ? 8u : 0u);
  // every divisor of the kernels in use a power of two (a zero or off range divides by 1)
  bool const pow2 = (!p.hat || exact_reciprocal(p.hat_cut)) &&
                    (!p.dpd || p.wf != 1 || !(p.rc > 0.) || exact_reciprocal(p.rc)) &&
                    (!p.dpd || !p.trans || p.twf != 1 || !(p.trc > 0.) || exact_reciprocal(p.trc));
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

#ifdef MARBLE_PAIR_SIMD_TARGETS
// the loop built for AVX-512 F (zmm, 8 pairs a vector), AVX2 and baseline
// x86-64, chosen once by the CPU (Utils::cpu_prefers_zmm, cpu_has_avx2):
// the same IEEE operations (no FMA: -ffp-contract=off, and none of these
// targets has FMA), so the same bits
__attribute__((target("avx512f"))) void block_forces_avx512(SimdPairParams const &p, bool mass, int n,
                                                             PairBlockSoA &b) {
  block_forces_switch(p, mass, n, b);
}
__attribute__((target("avx2"))) void block_forces_avx2(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
  block_forces_switch(p, mass, n, b);
}
#endif
void block_forces_baseline(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
  block_forces_switch(p, mass, n, b);
}
} // namespace

void pair_block_forces(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b) {
#ifdef MARBLE_PAIR_SIMD_TARGETS
  static auto *const fn = Utils::cpu_prefers_zmm() ? &block_forces_avx512
                          : Utils::cpu_has_avx2()  ? &block_forces_avx2
                                                   : &block_forces_baseline;
  fn(p, mass, n, b);
#else
  block_forces_baseline(p, mass, n, b);
#endif
}

std::vector<PairBlockForcesPath> pair_block_forces_paths() {
  std::vector<PairBlockForcesPath> out{{"baseline", &block_forces_baseline}};
#ifdef MARBLE_PAIR_SIMD_TARGETS
  if (Utils::cpu_has_avx2())
    out.push_back({"avx2", &block_forces_avx2});
  if (__builtin_cpu_supports("avx512f"))
    out.push_back({"avx512", &block_forces_avx512});
#endif
  return out;
}

} // namespace Marble
