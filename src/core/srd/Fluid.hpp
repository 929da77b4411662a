#pragma once
// Stochastic rotation dynamics (SRD / MPCD) solvent of point particles
// (reference.md section 6, seed 003 = Padding et al. 2005, doc/srd.md).
//
// The SRD particles live in their own structure of arrays, not in the
// ParticleStore: they have no pair interactions, move ballistically, and must
// stay out of the Verlet lists, the skin check and the force machinery. The
// MD particles (colloids, walls, their potentials) are integrated by the
// ordinary integrators of the same System; the SRD particles are streamed
// once per MD step (System::run_md calls md_step() after the drift) and
// collide every tau = n_tau * time_step.
//
// Noise is counter based (utils/noise.hpp): the grid shift is keyed by
// (seed, collision index), the rotation axis and the thermostat by
// (seed, collision index, global cell index), the Andersen velocities and the
// stochastic boundary by (seed, counter, particle id). A collision therefore
// does not depend on the loop order or on how the particles are stored.
#include "nonbonded/InteractionTable.hpp"
#include "srd/boundary_kernel.hpp"
#include "utils/Vector.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace Marble {

class System;
class BoxGeometry;
class ParticleStore;

namespace Srd {

enum class CollisionRule { srd, at };

struct Params {
  double cell_size = 1.;
  double tau = 0.1;   // collision interval (a multiple of the MD time step)
  double angle = 0.;  // rotation angle alpha in radians (rule srd)
  double kT = 1.;     // temperature of the thermostat, AT and stochastic walls
  double mass = 1.;   // mass of one SRD particle
  std::uint64_t seed = 0;
  bool shift = true;             // random grid shift (Galilean invariance)
  CollisionRule rule = CollisionRule::srd;
  bool thermostat = false;       // cell-level Maxwell-Boltzmann scaling
  bool conserve_angular = false; // AT+a: angular momentum conserving (rule at)
  // Channel walls: planes at x[wall_axis] = 0 (velocity wall_v_lo) and = L
  // (wall_v_hi) confine the SRD particles (-1: none). Collision cells are not
  // wrapped across them.
  int wall_axis = -1;
  int wall_rule = 0; // a BoundaryRule value
  Utils::Vector3d wall_v_lo{}, wall_v_hi{};
  // positions of the two planes along wall_axis (wall_hi < 0: the box
  // length); the SRD particles live in [wall_lo, wall_hi)
  double wall_lo = 0., wall_hi = -1.;
};

/** Boundary of colloid type c for SRD type s: a hard sphere of radius
 * (the srd_boundary kernel of the interaction table). */
using BoundaryParams = SRDBoundary::Params;

/** Reverse Poiseuille drive (viscosity measurement): acceleration +g along
 * flow_dir for particles with x[grad_dir] < L/2, -g above. */
struct Drive {
  bool on = false;
  int flow_dir = 0, grad_dir = 2;
  double g = 0.;
  Utils::Vector3d accel{}; // uniform acceleration of every SRD particle (drag method)
};

/** One axis of a rank's local collision-cell grid (collide.cpp): mode 0 the
 * whole periodic axis (local = global coordinate), 1 a split periodic axis
 * (local = raw index - off, raw = floor((x - shift)/a0)), 2 a wall axis
 * (local = clamp(raw + 1) - off); ext cells. */
struct AxisMap {
  int mode = 0, off = 0, ext = 0;
};

class Fluid {
public:
  static constexpr int max_type = 256;

  // SRD particles (folded positions)
  std::vector<Utils::Vector3d> pos, v;
  std::vector<int> id, type;

  explicit Fluid(Params const &p) : m_p(p) {}
  Params const &params() const { return m_p; }
  /** Number of MD steps per collision (set by check_time_step). */
  int steps_per_collision() const { return m_n_tau; }
  std::uint64_t n_collisions() const { return m_n_collisions; }
  std::uint64_t n_streams() const { return m_n_streams; }
  /** Checkpoint restore: the collision and streaming counters. */
  void set_counters(std::uint64_t collisions, std::uint64_t streams) {
    m_n_collisions = collisions, m_n_streams = streams;
    m_hit.clear(); // its stamps are streaming counts (collide.cpp)
  }
  int size() const { return static_cast<int>(pos.size()); }

  /** Throws std::invalid_argument unless tau is a multiple of @p dt and
   * cell_size divides the box; stores the number of steps per collision. */
  void check_geometry(BoxGeometry const &box, double dt);
  /** The planes of the channel walls along wall_axis for box length @p La. */
  double wall_lo() const { return m_p.wall_lo; }
  double wall_hi(double La) const { return m_p.wall_hi < 0. ? La : m_p.wall_hi; }
  /** Number of collision cells per axis. */
  Utils::Vector3i grid() const { return m_grid; }
  /** Ids of the SRD types. */
  bool is_srd_type(int t) const;

  /** Append @p n particles of type @p t, uniform in the box outside the
   * colloids, Maxwellian velocities at kT (zero total momentum of the new
   * ones); keyed by @p seed. */
  void add_particles(System const &s, int n, int t, double kT, std::uint64_t seed);

