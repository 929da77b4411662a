#pragma once
// Cell grid + Verlet lists with a skin and a ghost layer, over this rank's
// domain (regular domain decomposition: the box is cut into a node grid of
// px x py x pz boxes, one per MPI rank, equal unless set_domain_fractions
// moved the planes between them (load balance, system/balance.cpp); one
// rank owns the whole box).
//
// On rebuild: locals are folded into the box and sorted by cell; every local
// whose periodic image lies within `range` = max_cut + skin of the box gets a
// ghost copy there; the Verlet list holds each interacting pair once:
//   local-local pairs with i < j, and local-ghost pairs whose ghost shift is
//   lexicographically positive (the image with the opposite shift is dropped).
// Between rebuilds only the ghosts' positions/velocities are refreshed.
//
// With several ranks, a rebuild first migrates every particle to the rank
// whose domain holds its folded position, then each rank receives copies of
// the other ranks' particles within `range` of its domain from half of the
// sides (a half shell: an image goes from the rank at node coordinates a,
// shifted by n box lengths, to the rank at b if (a + n * grid) - b is
// lexicographically positive; of two ranks sharing a pair exactly one gets
// the other's particle and computes the pair), and large particles
// (colloids) of every other rank whatever their distance. Large-range types
// and colloid copies come from all sides; their pairs with another rank's
// particle are kept on the rank owning the smaller id. The force on a ghost
// (and the force/torque on a colloid copy) is sent back to its owner by
// reduce_ghost_forces(); ghost updates and force returns go point to point
// to the neighbour ranks only, and so do the migration and the ghost set-up
// at a rebuild (sizes probed; the all-rank alltoallv only for a particle
// bound for a rank that is not a neighbour, or for colloid copies).
// docs: doc/parallel.md.
//
// Large-range types (colloids of a suspension, doc/architecture.md "Two cell
// grids"): set_large_range() names types whose pairs reach much farther than
// the solvent's. They are kept out of the solvent grid (whose cells then have
// the solvent's range) and get a ghost layer of their own, wider range. The
// one pair list is the union of (a) the solvent-grid pairs of all other types
// (built exactly as without large-range types), (b) pairs among large-range
// particles from a coarse grid over those particles only, and (c) large-small
// pairs found by scanning the solvent cells within the large-small range
// around each large-range particle (locals and ghosts of every shift): the
// small partner is always a local, so each pair is listed once, on the small
// particle's rank.
#include "box/BoxGeometry.hpp"
#include "comm/Communicator.hpp"
#include "particles/ParticleStore.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <cstddef>
#include <vector>

namespace Marble {

/** The Verlet pair list in list order: the rows of the small locals i =
 * 0, 1, ... (compressed sparse rows: only the partners j of the pairs (i, j)
 * are stored, 4 bytes a pair, and i is read once per row), then the pairs
 * with large-range particles as (i, j) (@ref extra, CellSystem::build_wide_pairs).
 * Iterating it yields the pairs as std::array<int, 2>{i, j} in that order. */
struct VerletPairs {
  std::vector<int> row_start{0}; // row i: j[row_start[i]] .. j[row_start[i + 1] - 1]
  std::vector<int> j;            // row_start.back() entries, then 8 zeros (SIMD reads past a row)
  std::vector<std::array<int, 2>> extra;

  int n_rows() const { return static_cast<int>(row_start.size()) - 1; }
  std::size_t n_row_pairs() const { return static_cast<std::size_t>(row_start.back()); }
  std::size_t size() const { return n_row_pairs() + extra.size(); }
  bool empty() const { return size() == 0; }
  void clear() {
    row_start.assign(1, 0);
    j.clear();
    extra.clear();
  }

  class const_iterator {
  public:
    using value_type = std::array<int, 2>;
    using difference_type = std::ptrdiff_t;
    const_iterator() = default;
    const_iterator(VerletPairs const *l, std::size_t k) : m_l(l), m_k(k) { skip_empty_rows(); }
    value_type operator*() const {
      return m_k < m_l->n_row_pairs() ? value_type{m_row, m_l->j[m_k]}
                                      : m_l->extra[m_k - m_l->n_row_pairs()];
    }
    const_iterator &operator++() {
      ++m_k;
      skip_empty_rows();
      return *this;
    }
    const_iterator operator++(int) {
      auto t = *this;
      ++*this;
      return t;
    }
    bool operator==(const_iterator const &o) const { return m_k == o.m_k; }
    bool operator!=(const_iterator const &o) const { return m_k != o.m_k; }

