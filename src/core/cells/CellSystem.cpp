#include "cells/CellSystem.hpp"

#include "utils/errors.hpp"
#include "utils/cpu.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace Marble {

using Utils::Vector3d;

namespace {

/** Slot @p q of @p bufs, grown (never shrunk, so not refilled every call) to
 * at least @p bytes (storage aligned for any scalar type). */
void *grow_buffer(std::vector<std::vector<std::max_align_t>> &bufs, int q, std::size_t bytes) {
  if (bufs.size() <= static_cast<std::size_t>(q))
    bufs.resize(static_cast<std::size_t>(q) + 1);
  auto &b = bufs[static_cast<std::size_t>(q)];
  std::size_t const words = (bytes + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
  if (b.size() < words)
    b.resize(words);
  return b.data();
}

// rebuild() refuses ranges above 16 box lengths: at most 2 * 16 + 1 image shifts per axis
constexpr int kMaxShiftsPerAxis = 33;

// A ghost shift is "positive" if its first non-zero component is > 0.
bool shift_positive(Vector3d const &s) {
  for (int d = 0; d < 3; ++d) {
    if (s[d] > 0.)
      return true;
    if (s[d] < 0.)
      return false;
  }
  return false;
}

/** An image of a particle of the rank at node coordinates @p src, shifted by
 * @p n box lengths, is sent to the rank at @p dest (half shell) if the offset
 * (src + n * grid) - dest is lexicographically positive: of the two ranks of
 * a cross-rank pair the offsets are opposite, so exactly one gets the other's
 * particle (and computes the pair). On one rank (src = dest) this is the
 * positive-shift rule of the periodic images. */
bool half_shell_sends(std::array<int, 3> const &src, std::array<int, 3> const &n,
                      std::array<int, 3> const &grid, std::array<int, 3> const &dest) {
  for (int d = 0; d < 3; ++d) {
    int const off = src[d] + n[d] * grid[d] - dest[d];
    if (off != 0)
      return off > 0;
  }
  return false;
}

} // namespace

/** A pair of local @p i and ghost @p j (>= n_local): true if another rank
 * computes it (then it is left out here). Own periodic images: never. Other
 * ranks' small particles come in a half shell (make_ghosts), so the pair is
 * computed here. Large-range particles and colloid copies come from all
 * sides (a full shell): the rank owning the smaller id computes the pair. */
bool CellSystem::other_rank_computes(ParticleStore const &ps, int i, int j, int n_local) const {
  int const o = ps.ghost_owner[j - n_local];
  if (o >= 0 || (o == kRemoteGhost && !wide(ps.type[j])))
    return false;
  return ps.id[i] > ps.id[j];
}

// Cells are at least `range` wide, so all partners of a local are in the 27
// cells around it.
CellSystem::Grid::Grid(Vector3d const &lo_, Vector3d const &len, double range) {
  lo = lo_;
  for (int d = 0; d < 3; ++d) {
    n[d] = range > 0. ? std::max(1, static_cast<int>(len[d] / range)) : 1;
    n[d] = std::min(n[d], 256); // bounded memory for tiny cutoffs
    size[d] = len[d] / n[d];
    inv_size[d] = 1. / size[d];
    ext[d] = n[d] + 2;
  }
}

std::array<int, 3> CellSystem::node_grid(BoxGeometry const &box) const {
  int const n = m_comm ? m_comm->size() : 1;
  auto const &L = box.length();
  // Lees-Edwards: only the vorticity axis (neither the shear direction nor
  // the normal) is split, so every image across the shear plane, whose
  // position along the shear direction moves with the offset, stays within
  // the rank's own slab of the two unsplit axes (make_le_ghosts)
  auto const &le = box.lees_edwards();
  if (le.active()) {
    std::array<int, 3> g{1, 1, 1};
    g[3 - le.shear_plane_normal - le.shear_direction] = n;
    return g;
  }
  std::array<int, 3> best{n, 1, 1};
  double best_cost = std::numeric_limits<double>::infinity();
  // the factorisation with the smallest domain surface; ties: split x first
  for (int px = n; px >= 1; --px) {
    if (n % px)
      continue;
    for (int py = n / px; py >= 1; --py) {
      if ((n / px) % py)
        continue;
      int const pz = n / px / py;
      double const a = L[0] / px, b = L[1] / py, c = L[2] / pz;
      double const cost = a * b + b * c + a * c;
      if (cost < best_cost * (1. - 1e-12)) {
        best_cost = cost;
        best = {px, py, pz};
      }
    }
  }
  return best;
}

namespace {
int rank_of(std::array<int, 3> const &g, std::array<int, 3> const &c) {
  return (c[0] * g[1] + c[1]) * g[2] + c[2];
}
std::array<int, 3> coords_of(std::array<int, 3> const &g, int rank) {
  return {rank / (g[1] * g[2]), (rank / g[2]) % g[1], rank % g[2]};
}
int axis_coord(double x, double dl, int p) {
  double const c = std::floor(x / dl);
  return static_cast<int>(std::clamp(c, 0., static_cast<double>(p - 1)));
}
/** The node coordinates [lo, hi] along an axis of @p p domains of width
 * @p dl whose domain, grown by @p r, holds the coordinate @p x (lo > hi:
 * none); along an open axis the outer domains extend to infinity. */
std::pair<int, int> grown_domains(double x, double r, double dl, int p, bool periodic) {
  if (p == 1) {
    // one domain along the axis: the same answer without the divisions
    // (floor((x - r) / dl) < 1 iff x - r < dl, the quotient of a double
    // below dl being below 1 after rounding; floor((x + r) / dl) >= 0 iff
    // x + r >= 0)
    if (!periodic || (x - r < dl && x + r >= 0.))
      return {0, 0};
    return {1, 0};
  }
  int a = static_cast<int>(std::floor((x - r) / dl));
  int b = static_cast<int>(std::floor((x + r) / dl));
  if (!periodic) {
    a = std::clamp(a, 0, p - 1);
    b = std::clamp(b, 0, p - 1);
  }
  return {std::max(a, 0), std::min(b, p - 1)};
}
} // namespace

int CellSystem::AxisSplit::coord(double x) const {
  if (uniform)
    return axis_coord(x, dl, p);
  // the number of inner cuts at or below x (NaN: the last domain)
  auto const first = cut.begin() + 1, last = cut.begin() + p;
  return static_cast<int>(std::upper_bound(first, last, x) - first);
}

std::pair<int, int> CellSystem::AxisSplit::grown(double x, double r, bool periodic) const {
  if (uniform)
    return grown_domains(x, r, dl, p, periodic);
  // as grown_domains: a holds x - r, b holds x + r, -1 below the box and p
  // at or above it along a periodic axis (the images do the rest)
  int a = x - r >= L ? p : coord(x - r);
  int b = x + r < 0. ? -1 : coord(x + r);
  if (!periodic) {
    a = std::clamp(a, 0, p - 1);
    b = std::clamp(b, 0, p - 1);
  }
  return {std::max(a, 0), std::min(b, p - 1)};
}

CellSystem::AxisSplit CellSystem::axis_split(BoxGeometry const &box, std::array<int, 3> const &g, int d) const {
  AxisSplit a;
  a.p = g[d];
  a.L = box.length()[d];
  a.dl = a.L / a.p;
  auto const &f = m_fractions[static_cast<std::size_t>(d)];
  a.uniform = a.p == 1 || f.size() != static_cast<std::size_t>(a.p) + 1;
  if (!a.uniform) {
    a.cut.resize(f.size());
    for (int c = 0; c <= a.p; ++c)
      a.cut[static_cast<std::size_t>(c)] = c == 0 ? 0. : c == a.p ? a.L : f[static_cast<std::size_t>(c)] * a.L;
  }
  return a;
}

std::vector<double> CellSystem::domain_cuts(BoxGeometry const &box, int d) const {
  auto const g = node_grid(box);
  auto const a = axis_split(box, g, d);
  std::vector<double> out(static_cast<std::size_t>(a.p) + 1);
  for (int c = 0; c <= a.p; ++c)
    out[static_cast<std::size_t>(c)] = c == a.p ? a.L : a.lo(c);
  return out;
}

// The neighbour ranks: q is one if along every axis some periodic image of
// q's domain (none along an open axis) is adjacent to this rank's domain or
// at most @p radius from it: the node-coordinate offset k = |q + n grid - me|
// (n images) has k <= 1 or (k - 1) dl <= radius. The test uses only integer
// offsets and dl, so it is symmetric bit for bit: q lists me iff I list q.
// Every ghost of make_ghosts (images within max range of the domain) goes to
// a neighbour when radius >= that range; a migrating particle usually does
// (migrate checks and falls back to the all-rank exchange otherwise).
void CellSystem::update_neighbour_ranks(BoxGeometry const &box, double radius) {
  auto const g = node_grid(box);
  auto const &L = box.length();
  int const size = m_comm->size(), me = m_comm->rank();
  std::array<double, 8> const key{L[0], L[1], L[2], static_cast<double>(size),
                                  static_cast<double>(me), radius,
                                  static_cast<double>(box.periodic(0) + 2 * box.periodic(1) + 4 * box.periodic(2)),
                                  static_cast<double>(g[0]) * (size + 1) + g[1]}; // (the grid: Lees-Edwards changes it)
  if (key == m_nbr_key && m_nbr_fversion == m_fractions_version && !m_is_nbr.empty())
    return;
  m_nbr_key = key;
  m_nbr_fversion = m_fractions_version;
  auto const c = coords_of(g, me);
  std::array<std::vector<char>, 3> near;
  for (int d = 0; d < 3; ++d) {
    auto const ax = axis_split(box, g, d);
    double const dl = L[d] / g[d];
    double const lim = radius * (1. + 1e-6) + 1e-9 * L[d];
    int const nimg = box.periodic(d) ? static_cast<int>(std::ceil(radius / L[d])) + 1 : 0;
    near[d].assign(static_cast<std::size_t>(g[d]), 0);
    for (int qd = 0; qd < g[d]; ++qd)
      for (int n = -nimg; n <= nimg; ++n) {
        int const j = qd + n * g[d], k = std::abs(j - c[d]);
        if (k <= 1) {
          near[d][qd] = 1;
        } else if (ax.uniform) {
          if ((k - 1) * dl <= lim)
            near[d][qd] = 1;
        } else {
          // the gap between the lower domain (its coordinate lo, image 0)
          // and the upper one (hi, m box lengths up): the same expression on
          // both ranks of the pair, so the test stays symmetric bit for bit
          int const lo = j > c[d] ? c[d] : qd, hi = j > c[d] ? qd : c[d];
          int const m = j > c[d] ? n : -n;
          double const gap = (ax.cut[static_cast<std::size_t>(hi)] - ax.cut[static_cast<std::size_t>(lo) + 1]) +
                             static_cast<double>(m) * L[d];
          if (gap <= lim)
            near[d][qd] = 1;
        }
      }
  }
  m_nbrs.clear();
  m_is_nbr.assign(static_cast<std::size_t>(size), 0);
  for (int q = 0; q < size; ++q) {
    auto const qc = coords_of(g, q);
    if (q != me && near[0][qc[0]] && near[1][qc[1]] && near[2][qc[2]]) {
      m_nbrs.push_back(q);
      m_is_nbr[q] = 1;
    }
  }
}

int CellSystem::rank_at(std::array<int, 3> const &grid, std::array<int, 3> const &coords) {
  return rank_of(grid, coords);
}
std::array<int, 3> CellSystem::coords_at(std::array<int, 3> const &grid, int rank) {
  return coords_of(grid, rank);
}

int CellSystem::owner_rank(Vector3d const &pos, BoxGeometry const &box) const {
  if (!parallel())
    return 0;
  auto const g = node_grid(box);
  std::array<int, 3> c{};
  for (int d = 0; d < 3; ++d)
    c[d] = axis_split(box, g, d).coord(pos[d]);
  return rank_of(g, c);
}

std::pair<Vector3d, Vector3d> CellSystem::local_domain(BoxGeometry const &box) const {
  auto const &L = box.length();
  if (!parallel())
    return {Vector3d{0., 0., 0.}, L};
  auto const g = node_grid(box);
  auto const c = coords_of(g, m_comm->rank());
  Vector3d lo, len;
  for (int d = 0; d < 3; ++d) {
    auto const ax = axis_split(box, g, d);
    if (ax.uniform) {
      len[d] = L[d] / g[d];
      lo[d] = c[d] * len[d];
    } else {
      lo[d] = ax.lo(c[d]);
      len[d] = ax.cut[static_cast<std::size_t>(c[d]) + 1] - lo[d];
    }
  }
  return {lo, len};
}

namespace {
struct MigrationRecord {
  ParticleProperties p;
  Vector3d f, torque;
};
static_assert(std::is_trivially_copyable_v<MigrationRecord>);
static_assert(std::is_trivially_copyable_v<GhostRecord>);
struct GhostUpdate {
  Vector3d pos, v, omega;
};
struct GhostForce {
  Vector3d f, torque;
};
// an owner's state for its ghost at @p shift, and that state written into ghost @p g
GhostUpdate ghost_update_of(ParticleStore const &ps, int i, Vector3d const &shift) {
  GhostUpdate u;
  u.pos = ps.pos[i] + shift;
  u.v = ps.v[i];
#ifdef ROTATION
  u.omega = ps.omega[i];
#endif
  return u;
}
void apply_ghost_update(ParticleStore &ps, int g, GhostUpdate const &u) {
  ps.pos[g] = u.pos;
  ps.v[g] = u.v;
#ifdef ROTATION
  ps.omega[g] = u.omega;
#endif
}
} // namespace

// Send every local whose folded position lies in another rank's domain to
// that rank (with its force and torque of the last step, which the next half
// kick uses). During a run a particle moves at most ~1.5 skins between two
// rebuilds, so it goes to a neighbour rank: then one point-to-point message
// to each neighbour (sizes probed). One reduction decides it: if any rank
// has a particle for a rank that is not its neighbour (the user moved it,
// a checkpoint was loaded, ...) all ranks take the all-rank alltoallv.
void CellSystem::migrate(ParticleStore &ps, BoxGeometry const &box) const {
  int const size = m_comm->size(), me = m_comm->rank();
  auto const g = node_grid(box);
  auto const &L = box.length();
  std::vector<std::vector<MigrationRecord>> send(size);
  std::vector<int> leaving;
  bool far = false;
  // a particle well inside this rank's domain (a margin far above the
  // round-off of x / dl) stays: six comparisons instead of three divisions
  auto const me_at = coords_of(g, me);
  std::array<AxisSplit, 3> const ax{axis_split(box, g, 0), axis_split(box, g, 1), axis_split(box, g, 2)};
  double in_lo[3], in_hi[3];
  for (int d = 0; d < 3; ++d) {
    // (the equal split's lo(c) is c * (L / g), as before)
    double const margin = 1e-9 * (L[d] + 1.);
    in_lo[d] = me_at[d] == 0 ? -std::numeric_limits<double>::infinity() : ax[d].lo(me_at[d]) + margin;
    in_hi[d] = me_at[d] == g[d] - 1 ? std::numeric_limits<double>::infinity() : ax[d].lo(me_at[d] + 1) - margin;
  }
  for (int i = 0; i < ps.n_local(); ++i) {
    Vector3d const &x = ps.pos[i];
    if (x[0] >= in_lo[0] && x[0] < in_hi[0] && x[1] >= in_lo[1] && x[1] < in_hi[1] && x[2] >= in_lo[2] &&
        x[2] < in_hi[2])
      continue;
    std::array<int, 3> c{};
    for (int d = 0; d < 3; ++d)
      c[d] = ax[d].coord(ps.pos[i][d]);
    int const r = rank_of(g, c);
    if (r == me)
      continue;
    MigrationRecord rec;
    rec.p = ps.get(ps.id[i]);
    rec.f = ps.f[i];
#ifdef ROTATION
    rec.torque = ps.torque[i];
#endif
    send[r].push_back(rec);
    leaving.push_back(ps.id[i]);
    far |= !m_is_nbr[r];
  }
  for (int pid : leaving)
    ps.remove(pid);
  auto const recv = m_comm->any(far) ? m_comm->alltoallv(send) : m_comm->neighbor_exchange_var(m_nbrs, send);
  for (auto const &from : recv)
    for (auto const &rec : from) {
      ps.add(rec.p);
      int const i = ps.n_local() - 1;
      ps.f[i] = rec.f;
#ifdef ROTATION
      ps.torque[i] = rec.torque;
#endif
    }
}

void CellSystem::sort_locals(ParticleStore &ps, BoxGeometry const &box) {
  int const n = ps.n_local();
  m_local_cells_ready = false;
  if (m_range <= 0.)
    return;
  auto const dom = local_domain(box);
  Grid const g(dom.first, dom.second, m_range);
  // large-range locals go last (one extra bucket after the cells)
  auto &cell = m_scratch_cell, &count = m_scratch_fill;
  cell.resize(static_cast<std::size_t>(n));
  count.assign(static_cast<std::size_t>(g.n_total() + 2), 0);
  bool const any_wide = !m_wide.empty();
  for (int i = 0; i < n; ++i) {
    cell[i] = (any_wide && wide(ps.type[i])) ? g.n_total() : g.local_index(ps.pos[i]);
    ++count[cell[i] + 1];
  }
  for (int c = 0; c <= g.n_total(); ++c)
    count[c + 1] += count[c];
  auto &order = m_scratch_ghost_begin; // free here: build_pairs fills it after the sort
  order.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    order[count[cell[i]]++] = i;
  bool sorted = true;
  for (int i = 0; i < n && sorted; ++i)
    sorted = order[i] == i;
  // (rebuild overwrites pos_at_rebuild right after the sort)
  if (!sorted)
    ps.permute_locals(order, /*skip_pos_at_rebuild=*/true);
  // the locals' cells in the new order, for build_pairs: bucket c is now
  // [count[c - 1], count[c]) (the large-range bucket: -1, as there)
  if (!sorted)
    for (int c = 0, k = 0; c <= g.n_total(); ++c) {
      int const v = c == g.n_total() ? -1 : c;
      for (; k < count[c]; ++k)
        cell[k] = v;
    }
  else if (any_wide)
    for (int k = 0; k < n; ++k)
      cell[k] = cell[k] == g.n_total() ? -1 : cell[k];
  m_local_cells_ready = true;
}

void CellSystem::make_ghosts(ParticleStore &ps, BoxGeometry const &box) {
  ps.clear_ghosts();
  int const size = m_comm ? m_comm->size() : 1, me = m_comm ? m_comm->rank() : 0;
  m_send.assign(static_cast<std::size_t>(size), {});
  m_send_index.assign(static_cast<std::size_t>(size), {});
  m_ghost_rep_valid = false;
  m_recv_begin.assign(static_cast<std::size_t>(size), ps.n_local());
  m_recv_count.assign(static_cast<std::size_t>(size), 0);
  m_rep_send.assign(static_cast<std::size_t>(size), {}); // (every return below leaves them valid)
  m_rep_recv.assign(static_cast<std::size_t>(size), {});
  m_le_images = false;
  m_le_k.clear();
  m_boundary_axis = -1;
  m_boundary_side.clear();
  if (m_range <= 0.)
    return;
  if (m_le.active()) {
    make_le_ghosts(ps, box);
    mark_boundary_sides(ps, box);
    return;
  }
  bool const par = size > 1;
  int const n = ps.n_local();
  auto const &L = box.length();
  auto const g = node_grid(box);
  bool const any_wide = !m_wide.empty();
  double const r_wide = std::max(m_range_ll, m_range_ls);
  double const r_max = std::max(m_range, r_wide);
  std::array<int, 3> nimg{};
  for (int d = 0; d < 3; ++d)
    nimg[d] = box.periodic(d) ? static_cast<int>(std::ceil(r_max / L[d])) : 0;
  // One rank: only images with a positive shift (build_pairs keeps the
  // local-ghost pair whose ghost shift is positive, so the others would only
  // cost ghost updates and force reductions). Several ranks: every shift, since
  // other ranks need the images on all sides. Large-range particles: every
  // shift (their pairs with small particles are listed from the large side).
  // (one rank: the !par && !w && !pos_shift test in the loop below)
  for (int d = 0; d < 3; ++d)
    if (2 * nimg[d] + 1 > kMaxShiftsPerAxis)
      throw Utils::RuntimeError("internal error: too many periodic images along axis " + std::to_string(d));
  std::array<int, 3> const me_at = coords_of(g, me);
  std::array<AxisSplit, 3> const split{axis_split(box, g, 0), axis_split(box, g, 1), axis_split(box, g, 2)};
  Vector3d dl;
  for (int d = 0; d < 3; ++d)
    dl[d] = L[d] / g[d];
  // One range: a particle farther than the range (plus a margin far above
  // round-off) from every face of its domain along the periodic or split
  // axes gets no ghost (every shift has a non-zero component along some
  // periodic axis, whose cheap reject below then holds, and the unshifted
  // position lies in no other rank's grown domain): skip it without visiting
  // the shifts. On one rank the domain is the box.
  bool const interior_test = !any_wide;
  Vector3d in_lo, in_hi;
  for (int d = 0; d < 3; ++d) {
    double const margin = 1e-9 * (L[d] + m_range);
    bool const edge = box.periodic(d) || g[d] > 1;
    double const lo = par ? split[d].lo(me_at[d]) : 0.;
    double const hi = par ? (split[d].uniform ? lo + dl[d] : split[d].lo(me_at[d] + 1)) : L[d];
    in_lo[d] = edge ? lo + m_range + margin : -std::numeric_limits<double>::infinity();
    in_hi[d] = edge ? hi - m_range - margin : std::numeric_limits<double>::infinity();
  }
  for (int i = 0; i < n; ++i) {
    Vector3d const p = ps.pos[i];
    if (interior_test && p[0] >= in_lo[0] && p[0] < in_hi[0] && p[1] >= in_lo[1] && p[1] < in_hi[1] &&
        p[2] >= in_lo[2] && p[2] < in_hi[2] && !replicated(ps.type[i]))
      continue;
    bool const w = any_wide && wide(ps.type[i]);
    double const r = w ? r_wide : m_range;
    if (replicated(ps.type[i])) {
      // colloids: a copy on every other rank; their pairs are found by
      // Colloids (own periodic images included), never through ghosts
      for (int q = 0; q < size; ++q)
        if (q != me)
          m_send[q].push_back({i, 0, Vector3d{0., 0., 0.}});
      continue;
    }
    // the shifts whose image passes the cheap reject (farther than the range
    // from the box on some axis: no ghost), axis by axis, in the order of
    // the full (sx, sy, sz) loop: the same ghosts in the same order
    // (and, per axis, the node coordinates [alo, ahi] whose domain, grown by
    // the range, holds the image's coordinate p + s L; a coordinate no grown
    // domain holds rules out its shift: along an axis, as the whole shift
    // did before, so the same ghosts in the same order)
    int ax[3][kMaxShiftsPerAxis], alo[3][kMaxShiftsPerAxis], ahi[3][kMaxShiftsPerAxis], n_ax[3];
    for (int d = 0; d < 3; ++d) {
      n_ax[d] = 0;
      for (int s = -nimg[d]; s <= nimg[d]; ++s) {
        double const sh = s * L[d];
        if (s != 0 && (p[d] + sh < -r || p[d] + sh >= L[d] + r))
          continue;
        auto const [a, b] = split[d].grown(p[d] + sh, r, box.periodic(d));
        if (a > b)
          continue;
        ax[d][n_ax[d]] = s, alo[d][n_ax[d]] = a, ahi[d][n_ax[d]] = b;
        ++n_ax[d];
      }
    }
    for (int kx = 0; kx < n_ax[0]; ++kx)
      for (int ky = 0; ky < n_ax[1]; ++ky)
        for (int kz = 0; kz < n_ax[2]; ++kz) {
          std::array<int, 3> const ish{ax[0][kx], ax[1][ky], ax[2][kz]};
          Vector3d const sh{ish[0] * L[0], ish[1] * L[1], ish[2] * L[2]};
          bool const pos_shift = shift_positive(sh);
          if (!par && !w && !pos_shift)
            continue;
          std::array<int, 3> const lo{alo[0][kx], alo[1][ky], alo[2][kz]};
          std::array<int, 3> const hi{ahi[0][kx], ahi[1][ky], ahi[2][kz]};
          bool const own_image = w ? (sh[0] != 0. || sh[1] != 0. || sh[2] != 0.) : pos_shift;
          for (int cx = lo[0]; cx <= hi[0]; ++cx)
            for (int cy = lo[1]; cy <= hi[1]; ++cy)
              for (int cz = lo[2]; cz <= hi[2]; ++cz) {
                int const dest = rank_of(g, {cx, cy, cz});
                if (dest == me) {
                  if (own_image)
                    ps.add_ghost(i, sh);
                } else if (w || half_shell_sends(me_at, ish, g, {cx, cy, cz})) {
                  m_send[dest].push_back({i, 0, sh}); // large-range particles: a full shell
                }
              }
        }
  }
  exchange_ghosts(ps);
  mark_boundary_sides(ps, box);
}

// boundary_sides(): with the node grid split along one axis a, every
// particle another rank holds lies within the ghost range of one face of
// this domain along a at the build: a sent local within the range inside,
// another rank's particle within the range outside (its image's position).
// Domains at least twice that range wide (the Shardlow sweep's condition)
// put it on one side of the middle, so that side names the face.
void CellSystem::mark_boundary_sides(ParticleStore const &ps, BoxGeometry const &box) {
  m_boundary_axis = -1;
  m_boundary_side.clear();
  if (!parallel())
    return;
  auto const g = node_grid(box);
  int a = -1, n_split = 0;
  for (int d = 0; d < 3; ++d)
    if (g[d] > 1)
      a = d, ++n_split;
  if (n_split != 1)
    return;
  m_boundary_axis = a;
  double const dl = box.length()[a] / g[a];
  auto const ax = axis_split(box, g, a);
  int const ca = coords_at(g, m_comm->rank())[a];
  double const mid = ax.uniform ? (ca + 0.5) * dl : 0.5 * (ax.lo(ca) + ax.lo(ca + 1));
  int const nl = ps.n_local(), n = ps.size();
  m_boundary_side.assign(static_cast<std::size_t>(n), 0);
  auto side = [&](int k) -> char { return replicated(ps.type[k]) ? 3 : (ps.pos[k][a] < mid ? 1 : 2); };
  for (auto const &q : m_send_index)
    for (int i : q)
      m_boundary_side[i] |= side(i);
  for (int k = nl; k < n; ++k)
    if (ps.ghost_owner[k - nl] < 0)
      m_boundary_side[k] = side(k);
}

// The ghosts of m_send to the other ranks (one message to each neighbour, or
// the all-rank exchange with colloid copies), appended after the own images;
// m_send_index, m_recv_begin/count and the replicated subsets for the
// exchanges between rebuilds. Lees-Edwards images carry their shift k along
// the normal (m_le_k) and move with their owner's velocity + k shear_velocity.
void CellSystem::exchange_ghosts(ParticleStore &ps) {
  int const size = m_comm ? m_comm->size() : 1;
  [[maybe_unused]] int const me = m_comm ? m_comm->rank() : 0;
  bool const par = size > 1;
  m_send_index.resize(static_cast<std::size_t>(size));
  for (int q = 0; q < size; ++q) {
    m_send_index[q].resize(m_send[q].size());
    for (std::size_t k = 0; k < m_send[q].size(); ++k)
      m_send_index[q][k] = m_send[q][k].index;
  }
  if (!par)
    return;
  // the records written straight into the message bytes and read back from
  // them (no typed copies on either side)
  constexpr std::size_t rec_bytes = sizeof(GhostRecord);
  std::vector<std::vector<char>> send(static_cast<std::size_t>(size)), recv;
  for (int q = 0; q < size; ++q) {
    send[q].resize(m_send[q].size() * rec_bytes);
    char *out = send[q].data();
    for (auto const &e : m_send[q]) {
      GhostRecord r = ps.ghost_record(e.index, e.shift);
      if (e.le_k != 0) {
        r.le_k = static_cast<std::int8_t>(e.le_k);
        r.v[m_le.shear_direction] += e.le_k * m_le.shear_velocity;
      }
      std::memcpy(out, &r, rec_bytes);
      out += rec_bytes;
    }
  }
  // Colloid copies go to every rank: then the all-rank alltoallv. Otherwise
  // every ghost goes to a neighbour rank (images within r_max of this
  // domain): one message to each (sizes probed), no all-rank call.
  bool const any_replicated =
      std::any_of(m_replicated.begin(), m_replicated.end(), [](char c) { return c != 0; });
#ifndef NDEBUG
  for (int q = 0; q < size; ++q)
    if (!any_replicated && !m_send[q].empty() && !m_is_nbr[q])
      throw Utils::RuntimeError("internal error: a ghost for rank " + std::to_string(q) +
                                ", which is not a neighbour of rank " + std::to_string(me));
#endif
  if (any_replicated)
    recv = m_comm->alltoallv_bytes(send);
  else
    m_comm->neighbor_exchange_var_bytes(m_nbrs, send, recv);
  recv.resize(static_cast<std::size_t>(size));
  for (int q = 0; q < size; ++q) {
    m_recv_begin[q] = ps.size();
    std::size_t const n_in = recv[q].size() / rec_bytes;
    m_recv_count[q] = static_cast<int>(n_in);
    char const *in = recv[q].data();
    for (std::size_t k = 0; k < n_in; ++k, in += rec_bytes) {
      GhostRecord rec;
      std::memcpy(&rec, in, rec_bytes);
      ps.add_remote_ghost(rec, replicated(rec.type) ? kRemoteColloidGhost : kRemoteGhost);
      if (m_le_images)
        m_le_k.push_back(rec.le_k);
    }
  }
  // the replicated types' subset of the exchange (both sides select by type,
  // in the same order)
  if (!any_replicated)
    return;
  for (int q = 0; q < size; ++q) {
    for (std::size_t k = 0; k < m_send[q].size(); ++k)
      if (replicated(ps.type[m_send[q][k].index]))
        m_rep_send[q].push_back(static_cast<int>(k));
    for (int g = m_recv_begin[q]; g < m_recv_begin[q] + m_recv_count[q]; ++g)
      if (ps.ghost_owner[g - ps.n_local()] == kRemoteColloidGhost)
        m_rep_recv[q].push_back(g);
  }
}

// Lees-Edwards images (no marble colloids; System refuses them).
// The image of local i with integer shift (m_x, m_y, m_z) lies at
//   p + sum_d m_d L_d e_d + m_n * offset e_s     (n: normal, s: shear direction),
// moves with v + m_n * shear_velocity e_s, and is made if it lies within the
// range of the box along n and s and of some rank's domain along the third
// (vorticity) axis t. Several ranks: node_grid splits only t, so an image's
// place along s, which moves with the offset, never decides its rank.
// The images go by the half-shell rule of make_ghosts with the integer
// tuple (m_n, m_s, m_t) in place of the shift (src + m grid - dest
// lexicographically positive; on one rank: only positive tuples): the image
// of j seen from i and that of i seen from j have opposite tuples (the offset
// term is linear in m_n), so each pair is listed once, on one rank. The tuple
// along s is chosen at the build with the offset of the build (wrapped into
// [0, L_s)); between builds update_ghosts moves the images by
// m_n * (offset - offset at build), and the list check counts that drift
// (le_half_skin_budget). Large-range particles get images of every non-zero
// tuple within their range and go to every rank in range (a full shell), as in
// make_ghosts (build_wide_pairs lists their pairs). Each ghost's m_n is kept
// in m_le_k (the other ranks' images too: GhostRecord::le_k).
void CellSystem::make_le_ghosts(ParticleStore &ps, BoxGeometry const &box) {
  bool const any_wide = !m_wide.empty();
  double const r_wide = std::max(m_range_ll, m_range_ls);
  double const r_max = std::max(m_range, r_wide);
  int const dn = m_le.shear_plane_normal, ds = m_le.shear_direction, dt = 3 - dn - ds;
  auto const &L = box.length();
  if (std::any_of(m_replicated.begin(), m_replicated.end(), [](char c) { return c != 0; }))
    throw Utils::RuntimeError(
        "cannot build the pair lists with Lees-Edwards boundary conditions: marble colloids are not "
        "supported (doc/lees-edwards.md)");
  // build_wide_pairs keeps a large-large image pair by the sign of its shift
  // vector, which is the sign of the integer tuple for |m_n| <= 1
  if (any_wide && r_max > L[dn])
    throw Utils::RuntimeError(
        "cannot build the pair lists with Lees-Edwards boundary conditions: the large-range "
        "interaction range " + std::to_string(r_max) + " exceeds the box length along the shear-plane "
        "normal (" + std::to_string(L[dn]) + "): enlarge the box or set "
        "system.cell_system.large_range_types = None");
  int const me = m_comm ? m_comm->rank() : 0;
  auto const g = node_grid(box);
  if (g[dn] != 1 || g[ds] != 1)
    throw Utils::RuntimeError("internal error: a Lees-Edwards node grid splits the shear plane");
  auto const me_at = coords_of(g, me);
  double const dl = L[dt] / g[dt];
  auto const ax_t = axis_split(box, g, dt);
  int const n = ps.n_local();
  double const off = box.le_offset_wrapped();
  m_le_offset_at_build = m_le.pos_offset;
  m_le_images = true;
  int const nimg_n = static_cast<int>(std::ceil(r_max / L[dn]));
  m_le_kmax = std::max(1, nimg_n); // (the images' drift between builds: le_drift)
  int const nimg_t = box.periodic(dt) ? static_cast<int>(std::ceil(r_max / L[dt])) : 0;
  // the faces along t: the domain's (the box's on one rank)
  bool const edge_t = box.periodic(dt) || g[dt] > 1;
  double const lo_t = ax_t.lo(me_at[dt]);
  double const hi_t = me_at[dt] == g[dt] - 1 ? L[dt] : ax_t.uniform ? lo_t + dl : ax_t.lo(me_at[dt] + 1);
  for (int i = 0; i < n; ++i) {
    Vector3d const p = ps.pos[i];
    bool const w = any_wide && wide(ps.type[i]);
    double const r = w ? r_wide : m_range;
    // farther than the range (plus a margin) from every face: no image within range
    bool interior = true;
    for (int d = 0; d < 3 && interior; ++d) {
      double const margin = 1e-9 * (L[d] + r);
      if (d == dt) {
        if (edge_t)
          interior = p[d] >= lo_t + r + margin && p[d] < hi_t - r - margin;
      } else if (box.periodic(d)) {
        interior = p[d] >= r + margin && p[d] < L[d] - r - margin;
      }
    }
    if (interior)
      continue;
    auto outside = [&](double q, int d) { return q < -r || q >= L[d] + r; };
    for (int k = -nimg_n; k <= nimg_n; ++k) {
      if (k != 0 && outside(p[dn] + k * L[dn], dn))
        continue;
      double const base = p[ds] + k * off; // along s before the box shifts
      int const m_lo = static_cast<int>(std::floor((-r - base) / L[ds])) - 1;
      int const m_hi = static_cast<int>(std::ceil((L[ds] + r - base) / L[ds])) + 1;
      for (int m = m_lo; m <= m_hi; ++m) {
        if ((k != 0 || m != 0) && outside(base + m * L[ds], ds))
          continue;
        for (int l = -nimg_t; l <= nimg_t; ++l) {
          if (l != 0 && outside(p[dt] + l * L[dt], dt))
            continue;
          std::array<int, 3> t{};
          t[dn] = k, t[ds] = m, t[dt] = l;
          Vector3d sh{0., 0., 0.};
          sh[dn] = k * L[dn];
          sh[ds] = k * off + m * L[ds];
          sh[dt] = l * L[dt];
          // the ranks along t whose domain, grown by the range, holds the image
          auto const [c_lo, c_hi] = ax_t.grown(p[dt] + sh[dt], r, box.periodic(dt));
          bool const nonzero = k != 0 || m != 0 || l != 0;
          for (int c = c_lo; c <= c_hi; ++c) {
            std::array<int, 3> dest_at{0, 0, 0};
            dest_at[dt] = c;
            int const dest = rank_of(g, dest_at);
            // small particles: the half shell (one rank: positive tuples);
            // large-range particles: every rank and non-zero tuple (their
            // pairs with small ones are listed from the large side)
            bool const sends = w ? (dest != me || nonzero) : half_shell_sends(me_at, t, g, dest_at);
            if (!sends)
              continue;
            if (dest == me) {
              ps.add_ghost(i, sh);
              ps.v.back()[ds] += k * m_le.shear_velocity;
              m_le_k.push_back(k);
            } else {
              m_send[dest].push_back({i, k, sh});
            }
          }
        }
      }
    }
  }
  exchange_ghosts(ps);
}

namespace {

/** A run of candidate slots [k0, k1) of the cell-ordered members. */
struct CandidateRange {
  int k0, k1;
};

/** The second output of a candidate scan: the partners within sqrt(@p inner2)
 * (<= the range) appended to @p out from slot @p n, in the same order. */
struct InnerOut {
  double inner2;
  int *out;
  std::size_t n;
};

/** Append members[k] (the partner j of the pair (i, j)) for every candidate k
 * of @p ranges (in order) with |p_i - p_k|^2 < @p range2 to @p out from slot
 * @p n; returns the new count. Scalar/SSE2 form. The coordinate and member
 * arrays are padded by 4 slots. */
template <bool Inner>
std::size_t scan_candidates(double const *pi, double range2, CandidateRange const *ranges,
                            int n_ranges, double const *mx, double const *my, double const *mz,
                            int const *members, int *out, std::size_t n, InnerOut &in) {
#ifdef __SSE2__
  __m128d const px = _mm_set1_pd(pi[0]), py = _mm_set1_pd(pi[1]), pz = _mm_set1_pd(pi[2]);
  __m128d const r2v = _mm_set1_pd(range2);
  [[maybe_unused]] __m128d const i2v = _mm_set1_pd(in.inner2);
#endif
  [[maybe_unused]] int *const oin = in.out;
  std::size_t m = in.n;
  for (int q = 0; q < n_ranges; ++q) {
    int k = ranges[q].k0;
    int const k1 = ranges[q].k1;
#ifdef __SSE2__
    // two candidates at a time (same arithmetic as the scalar test)
    for (; k + 1 < k1; k += 2) {
      __m128d const dx = _mm_sub_pd(px, _mm_loadu_pd(mx + k));
      __m128d const dy = _mm_sub_pd(py, _mm_loadu_pd(my + k));
      __m128d const dz = _mm_sub_pd(pz, _mm_loadu_pd(mz + k));
      __m128d const d2 =
          _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
      int const mask = _mm_movemask_pd(_mm_cmplt_pd(d2, r2v));
      [[maybe_unused]] int const mi = Inner ? _mm_movemask_pd(_mm_cmplt_pd(d2, i2v)) : 0;
      out[n] = members[k];
      n += static_cast<std::size_t>(mask & 1);
      out[n] = members[k + 1];
      n += static_cast<std::size_t>(mask >> 1);
      if constexpr (Inner) {
        oin[m] = members[k];
        m += static_cast<std::size_t>(mi & 1);
        oin[m] = members[k + 1];
        m += static_cast<std::size_t>(mi >> 1);
      }
    }
#endif
    for (; k < k1; ++k) {
      double const dx = pi[0] - mx[k], dy = pi[1] - my[k], dz = pi[2] - mz[k];
      double const d2 = dx * dx + dy * dy + dz * dz;
      out[n] = members[k];
      n += (d2 < range2) ? 1 : 0;
      if constexpr (Inner) {
        oin[m] = members[k];
        m += (d2 < in.inner2) ? 1 : 0;
      }
    }
  }
  in.n = m;
  return n;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define MARBLE_CELLS_AVX2 1
/** For each 4-bit lane mask: the bytes of the selected 32-bit lanes first,
 * in lane order (a pshufb control); and the lane count. */
struct CompressTable {
  alignas(16) std::int8_t perm[16][16];
  int count[16];
  constexpr CompressTable() : perm{}, count{} {
    for (int m = 0; m < 16; ++m) {
      int c = 0;
      for (int l = 0; l < 4; ++l)
        if ((m >> l) & 1) {
          for (int b = 0; b < 4; ++b)
            perm[m][4 * c + b] = static_cast<std::int8_t>(4 * l + b);
          ++c;
        }
      count[m] = c;
    }
  }
};
constexpr CompressTable kCompress{};

/** scan_candidates with AVX2: four candidates per test (the same arithmetic:
 * (dx^2 + dy^2) + dz^2 < range2, no FMA), the pairs within range written by
 * one permuted store; a range's tail is masked (the arrays are padded). */
template <bool Inner>
__attribute__((target("avx2"))) std::size_t
scan_candidates_avx2(double const *pi, double range2, CandidateRange const *ranges,
                     int n_ranges, double const *mx, double const *my, double const *mz,
                     int const *members, int *out, std::size_t n, InnerOut &in) {
  __m256d const px = _mm256_set1_pd(pi[0]), py = _mm256_set1_pd(pi[1]), pz = _mm256_set1_pd(pi[2]);
  __m256d const r2v = _mm256_set1_pd(range2);
  [[maybe_unused]] __m256d const i2v = _mm256_set1_pd(in.inner2);
  [[maybe_unused]] int *const oin = in.out;
  std::size_t mn = in.n;
  for (int q = 0; q < n_ranges; ++q) {
    int const k1 = ranges[q].k1;
    for (int k = ranges[q].k0; k < k1; k += 4) {
      __m256d const dx = _mm256_sub_pd(px, _mm256_loadu_pd(mx + k));
      __m256d const dy = _mm256_sub_pd(py, _mm256_loadu_pd(my + k));
      __m256d const dz = _mm256_sub_pd(pz, _mm256_loadu_pd(mz + k));
      __m256d const d2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                       _mm256_mul_pd(dz, dz));
      int const rem = k1 - k;
      int const tail = rem >= 4 ? 15 : (1 << rem) - 1;
      int const m = _mm256_movemask_pd(_mm256_cmp_pd(d2, r2v, _CMP_LT_OQ)) & tail;
      __m128i const js = _mm_loadu_si128(reinterpret_cast<__m128i const *>(members + k));
      __m128i const perm = _mm_load_si128(reinterpret_cast<__m128i const *>(kCompress.perm[m]));
      _mm_storeu_si128(reinterpret_cast<__m128i *>(out + n), _mm_shuffle_epi8(js, perm));
      n += static_cast<std::size_t>(kCompress.count[m]);
      if constexpr (Inner) {
        int const mi = _mm256_movemask_pd(_mm256_cmp_pd(d2, i2v, _CMP_LT_OQ)) & tail;
        __m128i const permi = _mm_load_si128(reinterpret_cast<__m128i const *>(kCompress.perm[mi]));
        _mm_storeu_si128(reinterpret_cast<__m128i *>(oin + mn), _mm_shuffle_epi8(js, permi));
        mn += static_cast<std::size_t>(kCompress.count[mi]);
      }
    }
  }
  in.n = mn;
  return n;
}

/** scan_candidates with AVX-512 (F + VL): eight candidates per test, the
 * same arithmetic in the same order ((dx^2 + dy^2) + dz^2 < range2; the
 * empty asm keeps the compiler from fusing a product and a sum into an FMA,
 * which would round differently), the range's tail masked, the partners
 * within range compressed into one 256-bit store. The coordinate and member
 * arrays are padded by 8 slots, @p out has 8 slots of room past the pairs. */
template <bool Inner>
__attribute__((target("avx512f,avx512vl,bmi2,popcnt"))) std::size_t
scan_candidates_avx512(double const *pi, double range2, CandidateRange const *ranges,
                       int n_ranges, double const *mx, double const *my, double const *mz,
                       int const *members, int *out, std::size_t n, InnerOut &in) {
  __m512d const px = _mm512_set1_pd(pi[0]), py = _mm512_set1_pd(pi[1]), pz = _mm512_set1_pd(pi[2]);
  __m512d const r2v = _mm512_set1_pd(range2);
  [[maybe_unused]] __m512d const i2v = _mm512_set1_pd(in.inner2);
  [[maybe_unused]] int *const oin = in.out;
  std::size_t mn = in.n;
  for (int q = 0; q < n_ranges; ++q) {
    int const k1 = ranges[q].k1;
    for (int k = ranges[q].k0; k < k1; k += 8) {
      __m512d const dx = _mm512_sub_pd(px, _mm512_loadu_pd(mx + k));
      __m512d const dy = _mm512_sub_pd(py, _mm512_loadu_pd(my + k));
      __m512d const dz = _mm512_sub_pd(pz, _mm512_loadu_pd(mz + k));
      __m512d xx = _mm512_mul_pd(dx, dx), yy = _mm512_mul_pd(dy, dy), zz = _mm512_mul_pd(dz, dz);
      __asm__("" : "+v"(xx), "+v"(yy), "+v"(zz));
      __m512d const d2 = _mm512_add_pd(_mm512_add_pd(xx, yy), zz);
      unsigned const rem = static_cast<unsigned>(std::min(k1 - k, 8));
      __mmask8 const tail = static_cast<__mmask8>(_bzhi_u32(0xffu, rem));
      __mmask8 const m = _mm512_mask_cmp_pd_mask(tail, d2, r2v, _CMP_LT_OQ);
      __m256i const js = _mm256_loadu_si256(reinterpret_cast<__m256i const *>(members + k));
      _mm256_storeu_si256(reinterpret_cast<__m256i *>(out + n), _mm256_maskz_compress_epi32(m, js));
      n += static_cast<std::size_t>(_mm_popcnt_u32(m));
      if constexpr (Inner) {
        __mmask8 const mi = _mm512_mask_cmp_pd_mask(m, d2, i2v, _CMP_LT_OQ);
        _mm256_storeu_si256(reinterpret_cast<__m256i *>(oin + mn), _mm256_maskz_compress_epi32(mi, js));
        mn += static_cast<std::size_t>(_mm_popcnt_u32(mi));
      }
    }
  }
  in.n = mn;
  return n;
}

#endif

// The candidate-scan path: 0 scalar/SSE2, 1 AVX2, 2 AVX-512 (all give the same list).
int best_scan_path() {
#ifdef MARBLE_CELLS_AVX2
  static int const best = (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                           __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt"))
                              ? 2
                              : (Utils::cpu_has_avx2() ? 1 : 0);
  return best;
#else
  return 0;
#endif
}
int g_scan_path = -1; // -1: best_scan_path()

} // namespace

void CellSystem::set_scan_path(int path) { g_scan_path = path < 0 ? -1 : std::min(path, best_scan_path()); }
int CellSystem::scan_path() { return g_scan_path < 0 ? best_scan_path() : g_scan_path; }

// The list order (and so the force summation order) is: locals i ascending
// (one row of partners j per i, VerletPairs);
// for each, the 27 neighbour cells in (dz, dy, dx) order; in each cell its
// locals ascending, then its ghosts ascending. Since locals are sorted by cell,
// a neighbour cell below i's cell holds only locals < i, and in i's own cell
// the locals > i follow i directly: whole ranges are skipped instead of
// testing j > i per candidate. Candidates are read from a cell-ordered copy of
// the positions and appended without a branch (four at a time with AVX2).
// In that order the candidates of i are the member slots in ascending order.
// A neighbour cell (or a row of three) is skipped for i when the distance from
// p_i to the cell's near face(s) is already >= the range (minus a margin far
// above round-off): none of its candidates could pass the test, so the list
// is the same, pair for pair, as with every cell scanned.
void CellSystem::build_pairs(ParticleStore const &ps, BoxGeometry const &box) {
  m_cell_start.clear();
  m_cell_members.clear();
  m_inner_fresh = false;
  if (m_range <= 0.) {
    m_pairs.clear();
    return;
  }
  m_pairs.extra.clear();
  auto const dom = local_domain(box);
  m_grid = Grid(dom.first, dom.second, m_range);
  Grid const &g = m_grid;
  m_n_cells = g.n;
  int const n_all = ps.size(), n_local = ps.n_local();
  int const n_cells = g.n_total();
  m_n_local_at_build = n_local;
  // Large-range particles are not in this grid (cell -1): their locals were
  // sorted last (sort_locals), so the small locals are [0, n_small_local).
  bool const any_wide = !m_wide.empty();
  m_wide_locals.clear();
  auto &cell = m_scratch_cell;
  // the locals' cells come from sort_locals (same grid, same positions)
  bool const locals_ready = m_local_cells_ready && cell.size() == static_cast<std::size_t>(n_local);
  m_local_cells_ready = false;
  cell.resize(static_cast<std::size_t>(n_all));
  auto &start = m_cell_start;
  auto &members = m_cell_members;
  start.assign(n_cells + 1, 0);
  int n_members = 0;
  for (int i = 0; i < n_all; ++i) {
    if (any_wide && wide(ps.type[i])) {
      cell[i] = -1;
      if (i < n_local)
        m_wide_locals.push_back(i);
      continue;
    }
    if (!(locals_ready && i < n_local))
      cell[i] = i < n_local ? g.local_index(ps.pos[i]) : g.index(ps.pos[i]);
    ++start[cell[i] + 1];
    ++n_members;
  }
  int const n_small_local = n_local - static_cast<int>(m_wide_locals.size());
  // the AVX-512 scan reads up to 7 slots past a range and stores 8 partners
  // at the list's end; the finished list is padded by 8 zeros (VerletPairs:
  // the AVX-512 row select reads 8 partners at a time)
  constexpr int kPad = 8, kListPad = 8;
  members.resize(static_cast<std::size_t>(n_members + kPad));
  std::fill(members.end() - kPad, members.end(), 0);
  for (int c = 0; c < n_cells; ++c)
    start[c + 1] += start[c];
  auto &fill = m_scratch_fill;
  fill.assign(start.begin(), start.end() - 1);
  for (int i = 0; i < n_small_local; ++i)
    members[fill[cell[i]]++] = i;
  auto &ghost_begin = m_scratch_ghost_begin; // locals of cell c: [start[c], ghost_begin[c])
  ghost_begin.assign(fill.begin(), fill.end());
  for (int i = n_local; i < n_all; ++i)
    if (cell[i] >= 0)
      members[fill[cell[i]]++] = i;
  // Cell-ordered coordinates, one array per axis: contiguous reads below.
  auto &mx = m_scratch_x, &my = m_scratch_y, &mz = m_scratch_z;
  for (auto *m : {&mx, &my, &mz}) {
    m->resize(static_cast<std::size_t>(n_members + kPad));
    std::fill(m->end() - kPad, m->end(), 0.);
  }
  for (int k = 0; k < n_members; ++k) {
    auto const &p = ps.pos[members[k]];
    mx[k] = p[0];
    my[k] = p[1];
    mz[k] = p[2];
  }

  double const range2 = m_range * m_range;
  int const sy = g.ext[0], sz = g.ext[0] * g.ext[1];
  // margin of the face test: far above the round-off of positions and cell faces
  std::array<double, 3> eps{};
  for (int d = 0; d < 3; ++d)
    eps[d] = 1e-9 * (std::abs(g.lo[d]) + g.size[d] * g.ext[d]);
  int const path = scan_path();
  (void)path;
  // The list keeps its size between rebuilds (no zero fill of the whole
  // buffer): it grows only when a particle's candidates might not fit.
  std::size_t n_pairs = 0;
  auto &pj = m_pairs.j;
  auto &row = m_pairs.row_start;
  {
    std::size_t const want = std::max<std::size_t>(1024, pj.size() + pj.size() / 8 + 64);
    if (pj.size() < want)
      pj.resize(want);
  }
  row.resize(static_cast<std::size_t>(n_small_local) + 1);
  row[0] = 0;
  // The inner list (select_pairs): the partners within the largest cutoff
  // (a hair above it: a superset of what any select keeps; never above the
  // range, so a subset of the list, in its order). Same size as the list.
  // Only where asked for (set_inner_list: the Shardlow integrator, whose
  // list lives ~2 steps; at velocity Verlet's ~5 its second store does not pay).
  double const inner2 = std::min(m_inner_cut * m_inner_cut * (1. + 1e-12), range2);
  bool const want_inner = m_inner_wanted && inner2 < range2;
  auto &ij = m_inner.j;
  auto &irow = m_inner.row_start;
  InnerOut inner{inner2, nullptr, 0};
  if (want_inner) {
    irow.resize(row.size());
    irow[0] = 0;
    if (ij.size() < pj.size())
      ij.resize(pj.size());
  } else {
    m_inner.clear();
  }
  // Per cell, the candidate slots as items in list order: a row (dz, dy) of
  // three cells whose slots are contiguous (kRow: [a0, b0) [b0, b1) [b1, c1)),
  // i's own row from the slot after i (kOwn: [i+1, b1) [b1, c1)), or one cell
  // (kCell). Per particle the near-face test trims a row's first/last cell or
  // empties it without a branch; single cells (ghost-only cells below i's
  // cell: the domain's boundary layer) are tested one by one.
  enum : int { kRow, kOwn, kCell };
  struct Item {
    int kind, dz, dy, dx, a0, b0, b1, c1;
  };
  std::array<Item, 27> items{};
  std::array<CandidateRange, 27> kept{};
  for (int i_begin = 0; i_begin < n_small_local;) {
    int const ci = cell[i_begin];
    int i_end = i_begin;
    while (i_end < n_small_local && cell[i_end] == ci)
      ++i_end;
    std::size_t max_cand = 0;
    int const cc[3] = {ci % g.ext[0], (ci / g.ext[0]) % g.ext[1], ci / sz};
    double face_lo[3], face_hi[3];
    for (int d = 0; d < 3; ++d) {
      face_lo[d] = g.lo[d] + (cc[d] - 1) * g.size[d];
      face_hi[d] = face_lo[d] + g.size[d];
    }
    int n_items = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        int k0[3], k1[3];
        for (int dx = -1; dx <= 1; ++dx) {
          int const cj = ci + dx + dy * sy + dz * sz;
          int &lo = k0[dx + 1], &hi = k1[dx + 1];
          if (cj < 0 || cj >= n_cells) {
            lo = hi = 0;
            continue;
          }
          lo = cj < ci ? ghost_begin[cj] : start[cj];
          hi = start[cj + 1];
          if (cj == ci) // own cell: the list starts after i (set per particle)
            lo = start[ci];
          max_cand += static_cast<std::size_t>(std::max(0, hi - lo));
        }
        if (dz == 0 && dy == 0) {
          if (k1[0] > k0[0])
            items[n_items++] = {kCell, dz, dy, -1, k0[0], k1[0], 0, 0};
          items[n_items++] = {kOwn, dz, dy, 0, 0, 0, k1[1], std::max(k1[1], k1[2])};
        } else if (k1[0] == k0[1] && k1[1] == k0[2]) {
          items[n_items++] = {kRow, dz, dy, 0, k0[0], k0[1], k1[1], k1[2]};
        } else {
          for (int dx = -1; dx <= 1; ++dx)
            if (k1[dx + 1] > k0[dx + 1])
              items[n_items++] = {kCell, dz, dy, dx, k0[dx + 1], k1[dx + 1], 0, 0};
        }
      }
    for (int i = i_begin; i < i_end; ++i) {
      if (pj.size() < n_pairs + max_cand + kPad)
        pj.resize(2 * pj.size() + max_cand + kPad);
      if (want_inner) {
        if (ij.size() < inner.n + max_cand + kPad)
          ij.resize(2 * ij.size() + max_cand + kPad);
        inner.out = ij.data();
      }
      Vector3d const pi = ps.pos[i];
      int const self_next = start[ci] + (i - i_begin) + 1; // own cell: the slots after i
      // squared distances to the near faces of the neighbours at -1, 0, +1
      double gap2[3][3];
      for (int d = 0; d < 3; ++d) {
        double const a = std::max(0., pi[d] - face_lo[d] - eps[d]);
        double const b = std::max(0., face_hi[d] - pi[d] - eps[d]);
        gap2[d][0] = a * a;
        gap2[d][1] = 0.;
        gap2[d][2] = b * b;
      }
      int n_kept = 0;
      for (int q = 0; q < n_items; ++q) {
        Item const &it = items[q];
        double const gyz = gap2[2][it.dz + 1] + gap2[1][it.dy + 1];
        // 0/1 flags and integer arithmetic: no data-dependent branch
        if (it.kind == kCell) {
          kept[n_kept] = {it.a0, it.b0};
          n_kept += static_cast<int>(gyz + gap2[0][it.dx + 1] < range2);
          continue;
        }
        int const cut_left = static_cast<int>(gyz + gap2[0][0] >= range2);
        int const cut_right = static_cast<int>(gyz + gap2[0][2] >= range2);
        int const cut_row = static_cast<int>(gyz >= range2);
        int const lo = it.kind == kOwn ? self_next : it.a0 + cut_left * (it.b0 - it.a0);
        int hi = it.c1 - cut_right * (it.c1 - it.b1);
        hi -= cut_row * (hi - lo);
        kept[n_kept++] = {lo, hi};
      }
      auto scan = [&]<bool Inner>() {
#ifdef MARBLE_CELLS_AVX2
        if (path == 2)
          return scan_candidates_avx512<Inner>(pi.data(), range2, kept.data(), n_kept, mx.data(), my.data(),
                                               mz.data(), members.data(), pj.data(), n_pairs, inner);
        if (path == 1)
          return scan_candidates_avx2<Inner>(pi.data(), range2, kept.data(), n_kept, mx.data(), my.data(),
                                             mz.data(), members.data(), pj.data(), n_pairs, inner);
#endif
        return scan_candidates<Inner>(pi.data(), range2, kept.data(), n_kept, mx.data(), my.data(),
                                      mz.data(), members.data(), pj.data(), n_pairs, inner);
      };
      n_pairs = want_inner ? scan.template operator()<true>() : scan.template operator()<false>();
      row[static_cast<std::size_t>(i) + 1] = static_cast<int>(n_pairs);
      if (want_inner)
        irow[static_cast<std::size_t>(i) + 1] = static_cast<int>(inner.n);
    }
    i_begin = i_end;
  }
  pj.resize(n_pairs + kListPad); // padded by valid indices for SIMD reads past a row
  std::fill(pj.end() - kListPad, pj.end(), 0);
  if (want_inner) {
    ij.resize(inner.n + kListPad);
    std::fill(ij.end() - kListPad, ij.end(), 0);
  }
  members.resize(static_cast<std::size_t>(n_members));
  // A pair with another rank's particle is computed by the rank owning the
  // smaller id, but only for large-range particles and colloid copies (they
  // come from all sides); the half-shell ghosts of other ranks' small
  // particles are computed here (other_rank_computes). Without such ghosts
  // (a plain fluid) the list is final: no pass over all pairs.
  bool filter = false;
  if (parallel())
    for (int g = n_local; g < n_all && !filter; ++g) {
      int const o = ps.ghost_owner[g - n_local];
      filter = o == kRemoteColloidGhost || (o == kRemoteGhost && any_wide && wide(ps.type[g]));
    }
  // (the inner list is not filtered: with such ghosts select_pairs() is the list)
  bool const inner_ok = want_inner && !filter;
  if (filter) {
    std::size_t w = 0;
    for (int i = 0; i < n_small_local; ++i) {
      std::size_t const k0 = static_cast<std::size_t>(row[i]), k1 = static_cast<std::size_t>(row[i + 1]);
      row[i] = static_cast<int>(w);
      for (std::size_t k = k0; k < k1; ++k) {
        int const j = pj[k];
        pj[w] = j;
        w += (j >= n_local && other_rank_computes(ps, i, j, n_local)) ? 0 : 1;
      }
    }
    row[static_cast<std::size_t>(n_small_local)] = static_cast<int>(w);
    pj.resize(w + kListPad);
    std::fill(pj.end() - kListPad, pj.end(), 0);
  }
  if (any_wide)
    build_wide_pairs(ps, box, n_small_local, ghost_begin);
  // (the pairs with large-range particles are not pruned: with any, select_pairs() is the list)
  m_inner_fresh = inner_ok && m_pairs.extra.empty();
}

// Pairs with large-range particles, appended after the solvent-grid pairs:
// (b) among them, from a coarse grid over their locals and ghosts: local-local
// with i < j, local-(own image) with a positive shift, local-(other rank's
// particle) on the rank owning the smaller id, as in build_pairs; (c) with
// small particles: for each large-range particle (local or ghost, in index
// order) the small locals of the solvent cells within range_ls, listed as
// (large, small) for a local and (small, large) for a ghost. Since the large
// particles have ghosts of every shift out to range_ls and the small partner
// is always a local, every large-small pair is listed exactly once.
void CellSystem::build_wide_pairs(ParticleStore const &ps, BoxGeometry const &box,
                                  int n_small_local, std::vector<int> const &ghost_begin) {
  int const n_all = ps.size(), n_local = ps.n_local();
  std::vector<int> wide_all(m_wide_locals);
  for (int i = n_local; i < n_all; ++i)
    if (wide(ps.type[i]))
      wide_all.push_back(i);
  // (b) large-large
  if (m_range_ll > 0. && !m_wide_locals.empty()) {
    auto const dom = local_domain(box);
    Grid const g(dom.first, dom.second, m_range_ll);
    int const n_cells = g.n_total();
    std::vector<int> start(n_cells + 1, 0), cell(wide_all.size());
    for (std::size_t k = 0; k < wide_all.size(); ++k) {
      int const i = wide_all[k];
      cell[k] = i < n_local ? g.local_index(ps.pos[i]) : g.index(ps.pos[i]);
      ++start[cell[k] + 1];
    }
    for (int c = 0; c < n_cells; ++c)
      start[c + 1] += start[c];
    std::vector<int> fill(start.begin(), start.end() - 1), members(wide_all.size());
    for (std::size_t k = 0; k < wide_all.size(); ++k) // locals first in each cell, ascending
      members[static_cast<std::size_t>(fill[cell[k]]++)] = wide_all[k];
    double const range2 = m_range_ll * m_range_ll;
    for (std::size_t k = 0; k < m_wide_locals.size(); ++k) {
      int const i = m_wide_locals[k];
      int const ci = cell[k];
      std::array<int, 3> c{ci % g.ext[0], (ci / g.ext[0]) % g.ext[1], ci / (g.ext[0] * g.ext[1])};
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            int const cj = ((c[2] + dz) * g.ext[1] + (c[1] + dy)) * g.ext[0] + (c[0] + dx);
            for (int q = start[cj]; q < start[cj + 1]; ++q) {
              int const j = members[static_cast<std::size_t>(q)];
              if (j < n_local) {
                if (j <= i)
                  continue;
              } else if (ps.ghost_owner[j - n_local] >= 0 ? !shift_positive(ps.ghost_shift[j - n_local])
                                                          : other_rank_computes(ps, i, j, n_local)) {
                continue; // an own image: positive shifts only; another rank's: see build_pairs
              }
              if ((ps.pos[i] - ps.pos[j]).norm2() < range2)
                m_pairs.extra.push_back({i, j});
            }
          }
    }
  }
  // (c) large-small, through the solvent grid (small locals only)
  if (m_range_ls > 0. && !m_cell_start.empty() && n_small_local > 0) {
    Grid const &g = m_grid;
    double const r = m_range_ls, r2 = r * r;
    auto const &start = m_cell_start;
    auto const &members = m_cell_members;
    for (int const p : wide_all) {
      Vector3d const c = ps.pos[p];
      std::array<int, 3> lo{}, hi{};
      bool none = false;
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::max(1, g.coord(c[d] - r, d));
        hi[d] = std::min(g.n[d], g.coord(c[d] + r, d));
        none |= lo[d] > hi[d];
      }
      if (none)
        continue;
      // distance^2 from c to the slab of cell x along axis d
      auto gap2 = [&](int x, int d) {
        double const a = g.lo[d] + (x - 1) * g.size[d], b = a + g.size[d];
        double const e = c[d] < a ? a - c[d] : (c[d] > b ? c[d] - b : 0.);
        return e * e;
      };
      for (int z = lo[2]; z <= hi[2]; ++z) {
        double const gz = gap2(z, 2);
        if (gz >= r2)
          continue;
        for (int y = lo[1]; y <= hi[1]; ++y) {
          double const gy = gz + gap2(y, 1);
          if (gy >= r2)
            continue;
          for (int x = lo[0]; x <= hi[0]; ++x) {
            if (gy + gap2(x, 0) >= r2)
              continue;
            int const cc = (z * g.ext[1] + y) * g.ext[0] + x;
            for (int q = start[cc]; q < ghost_begin[cc]; ++q) {
              int const s = members[q];
              if ((ps.pos[s] - c).norm2() < r2)
                m_pairs.extra.push_back(p < n_local ? std::array<int, 2>{p, s} : std::array<int, 2>{s, p});
            }
          }
        }
      }
    }
  }
}

