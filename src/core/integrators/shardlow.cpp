// DPD integrators that remove most of the kT(dt) drift of plain velocity
// Verlet (doc/stability.md has the measurements):
//
// Shardlow S1 splitting (Shardlow 2003; Nikunen, Karttunen, Vattulainen 2003):
// one step is
//   1. a sweep over the DPD pairs of the main Verlet list, in list order: each
//      pair's relative velocity along e (and, with TRANS_DPD, across e) is
//      advanced over dt by the exact solution of its Ornstein-Uhlenbeck process
//        du = -(gamma M w^2 / mu) u dt + noise,   mu = m_i m_j / (m_i + m_j),
//        u' = a u + sqrt(kT/mu (1 - a^2)) sqrt(12) (e . xi),  a = exp(-gamma M
//        w^2 dt / mu),
//      the momentum mu (u' - u) e going to i and -mu (u' - u) e to j (momentum
//      is conserved pair by pair; the stationary variance of u is exactly kT/mu
//      for any dt, so the friction is unconditionally stable);
//      then, for pairs with lubrication (nonbonded/lubrication.hpp), the same
//      exact OU step along e with the squeeze friction a_sq(h) and its own noise;
//   2. velocity Verlet with the remaining forces (conservative forces, and the
//      colloid pairs and walls with their own explicit friction and noise).
// xi is the DPD pair noise of reference.md section 1 (uniform, variance 1/12,
// Philox keyed by seed, salt dpd, counter, ordered ids, sign by id order), so
// the sweep is reproducible; its result depends on the order of the pair list
// (fixed for a given particle set, decomposition and seed).
// Several MPI ranks: the pairs whose particles no other rank reads (neither
// is a ghost elsewhere nor another rank's particle) are swept first, on every
// rank at once; the others ("boundary" pairs) follow in rounds: with the node
// grid split along one axis, face rounds (every rank sweeps the pairs at the
// lower face of its domain, then those at the upper face: the two ranks that
// hold a particle have it at different faces), pairs at both faces of a
// narrow domain and other grids in rounds by the colour of the rank's domain
// (its node-grid coordinates modulo 2, or 3 where an odd periodic axis needs
// it, so neighbouring domains differ), one colour at a time; after each
// round the ghosts' velocity changes go to their owners and every ghost gets
// its owner's velocity. Domains at least twice the pair range
// wide keep two ranks of one colour from reaching the same particle, and the
// copies of another rank's particle that came as several periodic images all
// read and write one slot (CellSystem::ghost_representatives), so every pair
// update still sees the velocities the previous ones left (sequential
// semantics; the order, and so the trajectory, depends on the decomposition).
// The stick friction (surface_friction) changes spins too: they go through
// the rounds with the velocities. The marble coupling's pairs follow rank by
// rank (marble_sweep_rounds: a colloid spans many domains, so colours would
// not keep its pairs apart).
//
// DPD-VV (Besold, Vattulainen, Karttunen, Polson 2000): velocity Verlet whose
// forces for the next first half kick carry the DPD friction recomputed from
// the full-step velocities v(t + dt) instead of v(t + dt/2): after the second
// half kick dv = dt/2 F/m, F_i += sum_j -gamma M w^2 (e . (dv_i - dv_j)) e
// (and the transverse analogue): the friction is linear in v, so this is the
// friction of v(t + dt) minus that of v(t + dt/2). Colloid and wall friction
// stay explicit.
#include "integrators/dpd_integrators.hpp"
#include "forces/pair_simd.hpp"
#include "forces/pair_traversal.hpp"
#include "integrators/ou_exp.hpp"
#include "integrators/stability.hpp"
#include "nonbonded/surface_friction_apply.hpp"
#include "thermostats/ou_step.hpp"
#ifdef MARBLE
#include "marble/Colloids.hpp"
#endif
#include "system/System.hpp"
#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace Marble {

using Utils::Vector3d;

namespace {

/** The slot whose velocity list entry @p k reads and writes: a local itself,
 * a periodic image its owner, another rank's particle the one ghost slot that
 * stands for all its copies (@p rep: CellSystem::ghost_representatives; the
 * sweep's rounds send that slot's change to the owner). */
[[maybe_unused]] int owner(ParticleStore const &ps, int k, int const *rep = nullptr) {
  int const nl = ps.n_local();
  if (k < nl)
    return k;
  int const o = ps.ghost_owner[k - nl];
  return o >= 0 ? o : (rep ? rep[k - nl] : k);
}

#ifdef DPD

// Lees-Edwards: the velocity jump of list entry k. An image across
// the shear plane (shift k_n L_n along the normal, CellSystem::make_le_ghosts)
// moves with v_owner + k_n shear_velocity e_s, the velocity it carries in the
// force loop; the sweep reads the owners' current velocities (several ranks:
// another rank's particle from its representative slot, which the rounds fill
// with the owner's velocity, no jump), so it adds the jump to the relative
// velocity. Zero for locals and for images that do not
// cross the shear plane. The velocity change of a pair is the same in either
// frame, so it goes to the owners unchanged.
struct LEJump {
  bool on = false;
  int dir = 0;
  double vs = 0.;
  CellSystem const *cells = nullptr;
  explicit LEJump(System &sys) {
    auto const &le = sys.box().lees_edwards();
    if (!le.active())
      return;
    on = true;
    dir = le.shear_direction;
    vs = le.shear_velocity;
    cells = &sys.cells();
  }
  /** The jump of entry k along the shear direction (0 for locals). */
  double operator()(ParticleStore const &ps, int k) const { return cells->le_crossings(k, ps.n_local()) * vs; }
  /** The jump of v_i - v_j for the pair (i, j) of list entries. */
  Vector3d pair(ParticleStore const &ps, int i, int j) const {
    Vector3d w{0., 0., 0.};
    w[dir] = (*this)(ps, i) - (*this)(ps, j);
    return w;
  }
};
#endif // DPD
} // namespace

