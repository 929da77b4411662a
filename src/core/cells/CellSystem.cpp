#include "cells/CellSystem.hpp"

#include <algorithm>
#include <cmath>

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
  for (int i = 0; i < n; ++i) {
    Vector3d const p = ps.pos[i];
    for (int sx = -nimg[0]; sx <= nimg[0]; ++sx) {
      double const x = p[0] + sx * L[0];
      if (x < -m_range || x >= L[0] + m_range)
        continue;
      for (int sy = -nimg[1]; sy <= nimg[1]; ++sy) {
        double const y = p[1] + sy * L[1];
        if (y < -m_range || y >= L[1] + m_range)
          continue;
        for (int sz = -nimg[2]; sz <= nimg[2]; ++sz) {
          if (sx == 0 && sy == 0 && sz == 0)
            continue;
          double const z = p[2] + sz * L[2];
          if (z < -m_range || z >= L[2] + m_range)
            continue;
          ps.add_ghost(i, {sx * L[0], sy * L[1], sz * L[2]});
        }
      }
    }
  }
}

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
  m_n_local_at_build = n_local;
  std::vector<int> cell(n_all);
  auto &start = m_cell_start;
  auto &members = m_cell_members;
  start.assign(g.n_total() + 1, 0);
  members.resize(n_all);
  for (int i = 0; i < n_all; ++i) {
    cell[i] = g.index(ps.pos[i]);
    ++start[cell[i] + 1];
  }
  for (int c = 0; c < g.n_total(); ++c)
    start[c + 1] += start[c];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int i = 0; i < n_all; ++i)
      members[fill[cell[i]]++] = i;
  }
  double const range2 = m_range * m_range;
  m_pairs.reserve(static_cast<std::size_t>(n_local) * 24);
  int const sx = 1, sy = g.ext[0], sz = g.ext[0] * g.ext[1];
  for (int i = 0; i < n_local; ++i) {
    int const ci = cell[i];
    Vector3d const pi = ps.pos[i];
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int const cj = ci + dx * sx + dy * sy + dz * sz;
          if (cj < 0 || cj >= g.n_total())
            continue;
          for (int k = start[cj]; k < start[cj + 1]; ++k) {
            int const j = members[k];
            if (j < n_local) {
              if (j <= i)
                continue;
            } else if (!shift_positive(ps.ghost_shift[j - n_local])) {
              continue;
            }
            if ((pi - ps.pos[j]).norm2() < range2)
              m_pairs.push_back({i, j});
          }
        }
  }
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
