// SRD collision step (reference.md section 6; Malevanets & Kapral 1999;
// Andersen variant: Allahyari & Gompper / Noguchi et al.; the cell thermostat
// draws the relative kinetic energy of a cell from its Gamma distribution).
//
// On several MPI ranks (doc/srd.md, "Parallel runs"): the SRD particles are
// first migrated to the rank whose domain holds them, then every rank sorts
// its particles into the (global, shifted) collision cells. A cell that may
// straddle a domain face (a cell of the slabs next to a face whose extent
// overlaps the domains of several ranks, found from the geometry alone, so
// every rank agrees) has its sums (count, momentum, and the Andersen and
// angular parts) exchanged with the other ranks it overlaps (a neighbour
// exchange, no global reduction) and added (exactly: integer sums) before the
// collision, and, for the thermostat and the angular-momentum correction, a
// second set of sums after the first half of it; all other cells are local. The noise of a cell is
// keyed by its global index, so every rank applies the same rotation and the
// trajectory does not depend on the number of ranks, bit for bit. Each rank
// sorts its particles into its local cell grid (its domain plus one cell).
#include "srd/Fluid.hpp"
#include "srd/random.hpp"

#include "box/BoxGeometry.hpp"
#include "system/System.hpp"

#include "utils/errors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace Marble::Srd {

using Utils::Vector3d;