#ifdef DPD
namespace {
/** What the DPD update of each selected pair of a block needs that depends on
 * positions, masses and noise only (integrators/shardlow.cpp, pre-pass): the
 * same expressions as the one-pass loop had, so the same bits. */
struct SweepBlock {
  enum : unsigned char { in_range = 1, dpd = 2, radial = 4, trans = 8, unit_masses = 16, mu_folded = 32 };
  std::array<unsigned char, kPairBlock> flags;
  std::array<int, kPairBlock> oi, oj;
  std::array<Vector3d, kPairBlock> e;
  std::array<double, kPairBlock> ar, nr; // radial: a - 1 and s (e . xi)
  std::array<double, kPairBlock> mu, mi, mj, kT_mu;
  alignas(32) std::array<double, kPairBlock> sd;            // an OU step's noise amplitude
#ifdef TRANS_DPD
  std::array<double, kPairBlock> at;  // transverse: a - 1
  std::array<Vector3d, kPairBlock> nt; // and s (xi - (e . xi) e)
#endif
};
/** DPDWeight::weight with the division by r_cut a multiplication where that
 * is exact (@p inv_rc = 1 / r_cut, @p pow2 = exact_reciprocal(r_cut)): the same bits. */
inline double dpd_weight(DPDWeight const &wp, double r, double inv_rc, bool pow2) {
  if (r >= wp.r_cut)
    return 0.;
  if (wp.weight_function == 0)
    return 1.;
  double const x = pow2 ? r * inv_rc : r / wp.r_cut;
  return 1. - (wp.k == 1. ? x : std::pow(x, wp.k));
}

/** Per type pair: the reciprocal cutoffs of the DPD weights and whether they are exact. */
struct SweepTypePair {
  double inv_rc = 0., inv_rct = 0.;
  bool pow2 = false, pow2t = false;
};

/** mu = mi mj / (mi + mj) and what follows from it, for the last pair's
 * masses: consecutive pairs mostly have the same (a solvent of one mass), and
 * the same operations on the same masses give the same bits. */
struct PairMasses {
  double mi = std::numeric_limits<double>::quiet_NaN(), mj = mi; // NaN: no pair yet
  double mu = 0., mfac = 1., kT_over_mu = 0., inv_mu = 0.;
  bool mu_pow2 = false;
  void set(double a, double b, double kT) {
    if (a == mi && b == mj)
      return;
    mi = a, mj = b;
    mu = a * b / (a + b);
    mfac = dpd_mass_factor(a, b);
    kT_over_mu = kT / mu;
    mu_pow2 = exact_reciprocal(mu);
    inv_mu = 1. / mu;
  }
  /** x / mu (a multiplication when that is exact). */
  double over_mu(double x) const { return mu_pow2 ? x * inv_mu : x / mu; }
};
/** for_each_pair_block with the SIMD row select of the force pass
 * (forces/pair_simd.hpp: the same pairs by the same test, the same
 * differences d = r_i - r_j, in list order; blocks of at most @p limit + 4
 * selected pairs): calls fn(PairBlock const &, PairBlockSoA const &) with
 * the pairs and their d in B.dx, B.dy, B.dz. */
template <class Fn>
void for_each_selected_block(ParticleStore const &ps, PairList const &pairs, InteractionTable const &ia,
                             PairBlockSoA &B, Fn &&fn) {
  constexpr int limit = 248;
  static_assert(limit + 8 <= kPairBlock);
  int const nt = ia.n_types();
  auto cut2 = pair_cut2_table(ia);
  if (cut2.empty())
    cut2.push_back(0.);
  auto const *const pos = ps.pos.data();
  auto const *const typ = ps.type.data();
  std::array<std::array<int, 2>, kPairBlock> bij;
  PairBlock b;
  auto process = [&](int n) {
    if (n == 0)
      return;
    for (int s = 0; s < n; ++s)
      b.i[s] = bij[s][0], b.j[s] = bij[s][1];
    b.size = n;
    fn(static_cast<PairBlock const &>(b), static_cast<PairBlockSoA const &>(B));
  };
  RowCursor cur;
  int const n_rows = pairs.n_rows();
  while (cur.i < n_rows)
    process(pair_rows_select(pairs.row_start.data(), pairs.j.data(), n_rows, cur, limit, pos, typ, cut2.data(),
                             nt, bij.data(), B));
  std::size_t const n_extra = pairs.extra.size();
  for (std::size_t b0 = 0; b0 < n_extra; b0 += limit) {
    int const nb = static_cast<int>(std::min<std::size_t>(limit, n_extra - b0));
    process(pair_block_select(pairs.extra.data() + b0, nb, pos, typ, cut2.data(), nt, bij.data(), B));
  }
}
/** Colours along an axis of @p g domains: neighbouring domains (across a
 * periodic wrap too) get different colours, domains of one colour are at
 * least two apart; 1 for an unsplit axis. */
int colours_along(int g, bool periodic) {
  if (g <= 1)
    return 1;
  int k = 2;
  while (periodic && g % k == 1) // (the last domain and the first are neighbours)
    ++k;
  return k;
}

/** Several ranks: the boundary pairs buf.deferred (list entries, in list
 * order; their r_i - r_j in buf.deferred_d) swept in rounds (face rounds,
 * then colour rounds; see below), @p sweep(block, its d) doing one block; after each round
 * the ghosts' velocity changes (and, @p spins, their spin changes: the stick
 * friction's torques) are added to their owners' and every ghost gets its
 * owner's velocity (after the last round only the first: the next step's
 * ghost update refreshes them). buf.sent: the locals sent to other ranks as
 * ghosts, the only locals a reduction can change, so a round costs
 * O(ghosts + sent), not O(particles). Collective. */
template <class Sweep> void sweep_boundary_rounds(System &sys, ShardlowBuffers &buf, bool spins, Sweep &&sweep) {
  auto const &pairs = buf.deferred;
  auto const &sent = buf.sent;
  auto &ps = sys.particles();
  auto &cells = sys.cells();
  auto const g = cells.node_grid(sys.box());
  auto const at = CellSystem::coords_at(g, sys.comm().rank());
  int mine = 0, n_colours = 1;
  for (int d = 0; d < 3; ++d) {
    int const k = colours_along(g[d], sys.box().periodic(d));
    mine = mine * k + at[d] % k;
    n_colours *= k;
  }
  constexpr int kBlock = 248; // (as the select's blocks)
  int const nl = ps.n_local(), n = ps.size();
  // one round's changes dq of a quantity q (v or omega) of the ghosts, from
  // q0 before the round (buf: kept between steps); dq's entries are zero
  // between rounds (the locals' always but the sent ones', cleared after
  // each round with the ghosts')
  std::array<std::vector<Vector3d> *, 2> q{&ps.v, nullptr};
#ifdef ROTATION
  if (spins)
    q[1] = &ps.omega;
#else
  (void)spins;
#endif
  for (int k = 0; k < 2; ++k)
    if (q[k]) {
      auto &dq = buf.dq[k];
      if (!buf.dq_clean[k])
        dq.assign(static_cast<std::size_t>(n), Vector3d{});
      else
        dq.resize(static_cast<std::size_t>(n)); // (new entries zero)
      buf.dq_clean[k] = false; // (until the rounds are done: an exception in a sweep leaves it so)
    }
  // The rounds. Face rounds (the node grid split along one axis a:
  // CellSystem::boundary_sides): every rank sweeps its pairs at the lower
  // face of its domain along a in round 0 and those at the upper face in
  // round 1. Two ranks never touch one particle in a round: a particle
  // another rank holds lies within the range of one face of each domain
  // that holds it, the lower face of one and the upper of the other (domains
  // at least twice the range wide), and every other particle only its rank
  // touches. A pair with particles at both faces (domains narrower than
  // three times the range) follows in colour rounds. Otherwise (a grid split
  // along several axes): one round per colour, in which the ranks of that
  // colour sweep all their boundary pairs while the others wait.
  // (buf.face: decided once per step by the sweep, from the node grid alone,
  // so every rank runs the same rounds)
  bool const face = buf.face;
  int const a = cells.boundary_axis();
  int n_rounds = n_colours;
  if (face) {
    for (auto &v : buf.side_pairs)
      v.clear();
    auto const &side = buf.boundary;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      int const c = side[pairs[k][0]] | side[pairs[k][1]]; // (1, 2 or 3: deferred pairs touch a boundary particle)
      buf.side_pairs[c - 1].push_back(static_cast<int>(k));
    }
    // the colour rounds for pairs at both faces, when some rank has one
    // (possible only in domains narrower than three ranges; one collective
    // then, which spares two or more rounds' exchanges when none has)
    double const range = std::max({cells.range(), cells.range_ll(), cells.range_ls()});
    bool const narrow = sys.box().length()[a] / g[a] < 3. * range;
#ifndef NDEBUG
    bool const both = sys.comm().any(!buf.side_pairs[2].empty()); // (collective: every rank stops, not one)
    if (both && !narrow)
      throw Utils::RuntimeError("internal error: a Shardlow boundary pair at both faces of a domain at least "
                                "three times the pair range wide");
#else
    bool const both = narrow && sys.comm().any(!buf.side_pairs[2].empty());
#endif
    n_rounds = 2 + (both ? n_colours : 0);
  }
  PairBlock b;
  std::array<Vector3d, kBlock> d;
  // sweep the deferred pairs of @p idx (all of them: nullptr), in their order
  auto sweep_pairs = [&](std::vector<int> const *idx) {
    std::size_t const m_all = idx ? idx->size() : pairs.size();
    for (std::size_t p0 = 0; p0 < m_all; p0 += kBlock) {
      int const m = static_cast<int>(std::min<std::size_t>(kBlock, m_all - p0));
      for (int s = 0; s < m; ++s) {
        std::size_t const k = idx ? static_cast<std::size_t>((*idx)[p0 + s]) : p0 + s;
        b.i[s] = pairs[k][0], b.j[s] = pairs[k][1];
        d[s] = buf.deferred_d[k];
      }
      b.size = m;
      sweep(static_cast<PairBlock const &>(b), static_cast<Vector3d const *>(d.data()));
    }
  };
  std::vector<int> const none;
  for (int r = 0; r < n_rounds; ++r) {
    // this rank's pairs in round r
    std::vector<int> const *idx = &none;
    if (!face)
      idx = r == mine ? nullptr : &none;
    else if (r < 2)
      idx = &buf.side_pairs[r];
    else
      idx = r - 2 == mine ? &buf.side_pairs[2] : &none;
    if (idx ? !idx->empty() : !pairs.empty()) {
      for (int k = 0; k < 2; ++k)
        if (q[k])
          buf.q0[k].assign(q[k]->begin() + nl, q[k]->end());
      sweep_pairs(idx);
      // (periodic images were booked on their owners, another rank's particle on its representative slot)
      auto const &rep = cells.ghost_representatives(ps);
      for (int k = 0; k < 2; ++k)
        if (q[k])
          for (int gi = nl; gi < n; ++gi)
            if (rep[gi - nl] == gi)
              buf.dq[k][gi] = (*q[k])[gi] - buf.q0[k][gi - nl];
    }
    for (int k = 0; k < 2; ++k) {
      if (!q[k])
        continue;
      auto &dq = buf.dq[k];
      cells.reduce_ghost_values(ps, dq);
      for (int i : sent) {
        (*q[k])[i] += dq[i];
        dq[i] = Vector3d{};
      }
      std::fill(dq.begin() + nl, dq.end(), Vector3d{});
      if (r + 1 < n_rounds)
        cells.fill_ghost_values(ps, *q[k]);
    }
  }
  for (int k = 0; k < 2; ++k)
    if (q[k])
      buf.dq_clean[k] = true;
}