  private:
    void skip_empty_rows() {
      while (m_row < m_l->n_rows() && static_cast<std::size_t>(m_l->row_start[m_row + 1]) <= m_k)
        ++m_row;
    }
    VerletPairs const *m_l = nullptr;
    std::size_t m_k = 0;
    int m_row = 0;
  };
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, size()}; }
};

class CellSystem {
public:
  double skin() const { return m_skin; }
  void set_skin(double s) {
    m_skin = s;
    m_valid = false;
  }
  double range() const { return m_range; }
  bool valid() const { return m_valid; }
  void invalidate() {
    m_valid = false;
    m_inner_fresh = false;
  }

  /** Fold, migrate, sort, make ghosts, build the pair list for pair range
   * @p max_cut. Collective. */
  void rebuild(ParticleStore &ps, BoxGeometry const &box, double max_cut);
  /** Copy positions (+ shift), velocities and omega from owners to ghosts. Collective. */
  void update_ghosts(ParticleStore &ps) const;
  /** Add ghost forces (and torques) to their owners. Collective. */
  void reduce_ghost_forces(ParticleStore &ps) const;
  /** @p x has one entry per particle (locals and ghosts): fill the ghosts'
   * entries from their owners' (periodic images locally, other ranks' via
   * the ghost exchange). Collective. */
  void fill_ghost_values(ParticleStore const &ps, std::vector<Utils::Vector3d> &x) const;
  /** Add the ghosts' entries of @p x to their owners' (the reverse of
   * fill_ghost_values). Collective. */
  void reduce_ghost_values(ParticleStore const &ps, std::vector<Utils::Vector3d> &x) const;
  /** Set @p flag[i] = 1 for every local i that the last build sent to another
   * rank as a ghost (the locals other ranks can read and write: the Shardlow
   * sweep's boundary, integrators/shardlow.cpp). Not collective. */
  void mark_sent_locals(std::vector<char> &flag) const {
    for (auto const &q : m_send_index)
      for (int i : q)
        flag[static_cast<std::size_t>(i)] = 1;
  }
  /** With the node grid split along exactly one axis (several ranks), that
   * axis; else -1 (then boundary_sides() is empty). */
  int boundary_axis() const { return m_boundary_axis; }
  /** With boundary_axis() >= 0: per particle (locals, then ghosts) the side
   * of this rank's domain along that axis at which another rank can read or
   * write it, from the last build's positions: 1 the lower half of the domain
   * (a local sent as a ghost or another rank's particle, below the middle),
   * 2 the upper half, 3 both or neither (other ranks' colloid copies), 0 none
   * (locals no other rank holds; periodic images of locals: see their
   * owners). The Shardlow sweep's face rounds (integrators/shardlow.cpp)
   * read it. Not collective. */
  std::vector<char> const &boundary_sides() const { return m_boundary_side; }
  /** For each ghost (index g - n_local) the slot that stands for its
   * particle: a periodic image of a local its owner; another rank's particle
   * the first of its ghost slots (a particle can arrive as several periodic
   * images, along an axis the node grid does not split or as a large-range
   * type). Built on first use after each build. Not collective. */
  std::vector<int> const &ghost_representatives(ParticleStore const &ps) const;
  /** update_ghosts for the other ranks' copies of the replicated (colloid)
   * types only: positions, velocities and omega; the other ghosts keep their
   * values (the RESPA substeps, whose colloid pairs read locals and these
   * copies only). Collective; nothing on one rank. */
  void update_replicated_ghosts(ParticleStore &ps) const;
  /** reduce_ghost_values for the other ranks' copies of the replicated types
   * only (the entries of every other ghost must be zero). Collective. */
  void reduce_replicated_ghost_values(std::vector<Utils::Vector3d> &x) const;
  /** True if some local (on any rank) moved more than skin/2 since the last rebuild. Collective.
   * With Lees-Edwards: more than (skin - |offset change since the build|) / 2. */
  bool displacement_exceeds_half_skin(ParticleStore const &ps) const;
  /** Whether the pair test below applies to the last build: no Lees-Edwards
   * images, no large-range types, and every periodic box length at least 3
   * pair ranges (one image of a pair within reach). */
  bool pair_test_applies() const;
  /** The list's exact test (doc/benchmarks.md "The Verlet list's life"),
   * called once some local has moved more than skin/2 since the build: true
   * if some pair within the rebuild's max_cut now may be missing from the
   * list, i.e. a pair whose distance at the build was at least the range
   * (cut + skin) is now closer than max_cut, or the fastest local has moved
   * a whole skin. Such a pair moved apart by more than the skin, so both its
   * particles moved more than skin - d_max: only those are compared (all
   * ranks' ones, minimum images). Also true if more than 1/128 of all
   * particles moved more than skin/2 (then a rebuild is cheaper than the
   * test). @p disp2: each local's squared displacement since the build, if
   * the caller has it (else computed here). @p reach: a displacement that
   * another list built at the same time tolerates only while d_max + (the
   * largest @p reach over the ranks) stays below the skin (the colloid pair
   * list: the largest colloid displacement since the build; < 0: none);
   * true once it does not. Collective; needs pair_test_applies(). */
  bool pairs_may_be_missing(ParticleStore const &ps, float const *disp2 = nullptr, double reach = -1.) const;