namespace {
Vector3d cross(Vector3d const &a, Vector3d const &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}


// Solve the symmetric 3x3 system A x = b (Cramer); false if singular.
bool solve3(double const A[3][3], Vector3d const &b, Vector3d &x) {
  double const det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  double const scale = A[0][0] + A[1][1] + A[2][2];
  if (!(std::abs(det) > 1e-12 * scale * scale * scale))
    return false;
  for (int k = 0; k < 3; ++k) {
    double M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M[i][j] = (j == k) ? b[i] : A[i][j];
    x[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
           det;
  }
  return true;
}

// Per-cell sums. A: count, sum v, sum xi (AT), sum r (AT+a).
// B: relative kinetic energy (thermostat) or the inertia tensor and the
// angular momentum to restore (AT+a). Every sum but the count is held as two
// limbs (below): A = [n, v (3 x 2), xi (3 x 2), r (3 x 2)],
// B = [e (2), I (9 x 2), dL (3 x 2)].
constexpr int nA = 19, nB = 26;

// The cell sums are exact: a term x (|x| < 2^20) is cut to a multiple of
// 2^-60 (the velocities: 2^-45, below), held as two integer-valued doubles
// hi = round(x 2^20), lo = round((x 2^20 - hi) 2^40), rounded to nearest
// (even) by adding and subtracting 1.5 2^52: a fixed function of x. Sums of
// such integers stay exact in double precision (|hi| < 2^40, |lo| <= 2^39,
// fewer than 2^13 terms: below 2^53), so a sum does not depend on the order
// of its terms, and a cell split between MPI ranks (partial sums added in any
// order) gets the same bits as on one rank: the trajectory does not depend
// on the number of ranks at all (doc/srd.md, "Parallel runs").
// The velocity sums (the hot loop) are cut to 2^-45 (a momentum error per
// particle and collision < 1.5e-14, below the tests' 1e-13): two limbs
// hi = round(v 2^20), lo = round((v 2^20 - hi) 2^25) (hi 2^25 + lo =
// round(v 2^45), hi 2^25 being even), or, where that is exact (|v| < 64 and
// n max|v| < 256), one limb round(v 2^45) in lo and 0 in hi: its value
// lo 2^-45 is exact, and the two-limb value hi 2^-20 + lo 2^-45 (rounded
// once) is then the same bits, so either form may be used by any rank.
constexpr double kMagic = 6755399441055744.; // 1.5 2^52
constexpr double kTermLimit = 1048576.;      // 2^20
constexpr int kCellLimit = 1 << 13;
/** floor(t) as an int by truncation and correction (no libm call). */
inline int floor_to_int(double t) {
  int k = static_cast<int>(t);
  return k - (t < static_cast<double>(k));
}

/** Cell k wrapped into [0, nd): without an integer division for k in [-nd, 2 nd). */
inline int periodic_cell(int k, int nd) {
  k += k < 0 ? nd : (k >= nd ? -nd : 0);
  if (static_cast<unsigned>(k) >= static_cast<unsigned>(nd)) [[unlikely]] {
    k %= nd;
    k = k < 0 ? k + nd : k;
  }
  return k;
}

inline void add_exact(double x, double *s) {
  double const y = x * 1048576.; // 2^20, exact
  double const h = (y + kMagic) - kMagic;
  s[0] += h;
  s[1] += ((y - h) * 1099511627776. + kMagic) - kMagic; // y - h exact, times 2^40
}
inline double exact_value(double const *s) { return s[0] * 9.5367431640625e-07 + s[1] * 8.673617379884035e-19; }
inline void add_exact_v(double x, double *s) {
  double const y = x * 1048576.;
  double const h = (y + kMagic) - kMagic;
  s[0] += h;
  s[1] += ((y - h) * 33554432. + kMagic) - kMagic; // times 2^25
}
inline double exact_value_v(double const *s) { return s[0] * 9.5367431640625e-07 + s[1] * 2.842170943040401e-14; }

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define MARBLE_SRD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MARBLE_SRD_CLONES
#endif
// The rotation axes of a block of cells (global indices @p cell): one cell
// per SIMD lane, the same bits as cell_axis() one at a time (random.hpp).
MARBLE_SRD_CLONES void cell_axes(Utils::PairNoiseKey const key, int const *__restrict cell, int n,
                                 double *__restrict x, double *__restrict y, double *__restrict z) {
  for (int k = 0; k < n; ++k)
    cell_axis_z_phi(key, static_cast<std::uint32_t>(cell[k]), x[k], y[k], z[k]);
  for (int k = 0; k < n; ++k)
    cell_axis_xy(x[k], y[k], z[k]);
}

struct SrdRecord {
  Vector3d pos, v;
  int id, type;
};
static_assert(std::is_trivially_copyable_v<SrdRecord>);
} // namespace

std::array<std::pair<double, double>, 3> Fluid::domain_box(System &s) const {
  std::array<std::pair<double, double>, 3> out;
  double const inf = std::numeric_limits<double>::infinity();
  out.fill({-inf, inf});
  auto const &comm = s.comm();
  if (!comm.parallel())
    return out;
  auto const &box = s.box();
  auto const ng = s.cells().node_grid(box);
  int const me = comm.rank();
  auto const mc = CellSystem::coords_at(ng, me);
  for (int d = 0; d < 3; ++d) {
    if (ng[d] < 2)
      continue;
    // the node coordinate of CellSystem::owner_rank (clamp(floor(x / dl)),
    // or the domain cuts) is monotonic in x: the slab is [first x of
    // coordinate mc, first x of mc + 1)
    auto const ax = s.cells().axis_split(box, ng, d);
    auto coord = [&](double x) { return ax.coord(x); };
    auto first_at = [&](int j) {
      if (j <= 0)
        return -inf;
      if (j >= ng[d])
        return inf;
      double x = ax.lo(j);
      while (coord(x) >= j)
        x = std::nextafter(x, -inf);
      while (coord(x) < j)
        x = std::nextafter(x, inf);
      return x;
    };
    out[d] = {first_at(mc[d]), first_at(mc[d] + 1)};
  }
  return out;
}

void Fluid::migrate(System &s) {
  auto const &comm = s.comm();
  bool const listed = m_leave_valid;
  m_leave_valid = false;
  if (!comm.parallel())
    return;
  auto const &box = s.box();
  // the owner rank of CellSystem::owner_rank (node coordinate
  // clamp(floor(x / (L/g)))) with the node grid found once, not per
  // particle; whether a particle stays by comparisons with this rank's slab
  // bounds (domain_box: the same answer). The particles that left are listed
  // by the streaming step before the collision (pure fluid: fused with the
  // streaming loop, no pass of its own), else found by a scan.
  auto const ng = s.cells().node_grid(box);
  auto const dom = domain_box(s);
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d)
    lo[d] = dom[d].first, hi[d] = dom[d].second;
  int const n = size();
  if (!listed) {
    m_leave.clear();
    for (int i = 0; i < n; ++i) {
      auto const &x = pos[i];
      if (!(x[0] >= lo[0] && x[0] < hi[0] && x[1] >= lo[1] && x[1] < hi[1] && x[2] >= lo[2] && x[2] < hi[2]))
        [[unlikely]] m_leave.push_back(i);
    }
  }
  std::vector<std::vector<SrdRecord>> send(comm.size());
  std::array<CellSystem::AxisSplit, 3> const ax{s.cells().axis_split(box, ng, 0), s.cells().axis_split(box, ng, 1),
                                                 s.cells().axis_split(box, ng, 2)};
  for (int i : m_leave) {
    std::array<int, 3> c{};
    for (int d = 0; d < 3; ++d)
      c[d] = ax[d].coord(pos[i][d]);
    send[CellSystem::rank_at(ng, c)].push_back({pos[i], v[i], id[i], type[i]});
  }
  auto const recv = comm.alltoallv(send);
  // the arrivals fill the holes of the leavers, then are appended, or the
  // last particles fill the remaining holes: O(moved particles), no pass
  // over the arrays (the storage order is not the ids' on several ranks
  // anyway; the cell sums do not depend on it)
  std::size_t h = 0;
  auto put = [&](int i, SrdRecord const &rec) { pos[i] = rec.pos, v[i] = rec.v, id[i] = rec.id, type[i] = rec.type; };
  for (auto const &from : recv)
    for (auto const &rec : from) {
      if (h < m_leave.size()) {
        put(m_leave[h++], rec);
      } else {
        pos.push_back(rec.pos), v.push_back(rec.v), id.push_back(rec.id), type.push_back(rec.type);
      }
    }
  if (h < m_leave.size()) {
    // holes m_leave[h..) (ascending): fill each from the last particle that is no hole
    int last = size() - 1;
    std::size_t top = m_leave.size(); // holes [h, top) still open
    while (h < top) {
      if (last == m_leave[top - 1]) { // the last one is a hole itself: drop it
        --top, --last;
        continue;
      }
      int const i = m_leave[h++];
      pos[i] = pos[last], v[i] = v[last], id[i] = id[last], type[i] = type[last];
      --last;
    }
    int const keep = last + 1;
    pos.resize(keep), v.resize(keep), id.resize(keep), type.resize(keep);
  }
  m_leave.clear();
}

