#pragma once
// Checkpoints of the whole core state, bit for bit (doc/io.md).
//
// A blob is  magic (8 bytes) | format version (u32) | payload size (u64) |
// CRC-32 of the payload (u32) | payload.  The System payload starts with the
// build's feature list and a layout signature (sizes of the parameter structs,
// which are stored as raw bytes), then the global state (box, time step, time,
// step counter, integrator, thermostat, interaction table, colloid couplings,
// walls, force/list validity, the requested large-range types of the cell
// system) and one particle block per MPI rank, in rank
// order: every local particle with every property, in the stored (cell-sorted)
// order, including the forces/torques of the last step and pos_at_rebuild.
//
// Loading validates the whole blob (size, magic, version, checksum, features,
// layout, rank count, internal consistency) before anything is changed: a bad
// blob throws Utils::RuntimeError and leaves the System untouched. After a
// load the Verlet and colloid pair lists are rebuilt at the saved positions
// (System::rebuild_lists_at_saved_positions) and the saved forces are kept, so
// the continued run is bit-identical to an uninterrupted one.
#include "system/System.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace Marble {

struct CheckpointAccess;

namespace Checkpoint {

// 2: interactions by kernel field lists; 3: Langevin/Brownian thermostats,
// per-particle gamma; 4: the requested large-range types of the cell system
// (cell_system.large_range_types); 5: the integrator's RESPA substeps; 6: the
// domain planes (cell_system.domain_cuts); 7: the automatic load balance
// (set_load_balance) and its count of balances; 8: the Verlet list check
// (cell_system.list_check). Blobs of version 3 still load (as "auto"; 3 and 4
// with substeps = 1; before 6 equal domains, before 7 no automatic balance,
// before 8 the half-skin check their writer had).
inline constexpr std::uint32_t format_version = 8;
inline constexpr std::uint32_t oldest_readable_version = 3;

/** CRC-32 (IEEE 802.3, as zlib.crc32) of @p n bytes. */
std::uint32_t crc32(char const *data, std::size_t n, std::uint32_t crc = 0);

/** The System's whole core state. Collective: every rank's particles are
 * gathered, every rank returns the same blob. Does not change the System. */
std::vector<char> save_system(System const &system);

/** Restore @p blob into @p system. Collective; the number of ranks must be the
 * one the blob was written with (each rank takes its own block). Throws
 * Utils::RuntimeError for a truncated/corrupt blob, another build's blob or
 * another rank count, without changing the System. */
void load_system(System &system, std::vector<char> const &blob);

/** State of an accumulator (Correlator, TimeSeries, MeanVarianceCalculator). */
std::vector<char> save_accumulator(AutoUpdate const &acc);
/** Restore into an accumulator of the same kind and construction parameters
 * (Utils::RuntimeError otherwise, leaving it untouched). */
void load_accumulator(AutoUpdate &acc, std::vector<char> const &blob);

} // namespace Checkpoint
} // namespace Marble
