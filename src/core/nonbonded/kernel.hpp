#pragma once
// What every pair kernel declares (doc/adding-an-interaction.md):
//   static constexpr char const *name, *feature, *py_class;  KernelRole role;
//   struct Params { bool active; ... };   static std::vector<Field<Params>> const &fields();
//   static bool activates(Params const &)  -- does set_params switch it on?
//   static double range(Params const &)    -- largest distance at which it acts
//   optional: static void finish(Params &) -- derived values, cross-field checks
// and, by role:
//   conservative:     force_over_r(P, r), energy(P, r)        (F_i = force_over_r d)
//   pair_dissipative: salt, force(P, d, r, v_ij, xi, M_ij), refresh(P &, kT, dt)
//   colloid_surface:  salt, force(P, d, dist, v_bead, v_colloid, omega, xi), refresh
//   rotational_pair:  salt, force(P, d, r, v_ij, omega_i, omega_j, xi), refresh;
//                     symmetric, served by the main Verlet list (its range counts in max_cut)
//                     but evaluated in its own pass with the spins and torques
//                     (nonbonded/surface_friction_apply.hpp), not in the pair loop
//   wall_surface:     salt, refresh (the wall traversal applies it)
//   srd_boundary:     nothing more (the SRD streaming step applies it)
// Colloid-surface, wall-surface and SRD-boundary kernels are ordered: non_bonded_inter[c, s] with c
// the colloid or wall type; pair kernels are symmetric.
#include "nonbonded/fields.hpp"

#include <string_view>

namespace Marble {

enum class KernelRole { conservative, pair_dissipative, colloid_surface, wall_surface, srd_boundary, rotational_pair };

constexpr bool is_ordered(KernelRole r) {
  return r == KernelRole::colloid_surface || r == KernelRole::wall_surface || r == KernelRole::srd_boundary;
}
constexpr bool in_pair_loop(KernelRole r) {
  return r == KernelRole::conservative || r == KernelRole::pair_dissipative;
}
/** Kernels whose pairs the main Verlet list must hold (their range counts in max_cut). */
constexpr bool in_main_list(KernelRole r) { return in_pair_loop(r) || r == KernelRole::rotational_pair; }

/** Is feature @p name compiled in? (from the generated feature list) */
constexpr bool feature_on(std::string_view name, std::string_view active) {
  while (!active.empty()) {
    auto const sp = active.find(' ');
    if (active.substr(0, sp) == name)
      return true;
    if (sp == std::string_view::npos)
      break;
    active.remove_prefix(sp + 1);
  }
  return false;
}

/** Noise prefactor sqrt(24 kT gamma / dt) of uniform noise (variance 1/12). */
inline double noise_prefactor(double kT, double gamma, double dt) {
  return (dt > 0. && kT > 0. && gamma > 0.) ? std::sqrt(24. * kT * gamma / dt) : 0.;
}

} // namespace Marble
