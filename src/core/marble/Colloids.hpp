#pragma once
// Large particles (marble colloids) and their pair interactions.
//
// A particle type that is the first type of an active colloid-surface kernel
// (non_bonded_inter[c, s].marble) is a "colloid type". All pairs involving a
// colloid are found by a search over the solvent's cell grid around each
// colloid (and its periodic images) within range + skin, so colloids never
// enlarge the solvent's cells; the main Verlet list skips these pairs
// (InteractionTable large types). This pair list serves the colloid's pair
// kernels (e.g. the LJ excluded volume with offset, DPD; forces/pair_force.hpp)
// and the marble surface coupling.
#include "box/BoxGeometry.hpp"
#include "cells/CellSystem.hpp"
#include "marble/marble_kernel.hpp"
#include "nonbonded/InteractionTable.hpp"
#include "particles/ParticleStore.hpp"
#include "thermostats/NoiseContext.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace Marble {

class Colloids {
public:
  /** The colloid types (InteractionTable::colloid_types()). */
  void set_types(std::vector<char> const &is_colloid);
  bool is_colloid_type(int t) const { return t < static_cast<int>(m_is_colloid.size()) && m_is_colloid[t]; }
  std::vector<char> const &colloid_types() const { return m_is_colloid; }
  bool any() const { return m_any; }

  /** Rebuild the colloid pair list; call right after the cell system's rebuild. */
  void rebuild(ParticleStore const &ps, BoxGeometry const &box, CellSystem const &cells,
               InteractionTable const &ia);
  /** Add all colloid pair forces and torques to locals (@p with_marble false:
   * without the marble coupling, which the Shardlow sweep then updates). */
  void add_forces(ParticleStore &ps, InteractionTable const &ia, NoiseContext const &noise,
                  bool with_conservative = true, bool with_marble = true) const;
  /** Shardlow: the exact pair update of the marble coupling's friction and
   * noise over @p dt, pair by pair in list order. Velocities and spins of the
   * pairs' particles change (on several ranks also those of the other ranks'
   * colloid copies: integrators/shardlow.cpp sends the changes to the
   * owners); nothing else. @p fixed (several ranks): per list index, whether
   * the colloid has a fixed coordinate (copies included); null: the locals'
   * own flags, a copy counting as free (one rank, where every pair's colloid
   * is a local, or no colloid fixed on any rank). */
  void shardlow_marble_sweep(ParticleStore &ps, InteractionTable const &ia, NoiseContext const &noise,
                             double kT, double dt, std::vector<char> const *fixed = nullptr) const;
  /** RESPA's fast forces: only the conservative pair kernels of the colloid
   * pairs, added to @p f (indexed like ps, at least ps.size() long). */
  void add_conservative_forces(ParticleStore const &ps, InteractionTable const &ia,
                               std::vector<Utils::Vector3d> &f) const;
  /** Energy per type pair (n_types^2, upper triangle) and virial tensor of
   * the conservative colloid pair forces; adds to @p energy / @p virial. */
  void conservative(ParticleStore const &ps, InteractionTable const &ia,
                    std::vector<double> &energy, std::array<double, 9> &virial) const;
  /** Virial tensors sum d (x) F of the colloid pairs' dissipative pair kernels
   * (DPD) and of the marble coupling, with the current velocities and the
   * noise of @p noise (d = r_partner - r_colloid, F on the partner); adds. */
  void dissipative_virial(ParticleStore const &ps, InteractionTable const &ia, NoiseContext const &noise,
                          std::array<double, 9> &dpd, std::array<double, 9> &marble) const;
  /** Empty if fine, else a message naming a colloid that cannot take torque. */
  std::string check_rotation(ParticleStore const &ps, InteractionTable const &ia) const;
  std::size_t n_pairs() const { return m_pairs.size(); }
  /** The local indices of every particle of a colloid pair (colloids and
   * partners) and of every local colloid, ascending, as of the last rebuild:
   * outside them the colloid pairs' forces are zero, also after the ghosts'
   * forces came back (RESPA's substeps need only these). */
  std::vector<int> const &pair_members() const { return m_members; }
  /** The other ranks' colloid copies (ghost indices) in a colloid pair, ascending,
   * as of the last rebuild: the only ghosts the pairs' forces act on. */
  std::vector<int> const &pair_copies() const { return m_copies; }

private:
  void find_pairs(ParticleStore const &ps, BoxGeometry const &box, CellSystem const &cells,
                  InteractionTable const &ia);
  template <class Fn>
  void for_each_pair_force(ParticleStore const &ps, InteractionTable const &ia, NoiseContext const &noise,
                           Fn &&fn, bool with_marble = true) const;
  struct Pair {
    int colloid, other;
    Utils::Vector3d shift; // image of the colloid: pos[colloid] + shift
  };
  bool m_any = false;
  std::vector<char> m_is_colloid;
  std::vector<Pair> m_pairs;
  std::vector<int> m_members;
  std::vector<int> m_copies;
};

} // namespace Marble
