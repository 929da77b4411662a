#pragma once
// The list of pair kernels: every interaction of the engine is one entry here
// (doc/adding-an-interaction.md). A kernel whose feature is not compiled in
// stays known by name (its set_params raises FeaturesError naming the
// feature) but has no storage and no code in the loops. The order is the
// order in which the pair loop adds the kernels' forces.
#include "constraints/tunable_slip.hpp"
#include "marble/marble_kernel.hpp"
#include "nonbonded/contact.hpp"
#include "nonbonded/hat.hpp"
#include "nonbonded/lennard_jones.hpp"
#include "nonbonded/lubrication.hpp"
#include "nonbonded/morse.hpp"
#include "nonbonded/surface_friction.hpp"
#include "srd/boundary_kernel.hpp"
#include "thermostats/dpd.hpp"

namespace Marble {

template <class... Ks> struct TypeList {};

// new kernels go after the existing ones of their role (the summation order of
// existing scenes stays the same: testsuite/python/test_registry_regression.py)
using AllKernels = TypeList<LennardJones, Hat, Morse, Contact, DPDPair, Lubrication, MarbleSurface,
                            TunableSlip, SRDBoundary, SurfaceFriction>;

} // namespace Marble
