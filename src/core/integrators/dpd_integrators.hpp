#pragma once
// The thermostat parts of the DPD integrators that replace plain velocity
// Verlet's explicit pair friction (integrators/shardlow.cpp, doc/stability.md).
#include "config/features.hpp"
#include "system/System.hpp"

#include <vector>

namespace Marble {
#ifdef DPD
/** Shardlow S1: exact pairwise friction + noise update of the velocities of
 * every DPD pair of the main list, in list order. */
void shardlow_sweep(System &sys);
/** Several ranks: throw if a domain is narrower than twice the pair range
 * along a split axis (the sweep's rounds need it); lists must be valid.
 * The same on every rank. */
void check_shardlow_decomposition(System &sys);
/** DPD-VV: add to the forces the pair friction of the velocity change @p dv
 * of the last half kick (locals). */
void add_friction_of_dv(System &sys, std::vector<Utils::Vector3d> const &dv);
#endif
} // namespace Marble