#ifdef MARBLE
/** Several ranks: the marble coupling's sweep (Colloids::shardlow_marble_sweep)
 * rank by rank, in rank order (ranks without a coupling pair skipped). Every
 * pair's partner is a local of the rank that lists it; its colloid is a local
 * or that rank's copy of another rank's colloid (one copy per rank, CellSystem:
 * replicated types). After a rank's turn its copies' changes of velocity and
 * spin go to the owners (reduce_replicated_ghost_values) and every copy gets
 * its owner's new state (update_replicated_ghosts), so each pair update sees
 * the velocities the previous ones left: sequential, as on one rank, in the
 * order rank 0's pairs, rank 1's, ... A colloid spans many domains, so rounds
 * by domain colour would not keep two ranks of one colour apart; the marble
 * pairs are few (a shell) against the solvent's. Collective. */
void marble_sweep_rounds(System &sys, NoiseContext const &noise, double kT, double dt) {
  auto &ps = sys.particles();
  auto const &cells = sys.cells();
  auto const &col = sys.colloids();
  auto const &comm = sys.comm();
  int const nl = ps.n_local(), n = ps.size();
  cells.update_replicated_ghosts(ps); // the copies at their owners' velocities and spins (after the kick)
  std::vector<int> local_colloids;
  bool any_fixed = false;
  for (int i = 0; i < nl; ++i)
    if (col.is_colloid_type(ps.type[i])) {
      local_colloids.push_back(i);
      any_fixed = any_fixed || ps.has_fixed(i);
    }
  // a fixed colloid acts as infinitely heavy: its copies must know (the
  // fixed flags are the locals' only). Without a fixed colloid on any rank
  // the sweep's own test (a local's flags; a copy: not fixed) holds.
  std::vector<char> fixed;
  if (comm.any(any_fixed)) {
    std::vector<Vector3d> x(static_cast<std::size_t>(n));
    for (int i : local_colloids)
      x[i][0] = ps.has_fixed(i) ? 1. : 0.;
    cells.fill_ghost_values(ps, x);
    fixed.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k)
      fixed[k] = x[k][0] > 0.5;
  }
  std::vector<int> const has_pairs = comm.allgather(col.n_pairs() > 0 ? 1 : 0);
  int last = -1;
  for (int r = 0; r < static_cast<int>(has_pairs.size()); ++r)
    if (has_pairs[r])
      last = r;
  auto const &copies = col.pair_copies();
  std::vector<Vector3d> dv(static_cast<std::size_t>(n)), dw(dv.size()), v0, w0;
  for (int r = 0; r <= last; ++r) {
    if (!has_pairs[r])
      continue;
    if (r == comm.rank()) {
      v0.clear(), w0.clear();
      for (int g : copies)
        v0.push_back(ps.v[g]), w0.push_back(ps.omega[g]);
      col.shardlow_marble_sweep(ps, sys.interactions(), noise, kT, dt, fixed.empty() ? nullptr : &fixed);
      for (std::size_t k = 0; k < copies.size(); ++k) {
        dv[copies[k]] = ps.v[copies[k]] - v0[k];
        dw[copies[k]] = ps.omega[copies[k]] - w0[k];
      }
    }
    cells.reduce_replicated_ghost_values(dv);
    cells.reduce_replicated_ghost_values(dw);
    for (int i : local_colloids) {
      ps.v[i] += dv[i];
      ps.omega[i] += dw[i];
      dv[i] = dw[i] = Vector3d{};
    }
    for (int g : copies)
      dv[g] = dw[g] = Vector3d{};
    if (r < last) // (after the last: the next step's ghost update)
      cells.update_replicated_ghosts(ps);
  }
}
#endif // MARBLE
} // namespace