  // --- Lees-Edwards (box/LeesEdwards.hpp; no marble colloids; several ranks: node_grid splits the vorticity axis only) ---
  /** The current Lees-Edwards state (offset, shear velocity) for the ghost
   * updates; rebuild() takes it from the box. */
  void set_lees_edwards(LeesEdwardsBC const &le) { m_le = le; }
  /** Lees-Edwards: how many box lengths along the shear-plane normal the image
   * at list entry @p k is shifted (its velocity carries k times the shear
   * velocity); 0 for locals and without Lees-Edwards images. Every ghost,
   * own image or another rank's particle. */
  int le_crossings(int k, int n_local) const {
    return m_le_images && k >= n_local ? m_le_k[static_cast<std::size_t>(k - n_local)] : 0;
  }
  /** How far the images across the shear plane moved since the list build
   * (0 without Lees-Edwards images): |offset - offset at the build| times the
   * largest shift |k| along the normal that the build may make (> 1 when the
   * range exceeds the box along the normal; the same on every rank). */
  double le_drift(double pos_offset) const {
    return m_le_images ? m_le_kmax * std::abs(pos_offset - m_le_offset_at_build) : 0.;
  }
  /** The displacement limit of the list check: skin/2 less half the image drift (< 0: rebuild). */
  double le_half_skin_budget(double pos_offset) const { return 0.5 * (m_skin - le_drift(pos_offset)); }

  // --- domain decomposition ---
  void set_comm(Communicator const *comm) { m_comm = comm; }
  /** Large-range types (@p types[t] != 0; empty: none) with the largest
   * cutoff among their pairs (@p cut_ll) and between them and the other types
   * (@p cut_ls), skin not included. See the file comment. */
  void set_large_range(std::vector<char> const &types, double cut_ll, double cut_ls) {
    bool const any = std::find(types.begin(), types.end(), char(1)) != types.end();
    std::vector<char> t = any ? types : std::vector<char>{};
    if (t != m_wide || cut_ll != m_cut_ll || cut_ls != m_cut_ls)
      m_valid = false;
    m_wide = std::move(t);
    m_cut_ll = any ? cut_ll : 0.;
    m_cut_ls = any ? cut_ls : 0.;
  }
  std::vector<char> const &large_range_types() const { return m_wide; }
  /** Pair range (cutoff + skin) among large-range types and to the others (0: none). */
  double range_ll() const { return m_range_ll; }
  double range_ls() const { return m_range_ls; }
  /** Types whose particles every rank gets a copy of (colloids). */
  void set_replicated_types(std::vector<char> const &t) {
    m_replicated = t;
    m_valid = false;
  }
  /** Ranks per axis: the factorisation of the rank count with the smallest
   * domain surface for @p box; with Lees-Edwards only the vorticity axis is split. */
  std::array<int, 3> node_grid(BoxGeometry const &box) const;
  /** Rank of the domain at @p coords of the node grid @p grid. */
  static int rank_at(std::array<int, 3> const &grid, std::array<int, 3> const &coords);
  /** Node-grid coordinates of @p rank in the node grid @p grid (inverse of rank_at). */
  static std::array<int, 3> coords_at(std::array<int, 3> const &grid, int rank);
  /** Rank owning the (folded) position @p pos. */
  int owner_rank(Utils::Vector3d const &pos, BoxGeometry const &box) const;