  // --- boundaries (colloid type c, SRD type s) ---
  /** The srd_boundary kernel of types (c, s) in the System's interaction
   * table (attached by prepare(), stream() and relocate_overlapping()). */
  BoundaryParams boundary(int c, int s) const;
  bool any_boundary() const;

  /** Before a run: geometry checks, colloids able to take torque, and SRD
   * particles found inside a colloid are moved out (returns how many). */
  int prepare(System &s);
  /** Move SRD particles found inside a colloid to random free places
   * (keyed by seed, step, id); returns how many were moved. */
  int move_out(System &s);
  /** One MD step: stream by time_step (bouncing off colloids, handing the
   * impulses to them) and collide when due. Called after the MD drift. */
  void md_step(System &s);
  /** One collision at the current state (grid shift, rotation/AT, thermostat).
   * Collective: migrates the SRD particles to the ranks owning their
   * positions, cells straddling domain faces are reduced over the ranks. */
  void collide(System &s);
  /** Send every SRD particle to the rank whose domain holds it. Collective. */
  void migrate(System &s);
  /** This rank's domain as [lo, hi) per axis (+-infinity along an axis not
   * split between ranks): a position is this rank's (CellSystem::owner_rank)
   * iff it lies inside, bit for bit. */
  std::array<std::pair<double, double>, 3> domain_box(System &s) const;
  /** Number of SRD particles on all ranks. Collective. */
  long long global_size(System const &s) const;
  /** Forget the cell index of the last collision (after particles were
   * added, moved or given new velocities outside a run): the colloids then
   * search all SRD particles until the next collision. */
  void invalidate_index() { m_index_valid = false; }

  Drive drive;

  /** Sum of momentum exchanged with colloids (diagnostics; the same on every rank). */
  Utils::Vector3d momentum_to_colloids{};
  /** Momentum handed to the lower / upper channel wall (wall stress): this
   * rank's share, sum over the ranks for the total. */
  Utils::Vector3d momentum_to_wall_lo{}, momentum_to_wall_hi{};

private:
  void stream(System &s, double dt);
  void walls(std::uint64_t step, double dt, Utils::Vector3d const &L);
  int relocate_overlapping(System &s, std::uint64_t key);
  /** Append the indices of the particles that may lie within @p r of @p R
   * (needs the cell index of the last collision). */
  void near(Utils::Vector3d R, double r, Utils::Vector3d const &L, std::vector<int> &out) const;
  Params m_p;
  int m_n_tau = 0;
  Utils::Vector3i m_grid{};
  std::uint64_t m_n_collisions = 0;
  std::uint64_t m_n_streams = 0;
  InteractionTable const *m_ia = nullptr; // the System's interaction table
  // collision scratch
  std::vector<int> m_cell, m_count, m_start, m_id2, m_t2, m_slot;
  std::vector<Utils::Vector3d> m_p2, m_v2, m_xi, m_r;
  // parallel collision scratch (collide.cpp), kept between collisions (no
  // allocations per collision once the sizes settled): per axis of the local
  // grid the global coordinate of each local one, and the node coordinates
  // (domain slabs) a cell of that coordinate overlaps (CSR: lst[beg[l],
  // beg[l + 1])), whether this rank's is among them and whether there are
  // several; the shared cells (global, local index) and per rank the slots
  // shared with it; the cell sums of the shared cells; the message buffers
  struct ParallelScratch {
    std::array<std::vector<int>, 3> glob, beg, lst;
    std::array<std::vector<char>, 3> mine, multi;
    std::vector<std::pair<int, int>> found;
    std::vector<int> shared, shared_g; // local and global index
    std::array<std::vector<double>, 3> axis; // rotation axes of the shared cells
    std::vector<std::vector<int>> peer_cells;
    std::vector<double> bufA, bufB;
    std::vector<std::vector<char>> send, recv;
  } m_par;
  // colloid search (stream): the particles are in the cell order of the
  // last collision (m_count: cell starts); m_disp bounds how far any
  // particle moved since, m_vmax the speeds; particles bounced off a colloid
  // since then (m_loose) are checked one by one
  bool m_index_valid = false;
  Utils::Vector3d m_index_shift{};
  Utils::Vector3i m_index_dim{}; // the local grid's extent
  std::array<AxisMap, 3> m_index_axes{};
  double m_disp = 0., m_vmax = 0.;
  std::vector<std::uint64_t> m_hit;
  std::vector<int> m_loose;
  std::vector<char> m_is_loose;
  // walled channel with colloids: per particle its index in the step's list
  // of flights that hit a wall, -1 if none (stream)
  std::vector<int> m_wslot;
  // the particles that left this rank's domain (ascending index), listed by
  // the streaming step just before a collision (m_leave_valid), used and
  // cleared by the migration of that collision
  std::vector<int> m_leave;
  bool m_leave_valid = false;
};

} // namespace Srd
} // namespace Marble