void CellSystem::rebuild(ParticleStore &ps, BoxGeometry const &box, double max_cut) {
  double const range = max_cut > 0. ? max_cut + m_skin : 0.;
  // Periodic images are made up to ceil(range / L) boxes away on each side:
  // refuse absurd ranges (e.g. a cutoff of 1e300) before the image count
  // overflows an int (found by testsuite/python/test_fuzz_api.py under UBSan).
  constexpr double max_images = 16.;
  for (int d = 0; d < 3; ++d)
    if (!(range <= max_images * box.length()[d]))
      throw Utils::RuntimeError(
          "the interaction range " + std::to_string(range) + " (largest cutoff + skin) is more "
          "than " + std::to_string(static_cast<int>(max_images)) + " box lengths along axis " +
          std::to_string(d) + " (" + std::to_string(box.length()[d]) +
          "): reduce the cutoff or enlarge the box");
  bool const any_wide = !m_wide.empty();
  m_range_ll = any_wide && m_cut_ll > 0. ? m_cut_ll + m_skin : 0.;
  m_range_ls = any_wide && m_cut_ls > 0. ? m_cut_ls + m_skin : 0.;
  for (int d = 0; d < 3; ++d)
    if (!(std::max(m_range_ll, m_range_ls) <= max_images * box.length()[d]))
      throw Utils::RuntimeError(
          "the large-range interaction range " +
          std::to_string(std::max(m_range_ll, m_range_ls)) + " (largest colloid cutoff + skin) is "
          "more than " + std::to_string(static_cast<int>(max_images)) + " box lengths along axis " +
          std::to_string(d) + ": reduce the cutoff or enlarge the box");
  ps.clear_ghosts();
  m_range = range;
  m_inner_cut = max_cut > 0. ? max_cut : 0.;
  m_inner_fresh = false;
  m_le = box.lees_edwards();
  if (!m_le.active()) {
    // a coordinate in [0, 0.9999999 L) is left as it is by fold (its
    // floor(x / L) is 0): fold only the particles with some other coordinate
    // along a periodic axis (no division for the others; the same result)
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      bool const p = box.periodic(d);
      lo[d] = p ? 0. : -std::numeric_limits<double>::infinity();
      hi[d] = p ? box.length()[d] * (1. - 1e-7) : std::numeric_limits<double>::infinity();
    }
    for (int i = 0; i < ps.n_local(); ++i) {
      Vector3d const &x = ps.pos[i];
      if (!(x[0] >= lo[0] && x[0] < hi[0] && x[1] >= lo[1] && x[1] < hi[1] && x[2] >= lo[2] && x[2] < hi[2]))
        box.fold(ps.pos[i], ps.image[i]);
    }
  } else {
    // Lees-Edwards: a particle crossing the shear plane k times upwards gets
    // its velocity along the shear direction shifted by -k * shear_velocity
    // (its position by -k * offset: BoxGeometry::fold)
    for (int i = 0; i < ps.n_local(); ++i) {
      int const k = box.fold(ps.pos[i], ps.image[i]);
      if (k != 0)
        ps.v[i][m_le.shear_direction] -= k * m_le.shear_velocity;
    }
  }
  if (parallel()) {
    // neighbours: within the ghost range (every ghost goes to one) and 2
    // skins (every particle moved by a run between two rebuilds stays among
    // them: the pair test keeps a list while no local has moved a skin, and
    // the step after adds at most another, integrate.cpp refuses more)
    update_neighbour_ranks(box, std::max({m_range, m_range_ll, m_range_ls, 2. * m_skin}));
    migrate(ps, box);
  }
  sort_locals(ps, box);
  for (int i = 0; i < ps.n_local(); ++i)
    ps.pos_at_rebuild[i] = ps.pos[i];
  make_ghosts(ps, box);
  build_pairs(ps, box);
  m_box_l = box.length();
  for (int d = 0; d < 3; ++d)
    m_box_periodic[d] = box.periodic(d);
  m_n_global_at_build = -1; // (counted by the first pair test of this list)
  m_valid = true;
  ++m_n_rebuilds;
}

