#include "cells/CellSystem.hpp"

#include <algorithm>
#include <cmath>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace Marble {

using Utils::Vector3d;

namespace {

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

} // namespace

// Cells are at least `range` wide, so all partners of a local are in the 27
// cells around it.
CellSystem::Grid::Grid(BoxGeometry const &box, double range) {
  for (int d = 0; d < 3; ++d) {
    n[d] = range > 0. ? std::max(1, static_cast<int>(box.length()[d] / range)) : 1;
    n[d] = std::min(n[d], 256); // bounded memory for tiny cutoffs
    size[d] = box.length()[d] / n[d];
    ext[d] = n[d] + 2;
  }
}

void CellSystem::sort_locals(ParticleStore &ps, BoxGeometry const &box) {
  int const n = ps.n_local();
  for (int i = 0; i < n; ++i)
    box.fold(ps.pos[i], ps.image[i]);
  if (m_range <= 0.)
    return;
  Grid const g(box, m_range);
  std::vector<int> cell(n), count(g.n_total() + 1, 0);
  for (int i = 0; i < n; ++i) {
    cell[i] = g.index(ps.pos[i]);
    ++count[cell[i] + 1];
  }
  for (int c = 0; c < g.n_total(); ++c)
    count[c + 1] += count[c];
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i)
    order[count[cell[i]]++] = i;
  bool sorted = true;
  for (int i = 0; i < n && sorted; ++i)
    sorted = order[i] == i;
  if (!sorted)
    ps.permute_locals(order);
}

void CellSystem::make_ghosts(ParticleStore &ps, BoxGeometry const &box) const {
  ps.clear_ghosts();
  if (m_range <= 0.)
    return;
  int const n = ps.n_local();
  std::array<int, 3> nimg{};
  for (int d = 0; d < 3; ++d)
    nimg[d] = box.periodic(d) ? static_cast<int>(std::ceil(m_range / box.length()[d])) : 0;
  auto const &L = box.length();
  // Only images with a positive shift: the pair list never uses the others
  // (build_pairs keeps the local-ghost pair whose ghost shift is positive), so
  // creating them would only cost ghost updates and force reductions.
  std::vector<Vector3d> shifts;
  for (int sx = -nimg[0]; sx <= nimg[0]; ++sx)
    for (int sy = -nimg[1]; sy <= nimg[1]; ++sy)
      for (int sz = -nimg[2]; sz <= nimg[2]; ++sz) {
        Vector3d const sh{sx * L[0], sy * L[1], sz * L[2]};
        if (shift_positive(sh))
          shifts.push_back(sh);
      }
  for (int i = 0; i < n; ++i) {
    Vector3d const p = ps.pos[i];
    for (auto const &sh : shifts) {
      Vector3d const q = p + sh;
      if (q[0] < -m_range || q[0] >= L[0] + m_range || q[1] < -m_range || q[1] >= L[1] + m_range ||
          q[2] < -m_range || q[2] >= L[2] + m_range)
        continue;
      ps.add_ghost(i, sh);
    }
  }
}