void check_shardlow_decomposition(System &sys) {
  if (!sys.comm().parallel())
    return;
  auto &cells = sys.cells();
  double const r = std::max({cells.range(), cells.range_ll(), cells.range_ls()});
  auto const g = cells.node_grid(sys.box());
  auto const &L = sys.box().length();
  for (int d = 0; d < 3; ++d) {
    if (g[d] < 2)
      continue;
    // the narrowest domain along d (the equal split's L / g without domain cuts)
    auto const ax = cells.axis_split(sys.box(), g, d);
    double w = L[d] / g[d];
    for (std::size_t k = 0; k + 1 < ax.cut.size(); ++k) // (empty for the equal split)
      w = std::min(w, ax.cut[k + 1] - ax.cut[k]);
    if (w < 2. * r)
      throw Utils::RuntimeError(
          "cannot integrate with the Shardlow integrator on " + std::to_string(sys.comm().size()) +
          " MPI ranks: the domains are " + Utils::to_str(w) + " wide along axis " + std::to_string(d) +
          " (node grid " + std::to_string(g[0]) + " x " + std::to_string(g[1]) + " x " + std::to_string(g[2]) +
          (sys.box().lees_edwards().active() ? "; Lees-Edwards splits the vorticity axis only" : "") +
          "), less than twice the pair range (cutoff + skin = " + Utils::to_str(r) +
          "), which its sweep's rounds need; use fewer ranks, a larger box or a smaller skin, or "
          "integrator.set_vv() / set_dpd_vv() (doc/parallel.md)");
  }
}

