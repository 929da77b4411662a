// The force driver: the main Verlet list through the one pair traversal
// (forces/pair_traversal.hpp), with the set of pair-loop kernels fixed at
// compile time for each instantiation of the loop (one per subset of the
// kernel list, generated), so a scene pays only for the kernels some type
// pair uses.
#include "forces/pair_force.hpp"
#include "forces/pair_simd.hpp"
#include "forces/pair_traversal.hpp"
#include "system/System.hpp"
#include "thermostats/langevin.hpp"
#include "utils/errors.hpp"

#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace Marble {

using Utils::Vector3d;

namespace {


/** Kernels with a SIMD form (forces/pair_simd.hpp). */
constexpr unsigned simd_kernels() {
  return pair_loop_bit_if_compiled<LennardJones>() | pair_loop_bit_if_compiled<Hat>() |
         pair_loop_bit_if_compiled<DPDPair>();
}

/** The loop of a scene whose list-served type pairs all have the same kernels,
 * each with a SIMD form (simd_scene_params): per block of listed pairs,
 * select those within the cutoff and gather them into structures of arrays
 * (pair_block_select), draw the noise and compute the forces in SIMD lanes, then
 * add them up in list order (the summation order of the scalar loop; the
 * force on i is summed in registers over a run of pairs of the same i, the
 * same additions in the same order). */
/** Selected pairs per block of the row select: a block's structures of
 * arrays (~13 arrays of this length) then stay in the L1 cache. */
constexpr int kSelectLimit = 192;

/** The SIMD loop's private force buffer (Force4 records, zero between calls). */
std::vector<Force4> &force4_buffer() {
  thread_local std::vector<Force4> buf;
  return buf;
}

/** The SIMD loop's copy of the velocities (Rec4 records, lane 3 zero). */
std::vector<Rec4> &vel4_buffer() {
  thread_local std::vector<Rec4> buf;
  return buf;
}

void pair_loop_simd(ParticleStore &ps, PairList const &all_pairs, PairList const &inner_pairs,
                    InteractionTable const &ia, NoiseContext const &th, SimdPairParams const &sp) {
  // Right after a rebuild the inner list (CellSystem::select_pairs) holds the
  // same selected pairs in the same order with fewer listed pairs to test. It
  // changes where the blocks end, which changes no bit of the pairs scatter
  // (f_i += f pair by pair) but would of the run sums of long rows (LJ at
  // r_c = 2.5): those scenes keep the full list.
  PairList const &pairs = sp.lj == 0 ? inner_pairs : all_pairs;
  auto const *__restrict const pos = ps.pos.data();
  auto const *__restrict const pid = ps.id.data();
  // forces summed in 32-byte records (zero on entry: the same additions onto
  // the same zeros as in ps.f), copied to ps.f at the end, which needs no
  // zeroing of its own; the copy leaves the buffer zero for the next call
  auto &f4buf = force4_buffer();
  int const n_all = ps.size();
  if (static_cast<int>(f4buf.size()) < n_all)
    f4buf.resize(static_cast<std::size_t>(n_all), Force4{});
  Force4 *const f4 = f4buf.data();
  // the velocities as 32-byte records for the DPD gather
  auto &v4buf = vel4_buffer();
  Rec4 const *vel4 = nullptr;
  if (sp.dpd) {
    if (static_cast<int>(v4buf.size()) < n_all)
      v4buf.resize(static_cast<std::size_t>(n_all), Rec4{});
    auto const *const v = ps.v.data();
    Rec4 *const w = v4buf.data();
    for (int i = 0; i < n_all; ++i)
      w[i].v[0] = v[i][0], w[i].v[1] = v[i][1], w[i].v[2] = v[i][2];
    vel4 = w;
  }
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
  constexpr bool mass = true;
#else
  constexpr bool mass = false;
#endif
  bool const dpd = sp.dpd;
  // the squared cutoff of each type pair (0 for pairs the list does not serve)
  int const nt = ia.n_types();
  auto cut2_table = pair_cut2_table(ia);
  if (cut2_table.empty())
    cut2_table.push_back(0.);
  auto const *const typ = ps.type.data();
  auto soa = std::make_unique<PairBlockSoA>();
  PairBlockSoA &B = *soa;
  alignas(64) std::array<std::array<int, 2>, kPairBlock> bij;
  alignas(64) std::array<std::uint32_t, kPairBlock> lo, hi;
  alignas(64) std::array<double, kPairBlock> sign;
  Utils::PairNoiseKey const key(th.seed, static_cast<std::uint64_t>(DPDPair::salt), th.counter);
  // gather, noise, forces and scatter of the n selected pairs in bij / B.
  // With DPD the gather, the noise and the forces run over n rounded up to a
  // multiple of 8 (kPad), so no block ends in a scalar tail (a scalar Philox
  // draw costs ~4x a lane of the SIMD one): the padding slots repeat the last selected
  // pair (their d in B is whatever the select left there: finite), and only
  // the n real pairs are added up, so the forces are those of the n pairs,
  // bit for bit.
  constexpr int kPad = 8;
  static_assert(kSelectLimit + 8 + kPad <= kPairBlock);
  auto process = [&](int n, bool long_runs) {
    if (n == 0)
      return;
    int const np = dpd ? (n + kPad - 1) / kPad * kPad : n; // (no noise, no gather: no tail to save)
    for (int s = n; s < np; ++s)
      bij[s] = bij[n - 1];
    if (dpd) {
      pair_block_gather_dpd(bij.data(), np, vel4, pid, B, lo.data(), hi.data(), sign.data());
      if constexpr (mass)
        for (int s = 0; s < np; ++s)
          B.m[s] = pair_mass_factor(ps, bij[s][0], bij[s][1]);
      pair_noise_block_soa(key, np, lo.data(), hi.data(), sign.data(), B.xx, B.xy, B.xz);
    }
    pair_block_forces(sp, mass, np, B);
    pair_block_scatter(bij.data(), n, B, f4, long_runs); // f_i += f, f_j -= f, pair by pair in list order
  };
  // the rows, read in place (r_i once per row), then the extra pairs
  RowCursor cur;
  int const n_rows = pairs.n_rows();
  while (cur.i < n_rows) {
    int const i0 = cur.i;
    int const n = pair_rows_select(pairs.row_start.data(), pairs.j.data(), n_rows, cur, kSelectLimit, pos, typ,
                                   cut2_table.data(), nt, bij.data(), B);
    // more than ~12 selected pairs per row: long runs of one i (scatter)
    process(n, n > 12 * (cur.i - i0 + 1));
  }
  std::size_t const n_extra = pairs.extra.size();
  for (std::size_t b0 = 0; b0 < n_extra; b0 += kPairBlock) {
    int const nb = static_cast<int>(std::min<std::size_t>(kPairBlock, n_extra - b0));
    process(pair_block_select(pairs.extra.data() + b0, nb, pos, typ, cut2_table.data(), nt, bij.data(), B), false);
  }
  auto *const frc = ps.f.data();
  for (int i = 0; i < n_all; ++i) {
    double *const r = f4[i].v;
    frc[i][0] = r[0], frc[i][1] = r[1], frc[i][2] = r[2];
    r[0] = r[1] = r[2] = 0.;
  }
}

template <unsigned Mask>
void pair_loop(ParticleStore &ps, PairList const &pairs, PairList const &inner_pairs, InteractionTable const &ia,
               NoiseContext const &th) {
  // kernels of the mask active only on pairs the list does not serve (e.g.
  // colloid pairs) do not keep a scene from the SIMD form
  if constexpr ((Mask & simd_kernels()) != 0) {
    SimdPairParams sp;
    if (simd_scene_params(ia, Mask, sp))
      return pair_loop_simd(ps, pairs, inner_pairs, ia, th, sp); // writes every force
  } else {
    (void)inner_pairs;
  }
  for (auto &f : ps.f)
    f = {};
  auto const *const pos = ps.pos.data();
  auto const *const vel = ps.v.data();
  auto *const frc = ps.f.data();
  auto const *const typ = ps.type.data();
  // one block of noise per pair-dissipative kernel of the mask
  std::array<std::array<Vector3d, kPairBlock>, n_pair_loop_kernels> xi;
  for_each_pair_block(ps, pairs, ia, [&](PairBlock const &b) {
    for_each_kernel<PairLoopKernels>([&]<class K>() {
      if constexpr (K::role == KernelRole::pair_dissipative && (Mask & pair_loop_bit<K>) != 0)
        draw_block_noise<K>(b, ps, ia, th, xi[detail::IndexOf<K, PairLoopKernels>::value]);
    });
    for (int s = 0; s < b.size; ++s) {
      int const i = b.i[s], j = b.j[s];
      Vector3d const d = pos[i] - pos[j];
      double const r = std::sqrt(d.norm2());
      Vector3d const force = pair_force<Mask>(
          ia.get(typ[i], typ[j]), d, r, [&] { return vel[i] - vel[j]; },
          [&]<class K>() -> Vector3d const & { return xi[detail::IndexOf<K, PairLoopKernels>::value][s]; },
          [&] { return pair_mass_factor(ps, i, j); });
      frc[i] += force;
      frc[j] -= force;
    }
  });
}

/** False if no kernel of @p mask is active on a type pair the main list
 * serves (max_cut2 > 0; pairs of large types go to the colloid list): then
 * the pair loop would select the listed pairs only to add +-0 to forces that
 * start at +0, which leaves them +0, the same bits as zeroing them. */
bool mask_acts_on_list(InteractionTable const &ia, unsigned mask) {
  bool any = false;
  int const nt = ia.n_types();
  for (int a = 0; a < nt && mask != 0; ++a)
    for (int b = 0; b < nt; ++b) {
      IAParams const &p = ia.get(a, b);
      if (!(p.max_cut2 > 0.))
        continue;
      for_each_kernel<PairLoopKernels>([&]<class K>() {
        if ((mask & pair_loop_bit<K>) != 0 && p.get<K>().active)
          any = true;
      });
    }
  return any;
}

using LoopFn = void (*)(ParticleStore &, PairList const &, PairList const &, InteractionTable const &,
                        NoiseContext const &);

template <std::size_t... M> constexpr std::array<LoopFn, sizeof...(M)> make_loops(std::index_sequence<M...>) {
  return {&pair_loop<static_cast<unsigned>(M)>...};
}

constexpr auto loops = make_loops(std::make_index_sequence<std::size_t{1} << n_pair_loop_kernels>{});

} // namespace