// Own periodic images come first among the ghosts, other ranks' particles after them.
template <typename F> void CellSystem::for_each_own_image(ParticleStore const &ps, F &&fn) const {
  int const n_local = ps.n_local();
  for (int g = n_local; g < ps.size(); ++g) {
    int const o = ps.ghost_owner[g - n_local];
    if (o < 0)
      break;
    fn(g, o);
  }
}

// One point-to-point exchange of T records with the neighbour ranks: n_out(q)
// records to rank q, written by fill(q, out); n_in(q) from rank q, read by
// consume(q, in). The buffers only grow, so a run reuses them step after step.
template <typename T, typename NOut, typename NIn, typename Fill, typename Consume>
void CellSystem::exchange_records(NOut &&n_out, NIn &&n_in, Fill &&fill, Consume &&consume) const {
  static_assert(std::is_trivially_copyable_v<T>);
  int const size = m_comm->size();
  auto &sb = m_xblocks[0];
  auto &rb = m_xblocks[1];
  sb.clear();
  rb.clear();
  for (int q = 0; q < size; ++q) {
    std::size_t const n_o = n_out(q), n_i = n_in(q);
    if (n_o > 0) {
      T *const out = reinterpret_cast<T *>(grow_buffer(m_xsend, q, n_o * sizeof(T)));
      fill(q, out);
      sb.push_back({q, out, n_o * sizeof(T)});
    }
    if (n_i > 0)
      rb.push_back({q, grow_buffer(m_xrecv, q, n_i * sizeof(T)), n_i * sizeof(T)});
  }
  m_comm->neighbor_exchange_blocks(sb.data(), static_cast<int>(sb.size()), rb.data(), static_cast<int>(rb.size()));
  for (auto const &blk : rb)
    consume(blk.rank, reinterpret_cast<T const *>(blk.data));
}