  // --- domain cuts (load balance: doc/parallel.md "Load balance") ---
  /** The domains' boundaries along each axis as fractions of the box
   * length: for axis d, node_grid[d] + 1 increasing values from 0 to 1 (the
   * domain at node coordinate c is [f[c] L, f[c + 1] L)); an axis whose
   * entry does not have node_grid[d] + 1 values (empty: the default) is
   * split into equal parts, with the arithmetic of the equal split (so
   * trajectories without cuts keep every bit). The same on every rank
   * (the caller's duty: System::set_domain_fractions checks it). Invalidates
   * the lists. */
  void set_domain_fractions(std::array<std::vector<double>, 3> f) {
    m_fractions = std::move(f);
    ++m_fractions_version;
    invalidate();
  }
  std::array<std::vector<double>, 3> const &domain_fractions() const { return m_fractions; }
  /** The boundaries along axis @p d for @p box: node_grid[d] + 1 positions
   * from 0 to L (the equal split's c L / g where no cuts are set). */
  std::vector<double> domain_cuts(BoxGeometry const &box, int d) const;
  /** One axis of the decomposition: @p p domains over [0, L), equal (the
   * arithmetic of floor(x / dl)) or at the cuts. */
  struct AxisSplit {
    int p = 1;
    double L = 1., dl = 1.;
    bool uniform = true;
    std::vector<double> cut; // p + 1 positions when !uniform
    double lo(int c) const { return uniform ? c * dl : cut[static_cast<std::size_t>(c)]; }
    /** clamp(floor(x / dl), 0, p - 1) (equal), the domain holding x (cuts) */
    int coord(double x) const;
    /** the node coordinates [a, b] whose domain grown by r holds x (a > b: none) */
    std::pair<int, int> grown(double x, double r, bool periodic) const;
  };
  AxisSplit axis_split(BoxGeometry const &box, std::array<int, 3> const &g, int d) const;
  /** Lower corner and size of this rank's domain. */
  std::pair<Utils::Vector3d, Utils::Vector3d> local_domain(BoxGeometry const &box) const;

  VerletPairs const &pairs() const { return m_pairs; }
  /** The list for a consumer that selects the pairs within their cutoff
   * (every cutoff <= the rebuild's max_cut): right after a rebuild, at the
   * positions of the build, the rows hold only the pairs within max_cut
   * (written by the rebuild's candidate scan, which computes those distances
   * anyway; their order is that of pairs(), so a select gives the same pairs
   * in the same order); at any other time pairs(). update_ghosts (every
   * force computation that does not rebuild) and forget_inner() end it. */
  VerletPairs const &select_pairs() const { return m_inner_fresh ? m_inner : m_pairs; }
  /** Whether rebuilds write the inner list (default off: select_pairs() is
   * then pairs()); System turns it on for the Shardlow integrator. */
  void set_inner_list(bool on) { m_inner_wanted = on; }
  /** Whether select_pairs() is the build's inner list (tests). */
  bool inner_fresh() const { return m_inner_fresh; }
  /** Positions changed without update_ghosts or rebuild (e.g. put back after a
   * rebuild at other positions): select_pairs() is pairs() again. */
  void forget_inner() const { m_inner_fresh = false; }

