#pragma once
// The pair forces of a block of pairs in SIMD lanes (forces/pair_simd.cpp), for
// the common kernel sets: Lennard-Jones (any shift, offset and min), the
// Groot-Warren hat and the DPD pair thermostat (weight function 0, or 1 with
// k = 1; TRANS_DPD; the DPD_MASS_* factors; offsets), alone or together. forces.cpp takes this path where every type pair of the scene is
// served by it, the generic scalar loop (pair_force.hpp) everywhere else, so a
// kernel without a SIMD form works as before (doc/adding-an-interaction.md).
#include "forces/pair_traversal.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace Marble {

/** pair_loop_bit<K>, 0 for a kernel not compiled in. */
template <class K> constexpr unsigned pair_loop_bit_if_compiled() {
  if constexpr (compiled<K>)
    return pair_loop_bit<K>;
  else
    return 0u;
}

/** True if @p c is a power of two whose reciprocal is a normal number too:
 * then x / c and x * (1 / c) are the same real number, so the same double
 * (each is that number rounded once), whatever x. Used where a division is
 * replaced by a multiplication without changing any bit (the SIMD block's
 * cutoffs, the Shardlow sweep's cutoffs and reduced masses). */
inline bool exact_reciprocal(double c) {
  int e = 0;
  return c > 0. && std::frexp(c, &e) == 0.5 && e > -1000 && e < 1000;
}

/** One type pair's kernels in the form the SIMD block takes (off: 0 gain). */
struct SimdPairParams {
  // Lennard-Jones: 0 off, 1 offset 0 (computed from r^2 alone: no root),
  // 2 with an offset (the scalar kernel's arithmetic)
  int lj = 0;
  double lj_eps48 = 0., lj_sig2 = 0., lj_cut = 0., lj_off = 0., lj_min = 0.;
  bool hat = false;
  double hat_fmax = 0., hat_cut = 1., hat_off = 0.;
  bool dpd = false;
  double dpd_off = 0.;
  // radial and transverse weight: w = 1 (wf 0) or 1 - x / r_cut (wf 1, k = 1), 0 beyond r_cut
  int wf = 0, twf = 0;
  double gamma = 0., rc = 0., pref = 0.;
  bool trans = false;
  double tgamma = 0., trc = 0., tpref = 0.;
  bool operator==(SimdPairParams const &) const = default;
};

/** The block's pairs as structures of arrays: d = r_i - r_j, v = v_i - v_j,
 * xi the signed noise, m the pair mass factor (used with DPD_MASS_*). */
struct PairBlockSoA {
  alignas(64) double dx[kPairBlock], dy[kPairBlock], dz[kPairBlock];
  alignas(64) double vx[kPairBlock], vy[kPairBlock], vz[kPairBlock];
  alignas(64) double xx[kPairBlock], xy[kPairBlock], xz[kPairBlock];
  alignas(64) double m[kPairBlock];
  alignas(64) double fx[kPairBlock], fy[kPairBlock], fz[kPairBlock];
};

/** A vector (x, y, z, 0) in 32 bytes: the SIMD loop's private copies of
 * the velocities and its force buffer (one aligned 256-bit load, or
 * read-modify-write, per particle and pair; a record never straddles a cache
 * line). */
struct alignas(32) Rec4 {
  double v[4];
};
using Force4 = Rec4;

/** Select the listed pairs blk[0 .. nb) within their type pair's squared
 * cutoff (@p cut2_table, a * nt + b; a NaN distance is kept: the force check
 * reports it) and gather them: pair and d = r_i - r_j at the next free slot,
 * in list order. One pass with no data-dependent branch; with AVX2 four
 * listed pairs at a time (compare, then a compress by permutation; with
 * several types the four cutoffs gathered from the table), else scalar: the
 * same subtractions, the same bits. Returns the number selected. */
int pair_block_select(std::array<int, 2> const *blk, int nb, Utils::Vector3d const *pos, int const *typ,
                      double const *cut2_table, int nt, std::array<int, 2> *bij, PairBlockSoA &b);

/** Where pair_rows_select stopped: row @p i, its listed pair at slot @p k of
 * VerletPairs::j. Start at {0, 0}; done when i == n_rows. */
struct RowCursor {
  int i = 0, k = 0;
};

/** pair_block_select on the rows of a VerletPairs list (@p row_start, @p pj,
 * @p n_rows; pj padded by 8 valid indices), from @p c on: the selected pairs
 * (i, j) and d at slots 0, 1, ... of @p bij and @p b, in list order, until
 * more than @p limit (<= kPairBlock - 8) are stored or the rows end; @p c
 * then says where to go on. r_i is loaded once per row. The same selection
 * and the same bits as pair_block_select on the expanded pairs. Eight listed
 * pairs a group in AVX-512 registers where Utils::cpu_prefers_zmm() (and at
 * most 8 types), else four with AVX2, else scalar. */