// Owners -> other ranks' ghosts: pack(send entry) for each entry of m_send,
// unpack(ghost index, value) on the receiving rank, in the same order. The
// sizes are fixed between rebuilds (m_send[q] out, m_recv_count[q] in), so
// the data go point to point to the neighbour ranks, with no count exchange.
template <typename T, typename Pack, typename Unpack>
void CellSystem::to_remote_ghosts(Pack &&pack, Unpack &&unpack) const {
  exchange_records<T>(
      [&](int q) { return m_send[q].size(); },
      [&](int q) { return static_cast<std::size_t>(m_recv_count[q]); },
      [&](int q, T *out) {
        SendEntry const *const e = m_send[q].data();
        std::size_t const n = m_send[q].size();
        for (std::size_t k = 0; k < n; ++k)
          out[k] = pack(e[k]);
      },
      [&](int q, T const *in) {
        int const g0 = m_recv_begin[q], n = m_recv_count[q];
        for (int k = 0; k < n; ++k)
          unpack(g0 + k, in[k]);
      });
}

// The reverse: pack(ghost index) for the ghosts from each rank, unpack(local
// index, value) on their owner.
template <typename T, typename Pack, typename Unpack>
void CellSystem::from_remote_ghosts(Pack &&pack, Unpack &&unpack) const {
  exchange_records<T>(
      [&](int q) { return static_cast<std::size_t>(m_recv_count[q]); },
      [&](int q) { return m_send[q].size(); },
      [&](int q, T *out) {
        int const g0 = m_recv_begin[q], n = m_recv_count[q];
        for (int k = 0; k < n; ++k)
          out[k] = pack(g0 + k);
      },
      [&](int q, T const *in) {
        int const *const idx = m_send_index[q].data();
        std::size_t const n = m_send_index[q].size();
        for (std::size_t k = 0; k < n; ++k)
          unpack(idx[k], in[k]);
      });
}