void shardlow_sweep(System &sys) {
  auto &ps = sys.particles();
  auto const &ia = sys.interactions();
  double const dt = sys.time_step();
  NoiseContext const noise = sys.noise_context(true);
  double const kT = sys.thermostat().dpd.kT;
  LEJump const le_jump(sys);
  std::array<Vector3d, kPairBlock> xi;
  auto const blk = std::make_unique<SweepBlock>();
  SweepBlock &B = *blk;
  int const n_types = ia.n_types();
  std::vector<SweepTypePair> tp(static_cast<std::size_t>(n_types) * n_types);
  for (int t1 = 0; t1 < n_types; ++t1)
    for (int t2 = 0; t2 < n_types; ++t2) {
      DPDParams const &p = ia.get(t1, t2).get<DPDPair>();
      SweepTypePair &q = tp[t1 * n_types + t2];
      q.pow2 = exact_reciprocal(p.radial.r_cut);
      q.inv_rc = q.pow2 ? 1. / p.radial.r_cut : 0.;
#ifdef TRANS_DPD
      q.pow2t = exact_reciprocal(p.trans.r_cut);
      q.inv_rct = q.pow2t ? 1. / p.trans.r_cut : 0.;
#endif
    }
  PairMasses pm;
#ifdef TRANS_DPD
  bool const any_sf = ia.any_active<SurfaceFriction>();
  // shared shells (positions fixed during the sweep; several ranks: counted
  // over all ranks, through the ghost exchange)
  std::vector<int> const sf_shells =
      any_sf ? surface_friction_shells(ps, sys.cells(), ia, sys.comm().parallel()) : std::vector<int>{};
#endif
#ifdef LUBRICATION
  std::array<Vector3d, kPairBlock> xi_lub;
  bool const any_lub = ia.any_active<Lubrication>();
#endif
  auto const soa = std::make_unique<PairBlockSoA>();
  // Several ranks: boundary[k] for list entry k = another rank reads or
  // writes its velocity (a local sent as a ghost, or another rank's
  // particle; a periodic image as its owner). The pairs touching one are
  // deferred to the rounds below.
  bool const par = sys.comm().parallel();
  int const nl = ps.n_local();
  // (several ranks: one slot for each other rank's particle, however many images of it came)
  int const *const rep = par ? sys.cells().ghost_representatives(ps).data() : nullptr;
  // (several ranks: the flags, the sent locals and the deferred pairs in buffers kept between steps)
  ShardlowBuffers &buf = sys.shardlow_buffers();
  std::vector<char> &boundary = buf.boundary;
  auto &deferred = buf.deferred;
  auto &deferred_d = buf.deferred_d;
  deferred.clear();
  deferred_d.clear();
  // the stick friction's torques change spins, which its rounds then carry too
#if defined(TRANS_DPD) && defined(ROTATION)
  bool const spins = any_sf;
#else
  bool const spins = false;
#endif
  if (par) {
    sys.cells().fill_ghost_values(ps, ps.v); // the ghosts at their owners' velocities (after the kick)
#ifdef ROTATION
    if (spins)
      sys.cells().fill_ghost_values(ps, ps.omega); // (and spins)
#endif
    // (with the face rounds, the flag is the side: CellSystem::boundary_sides)
    // (decided from the node grid alone, the same on every rank: the rounds
    // that follow are collective)
    auto const &sides = sys.cells().boundary_sides();
    bool const face = buf.face = sys.cells().boundary_axis() >= 0;
    if (face && sides.size() != static_cast<std::size_t>(ps.size()))
      throw Utils::RuntimeError("internal error: the Shardlow sweep's boundary sides (" + std::to_string(sides.size()) +
                                ") do not match the particles (" + std::to_string(ps.size()) +
                                "): the ghosts changed without a rebuild");
    if (face) {
      boundary.assign(sides.begin(), sides.end());
    } else {
      boundary.assign(static_cast<std::size_t>(ps.size()), 0);
      sys.cells().mark_sent_locals(boundary);
    }
    buf.sent.clear();
    for (int i = 0; i < nl; ++i)
      if (boundary[i])
        buf.sent.push_back(i);
    for (int k = nl; k < ps.size(); ++k) {
      int const o = ps.ghost_owner[k - nl];
      boundary[k] = o >= 0 ? boundary[o] : (face ? boundary[k] : 1);
    }
  }
  // (defer: a block's interior pairs, compacted)
  auto const inner = par ? std::make_unique<PairBlock>() : nullptr;
  auto const inner_d = par ? std::make_unique<PairBlockSoA>() : nullptr;
  // one block of selected pairs (b0, their d in D0); @p defer: leave the
  // boundary pairs (those at a distance > 0, which the sweep would update)
  // with their d for the rounds, and sweep the others: the same pairs in the
  // same order with the same operands as if they were skipped one by one
  // below (every step of a pair's update is per pair: the noise, the
  // exponentials and roots of the blocks, the masses), without computing the
  // deferred pairs' factors twice
  auto sweep_block = [&](PairBlock const &b0, PairBlockSoA const &D0, bool defer) {
    PairBlock const *pb = &b0;
    PairBlockSoA const *pD = &D0;
    if (defer) {
      int s0 = 0;
      while (s0 < b0.size && !(boundary[b0.i[s0]] | boundary[b0.j[s0]]))
        ++s0;
      if (s0 < b0.size) { // some boundary pair: compact the others
        PairBlock &c = *inner;
        PairBlockSoA &C = *inner_d;
        int m = 0;
        for (int s = 0; s < b0.size; ++s) {
          int const i = b0.i[s], j = b0.j[s];
          Vector3d const d{D0.dx[s], D0.dy[s], D0.dz[s]};
          if (boundary[i] | boundary[j]) {
            if (d.norm2() > 0.) {
              deferred.push_back({i, j});
              deferred_d.push_back(d);
            }
            continue;
          }
          c.i[m] = i, c.j[m] = j;
          C.dx[m] = d[0], C.dy[m] = d[1], C.dz[m] = d[2];
          ++m;
        }
        c.size = m;
        if (m == 0)
          return;
        pb = &c, pD = &C;
      }
    }
    PairBlock const &b = *pb;
    PairBlockSoA const &D = *pD;
    // the noise of the block's pairs (independent draws the CPU overlaps)
    if (kT > 0.)
      draw_block_noise<DPDPair>(b, ps, ia, noise, xi);
    else
      std::fill(xi.begin(), xi.begin() + b.size, Vector3d{});
#ifdef LUBRICATION
    if (any_lub) {
      if (kT > 0.)
        draw_block_noise<Lubrication>(b, ps, ia, noise, xi_lub);
      else
        std::fill(xi_lub.begin(), xi_lub.begin() + b.size, Vector3d{});
    }
#endif
    // pre-pass: the DPD pair update's factors, which do not depend on the
    // velocities (independent pairs: the CPU overlaps their square roots,
    // exponentials and divisions)
    for (int s = 0; s < b.size; ++s) {
      int const i = b.i[s], j = b.j[s];
      Vector3d const d{D.dx[s], D.dy[s], D.dz[s]}; // ps.pos[i] - ps.pos[j]
      double const r2 = d.norm2();
      unsigned char f = 0;
      if (r2 > 0.) {
        f = SweepBlock::in_range;
        int const ti = ps.type[i], tj = ps.type[j];
        DPDParams const &p = ia.get(ti, tj).get<DPDPair>();
        if (p.active) {
          SweepTypePair const &q = tp[ti * n_types + tj];
          double const r = std::sqrt(r2);
          double const w = dpd_weight(p.radial, DPDPair::gap(p, r), q.inv_rc, q.pow2);
#ifdef TRANS_DPD
          double const wt = dpd_weight(p.trans, DPDPair::gap(p, r), q.inv_rct, q.pow2t);
          bool const acts = !(w <= 0. && wt <= 0.);
#else
          bool const acts = !(w <= 0.);
#endif
          if (acts) {
            f |= SweepBlock::dpd;
            int const oi = owner(ps, i, rep), oj = owner(ps, j, rep);
            double const mi = ps.get_mass(oi), mj = ps.get_mass(oj);
            pm.set(mi, mj, kT);
            double const mu = pm.mu, mfac = pm.mfac;
            Vector3d const e = d / r;
            B.oi[s] = oi, B.oj[s] = oj, B.mi[s] = mi, B.mj[s] = mj, B.mu[s] = mu, B.e[s] = e;
            // x / 1 is x: unit masses need no division in the velocity pass
            if (mi == 1. && mj == 1.)
              f |= SweepBlock::unit_masses;
            // a power-of-two mu multiplies the factors below instead of
            // each momentum change: the same bits (scaling by 2^k commutes
            // with rounding), one multiplication less on the sweep's chain
            if (pm.mu_pow2)
              f |= SweepBlock::mu_folded;
            // the rates lambda dt of the OU steps (their factors follow below)
            if (w > 0. && p.radial.gamma > 0.) {
              B.ar[s] = pm.over_mu(p.radial.gamma * mfac * w * w * dt);
              B.kT_mu[s] = pm.kT_over_mu;
              f |= SweepBlock::radial;
            }
#ifdef TRANS_DPD
            if (wt > 0. && p.trans.gamma > 0.) {
              B.at[s] = pm.over_mu(p.trans.gamma * mfac * wt * wt * dt);
              B.kT_mu[s] = pm.kT_over_mu;
              f |= SweepBlock::trans;
            }
#endif
          }
        }
      }
      B.flags[s] = f;
    }
    // the OU factors a = exp(-lambda dt) (struct OU, in separate loops: the
    // exponentials of a block 4 at a time, integrators/ou_exp.hpp, within
    // 1 ulp of std::exp). Pairs without the friction get exp(0), unused.
    unsigned any_flags = 0;
    for (int s = 0; s < b.size; ++s) {
      unsigned const f = B.flags[s];
      any_flags |= f;
      B.ar[s] = (f & SweepBlock::radial) ? -B.ar[s] : 0.;
#ifdef TRANS_DPD
      B.at[s] = (f & SweepBlock::trans) ? -B.at[s] : 0.;
#endif
    }
    // (then the noise amplitudes sqrt(12 kT/mu (1 - a^2)), 4 at a time,
    // and a - 1; sqrt(12): xi has variance 1/12. Lanes without the
    // friction compute from stale kT/mu, unused.)
    if (any_flags & SweepBlock::radial) {
      exp_neg_block(B.ar.data(), B.ar.data(), b.size);
      ou_amplitude_block(B.ar.data(), B.kT_mu.data(), b.size, B.sd.data(), B.ar.data());
    }
#ifdef TRANS_DPD
    if (any_flags & SweepBlock::trans)
      exp_neg_block(B.at.data(), B.at.data(), b.size);
#endif
    for (int s = 0; s < b.size; ++s) {
      unsigned const f = B.flags[s];
      if (f & SweepBlock::radial) {
        B.nr[s] = B.sd[s] * (B.e[s] * xi[s]);
        if (f & SweepBlock::mu_folded) {
          B.ar[s] *= B.mu[s];
          B.nr[s] *= B.mu[s];
        }
      }
#ifdef TRANS_DPD
      if (f & SweepBlock::trans) {
        double const a = B.at[s];
        double const sd = std::sqrt(12. * B.kT_mu[s] * (1. - a * a));
        Vector3d const &e = B.e[s];
        Vector3d const xi_perp = xi[s] - (e * xi[s]) * e;
        B.at[s] = a - 1.;
        B.nt[s] = sd * xi_perp;
        if (f & SweepBlock::mu_folded) {
          B.at[s] *= B.mu[s];
          B.nt[s] *= B.mu[s];
        }
      }
#endif
    }
    // the sequential exact pair updates in list order. The velocity of the
    // row's owner oi is held in registers (vi, for owner ci) while its pairs
    // follow one another, and written back when the owner changes: the
    // chain of updates through v_i does not go through memory (a store
    // forwarded to the next pair's load). oj == oi (a particle's own image,
    // boxes below twice the cutoff) goes through memory.
    int ci = -1;
    Vector3d vi{};
    for (int s = 0; s < b.size; ++s) {
      unsigned const f = B.flags[s];
      if (!(f & SweepBlock::in_range))
        continue;
      int const i = b.i[s], j = b.j[s];
      // Lees-Edwards: the jump of v_i - v_j across the shear plane (none
      // for local-local pairs)
      bool const jump = le_jump.on && (i >= ps.n_local() || j >= ps.n_local());
      Vector3d const vjump = jump ? le_jump.pair(ps, i, j) : Vector3d{};
      // the DPD pair update
      if (f & SweepBlock::dpd) {
        int const oi = B.oi[s], oj = B.oj[s];
        Vector3d const &e = B.e[s];
        // the pair's momentum change for the velocities vi_, vj_
        auto momentum = [&](Vector3d const &vi_, Vector3d const &vj_) {
          Vector3d const vij = jump ? vi_ - vj_ + vjump : vi_ - vj_;
          double const u = e * vij;
          Vector3d du{};
          if (f & SweepBlock::radial)
            du = (B.ar[s] * u + B.nr[s]) * e;
#ifdef TRANS_DPD
          if (f & SweepBlock::trans) {
            Vector3d const u_perp = vij - u * e;
            du += B.at[s] * u_perp + B.nt[s];
          }
#endif
          return (f & SweepBlock::mu_folded) ? du : B.mu[s] * du;
        };
        if (oj == oi) { // (a particle and its own image) in memory
          if (ci >= 0)
            ps.v[ci] = vi;
          ci = -1;
          Vector3d const dp = momentum(ps.v[oi], ps.v[oj]);
          ps.v[oi] += (f & SweepBlock::unit_masses) ? dp : dp / B.mi[s];
          ps.v[oj] -= (f & SweepBlock::unit_masses) ? dp : dp / B.mj[s];
        } else {
          if (oi != ci) {
            if (ci >= 0)
              ps.v[ci] = vi;
            ci = oi;
            vi = ps.v[oi];
          }
          Vector3d const vj = ps.v[oj];
          Vector3d const dp = momentum(vi, vj);
          if (f & SweepBlock::unit_masses) {
            vi += dp;
            ps.v[oj] = vj - dp;
          } else {
            vi += dp / B.mi[s];
            ps.v[oj] = vj - dp / B.mj[s];
          }
        }
      }
#if defined(TRANS_DPD) || defined(LUBRICATION)
      if (
#ifdef TRANS_DPD
          any_sf ||
#endif
#ifdef LUBRICATION
          any_lub ||
#endif
          false) {
        // (these read and write the owners' velocities in memory)
        if (ci >= 0)
          ps.v[ci] = vi;
        ci = -1;
        IAParams const &pair = ia.get(ps.type[i], ps.type[j]);
        Vector3d const d{D.dx[s], D.dy[s], D.dz[s]}; // ps.pos[i] - ps.pos[j] (the select's bits)
        [[maybe_unused]] double const r2 = d.norm2();
#ifdef TRANS_DPD
        // the stick friction's exact update of the pair's tangential contact
        // velocity, spins included (nonbonded/surface_friction_apply.hpp)
        if (any_sf) {
          SurfaceFriction::Params const &sp = pair.get<SurfaceFriction>();
          if (sp.active)
            surface_friction_pair_update(ps, sp, i, j, owner(ps, i, rep), owner(ps, j, rep), kT, dt, noise,
                                         surface_friction_scale(sp, sf_shells, i, j), jump ? &vjump : nullptr);
        }
#endif
#ifdef LUBRICATION
        // then the pair's lubrication, its own exact OU step along e (rate
        // a_sq/mu; composing the two OU steps is exact: both keep the variance
        // kT/mu): the stiff near-contact friction does not limit dt
        if (any_lub) {
          Lubrication::Params const &lp = pair.get<Lubrication>();
          if (!lp.active)
            continue;
          double const r = std::sqrt(r2);
          double const h = r - lp.offset;
          if (h >= lp.h_cut)
            continue;
          int const oi = owner(ps, i, rep), oj = owner(ps, j, rep);
          double const mi = ps.get_mass(oi), mj = ps.get_mass(oj);
          double const mu = mi * mj / (mi + mj);
          Vector3d const e = d / r;
          double const u = e * (jump ? ps.v[oi] - ps.v[oj] + vjump : ps.v[oi] - ps.v[oj]);
          OU const ou(Lubrication::friction(lp, h) * dt / mu, kT / mu);
          double const du = (ou.a - 1.) * u + ou.s * Lubrication::noise_weight(lp, h) * (e * xi_lub[s]);
          Vector3d const dp = (mu * du) * e;
          ps.v[oi] += dp / mi;
          ps.v[oj] -= dp / mj;
        }
#endif
      }
#endif
    }
    if (ci >= 0)
      ps.v[ci] = vi;
  };
  // (select_pairs: right after a rebuild, the pairs within the largest cutoff only)
  for_each_selected_block(ps, sys.cells().select_pairs(), ia, *soa,
                          [&](PairBlock const &b, PairBlockSoA const &D) { sweep_block(b, D, par); });
  if (par)
    sweep_boundary_rounds(sys, buf, spins, [&](PairBlock const &b, Vector3d const *d) {
      for (int s = 0; s < b.size; ++s)
        soa->dx[s] = d[s][0], soa->dy[s] = d[s][1], soa->dz[s] = d[s][2];
      sweep_block(b, *soa, false);
    });
#ifdef MARBLE
  // then the marble colloids' surface coupling, pair by pair in the colloid
  // list's order: its own exact update (marble/Colloids.cpp), so a large
  // gamma dt does not bias it (the explicit coupling at nu = gamma dt / m = 0.6
  // gave a 3 % larger D, doc/speed-accuracy.md)
  if (sys.colloids().any()) {
    if (par)
      marble_sweep_rounds(sys, noise, kT, dt);
    else
      sys.colloids().shardlow_marble_sweep(ps, ia, noise, kT, dt);
  }
#endif
}