int pair_rows_select(int const *row_start, int const *pj, int n_rows, RowCursor &c, int limit,
                     Utils::Vector3d const *pos, int const *typ, double const *cut2_table, int nt,
                     std::array<int, 2> *bij, PairBlockSoA &b);

/** The DPD inputs of the selected pairs bij[0 .. n): v = v_i - v_j into @p b
 * (from @p vel4, the velocities as Rec4 records) and the ordered ids and
 * noise sign (order_pair_ids) into @p lo, @p hi, @p sign; with AVX2 four
 * pairs at a time, else scalar: the same bits. */
void pair_block_gather_dpd(std::array<int, 2> const *bij, int n, Rec4 const *vel4, int const *pid,
                           PairBlockSoA &b, std::uint32_t *lo, std::uint32_t *hi, double *sign);

/** Add the forces b.fx/fy/fz of the selected pairs bij[0 .. n) into @p f4:
 * per pair, in list order, f4[i] += f and f4[j] -= f, component by component:
 * the additions of the scalar loop in its order, so the same bits. With AVX2
 * the three components in one 256-bit lane set (lane 3 stays 0), f_i summed
 * in a register over a run of one i where @p long_runs (e.g. LJ at r_c =
 * 2.5), else through memory with no branch (DPD: runs of ~6 pairs). */
void pair_block_scatter(std::array<int, 2> const *bij, int n, PairBlockSoA const &b, Force4 *f4,
                        bool long_runs = false);

/** Every code path of pair_block_scatter this CPU has (tests). */
struct PairScatterPath {
  char const *name;
  void (*scatter)(std::array<int, 2> const *, int, PairBlockSoA const &, Force4 *);
};
std::vector<PairScatterPath> pair_scatter_paths();

/** Every code path of pair_block_select for one-type scenes (nt = 1) and of
 * pair_block_gather_dpd this CPU has, by name ("scalar", "avx2"), for the
 * tests that check that they agree bit for bit. */
struct PairSelectPath {
  char const *name;
  int (*select)(std::array<int, 2> const *, int, Utils::Vector3d const *, double, std::array<int, 2> *,
                PairBlockSoA &);
  void (*gather_dpd)(std::array<int, 2> const *, int, Rec4 const *, int const *, PairBlockSoA &,
                     std::uint32_t *, std::uint32_t *, double *);
};
std::vector<PairSelectPath> pair_select_paths();

/** Every code path of pair_rows_select for one-type scenes this CPU has (tests). */
struct PairRowsSelectPath {
  char const *name;
  int (*select)(int const *, int const *, int, RowCursor &, int, Utils::Vector3d const *, double,
                std::array<int, 2> *, PairBlockSoA &);
};
std::vector<PairRowsSelectPath> pair_rows_select_paths();

/** Every code path of pair_block_select and pair_rows_select for scenes of
 * several types (nt > 1: the squared cutoff from the type-pair table) this
 * CPU has (tests). */
struct PairTypedSelectPath {
  char const *name;
  int (*select)(std::array<int, 2> const *, int, Utils::Vector3d const *, int const *, double const *, int,
                std::array<int, 2> *, PairBlockSoA &);
  int (*rows_select)(int const *, int const *, int, RowCursor &, int, Utils::Vector3d const *, int const *,
                     double const *, int, std::array<int, 2> *, PairBlockSoA &);
};
std::vector<PairTypedSelectPath> pair_typed_select_paths();

/** f = force on i of the pairs s < n of @p b (all of one type pair, @p p);
 * @p mass: use b.m (DPD_MASS_*), else M = 1. */
void pair_block_forces(SimdPairParams const &p, bool mass, int n, PairBlockSoA &b);

/** Every build of pair_block_forces this CPU runs (baseline x86-64, AVX2,
 * AVX-512 F), by name, for the tests that check that they agree bit for bit. */
struct PairBlockForcesPath {
  char const *name;
  void (*forces)(SimdPairParams const &, bool, int, PairBlockSoA &);
};
std::vector<PairBlockForcesPath> pair_block_forces_paths();

/** The SIMD form of a type pair's parameters, or false where it has none. */
bool simd_pair_params(IAParams const &ia, unsigned mask, SimdPairParams &out);

/** The SIMD form shared by every type pair the main Verlet list serves
 * (max_cut2 > 0: e.g. all but the colloid pairs of a marble scene), or false
 * where they differ or one has no SIMD form. */
bool simd_scene_params(InteractionTable const &ia, unsigned mask, SimdPairParams &out);

} // namespace Marble