void CellSystem::update_ghosts(ParticleStore &ps) const {
  m_inner_fresh = false; // the positions are no longer those of the build
  int const ds = m_le.shear_direction;
  double const doff = m_le.pos_offset - m_le_offset_at_build, vs = m_le.shear_velocity;
  if (m_le_images) { // Lees-Edwards images: moved with the offset, velocity jump
    int const nl = ps.n_local();
    for_each_own_image(ps, [&](int g, int o) {
      int const k = m_le_k[static_cast<std::size_t>(g - nl)];
      ps.pos[g] = ps.pos[o] + ps.ghost_shift[g - nl];
      ps.v[g] = ps.v[o];
      if (k != 0) {
        ps.pos[g][ds] += k * doff;
        ps.v[g][ds] += k * vs;
      }
#ifdef ROTATION
      ps.omega[g] = ps.omega[o];
#endif
    });
  } else {
    for_each_own_image(ps, [&](int g, int o) {
      ps.pos[g] = ps.pos[o] + ps.ghost_shift[g - ps.n_local()];
      ps.v[g] = ps.v[o];
#ifdef ROTATION
      ps.omega[g] = ps.omega[o];
#endif
    });
  }
  if (!parallel())
    return;
  // (le_k: a Lees-Edwards image's shift along the normal, 0 for every other ghost)
  to_remote_ghosts<GhostUpdate>(
      [&](SendEntry const &e) {
        GhostUpdate u = ghost_update_of(ps, e.index, e.shift);
        if (e.le_k != 0) {
          u.pos[ds] += e.le_k * doff;
          u.v[ds] += e.le_k * vs;
        }
        return u;
      },
      [&](int g, GhostUpdate const &u) { apply_ghost_update(ps, g, u); });
}