// The list order (and so the force summation order) is: locals i ascending;
// for each, the 27 neighbour cells in (dz, dy, dx) order; in each cell its
// locals ascending, then its ghosts ascending. Since locals are sorted by cell,
// a neighbour cell below i's cell holds only locals < i, and in i's own cell
// the locals > i follow i directly: whole ranges are skipped instead of
// testing j > i per candidate. Candidates are read from a cell-ordered copy of
// the positions and appended without a branch.
void CellSystem::build_pairs(ParticleStore const &ps, BoxGeometry const &box) {
  m_pairs.clear();
  m_cell_start.clear();
  m_cell_members.clear();
  if (m_range <= 0.)
    return;
  m_grid = Grid(box, m_range);
  Grid const &g = m_grid;
  m_n_cells = g.n;
  int const n_all = ps.size(), n_local = ps.n_local();
  int const n_cells = g.n_total();
  m_n_local_at_build = n_local;
  std::vector<int> cell(n_all);
  auto &start = m_cell_start;
  auto &members = m_cell_members;
  start.assign(n_cells + 1, 0);
  members.resize(n_all);
  for (int i = 0; i < n_all; ++i) {
    cell[i] = g.index(ps.pos[i]);
    ++start[cell[i] + 1];
  }
  for (int c = 0; c < n_cells; ++c)
    start[c + 1] += start[c];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n_local; ++i)
    members[fill[cell[i]]++] = i;
  std::vector<int> ghost_begin(fill); // locals of cell c: [start[c], ghost_begin[c])
  for (int i = n_local; i < n_all; ++i)
    members[fill[cell[i]]++] = i;
  // Cell-ordered coordinates, one array per axis: contiguous reads below.
  std::vector<double> mx(n_all + 1), my(n_all + 1), mz(n_all + 1);
  for (int k = 0; k < n_all; ++k) {
    auto const &p = ps.pos[members[k]];
    mx[k] = p[0];
    my[k] = p[1];
    mz[k] = p[2];
  }

  double const range2 = m_range * m_range;
  std::array<int, 27> offsets{};
  {
    int const sy = g.ext[0], sz = g.ext[0] * g.ext[1];
    int q = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          offsets[q++] = dx + dy * sy + dz * sz;
  }
  // For each cell holding locals, the candidate ranges of `members` in list
  // order, merged where contiguous (the three cells of a stencil row are
  // adjacent in memory). kSelf marks the range that starts after i itself.
  constexpr int kSelf = -1;
  std::vector<std::array<int, 2>> ranges;
  ranges.reserve(27);
  std::size_t n_pairs = 0;
  m_pairs.resize(std::max<std::size_t>(1024, static_cast<std::size_t>(n_local) * 24));
  for (int i_begin = 0; i_begin < n_local;) {
    int const ci = cell[i_begin];
    int i_end = i_begin;
    while (i_end < n_local && cell[i_end] == ci)
      ++i_end;
    ranges.clear();
    for (int const off : offsets) {
      int const cj = ci + off;
      if (cj < 0 || cj >= n_cells)
        continue;
      int const k0 = cj < ci ? ghost_begin[cj] : (cj == ci ? kSelf : start[cj]);
      int const k1 = start[cj + 1];
      if (k0 != kSelf && k1 <= k0)
        continue;
      if (!ranges.empty() && k0 != kSelf && ranges.back()[1] == k0)
        ranges.back()[1] = k1;
      else
        ranges.push_back({k0, k1});
    }
    std::size_t max_cand = 0;
    for (auto const &r : ranges)
      max_cand += static_cast<std::size_t>(r[1] - (r[0] == kSelf ? start[ci] : r[0]));
    for (int i = i_begin; i < i_end; ++i) {
      if (m_pairs.size() < n_pairs + max_cand)
        m_pairs.resize(2 * m_pairs.size() + max_cand);
      auto *const out = m_pairs.data();
      Vector3d const pi = ps.pos[i];
      int const self_k = start[ci] + (i - i_begin); // i's slot in its cell
#ifdef __SSE2__
      __m128d const px = _mm_set1_pd(pi[0]), py = _mm_set1_pd(pi[1]), pz = _mm_set1_pd(pi[2]);
      __m128d const r2v = _mm_set1_pd(range2);
#endif
      for (auto const &r : ranges) {
        int k = r[0] == kSelf ? self_k + 1 : r[0];
        int const k1 = r[1];
#ifdef __SSE2__
        // two candidates at a time (same arithmetic as the scalar test)
        for (; k + 1 < k1; k += 2) {
          __m128d const dx = _mm_sub_pd(px, _mm_loadu_pd(mx.data() + k));
          __m128d const dy = _mm_sub_pd(py, _mm_loadu_pd(my.data() + k));
          __m128d const dz = _mm_sub_pd(pz, _mm_loadu_pd(mz.data() + k));
          __m128d const d2 =
              _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
          int const mask = _mm_movemask_pd(_mm_cmplt_pd(d2, r2v));
          out[n_pairs] = {i, members[k]};
          n_pairs += static_cast<std::size_t>(mask & 1);
          out[n_pairs] = {i, members[k + 1]};
          n_pairs += static_cast<std::size_t>(mask >> 1);
        }
#endif
        for (; k < k1; ++k) {
          double const dx = pi[0] - mx[k], dy = pi[1] - my[k], dz = pi[2] - mz[k];
          out[n_pairs] = {i, members[k]};
          n_pairs += (dx * dx + dy * dy + dz * dz < range2) ? 1 : 0;
        }
      }
    }
    i_begin = i_end;
  }
  m_pairs.resize(n_pairs);
}

void CellSystem::rebuild(ParticleStore &ps, BoxGeometry const &box, double max_cut) {
  ps.clear_ghosts();
  m_range = max_cut > 0. ? max_cut + m_skin : 0.;
  sort_locals(ps, box);
  for (int i = 0; i < ps.n_local(); ++i)
    ps.pos_at_rebuild[i] = ps.pos[i];
  make_ghosts(ps, box);
  build_pairs(ps, box);
  m_valid = true;
  ++m_n_rebuilds;
}

void CellSystem::update_ghosts(ParticleStore &ps) const {
  int const n_local = ps.n_local();
  for (int g = n_local; g < ps.size(); ++g) {
    int const o = ps.ghost_owner[g - n_local];
    ps.pos[g] = ps.pos[o] + ps.ghost_shift[g - n_local];
    ps.v[g] = ps.v[o];
#ifdef ROTATION
    ps.omega[g] = ps.omega[o];
#endif
  }
}

void CellSystem::reduce_ghost_forces(ParticleStore &ps) const {
  int const n_local = ps.n_local();
  for (int g = n_local; g < ps.size(); ++g) {
    int const o = ps.ghost_owner[g - n_local];
    ps.f[o] += ps.f[g];
#ifdef ROTATION
    ps.torque[o] += ps.torque[g];
#endif
  }
}

bool CellSystem::displacement_exceeds_half_skin(ParticleStore const &ps) const {
  double const lim2 = 0.25 * m_skin * m_skin;
  for (int i = 0; i < ps.n_local(); ++i)
    if ((ps.pos[i] - ps.pos_at_rebuild[i]).norm2() > lim2)
      return true;
  return false;
}

} // namespace Marble
