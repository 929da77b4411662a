#pragma once
// The one traversal of the main Verlet list, used by the forces, energy,
// pressure, DPD stress, Shardlow and DPD-VV (doc/architecture.md). The list is
// processed in blocks of kPairBlock pairs: first the pairs within their type
// pair's cutoff are selected without a branch (half to two thirds of the
// listed pairs are outside: a branch there is mispredicted often), then the
// caller works on the selected pairs of the block, in list order, so the
// summation order (and the trajectory) is that of a plain one-pass loop. A
// NaN distance is kept (the force check reports it).
#include "cells/CellSystem.hpp"
#include "forces/pair_noise.hpp"
#include "nonbonded/InteractionTable.hpp"
#include "particles/ParticleStore.hpp"
#include "thermostats/NoiseContext.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace Marble {

using PairList = VerletPairs;

constexpr int kPairBlock = 512;

/** Call fn(std::array<int, 2> const *pairs, int n) for consecutive chunks of
 * at most kPairBlock listed pairs (i, j) of @p list, in list order: the rows
 * expanded into a buffer, the extra pairs as they are stored. */
template <class Fn> void for_each_listed_chunk(PairList const &list, Fn &&fn) {
  std::array<std::array<int, 2>, kPairBlock> buf;
  int m = 0;
  int const *const row = list.row_start.data();
  int const *const pj = list.j.data();
  int const n_rows = list.n_rows();
  for (int i = 0; i < n_rows; ++i)
    for (int k = row[i]; k < row[i + 1]; ++k) {
      buf[m++] = {i, pj[k]};
      if (m == kPairBlock) {
        fn(static_cast<std::array<int, 2> const *>(buf.data()), m);
        m = 0;
      }
    }
  if (m > 0)
    fn(static_cast<std::array<int, 2> const *>(buf.data()), m);
  std::size_t const n_extra = list.extra.size();
  for (std::size_t b0 = 0; b0 < n_extra; b0 += kPairBlock)
    fn(list.extra.data() + b0, static_cast<int>(std::min<std::size_t>(kPairBlock, n_extra - b0)));
}

/** The selected pairs of one block: (i[s], j[s]) for s < size, in list order. */
struct PairBlock {
  std::array<int, kPairBlock> i, j;
  int size = 0;
};

/** The squared cutoff of each type pair, in a small dense table (a * n_types + b). */
inline std::vector<double> pair_cut2_table(InteractionTable const &ia) {
  int const nt = ia.n_types();
  std::vector<double> cut2(static_cast<std::size_t>(nt) * nt);
  for (int a = 0; a < nt; ++a)
    for (int b = 0; b < nt; ++b)
      cut2[a * nt + b] = ia.get(a, b).max_cut2;
  return cut2;
}

/** The ids of a pair in increasing order (@p lo, @p hi) and the sign of the
 * pair noise (+1 if @p a < @p c), without a branch: the order of a listed
 * pair's ids is random, a branch on it would be mispredicted. */
inline void order_pair_ids(int a, int c, std::uint32_t &lo, std::uint32_t &hi, double &sign) {
  auto const ua = static_cast<std::uint32_t>(a), uc = static_cast<std::uint32_t>(c);
  std::uint32_t const less = ua < uc, m = 0u - less; // all ones if a < c
  lo = (ua & m) | (uc & ~m);
  hi = (uc & m) | (ua & ~m);
  sign = static_cast<double>(static_cast<int>(2 * less) - 1);
}

/** Call fn(PairBlock const &) for every block of @p pairs within their cutoff. */
template <class Fn>
void for_each_pair_block(ParticleStore const &ps, PairList const &pairs, InteractionTable const &ia,
                         Fn &&fn) {
  int const nt = ia.n_types();
  auto const cut2 = pair_cut2_table(ia);
  bool const one_type = nt == 1;
  double const cut2_0 = nt > 0 ? cut2[0] : 0.;
  auto const *const pos = ps.pos.data();
  auto const *const typ = ps.type.data();
  PairBlock b;
  for_each_listed_chunk(pairs, [&](std::array<int, 2> const *blk, int nb) {
    int m = 0;
    if (one_type) {
      for (int q = 0; q < nb; ++q) {
        int const i = blk[q][0], j = blk[q][1];
        b.i[m] = i, b.j[m] = j;
        m += !((pos[i] - pos[j]).norm2() >= cut2_0) ? 1 : 0;
      }
    } else {
      for (int q = 0; q < nb; ++q) {
        int const i = blk[q][0], j = blk[q][1];
        b.i[m] = i, b.j[m] = j;
        m += !((pos[i] - pos[j]).norm2() >= cut2[typ[i] * nt + typ[j]]) ? 1 : 0;
      }
    }
    b.size = m;
    fn(static_cast<PairBlock const &>(b));
  });
}

/** Call fn(i, j) for every pair of @p pairs within its cutoff, in list order. */
template <class Fn>
void for_each_pair(ParticleStore const &ps, PairList const &pairs, InteractionTable const &ia, Fn &&fn) {
  for_each_pair_block(ps, pairs, ia, [&](PairBlock const &b) {
    for (int s = 0; s < b.size; ++s)
      fn(b.i[s], b.j[s]);
  });
}

/** The pair noise of a symmetric dissipative kernel (reference.md section 1):
 * Philox4x32-10 keyed by (seed, salt, step) and the unordered pair of ids,
 * signed by id order so that F_j = -F_i (utils/philox4x32.hpp). */
inline Utils::Vector3d pair_noise(NoiseContext const &n, Utils::RNGSalt salt, int id_i, int id_j) {
  bool const flip = !(id_i < id_j);
  Utils::PairNoiseKey const k(n.seed, static_cast<std::uint64_t>(salt), n.counter);
  auto const x = Utils::pair_uniform3(k, static_cast<std::uint32_t>(flip ? id_j : id_i),
                                      static_cast<std::uint32_t>(flip ? id_i : id_j));
  Utils::Vector3d const v{x[0], x[1], x[2]};
  return flip ? -v : v;
}

/** The noise of kernel @p K for the pairs of block @p b (the same numbers as
 * pair_noise), drawn for the whole block at once in SIMD lanes
 * (forces/pair_noise.cpp). Pairs whose type pair lacks K get a draw too
 * (unused): cheaper than a branch. */
template <class K>
void draw_block_noise(PairBlock const &b, ParticleStore const &ps, [[maybe_unused]] InteractionTable const &ia,
                      NoiseContext const &n, std::array<Utils::Vector3d, kPairBlock> &xi) {
  auto const *const pid = ps.id.data();
  alignas(64) std::array<std::uint32_t, kPairBlock> lo, hi;
  alignas(64) std::array<double, kPairBlock> sign;
  for (int s = 0; s < b.size; ++s)
    order_pair_ids(pid[b.i[s]], pid[b.j[s]], lo[s], hi[s], sign[s]);
  pair_noise_block(Utils::PairNoiseKey(n.seed, static_cast<std::uint64_t>(K::salt), n.counter), b.size,
                   lo.data(), hi.data(), sign.data(), xi.data());
}

/** M_ij of the pair (DPD_MASS_RED / DPD_MASS_LIN; 1 otherwise). */
inline double pair_mass_factor([[maybe_unused]] ParticleStore const &ps, [[maybe_unused]] int i,
                               [[maybe_unused]] int j) {
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
  return dpd_mass_factor(ps.get_mass(i), ps.get_mass(j));
#else
  return 1.;
#endif
}

} // namespace Marble