void CellSystem::update_replicated_ghosts(ParticleStore &ps) const {
  m_inner_fresh = false;
  if (!parallel())
    return;
  exchange_records<GhostUpdate>(
      [&](int q) { return m_rep_send[q].size(); }, [&](int q) { return m_rep_recv[q].size(); },
      [&](int q, GhostUpdate *out) {
        for (int k : m_rep_send[q]) {
          SendEntry const &e = m_send[q][static_cast<std::size_t>(k)];
          *out++ = ghost_update_of(ps, e.index, e.shift);
        }
      },
      [&](int q, GhostUpdate const *in) {
        for (int g : m_rep_recv[q])
          apply_ghost_update(ps, g, *in++);
      });
}

void CellSystem::reduce_replicated_ghost_values(std::vector<Utils::Vector3d> &x) const {
  if (!parallel())
    return;
  exchange_records<Vector3d>(
      [&](int q) { return m_rep_recv[q].size(); }, [&](int q) { return m_rep_send[q].size(); },
      [&](int q, Vector3d *out) {
        for (int g : m_rep_recv[q])
          *out++ = x[g];
      },
      [&](int q, Vector3d const *in) {
        for (int k : m_rep_send[q])
          x[m_send_index[q][static_cast<std::size_t>(k)]] += *in++;
      });
}