void Fluid::collide(System &s) {
  m_ia = &s.interactions();
  migrate(s);
  auto const &comm = s.comm();
  auto const &box = s.box();
  auto const &L = box.length();
  double const a0 = m_p.cell_size;
  std::uint64_t const c = m_n_collisions;
  Vector3d shift{};
  if (m_p.shift) // uniform in (-a0/2, a0/2]^3, keyed by (seed, collision)
    shift = a0 * Utils::noise_uniform(m_p.seed, Utils::RNGSalt::srd_shift, c, 0, 0);
  int const n = size();
  // along a wall axis the cells are not wrapped (k + 1 in [0, n + 1]): no
  // cell holds particles from both sides of a wall
  Utils::Vector3i gdim = m_grid;
  if (m_p.wall_axis >= 0)
    gdim[m_p.wall_axis] += 2;
  double const inv_a0 = 1. / a0;
  // The rank's local cell grid: along an axis split between ranks, the cells
  // its domain [lo, lo + len) overlaps (raw index r = floor((x - shift)/a0)
  // from that of lo to that of lo + len, one more on each side against
  // round-off); along an axis not split (or one whose local range would
  // wrap onto itself) the whole axis. The sort, the cell loop and the shared
  // cell search then scale with the local domain, not with the box; the
  // noise is keyed by the global cell index, as before.
  auto const ng = s.cells().node_grid(box);
  auto const dom = s.cells().local_domain(box);
  std::array<AxisMap, 3> ax{};
  for (int d = 0; d < 3; ++d) {
    bool const wall = d == m_p.wall_axis;
    ax[d] = {wall ? 2 : 0, 0, gdim[d]};
    if (!comm.parallel() || ng[d] < 2)
      continue;
    int const r0 = static_cast<int>(std::floor((dom.first[d] - shift[d]) * inv_a0)) - 1;
    int const r1 = static_cast<int>(std::floor((dom.first[d] + dom.second[d] - shift[d]) * inv_a0)) + 1;
    if (wall) {
      int const k0 = std::clamp(r0 + 1, 0, gdim[d] - 1), k1 = std::clamp(r1 + 1, 0, gdim[d] - 1);
      ax[d] = {2, k0, k1 - k0 + 1};
    } else if (r1 - r0 + 1 < m_grid[d]) {
      ax[d] = {1, r0, r1 - r0 + 1};
    }
  }
  Utils::Vector3i const ldim{ax[0].ext, ax[1].ext, ax[2].ext};
  int const n_cells = ldim[0] * ldim[1] * ldim[2];
  auto &par = m_par;
  // global coordinate of local coordinate l along d
  auto &glob = par.glob;
  for (int d = 0; d < 3; ++d) {
    glob[d].resize(ldim[d]);
    for (int l = 0; l < ldim[d]; ++l) {
      int k = l + ax[d].off;
      if (ax[d].mode == 1)
        k = ((k % m_grid[d]) + m_grid[d]) % m_grid[d];
      glob[d][l] = k;
    }
  }
  bool const identity = ldim == gdim && ax[0].mode != 1 && ax[1].mode != 1 && ax[2].mode != 1;
  auto global_of = [&](int lc) {
    if (identity) // the whole box (one rank, or an axis not split): local = global
      return lc;
    int const l2 = lc % ldim[2], l1 = (lc / ldim[2]) % ldim[1], l0 = lc / (ldim[1] * ldim[2]);
    return (glob[0][l0] * gdim[1] + glob[1][l1]) * gdim[2] + glob[2][l2];
  };
  // counting sort of the particles into the shifted cells (local grid)
  m_cell.resize(n);
  m_count.assign(n_cells + 1, 0);
  if (ax[0].mode == 0 && ax[1].mode == 0 && ax[2].mode == 0) { // the whole periodic box (one rank)
    auto coord = [&](double x, int d) {
      int k = floor_to_int((x - shift[d]) * inv_a0);
      return periodic_cell(k, m_grid[d]);
    };
    int *__restrict cl = m_cell.data(), *__restrict cnt = m_count.data();
    for (int i = 0; i < n; ++i) {
      int const g = (coord(pos[i][0], 0) * ldim[1] + coord(pos[i][1], 1)) * ldim[2] + coord(pos[i][2], 2);
      cl[i] = g;
      ++cnt[g + 1];
    }
  } else {
    // x in [0, L) (or slightly outside), shift in (-a0/2, a0/2]: raw index
    // k in [-1, n_d]; floor by truncation and correction (no libm call), the
    // periodic wrap without an integer division where k is in [-n_d, 2 n_d);
    // a coordinate outside the local grid is flagged (and clamped)
    unsigned bad = 0;
    int mode[3], off[3], ext[3], nd[3], gd[3];
    double sh[3];
    for (int d = 0; d < 3; ++d)
      mode[d] = ax[d].mode, off[d] = ax[d].off, ext[d] = ax[d].ext, nd[d] = m_grid[d], gd[d] = gdim[d],
      sh[d] = shift[d];
    auto coord = [&](double x, int d) {
      int k = floor_to_int((x - sh[d]) * inv_a0);
      if (mode[d] == 0)
        return periodic_cell(k, nd[d]);
      if (mode[d] == 2)
        k = std::clamp(k + 1, 0, gd[d] - 1);
      k -= off[d];
      bad |= static_cast<unsigned>(k) >= static_cast<unsigned>(ext[d]);
      return std::clamp(k, 0, ext[d] - 1);
    };
    int *__restrict cl = m_cell.data(), *__restrict cnt = m_count.data();
    for (int i = 0; i < n; ++i) {
      int const g = (coord(pos[i][0], 0) * ldim[1] + coord(pos[i][1], 1)) * ldim[2] + coord(pos[i][2], 2);
      cl[i] = g;
      ++cnt[g + 1];
    }
    if (bad)
      throw Utils::RuntimeError("SRD collision " + std::to_string(c) + ": rank " + std::to_string(comm.rank()) +
                                " holds a particle outside its domain's collision cells (internal error: "
                                "particle migration)");
  }
  for (int g = 0; g < n_cells; ++g)
    m_count[g + 1] += m_count[g];
  m_start.assign(m_count.begin(), m_count.end() - 1);
  // scatter the arrays into cell order (stable: ascending old index within a
  // cell; sequential reads; contiguous cells, streaming stays sequential)
  m_p2.resize(n), m_v2.resize(n), m_id2.resize(n), m_t2.resize(n);
  {
    Vector3d const *__restrict p0 = pos.data(), *__restrict v0 = v.data();
    int const *__restrict i0 = id.data(), *__restrict t0 = type.data(), *__restrict cl = m_cell.data();
    Vector3d *__restrict p1 = m_p2.data(), *__restrict v1 = m_v2.data();
    int *__restrict i1 = m_id2.data(), *__restrict t1 = m_t2.data(), *__restrict st = m_start.data();
    for (int i = 0; i < n; ++i) {
      int const k = st[cl[i]]++;
      p1[k] = p0[i], v1[k] = v0[i], i1[k] = i0[i], t1[k] = t0[i];
    }
  }
  pos.swap(m_p2), v.swap(m_v2), id.swap(m_id2), type.swap(m_t2);

  // Cells shared between ranks. Along each axis, a cell of global coordinate
  // k can hold positions of the domain slabs (node coordinates) its extent
  // x in [shift + r a0, shift + (r + 1) a0) n [0, L) overlaps (r = k - 1 on a
  // wall axis; k and its periodic images in [-1, n] otherwise), widened by a
  // tolerance (an extra rank only exchanges zeros): from the geometry alone,
  // the same answer on every rank. The ranks a cell overlaps are the product
  // of its three axes' lists; a cell is this rank's if its node coordinate is
  // in all three, shared if in addition some list has several entries (only
  // the cells next to a domain face: the work is O(face cells), not
  // O(local cells)). Shared cells get slots in the order of their global
  // index (the same order on every rank); their sums are exchanged with the
  // other touching ranks only (point to point, sizes known on both sides)
  // and added (exactly: the same bits on every touching rank, in any order).
  auto &shared = par.shared; // this rank's shared cells (local index), ascending global index
  auto &peer_cells = par.peer_cells; // per rank q: slots shared with q, ascending
  shared.clear();
  par.shared_g.clear();
  if (comm.parallel()) {
    int const me = comm.rank();
    auto const mc = CellSystem::coords_at(ng, me);
    m_slot.assign(n_cells, -1);
    for (int d = 0; d < 3; ++d) {
      auto &beg = par.beg[d], &lst = par.lst[d];
      auto &mine = par.mine[d], &multi = par.multi[d];
      beg.assign(1, 0), lst.clear(), mine.assign(ldim[d], 0), multi.assign(ldim[d], 0);
      double const eps = 1e-9 * a0;
      auto const ax = s.cells().axis_split(box, ng, d); // (equal split: clamp(floor(x / dl)))
      for (int l = 0; l < ldim[d]; ++l) {
        int const k = glob[d][l];
        std::size_t const first = lst.size();
        auto add = [&](int r) {
          double const lo = std::max(0., shift[d] + r * a0 - eps);
          double const hi = std::min(L[d], shift[d] + (r + 1) * a0 + eps);
          if (!(hi > lo))
            return;
          int const j0 = ax.coord(lo), j1 = ax.coord(hi);
          for (int j = j0; j <= j1; ++j)
            lst.push_back(j);
        };
        if (d == m_p.wall_axis) {
          add(k - 1);
        } else {
          for (int r : {k - m_grid[d], k, k + m_grid[d]})
            if (r >= -1 && r <= m_grid[d])
              add(r);
        }
        std::sort(lst.begin() + static_cast<std::ptrdiff_t>(first), lst.end());
        lst.erase(std::unique(lst.begin() + static_cast<std::ptrdiff_t>(first), lst.end()), lst.end());
        beg.push_back(static_cast<int>(lst.size()));
        mine[l] = std::binary_search(lst.begin() + static_cast<std::ptrdiff_t>(first), lst.end(), mc[d]);
        multi[l] = lst.size() - first >= 2;
      }
    }
    // cells this rank holds particles of must be its own (else the migration failed)
    for (int d = 0; d < 3; ++d)
      for (int l = 0; l < ldim[d]; ++l) {
        if (par.mine[d][l])
          continue;
        int lo[3] = {0, 0, 0}, hi[3] = {ldim[0], ldim[1], ldim[2]};
        lo[d] = l, hi[d] = l + 1;
        for (int a = lo[0]; a < hi[0]; ++a)
          for (int b = lo[1]; b < hi[1]; ++b)
            for (int e = lo[2]; e < hi[2]; ++e) {
              int const lc = (a * ldim[1] + b) * ldim[2] + e;
              if (m_count[lc + 1] > m_count[lc])
                throw Utils::RuntimeError("SRD collision " + std::to_string(c) + ": rank " + std::to_string(me) +
                                          " holds particles of collision cell " + std::to_string(global_of(lc)) +
                                          " outside its domain (internal error: particle migration)");
            }
      }
    auto &found = par.found;
    found.clear();
    std::vector<int> multi2; // local z coordinates of this rank with several slabs
    for (int l = 0; l < ldim[2]; ++l)
      if (par.mine[2][l] && par.multi[2][l])
        multi2.push_back(l);
    for (int l0 = 0; l0 < ldim[0]; ++l0) {
      if (!par.mine[0][l0])
        continue;
      for (int l1 = 0; l1 < ldim[1]; ++l1) {
        if (!par.mine[1][l1])
          continue;
        int const row = (l0 * ldim[1] + l1) * ldim[2];
        int const grow = (glob[0][l0] * gdim[1] + glob[1][l1]) * gdim[2];
        if (par.multi[0][l0] || par.multi[1][l1]) {
          for (int l2 = 0; l2 < ldim[2]; ++l2)
            if (par.mine[2][l2])
              found.emplace_back(grow + glob[2][l2], row + l2);
        } else {
          for (int l2 : multi2)
            found.emplace_back(grow + glob[2][l2], row + l2);
        }
      }
    }
    std::sort(found.begin(), found.end());
    peer_cells.resize(comm.size());
    for (auto &pc : peer_cells)
      pc.clear();
    for (auto const &[g, lc] : found) {
      int const slot = static_cast<int>(shared.size());
      m_slot[lc] = slot;
      shared.push_back(lc);
      par.shared_g.push_back(g);
      int const l[3] = {lc / (ldim[1] * ldim[2]), (lc / ldim[2]) % ldim[1], lc % ldim[2]};
      auto const &B0 = par.beg[0], &B1 = par.beg[1], &B2 = par.beg[2];
      for (int a = B0[l[0]]; a < B0[l[0] + 1]; ++a)
        for (int b = B1[l[1]]; b < B1[l[1] + 1]; ++b)
          for (int e = B2[l[2]]; e < B2[l[2] + 1]; ++e) {
            int const r = CellSystem::rank_at(ng, {par.lst[0][a], par.lst[1][b], par.lst[2][e]});
            if (r != me)
              peer_cells[r].push_back(slot);
          }
    }
  }
  auto slot_of = [&](int g) { return comm.parallel() ? m_slot[g] : -1; };

  double const ca = std::cos(m_p.angle), sa = std::sin(m_p.angle);
  double const sig = std::sqrt(m_p.kT / m_p.mass);
  bool const at = m_p.rule == CollisionRule::at;
  bool const ang = at && m_p.conserve_angular;
  bool const thermo = !at && m_p.thermostat;
  if (at)
    m_xi.resize(n);
  if (ang)
    m_r.resize(n);

  // A: local sums of cell g (particles [b, e)); AT: draws xi, AT+a: r
  bool too_fast = false; // a term beyond the range of the exact sums
  // the largest |v component| of particles [b, e); false if one is not
  // below 2^20 (or not finite: a NaN fails every comparison)
  auto v_range = [&](int b, int e, double &big) {
    big = 0.;
    bool ok = true;
    for (int i = b; i < e; ++i)
      for (int d = 0; d < 3; ++d) {
        double const x = std::abs(v[i][d]);
        big = std::max(big, x);
        ok &= x < kTermLimit;
      }
    too_fast |= !ok;
    return ok;
  };
  auto sums_A = [&](int b, int e, double *A, bool shared_cell) {
    std::fill(A, A + (ang ? nA : at ? 13 : 7), 0.);
    A[0] = e - b;
    double vmax; // one limb where the sums stay below 2^53 (decided per cell: the same value either way)
    bool const ok = v_range(b, e, vmax);
    if (!shared_cell && ok && vmax < 64. && (e - b) * vmax < 256.) {
      double s0 = 0., s1 = 0., s2 = 0.; // one limb: round(v 2^45), exact sums below 2^53
      for (int i = b; i < e; ++i) {
        s0 += (v[i][0] * 35184372088832. + kMagic) - kMagic;
        s1 += (v[i][1] * 35184372088832. + kMagic) - kMagic;
        s2 += (v[i][2] * 35184372088832. + kMagic) - kMagic;
      }
      A[2] = s0, A[4] = s1, A[6] = s2;
    } else {
      for (int i = b; i < e; ++i)
        for (int d = 0; d < 3; ++d)
          add_exact_v(v[i][d], A + 1 + 2 * d);
    }
    if (at)
      for (int i = b; i < e; ++i) {
        auto const r = gauss4(m_p.seed, Utils::RNGSalt::srd_at, c, static_cast<std::uint64_t>(id[i]), 0);
        m_xi[i] = sig * Vector3d{r[0], r[1], r[2]};
        for (int d = 0; d < 3; ++d)
          add_exact(m_xi[i][d], A + 7 + 2 * d);
      }
    if (ang)
      for (int i = b; i < e; ++i) {
        // positions relative to the shifted cell's corner, no periodic jump
        for (int d = 0; d < 3; ++d) {
          double const y = pos[i][d] - shift[d];
          m_r[i][d] = y - a0 * std::floor(y / a0);
          add_exact(m_r[i][d], A + 13 + 2 * d);
        }
      }
    too_fast |= e - b >= kCellLimit;
  };
  struct Mean {
    double nc;
    Vector3d u, xm, rc;
  };
  auto means = [at, ang](double const *A) {
    Mean m{A[0], {}, {}, {}};
    double const inv = 1. / m.nc;
    for (int d = 0; d < 3; ++d) {
      m.u[d] = exact_value_v(A + 1 + 2 * d) * inv;
      if (at)
        m.xm[d] = exact_value(A + 7 + 2 * d) * inv;
      if (ang)
        m.rc[d] = exact_value(A + 13 + 2 * d) * inv;
    }
    return m;
  };
  // first half: rotation (rule srd) about @p axis, local B sums
  auto stage1 = [&](Vector3d const &axis, int b, int e, Mean const &m, double *B) {
    if (thermo || ang)
      std::fill(B, B + nB, 0.);
    if (!at) {
      // Rodrigues' rotation by alpha about the axis n as a matrix:
      // R w = c w + s (n x w) + (1 - c)(n.w) n
      double const k = 1. - ca;
      double const nx = axis[0], ny = axis[1], nz = axis[2];
      double const R[3][3] = {{ca + k * nx * nx, k * nx * ny - sa * nz, k * nx * nz + sa * ny},
                              {k * ny * nx + sa * nz, ca + k * ny * ny, k * ny * nz - sa * nx},
                              {k * nz * nx - sa * ny, k * nz * ny + sa * nx, ca + k * nz * nz}};
      for (int i = b; i < e; ++i) {
        Vector3d const w = v[i] - m.u;
        for (int d = 0; d < 3; ++d)
          v[i][d] = m.u[d] + (R[d][0] * w[0] + R[d][1] * w[1] + R[d][2] * w[2]);
      }
      if (thermo) {
        double big = 0.;
        for (int i = b; i < e; ++i) {
          double const e2 = (v[i] - m.u).norm2();
          big = e2 > big || e2 != e2 ? e2 : big; // keeps a NaN
          add_exact(e2, B);
        }
        too_fast |= !(big < kTermLimit);
      }
    } else if (ang) {
      double big = 0.;
      for (int i = b; i < e; ++i) {
        Vector3d const q = m_r[i] - m.rc;
        double const q2 = q.norm2();
        for (int x = 0; x < 3; ++x)
          for (int y = 0; y < 3; ++y)
            add_exact((x == y ? q2 : 0.) - q[x] * q[y], B + 2 + 2 * (3 * x + y));
        Vector3d const dL = cross(q, v[i] - m.u - (m_xi[i] - m.xm));
        for (int d = 0; d < 3; ++d) {
          big = std::abs(dL[d]) > big || dL[d] != dL[d] ? std::abs(dL[d]) : big; // keeps a NaN
          add_exact(dL[d], B + 20 + 2 * d);
        }
      }
      too_fast |= !(big < kTermLimit);
    }
  };
  // second half: thermostat scaling (srd) or the new velocities (AT)
  auto stage2 = [&](int g, int b, int e, Mean const &m, double const *B) {
    if (thermo) {
      // scale relative velocities so the cell's relative kinetic energy is a
      // draw from its equilibrium Gamma(3(nc-1)/2, kT) distribution
      double const e_now = 0.5 * m_p.mass * exact_value(B);
      int const dof = 3 * (static_cast<int>(m.nc) - 1);
      double e_new = 0.;
      for (int k = 0; k < dof; k += 4) {
        auto const r = gauss4(m_p.seed, Utils::RNGSalt::srd_thermo, c, static_cast<std::uint64_t>(g),
                              static_cast<std::uint64_t>(k / 4));
        for (int j = 0; j < 4 && k + j < dof; ++j)
          e_new += r[j] * r[j];
      }
      e_new *= 0.5 * m_p.kT;
      if (e_now > 0.) {
        double const f = std::sqrt(e_new / e_now);
        for (int i = b; i < e; ++i)
          v[i] = m.u + f * (v[i] - m.u);
      }
    }
    if (!at)
      return;
    Vector3d omega{};
    bool ok = false;
    if (ang) {
      double I[3][3];
      for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
          I[x][y] = exact_value(B + 2 + 2 * (3 * x + y));
      Vector3d const dL{exact_value(B + 20), exact_value(B + 22), exact_value(B + 24)};
      ok = solve3(I, dL, omega);
      if (!ok && m.nc == 2.) { // collinear pair: I = 2(q^2 - q q), dL is normal to q
        double const tr = I[0][0] + I[1][1] + I[2][2];
        ok = tr > 0.;
        omega = (tr > 0. ? 2. / tr : 0.) * dL;
      }
    }
    for (int i = b; i < e; ++i) {
      Vector3d xi = m_xi[i];
      if (ok)
        xi += cross(omega, m_r[i] - m.rc);
      v[i] = m.u + xi - m.xm;
    }
  };

  // local cells: everything at once; shared cells: their A sums collected
  // (only the sums in use: the count and the velocities; the Andersen draws
  // with rule at; the positions with AT+a)
  int const usedA = ang ? nA : at ? 13 : 7, usedB = ang ? nB : thermo ? 2 : 0;
  auto &bufA = par.bufA, &bufB = par.bufB;
  bufA.assign(shared.size() * nA, 0.);
  bufB.assign(usedB ? shared.size() * nB : 0, 0.);
  double A[nA], B[nB];
  // the largest speed after the collision (the colloid search's displacement bound)
  double v2max = 0.;
  auto speed2 = [&](int b, int e) {
    for (int i = b; i < e; ++i)
      v2max = std::max(v2max, v[i].norm2());
  };
  // the cells in blocks: first the rotation axes of the block (SIMD lanes),
  // then its cells
  auto const akey = axis_key(m_p.seed, c);
  constexpr int kBlock = 128;
  std::array<int, kBlock> bg{};
  std::array<double, kBlock> bx{}, by{}, bz{};
  for (int g0 = 0; g0 < n_cells; g0 += kBlock) {
    int const g1 = std::min(n_cells, g0 + kBlock);
    if (identity) {
      for (int g = g0; g < g1; ++g)
        bg[g - g0] = g;
    } else { // the global indices of the block, stepping the local coordinates
      int l2 = g0 % ldim[2], l1 = (g0 / ldim[2]) % ldim[1], l0 = g0 / (ldim[1] * ldim[2]);
      for (int g = g0; g < g1; ++g) {
        bg[g - g0] = (glob[0][l0] * gdim[1] + glob[1][l1]) * gdim[2] + glob[2][l2];
        if (++l2 == ldim[2]) {
          l2 = 0;
          if (++l1 == ldim[1])
            l1 = 0, ++l0;
        }
      }
    }
    if (!at)
      cell_axes(akey, bg.data(), g1 - g0, bx.data(), by.data(), bz.data());
    for (int g = g0; g < g1; ++g) {
      int const b = m_count[g], e = m_count[g + 1];
      if (e == b)
        continue;
      int const sl = slot_of(g);
      if (sl >= 0) {
        sums_A(b, e, &bufA[static_cast<std::size_t>(sl) * nA], true);
        continue;
      }
      if (e - b < 2) { // one particle: nothing to exchange
        double big;
        v_range(b, e, big);
        speed2(b, e);
        continue;
      }
      sums_A(b, e, A, false);
      auto const m = means(A);
      int const gg = bg[g - g0];
      stage1(Vector3d{bx[g - g0], by[g - g0], bz[g - g0]}, b, e, m, B);
      stage2(gg, b, e, m, B);
      speed2(b, e);
    }
  }
  // shared cells: exchange the sums (the first @p nk of each slot's @p stride)
  // with the other touching ranks, point to point (both sides know the sizes:
  // no count exchange, no all-rank call; a leading count checks them), and
  // add them: integer-valued doubles, exact, so the same bits on every
  // touching rank whatever the order
  auto exchange = [&](std::vector<double> &buf, int stride, int nk) {
    int const me = comm.rank(), P = comm.size();
    auto &send = par.send, &recv = par.recv;
    send.resize(P), recv.resize(P);
    for (int q = 0; q < P; ++q) {
      auto const &pc = peer_cells[q];
      std::size_t const bytes = pc.empty() ? 0 : (1 + pc.size() * static_cast<std::size_t>(nk)) * sizeof(double);
      send[q].resize(bytes), recv[q].resize(bytes);
      if (pc.empty())
        continue;
      char *dst = send[q].data();
      double const head = static_cast<double>(pc.size());
      std::memcpy(dst, &head, sizeof(double));
      dst += sizeof(double);
      for (int sl : pc) {
        std::memcpy(dst, &buf[static_cast<std::size_t>(sl) * stride], nk * sizeof(double));
        dst += nk * sizeof(double);
      }
    }
    comm.neighbor_exchange_bytes(send, recv);
    for (int q = 0; q < P; ++q) {
      auto const &pc = peer_cells[q];
      if (pc.empty())
        continue;
      char const *src = recv[q].data();
      double head;
      std::memcpy(&head, src, sizeof(double));
      if (head != static_cast<double>(pc.size()))
        throw Utils::RuntimeError("SRD collision " + std::to_string(c) + ": rank " + std::to_string(q) +
                                  " sent " + std::to_string(head) + " shared-cell sums, rank " +
                                  std::to_string(me) + " expected " + std::to_string(pc.size()) +
                                  " (internal error)");
      src += sizeof(double);
      double t[nB];
      for (int sl : pc) {
        std::memcpy(t, src, nk * sizeof(double));
        src += nk * sizeof(double);
        double *x = &buf[static_cast<std::size_t>(sl) * stride];
        for (int k = 0; k < nk; ++k)
          x[k] += t[k];
      }
    }
  };
  if (comm.parallel()) {
    exchange(bufA, nA, usedA);
    std::vector<Mean> ms(shared.size());
    // the rotation axes of the shared cells, all at once (SIMD lanes, the
    // same bits as one at a time)
    auto const &sg = par.shared_g;
    auto &sx = par.axis[0], &sy = par.axis[1], &sz = par.axis[2];
    sx.resize(sg.size()), sy.resize(sg.size()), sz.resize(sg.size());
    if (!at && !sg.empty())
      cell_axes(akey, sg.data(), static_cast<int>(sg.size()), sx.data(), sy.data(), sz.data());
    for (std::size_t k = 0; k < shared.size(); ++k) {
      double const *Ak = &bufA[k * nA];
      too_fast |= !(Ak[0] < kCellLimit);
      if (Ak[0] < 2.)
        continue;
      ms[k] = means(Ak);
      int const g = shared[k];
      stage1(Vector3d{sx[k], sy[k], sz[k]}, m_count[g], m_count[g + 1], ms[k], usedB ? &bufB[k * nB] : B);
    }
    if (thermo || ang)
      exchange(bufB, nB, usedB);
    for (std::size_t k = 0; k < shared.size(); ++k) {
      if (bufA[k * nA] < 2.)
        continue;
      int const g = shared[k];
      if (m_count[g + 1] > m_count[g])
        stage2(sg[k], m_count[g], m_count[g + 1], ms[k], usedB ? &bufB[k * nB] : B);
    }
  }
  if (comm.any(too_fast))
    throw Utils::RuntimeError("SRD collision " + std::to_string(c) +
                              ": an SRD velocity (or a cell sum term) is not finite or beyond 2^20, or a "
                              "collision cell holds more than 8192 particles (likely cause: a blow-up, e.g. "
                              "a too large drive or colloid force, or velocities set by hand); the "
                              "collision's sums cannot be exact");
  for (int g : shared)
    speed2(m_count[g], m_count[g + 1]);
  // the cell index for the colloid search of the next streaming steps
  m_vmax = std::sqrt(v2max);
  m_disp = 0.;
  m_index_shift = shift;
  m_index_axes = ax;
  m_index_dim = ldim;
  // m_hit holds stamps of streaming steps (older ones never match a later
  // stamp: no reset needed unless the size changed); m_is_loose is set
  // exactly at the indices listed in m_loose
  // (a size change, e.g. by migration, only zeroes the new entries: the old
  // stamps never match, and the flags set are cleared where they were set)
  m_hit.resize(n, 0);
  for (int i : m_loose)
    if (i < static_cast<int>(m_is_loose.size()))
      m_is_loose[i] = 0;
  m_is_loose.resize(n, 0);
  m_loose.clear();
  m_index_valid = true;
  ++m_n_collisions;
}

} // namespace Marble::Srd