// F_i += friction of the velocity change dv (pairs of the main list only):
// the DPD pair force without noise (thermostats/dpd.hpp), with the relative
// velocity change in place of the relative velocity. @p dv_of(k) gives the
// velocity change of list index k, @p add(k, f) books the force on it.
namespace {
template <typename DV, typename Add> void friction_of_dv_pairs(System &sys, DV dv_of, Add add) {
  auto const &ps = sys.particles();
  auto const &ia = sys.interactions();
  Vector3d const no_noise{};
  for_each_pair(ps, sys.cells().pairs(), ia, [&](int i, int j) {
    DPDParams const &p = ia.get(ps.type[i], ps.type[j]).get<DPDPair>();
    if (!p.active)
      return;
    Vector3d const d = ps.pos[i] - ps.pos[j];
    double const r2 = d.norm2();
    if (!(r2 > 0.))
      return;
    // ghosts carry their owner's mass
    Vector3d const f = DPDPair::force(p, d, std::sqrt(r2), dv_of(i) - dv_of(j), no_noise, pair_mass_factor(ps, i, j));
    add(i, f);
    add(j, -f);
  });
}
} // namespace

void add_friction_of_dv(System &sys, std::vector<Vector3d> const &dv) {
  auto &ps = sys.particles();
  if (!sys.comm().parallel()) { // every ghost is an image of a local: book on the owner
    friction_of_dv_pairs(
        sys, [&](int k) { return dv[owner(ps, k)]; },
        [&](int k, Vector3d const &f) { ps.f[owner(ps, k)] += f; });
    return;
  }
  // Several ranks: dv of the ghosts from the ghost exchange, the friction on
  // other ranks' particles accumulated per particle and sent back.
  int const n = ps.n_local();
  std::vector<Vector3d> dva(static_cast<std::size_t>(ps.size())), df(dva.size());
  std::copy(dv.begin(), dv.begin() + n, dva.begin());
  sys.cells().fill_ghost_values(ps, dva);
  friction_of_dv_pairs(
      sys, [&](int k) { return dva[k]; }, [&](int k, Vector3d const &f) { df[k] += f; });
  sys.cells().reduce_ghost_values(ps, df);
  for (int i = 0; i < n; ++i)
    ps.f[i] += df[i];
}
#endif // DPD


} // namespace Marble