void System::compute_forces(bool with_thermostat) { compute_forces_pass(with_thermostat, nullptr); }

namespace {
/** 1 if @p v holds an inf or a NaN (branchless: the pass over all locals vectorises). */
inline int not_finite(Utils::Vector3d const &v) {
  double const big = std::numeric_limits<double>::max();
  return (!(std::abs(v[0]) <= big) ? 1 : 0) | (!(std::abs(v[1]) <= big) ? 1 : 0) |
         (!(std::abs(v[2]) <= big) ? 1 : 0);
}
} // namespace

void System::compute_forces_checked(bool with_thermostat) {
  int bad = -1;
  compute_forces_pass(with_thermostat, &bad);
  try {
    m_comm.throw_if_any(bad >= 0 ? non_finite_force_message(bad) : std::string());
  } catch (...) {
    m_forces_valid = false;
    throw;
  }
}

void System::compute_forces_pass(bool with_thermostat, int *first_bad) {
  ensure_lists();
  // the pair loop sets every force (m_ps.f need not be zeroed here)
#ifdef ROTATION
  for (auto &t : m_ps.torque)
    t = {};
#endif
  NoiseContext const th = noise_context(with_thermostat);
  unsigned mask = m_ia.active_pair_kernels();
  // dissipative kernels need the thermostat; with Shardlow the integrator does them
  if (!th.on || !m_dpd_in_pair_loop)
    mask &= ~pair_kernels_with_role<KernelRole::pair_dissipative>();
  if (mask_acts_on_list(m_ia, mask))
    loops[mask](m_ps, m_cells.pairs(), m_cells.select_pairs(), m_ia, th);
  else // e.g. a DPD-only solvent under Shardlow: the loop would add only zeros
    for (auto &f : m_ps.f)
      f = {};
  add_extra_forces(with_thermostat); // colloid pairs, constraints
  m_cells.reduce_ghost_forces(m_ps);
  if (with_thermostat && m_thermo.langevin.active) // single-particle Langevin friction + noise
    add_langevin_forces(m_ps, m_thermo.langevin, m_time_step);
  // The last pass over the forces: the external forces added, and every
  // final force and torque tested (branchless; only compute_forces_checked
  // reads the result, and without external forces the pass runs only for it)
  int const n = m_ps.n_local();
  auto *const f = m_ps.f.data();
#ifdef ROTATION
  auto *const t = m_ps.torque.data();
#endif
#ifdef EXTERNAL_FORCE
  auto const *const ef = m_ps.ext_force.data();
#ifdef ROTATION
  auto const *const et = m_ps.ext_torque.data();
#endif
  bool const pass = true;
#else
  bool const pass = first_bad != nullptr;
#endif
  int any_bad = 0;
  if (pass) {
    for (int i = 0; i < n; ++i) {
#ifdef EXTERNAL_FORCE
      f[i] += ef[i];
#endif
      any_bad |= not_finite(f[i]);
#ifdef ROTATION
#ifdef EXTERNAL_FORCE
      t[i] += et[i];
#endif
      any_bad |= not_finite(t[i]);
#endif
    }
  }
  if (first_bad) {
    *first_bad = -1;
    for (int i = 0; any_bad && i < n; ++i) { // the first bad local, for the message
#ifdef ROTATION
      bool const bad = not_finite(f[i]) || not_finite(t[i]);
#else
      bool const bad = not_finite(f[i]);
#endif
      if (bad) {
        *first_bad = i;
        break;
      }
    }
  }
  m_forces_valid = true;
}