  /** Visit every local particle index whose cell overlaps the sphere of
   * @p radius around @p center (a superset of the particles within radius).
   * Valid after rebuild(); @p center may lie outside the box (periodic images
   * of large particles). Used by the colloid neighbour search, which thus
   * never enlarges the solvent's cells. */
  template <typename F>
  void for_each_local_near(Utils::Vector3d const &center, double radius, F &&fn) const {
    if (m_cell_start.empty())
      return;
    std::array<int, 3> lo{}, hi{};
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::max(1, m_grid.coord(center[d] - radius, d));
      hi[d] = std::min(m_grid.n[d], m_grid.coord(center[d] + radius, d));
      if (lo[d] > hi[d])
        return;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          int const c = (z * m_grid.ext[1] + y) * m_grid.ext[0] + x;
          for (int k = m_cell_start[c]; k < m_cell_start[c + 1]; ++k)
            if (m_cell_members[k] < m_n_local_at_build)
              fn(m_cell_members[k]);
        }
    for (int i : m_wide_locals) // not in the solvent grid: all of them (a superset)
      fn(i);
  }

  /** Regular grid over the domain plus one layer of ghost cells on each side. */
  struct Grid {
    std::array<int, 3> n{1, 1, 1}, ext{3, 3, 3};
    Utils::Vector3d size{1., 1., 1.}, lo{0., 0., 0.};
    Utils::Vector3d inv_size{1., 1., 1.}; // 1 / size (rounded)
    Grid() = default;
    Grid(Utils::Vector3d const &lo, Utils::Vector3d const &len, double range);
    /** floor((x - lo) / size) + 1, clamped to [0, ext - 1]. The quotient is
     * first taken as a product with 1 / size, which differs from it by a few
     * ulps at most: where the product is farther than 1e-9 from an integer
     * (and below 1e6) both have the same floor; otherwise (and for NaN or
     * infinities) the division decides. The same cells, one division less. */
    int coord(double x, int d) const {
      double const u = x - lo[d];
      double const t = u * inv_size[d];
      double f = std::floor(t);
      double const frac = t - f;
      if (!(frac > 1e-9 && frac < 1. - 1e-9 && std::abs(t) < 1e6))
        f = std::floor(u / size[d]);
      double const c = f + 1.;
      return static_cast<int>(std::clamp(c, 0., static_cast<double>(ext[d] - 1)));
    }
    /** Cell of a local: clamped into the domain's own cells (round-off at the
     * domain faces must not put a local into the ghost layer). */
    int local_index(Utils::Vector3d const &p) const {
      int c[3];
      for (int d = 0; d < 3; ++d)
        c[d] = std::clamp(coord(p[d], d), 1, n[d]);
      return (c[2] * ext[1] + c[1]) * ext[0] + c[0];
    }
    int index(Utils::Vector3d const &p) const {
      return (coord(p[2], 2) * ext[1] + coord(p[1], 1)) * ext[0] + coord(p[0], 0);
    }
    int n_total() const { return ext[0] * ext[1] * ext[2]; }
  };
  std::array<int, 3> const &n_cells() const { return m_n_cells; }
  /** Candidate-scan code path of the list build: 0 scalar/SSE2, 1 AVX2,
   * 2 AVX-512; all give the same list, pair for pair. set_scan_path(-1): the
   * best this CPU runs (the default); a path above that is lowered to it.
   * For tests and benchmarks (process-wide). */
  static void set_scan_path(int path);
  static int scan_path();
  long n_rebuilds() const { return m_n_rebuilds; }

