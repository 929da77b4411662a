#pragma once
// Constraints: planar walls acting on particle types (reference.md section 4).
//
// A wall has a unit normal n and a distance d from the origin; a particle at x
// is at distance z = n.x - d on the fluid side (z < 0 is a penetration and
// stops the run). Per (wall type, particle type) the wall exerts the
// conservative kernels of the InteractionTable evaluated at r = z (e.g. WCA),
// and with TUNABLE_SLIP the tunable-slip kernel (constraints/tunable_slip.hpp;
// Smiatek, Allen, Schmid 2008):
//   F = -gamma_L w(z) (v - v_wall) + sqrt(24 kT gamma_L / dt) sqrt(w(z)) xi,
//   w(z) = 1 - (z - offset)/z_c for offset <= z < offset + z_c (w = 1 below offset),
// where the optional offset moves the friction layer to where the fluid starts
// (the wall repulsion keeps beads at z >~ sigma; the slip-length formula of
// reference.md section 4 assumes a uniform fluid across the layer),
// with noise keyed by (particle id, wall id, counter). Momentum goes to the wall
// (accumulated in total_force for analysis).
#include "box/BoxGeometry.hpp"
#include "constraints/tunable_slip.hpp"
#include "nonbonded/InteractionTable.hpp"
#include "particles/ParticleStore.hpp"
#include "thermostats/NoiseContext.hpp"

#include <cstdint>
#include <vector>

namespace Marble {

struct Wall {
  Utils::Vector3d normal{0., 0., 1.};
  double dist = 0.;
  int type = 0;
  Utils::Vector3d velocity{};
  int id = 0; // stable id: keys the wall's noise
  Utils::Vector3d total_force{};
  double energy = 0.;
};

class Constraints {
  friend struct CheckpointAccess; // io/checkpoint.cpp

public:
  int add_wall(Wall w);
  void remove(int id);
  void clear() { m_walls.clear(); }
  std::vector<Wall> const &walls() const { return m_walls; }
  Wall const *find(int id) const;
  bool empty() const { return m_walls.empty(); }
  /** Types that walls use (their pairs are not in the main Verlet list). */
  std::vector<char> wall_types(int n_types) const;

  /** Add wall forces; throws Utils::RuntimeError on a wall penetration. */
  void add_forces(ParticleStore &ps, BoxGeometry const &box, InteractionTable const &ia,
                  NoiseContext const &noise, std::uint64_t step);
  /** Conservative wall energy of the current configuration. */
  double energy(ParticleStore const &ps, BoxGeometry const &box, InteractionTable const &ia) const;

private:
  std::vector<Wall> m_walls;
  int m_next_id = 0;
};

} // namespace Marble
