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

#include <array>
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
};

} // namespace Marble