private:
  struct SendEntry {
    int index;
    int le_k; // Lees-Edwards: the image's shift along the normal in box lengths (0 otherwise)
    Utils::Vector3d shift;
  };
  void make_ghosts(ParticleStore &ps, BoxGeometry const &box);
  void make_le_ghosts(ParticleStore &ps, BoxGeometry const &box);
  void exchange_ghosts(ParticleStore &ps);
  bool other_rank_computes(ParticleStore const &ps, int i, int j, int n_local) const;
  template <typename F> void for_each_own_image(ParticleStore const &ps, F &&fn) const;
  template <typename T, typename NOut, typename NIn, typename Fill, typename Consume>
  void exchange_records(NOut &&n_out, NIn &&n_in, Fill &&fill, Consume &&consume) const;
  template <typename T, typename Pack, typename Unpack>
  void to_remote_ghosts(Pack &&pack, Unpack &&unpack) const;
  template <typename T, typename Pack, typename Unpack>
  void from_remote_ghosts(Pack &&pack, Unpack &&unpack) const;
  void migrate(ParticleStore &ps, BoxGeometry const &box) const;
  void update_neighbour_ranks(BoxGeometry const &box, double radius);
  bool replicated(int type) const {
    return type >= 0 && type < static_cast<int>(m_replicated.size()) && m_replicated[type];
  }
  bool parallel() const { return m_comm && m_comm->parallel(); }
  bool wide(int type) const {
    return type >= 0 && type < static_cast<int>(m_wide.size()) && m_wide[type];
  }
  void build_wide_pairs(ParticleStore const &ps, BoxGeometry const &box, int n_small_local,
                        std::vector<int> const &ghost_begin);
  void sort_locals(ParticleStore &ps, BoxGeometry const &box);
  void build_pairs(ParticleStore const &ps, BoxGeometry const &box);

  double m_skin = 0.4;
  double m_range = 0.;
  // the box of the last build and the particle count over all ranks (pairs_may_be_missing;
  // the count -1 until its first call after the build)
  Utils::Vector3d m_box_l{1., 1., 1.};
  std::array<bool, 3> m_box_periodic{true, true, true};
  mutable long long m_n_global_at_build = -1;
  mutable std::vector<double> m_fast, m_hot, m_fast_sorted, m_fast_dsorted; // pairs_may_be_missing: scratch
  mutable std::vector<float> m_fast_d2;
  mutable std::vector<int> m_fast_cell, m_fast_start, m_fast_order;
  bool m_valid = false;
  long m_n_rebuilds = 0;
  std::array<int, 3> m_n_cells{1, 1, 1};
  VerletPairs m_pairs;
  // the pairs of m_pairs within the rebuild's max_cut at the build's positions
  // (rows only; extra as in m_pairs) and whether they are still those positions
  VerletPairs m_inner;
  mutable bool m_inner_fresh = false;
  int m_boundary_axis = -1;             // boundary_axis()
  std::vector<char> m_boundary_side;    // boundary_sides()
  void mark_boundary_sides(ParticleStore const &ps, BoxGeometry const &box);
  mutable std::vector<int> m_ghost_rep; // ghost_representatives(): its cache
  mutable bool m_ghost_rep_valid = false;
  double m_inner_cut = 0.; // the rebuild's max_cut
  bool m_inner_wanted = false;
  Grid m_grid;
  std::vector<int> m_cell_start, m_cell_members; // all particles (locals + ghosts) by cell
  // rebuild scratch, kept between rebuilds (no allocation or page faults per rebuild)
  std::vector<int> m_scratch_cell, m_scratch_fill, m_scratch_ghost_begin;
  std::vector<double> m_scratch_x, m_scratch_y, m_scratch_z;
  int m_n_local_at_build = 0;
  bool m_local_cells_ready = false; // m_scratch_cell holds the sorted locals' cells (sort_locals)
  Communicator const *m_comm = nullptr;
  std::vector<char> m_replicated;
  // large-range types: per-type flag, cutoffs (no skin), ranges (with skin)
  std::vector<char> m_wide;
  double m_cut_ll = 0., m_cut_ls = 0., m_range_ll = 0., m_range_ls = 0.;
  std::vector<int> m_wide_locals; // their local indices after the last rebuild
  // ghosts of this rank's particles on other ranks: m_send[r] (list order =
  // the order rank r stores them); ghosts from rank r: [m_recv_begin[r], + m_recv_count[r])
  std::vector<std::vector<SendEntry>> m_send;
  std::vector<int> m_recv_begin, m_recv_count;
  // the replicated types among them: positions k in m_send[r], and ghost indices from rank r
  std::vector<std::vector<int>> m_rep_send, m_rep_recv;
  // the other ranks whose domain (or a periodic image of it) lies within the
  // neighbour radius of this rank's domain along every axis, sorted; symmetric.
  // Migration and the ghost set-up at a rebuild talk to these only.
  std::vector<int> m_nbrs;
  std::vector<char> m_is_nbr;               // by rank
  std::array<double, 8> m_nbr_key{};        // box, rank count and rank, radius, periodicity, node grid of m_nbrs
  long m_nbr_fversion = -1;                 // the domain cuts' version of m_nbrs
  std::array<std::vector<double>, 3> m_fractions; // set_domain_fractions
  long m_fractions_version = 0;
  std::vector<std::vector<int>> m_send_index; // m_send[q][k].index, contiguous (force returns)
  // neighbour-exchange buffers by rank, kept and only grown (no refill per step)
  mutable std::vector<std::vector<std::max_align_t>> m_xsend, m_xrecv;
  mutable std::vector<Communicator::Block> m_xblocks[2];
  // Lees-Edwards: current state, the offset at the last build, the largest
  // |k| a build may make, and for each ghost (own image or another rank's
  // particle; ghost g: m_le_k[g - n_local]) its shift k along the normal
  LeesEdwardsBC m_le;
  double m_le_offset_at_build = 0.;
  int m_le_kmax = 1;
  bool m_le_images = false;
  std::vector<int> m_le_k;
};

} // namespace Marble