std::string System::non_finite_force_message(int i) const {
  return "non-finite force on particle " + std::to_string(m_ps.id[i]) + " at step " + std::to_string(m_step) +
         ": likely cause: overlapping particles (a singular potential at r -> 0) or a "
         "time step too large for the interactions; remove overlaps with "
         "integrator.set_steepest_descent() or reduce time_step";
}

void System::compute_fast_forces() {
  assert(m_cells.valid()); // the partial zeroing trusts the lists of the last rebuild
  // Outside the colloid pairs' particles the fast force is zero: after the
  // first call since a list rebuild only those are reset (and checked)
  bool partial = false;
#ifdef MARBLE
  partial = m_colloids.any() && m_f_fast.size() == static_cast<std::size_t>(m_ps.size()) &&
            m_f_fast_rebuild == m_cells.n_rebuilds();
#endif
  if (partial) {
    for_each_fast_member([&](int i) { m_f_fast[i] = Vector3d{}; });
#ifdef MARBLE
    for (int g : m_colloids.pair_copies()) // (the other copies' zeros were never written)
      m_f_fast[g] = Vector3d{};
#endif
  } else {
    m_f_fast.assign(static_cast<std::size_t>(m_ps.size()), Vector3d{});
    m_f_fast_rebuild = m_cells.n_rebuilds();
  }
#ifdef MARBLE
  if (m_colloids.any())
    m_colloids.add_conservative_forces(m_ps, m_ia, m_f_fast);
#endif
  if (m_comm.parallel()) {
    // several ranks: pairs with other ranks' colloids (the partners are
    // locals: Colloids::find_pairs) leave forces on those copies, returned to their owners
    m_cells.reduce_replicated_ghost_values(m_f_fast);
  }
  // collective: every rank throws, with the message of the first bad rank
  int bad = -1;
  for_each_fast_member([&](int i) {
    if (bad < 0 && not_finite(m_f_fast[i]))
      bad = i;
  });
  try {
    m_comm.throw_if_any(bad < 0 ? std::string()
                                : "non-finite fast (colloid pair) force on particle " +
                                      std::to_string(m_ps.id[bad]) + " at step " + std::to_string(m_step) +
                                      ": likely cause: overlapping particles or a time step too large for "
                                      "the interactions; reduce time_step or raise the integrator's substeps");
  } catch (...) {
    m_forces_valid = false;
    throw;
  }
}

} // namespace Marble
