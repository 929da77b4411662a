#pragma once
// Cell grid + Verlet lists with a skin and a ghost layer.
//
// On rebuild: locals are folded into the box and sorted by cell; every local
// whose periodic image lies within `range` = max_cut + skin of the box gets a
// ghost copy there; the Verlet list holds each interacting pair once:
//   local-local pairs with i < j, and local-ghost pairs whose ghost shift is
//   lexicographically positive (the image with the opposite shift is dropped).
// Between rebuilds only the ghosts' positions/velocities are refreshed.
#include "box/BoxGeometry.hpp"
#include "particles/ParticleStore.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace Marble {

class CellSystem {
public:
  double skin() const { return m_skin; }
  void set_skin(double s) {
    m_skin = s;
    m_valid = false;
  }
  double range() const { return m_range; }
  bool valid() const { return m_valid; }
  void invalidate() { m_valid = false; }

  /** Fold, sort, make ghosts, build the pair list for pair range @p max_cut. */
  void rebuild(ParticleStore &ps, BoxGeometry const &box, double max_cut);
  /** Copy positions (+ shift), velocities and omega from owners to ghosts. */
  void update_ghosts(ParticleStore &ps) const;
  /** Add ghost forces (and torques) to their owners. */
  void reduce_ghost_forces(ParticleStore &ps) const;
  /** True if some local moved more than skin/2 since the last rebuild. */
  bool displacement_exceeds_half_skin(ParticleStore const &ps) const;

  std::vector<std::array<int, 2>> const &pairs() const { return m_pairs; }

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
  }

  /** Regular grid over the box plus one layer of ghost cells on each side. */
  struct Grid {
    std::array<int, 3> n{1, 1, 1}, ext{3, 3, 3};
    Utils::Vector3d size{1., 1., 1.};
    Grid() = default;
    Grid(BoxGeometry const &box, double range);
    int coord(double x, int d) const {
      double const c = std::floor(x / size[d]) + 1.;
      return static_cast<int>(std::clamp(c, 0., static_cast<double>(ext[d] - 1)));
    }
    int index(Utils::Vector3d const &p) const {
      return (coord(p[2], 2) * ext[1] + coord(p[1], 1)) * ext[0] + coord(p[0], 0);
    }
    int n_total() const { return ext[0] * ext[1] * ext[2]; }
  };
  std::array<int, 3> const &n_cells() const { return m_n_cells; }
  long n_rebuilds() const { return m_n_rebuilds; }

private:
  void make_ghosts(ParticleStore &ps, BoxGeometry const &box) const;
  void sort_locals(ParticleStore &ps, BoxGeometry const &box);
  void build_pairs(ParticleStore const &ps, BoxGeometry const &box);

  double m_skin = 0.4;
  double m_range = 0.;
  bool m_valid = false;
  long m_n_rebuilds = 0;
  std::array<int, 3> m_n_cells{1, 1, 1};
  std::vector<std::array<int, 2>> m_pairs;
  Grid m_grid;
  std::vector<int> m_cell_start, m_cell_members; // all particles (locals + ghosts) by cell
  int m_n_local_at_build = 0;
};

} // namespace Marble