void CellSystem::reduce_ghost_forces(ParticleStore &ps) const {
  for_each_own_image(ps, [&](int g, int o) {
    ps.f[o] += ps.f[g];
#ifdef ROTATION
    ps.torque[o] += ps.torque[g];
#endif
  });
  if (!parallel())
    return;
  from_remote_ghosts<GhostForce>(
      [&](int g) {
        GhostForce gf;
        gf.f = ps.f[g];
#ifdef ROTATION
        gf.torque = ps.torque[g];
#endif
        return gf;
      },
      [&](int i, GhostForce const &gf) {
        ps.f[i] += gf.f;
#ifdef ROTATION
        ps.torque[i] += gf.torque;
#endif
      });
}

std::vector<int> const &CellSystem::ghost_representatives(ParticleStore const &ps) const {
  if (m_ghost_rep_valid && m_ghost_rep.size() == static_cast<std::size_t>(ps.n_ghost()))
    return m_ghost_rep;
  int const nl = ps.n_local(), ng = ps.n_ghost();
  m_ghost_rep.resize(static_cast<std::size_t>(ng));
  std::unordered_map<int, int> first; // particle id -> its first slot among the remote ghosts
  first.reserve(static_cast<std::size_t>(ng));
  for (int g = 0; g < ng; ++g) {
    int const o = ps.ghost_owner[g];
    m_ghost_rep[g] = o >= 0 ? o : first.emplace(ps.id[nl + g], nl + g).first->second;
  }
  m_ghost_rep_valid = true;
  return m_ghost_rep;
}

