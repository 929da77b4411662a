#pragma once
// Structure-of-arrays particle storage. Indices [0, n_local) are the particles
// this process owns; [n_local, size) are ghosts: periodic images (and, with
// MPI, copies of a neighbour's particles) that exist only for the pair loop.
// Local order is rebuilt by the cell system (sorted by cell for locality), so
// particles are addressed by id through index_of().
#include "config/features.hpp"
#include "utils/Vector.hpp"

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

namespace Marble {

struct ParticleProperties {
  int id = -1;
  int type = 0;
  Utils::Vector3d pos{};
  Utils::Vector3d v{};
  Utils::Vector3i image{};
  double mass = 1.;
  bool rotation = false;
  double rinertia = 1.;
  Utils::Vector3d omega{};
  Utils::Vector3d ext_force{};
  Utils::Vector3d ext_torque{};
  std::uint8_t fix = 0; // bit d set: coordinate d is fixed
  /** Langevin / Brownian friction of this particle; < 0: the thermostat's global value. */
  double gamma = -1.;
  double gamma_rot = -1.;
};

/** A copy of another rank's particle, sent at a rebuild (cells/CellSystem.cpp). */
struct GhostRecord {
  int id = -1, type = 0;
  Utils::Vector3d pos{}, v{}, omega{};
  double mass = 1., rinertia = 1.;
  std::uint8_t rotation = 0;
  /** Lees-Edwards: the image's shift along the shear-plane normal, in box
   * lengths (CellSystem::make_le_ghosts; |k| <= 16); 0 otherwise. */
  std::int8_t le_k = 0;
};

/** Ghost owner markers for copies of other ranks' particles. */
constexpr int kRemoteGhost = -1;         // ordinary particle of another rank
constexpr int kRemoteColloidGhost = -2;  // large particle (colloid) of another rank

class ParticleStore {
public:
  // Per-particle data (locals and ghosts).
  std::vector<int> id, type;
  std::vector<Utils::Vector3d> pos, v, f;
#ifdef MASS
  std::vector<double> mass;
#endif
#ifdef ROTATION
  std::vector<Utils::Vector3d> omega, torque;
  std::vector<double> rinertia;
  std::vector<std::uint8_t> rotation;
#endif
  // Local-only data (indices < n_local).
  std::vector<Utils::Vector3i> image;
  std::vector<Utils::Vector3d> pos_at_rebuild;
#ifdef EXTERNAL_FORCE
  std::vector<Utils::Vector3d> ext_force, ext_torque;
  std::vector<std::uint8_t> fix;
#endif
  // Per-particle Langevin/Brownian friction (< 0: the global value); always compiled in.
  std::vector<double> gamma, gamma_rot;
  // Ghost-only data, indexed by (ghost index - n_local).
  std::vector<int> ghost_owner;
  std::vector<Utils::Vector3d> ghost_shift;

  int n_local() const { return m_n_local; }
  int size() const { return static_cast<int>(id.size()); }
  int n_ghost() const { return size() - m_n_local; }

  double get_mass(int i) const {
#ifdef MASS
    return mass[i];
#else
    (void)i;
    return 1.;
#endif
  }

  /** Coordinate @p d of local particle @p i is fixed (EXTERNAL_FORCE's fix flags). */
  bool is_fixed(int i, int d) const {
#ifdef EXTERNAL_FORCE
    return (fix[i] >> d) & 1;
#else
    (void)i, (void)d;
    return false;
#endif
  }

  /** Some coordinate of local particle @p i is fixed. */
  bool has_fixed(int i) const {
#ifdef EXTERNAL_FORCE
    return fix[i] != 0;
#else
    (void)i;
    return false;
#endif
  }

  /** Local index of particle @p pid, or -1. */
  int index_of(int pid) const {
    return (pid >= 0 && pid < static_cast<int>(m_index.size())) ? m_index[pid] : -1;
  }
  bool exists(int pid) const { return index_of(pid) >= 0; }
  int max_id() const { return static_cast<int>(m_index.size()) - 1; }
  /** Ids of all local particles in ascending order. */
  std::vector<int> ids_sorted() const;

  /** Append a local particle (ghosts must have been cleared). */
  void add(ParticleProperties const &p);
  /** Remove a local particle by id (ghosts must have been cleared). */
  void remove(int pid);
  void clear();
  ParticleProperties get(int pid) const;

  /** Drop all ghosts. */
  void clear_ghosts();
  /** Append a ghost image of local @p owner shifted by @p shift. */
  void add_ghost(int owner, Utils::Vector3d const &shift);
  /** Append a copy of another rank's particle (owner marker kRemoteGhost or kRemoteColloidGhost). */
  void add_remote_ghost(GhostRecord const &r, int marker);
  /** The record another rank needs to make a ghost of local @p i at +@p shift. */
  GhostRecord ghost_record(int i, Utils::Vector3d const &shift) const;
  /** Reorder locals by @p order (new position k holds old order[k]). With
   * @p skip_pos_at_rebuild, pos_at_rebuild is left as it is (no longer
   * matching the locals: the caller overwrites it). */
  void permute_locals(std::vector<int> const &order, bool skip_pos_at_rebuild = false);

private:
  void append_ghost(GhostRecord const &r, int owner, Utils::Vector3d const &shift);
  template <typename F> void for_each_array(F &&f);
  template <typename F> void for_each_local_array(F &&f);
  int m_n_local = 0;
  std::vector<int> m_index; // id -> local index, -1 if absent
  // permute_locals' gather buffers, one per element type: an array is gathered
  // into the spare of its type, which then swaps with it (kept between calls:
  // no allocation, hence no fresh pages, and no copy back per rebuild)
  std::tuple<std::vector<int>, std::vector<double>, std::vector<std::uint8_t>,
             std::vector<Utils::Vector3d>, std::vector<Utils::Vector3i>>
      m_permute_spare;
};

} // namespace Marble