void CellSystem::fill_ghost_values(ParticleStore const &ps, std::vector<Vector3d> &x) const {
  for_each_own_image(ps, [&](int g, int o) { x[g] = x[o]; });
  if (parallel())
    to_remote_ghosts<Vector3d>([&](SendEntry const &e) { return x[e.index]; },
                               [&](int g, Vector3d const &v) { x[g] = v; });
}

void CellSystem::reduce_ghost_values(ParticleStore const &ps, std::vector<Vector3d> &x) const {
  for_each_own_image(ps, [&](int g, int o) { x[o] += x[g]; });
  if (parallel())
    from_remote_ghosts<Vector3d>([&](int g) { return x[g]; },
                                 [&](int i, Vector3d const &v) { x[i] += v; });
}

bool CellSystem::displacement_exceeds_half_skin(ParticleStore const &ps) const {
  double lim2 = 0.25 * m_skin * m_skin;
  if (m_le_images) { // Lees-Edwards: the images moved with the offset since the build
    double const b = le_half_skin_budget(m_le.pos_offset);
    if (!(b > 0.))
      return true; // (b is the same on every rank: all return here)
    lim2 = b * b;
  }
  bool exceeded = false;
  for (int i = 0; i < ps.n_local(); ++i)
    if ((ps.pos[i] - ps.pos_at_rebuild[i]).norm2() > lim2) {
      exceeded = true;
      break;
    }
  return m_comm ? m_comm->any(exceeded) : exceeded;
}

bool CellSystem::pair_test_applies() const {
  if (m_le_images || !m_wide.empty() || !(m_range > 0.) || !(m_inner_cut > 0.))
    return false;
  for (int d = 0; d < 3; ++d)
    if (m_box_periodic[d] && !(m_box_l[d] >= 3. * m_range))
      return false;
  return true;
}

bool CellSystem::pairs_may_be_missing(ParticleStore const &ps, float const *disp2, double reach) const {
  int const n = ps.n_local();
  auto const *const x = ps.pos.data();
  auto const *const x0 = ps.pos_at_rebuild.data();
  float const *src = disp2;
  if (!src) {
    m_fast_d2.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      m_fast_d2[static_cast<std::size_t>(i)] = static_cast<float>((x[i] - x0[i]).norm2());
    src = m_fast_d2.data();
  }
  float fmax2 = 0.f;
  bool nan = false;
  for (int i = 0; i < n; ++i) {
    fmax2 = src[i] > fmax2 ? src[i] : fmax2;
    nan |= src[i] != src[i];
  }
  if (nan)
    fmax2 = std::numeric_limits<float>::infinity(); // (then: rebuild, on every rank)
  // (float: relative error < 1e-7; every threshold below allows 1e-6)
  double const dmax2 = static_cast<double>(fmax2) * (1. + 1e-6);
  bool const par = m_comm && m_comm->parallel();
  // d_max and the other list's reach over all ranks (one reduction)
  double dr[2] = {std::sqrt(dmax2), reach};
  if (par)
    m_comm->max_inplace(dr, 2);
  double const dmax = dr[0];
  // A missing pair (i, j) was at least the range apart at the build and is
  // now within max_cut: |dx_i - dx_j| > skin, so d_i + d_j > skin. Say
  // d_i >= d_j: then d_i > skin/2 (i is "hot") and d_j > skin - d_i >=
  // skin - d_max (j is "warm"; hot ones are warm too). So every hot particle
  // of every rank is compared with the warm locals near it.
  double const eps = 1e-9 * m_skin;
  double const thr = m_skin - dmax - eps;
  if (!(thr > 0.))
    return true; // some local moved (almost) a skin: rebuild
  // the colloid pair list (marble/Colloids, built with this list) holds the
  // pairs within range + skin of the colloids at the build: it stays valid
  // while no bead and colloid came closer by a skin, d_max + d_colloid < skin
  if (dr[1] >= 0. && !(dmax + dr[1] < m_skin - eps))
    return true;
  if (!(dmax > 0.5 * m_skin))
    return false;
  double const thr2 = thr * thr, hot2 = (0.5 * m_skin - eps) * (0.5 * m_skin - eps);
  // records: x0, x, d, id
  constexpr int R = 8;
  m_fast.clear();
  m_hot.clear();
  float const thr2f = static_cast<float>(thr2 * (1. - 1e-6));
  for (int i = 0; i < n; ++i) {
    if (src[i] > thr2f) {
      double const d2 = (x[i] - x0[i]).norm2();
      double const rec[R] = {x0[i][0], x0[i][1], x0[i][2], x[i][0], x[i][1], x[i][2],
                             std::sqrt(d2), static_cast<double>(ps.id[i])};
      m_fast.insert(m_fast.end(), rec, rec + R);
      if (d2 > hot2)
        m_hot.insert(m_hot.end(), rec, rec + R);
    }
  }
  std::vector<double> gathered;
  if (par)
    gathered = m_comm->allgatherv(m_hot);
  std::vector<double> const &hot = par ? gathered : m_hot;
  long long const n_hot = static_cast<long long>(hot.size() / R);
  if (m_n_global_at_build < 0) // (every rank is here: the decisions above are the same on all)
    m_n_global_at_build = par ? m_comm->sum(static_cast<long long>(n)) : n;
  // more than 1/128 of the particles hot: the test would cost more than it
  // saves (doc/benchmarks.md: the list life against the rate, session 29)
  if (128 * n_hot > m_n_global_at_build)
    return true;
  long long const n_warm = static_cast<long long>(m_fast.size() / R);
  double const cut2 = m_inner_cut * m_inner_cut * (1. + 1e-12);
  double const range2 = m_range * m_range * (1. - 1e-12);
  auto mi2 = [&](double const *a, double const *b) {
    double r2 = 0.;
    for (int d = 0; d < 3; ++d) {
      // (one image shift suffices: positions lie within a few skins of the
      // box and the box is 3 ranges wide, so a pair near half a box length
      // is neither within max_cut nor was within the range)
      double dd = a[d] - b[d];
      double const L = m_box_l[d];
      if (m_box_periodic[d])
        dd = dd > 0.5 * L ? dd - L : (dd < -0.5 * L ? dd + L : dd);
      r2 += dd * dd;
    }
    return r2;
  };
  // hot record h against warm record w: both moved that far, not the same
  // particle, now within max_cut, at the build at least the range apart
  auto missing = [&](double const *h, double const *w) {
    return h[6] + w[6] > m_skin - eps && h[7] != w[7] && mi2(h + 3, w + 3) < cut2 && mi2(h, w) >= range2;
  };
  bool found = false;
  if (n_hot * n_warm <= 256) { // (a few: all against all)
    for (long long a = 0; a < n_hot && !found; ++a)
      for (long long b = 0; b < n_warm && !found; ++b)
        found = missing(hot.data() + R * a, m_fast.data() + R * b);
    return par ? m_comm->any(found) : found;
  }
  // the warm locals in a grid of cells at least max_cut wide over their
  // current positions (about two cells per warm local)
  double const vol = m_box_l[0] * m_box_l[1] * m_box_l[2];
  double const side = std::max(std::cbrt(vol / static_cast<double>(2 * n_warm + 1)), m_inner_cut);
  std::array<int, 3> nc{};
  for (int d = 0; d < 3; ++d)
    nc[d] = static_cast<int>(std::clamp(std::floor(m_box_l[d] / side), 1., 1024.));
  int const n_cells = nc[0] * nc[1] * nc[2];
  auto coord = [&](double v, int d) {
    double const L = m_box_l[d];
    if (m_box_periodic[d])
      v -= L * std::floor(v / L);
    // (clamped: still within one cell of every position closer than a cell)
    return std::clamp(static_cast<int>(std::floor(v / L * nc[d])), 0, nc[d] - 1);
  };
  m_fast_cell.resize(static_cast<std::size_t>(n_warm));
  m_fast_start.assign(static_cast<std::size_t>(n_cells) + 1, 0);
  for (long long a = 0; a < n_warm; ++a) {
    double const *p = m_fast.data() + R * a + 3;
    int const c = (coord(p[2], 2) * nc[1] + coord(p[1], 1)) * nc[0] + coord(p[0], 0);
    m_fast_cell[static_cast<std::size_t>(a)] = c;
    ++m_fast_start[static_cast<std::size_t>(c) + 1];
  }
  for (int c = 0; c < n_cells; ++c)
    m_fast_start[c + 1] += m_fast_start[c];
  // the warm records in cell order, and their displacements apart (the
  // first filter reads these in a row)
  m_fast_sorted.resize(m_fast.size());
  m_fast_dsorted.resize(static_cast<std::size_t>(n_warm));
  m_fast_order.assign(m_fast_start.begin(), m_fast_start.end() - 1); // (fill positions)
  for (long long a = 0; a < n_warm; ++a) {
    int const k = m_fast_order[static_cast<std::size_t>(m_fast_cell[a])]++;
    std::copy_n(m_fast.data() + R * a, R, m_fast_sorted.data() + R * k);
    m_fast_dsorted[static_cast<std::size_t>(k)] = m_fast[R * a + 6];
  }
  double const *const wd = m_fast_dsorted.data();
  double const need = m_skin - eps;
  for (long long a = 0; a < n_hot && !found; ++a) {
    double const *h = hot.data() + R * a;
    // the cells next to the hot particle's along each axis, each once: with
    // fewer than 3 cells along an axis, all of them
    std::array<std::array<int, 3>, 3> near{};
    std::array<int, 3> n_near{};
    for (int d = 0; d < 3; ++d) {
      int const c = coord(h[3 + d], d);
      if (nc[d] < 3) {
        for (int t = 0; t < nc[d]; ++t)
          near[d][n_near[d]++] = t;
        continue;
      }
      for (int t = c - 1; t <= c + 1; ++t)
        if (t >= 0 && t < nc[d])
          near[d][n_near[d]++] = t;
        else if (m_box_periodic[d])
          near[d][n_near[d]++] = (t + nc[d]) % nc[d];
    }
    double const need_w = need - h[6];
    for (int iz = 0; iz < n_near[2] && !found; ++iz)
      for (int iy = 0; iy < n_near[1] && !found; ++iy)
        for (int ix = 0; ix < n_near[0] && !found; ++ix) {
          int const c2 = (near[2][iz] * nc[1] + near[1][iy]) * nc[0] + near[0][ix];
          for (int k = m_fast_start[c2]; k < m_fast_start[c2 + 1] && !found; ++k)
            if (wd[k] > need_w)
              found = missing(h, m_fast_sorted.data() + R * k);
        }
  }
  return par ? m_comm->any(found) : found;
}

} // namespace Marble
