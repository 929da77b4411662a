#pragma once
// Explicit-friction and skin stability checks of the integrators
// (doc/stability.md has the measurements behind the limits).
#include <string>

namespace Marble {

class System;

/** Friction rates (1/time) of the scene, estimated from the parameters and the
 * mean number densities; nu = rate * dt is compared with the measured limits.
 */
struct FrictionRates {
  /// solvent DPD pairs of the main list, largest over particle types a:
  /// sum_b gamma_ab M_ab (1/m_a + 1/m_b) n_b int_0^rc w(r)^2 4 pi r^2 dr
  double dpd = 0.;
  std::string dpd_where;
  /// one-body-like friction on a bead: marble coupling gamma / m (w <= 1),
  /// tunable-slip wall gamma_L / m and, with explicit pair friction (not
  /// Shardlow), the stick surface_friction's gamma / m
  /// (nonbonded/surface_friction.hpp)
  double one_body = 0.;
  /// largest over types of dpd / kNuDpd + one_body / kNuOneBody: times dt,
  /// the fraction of the stability limit used by a bead
  double bead = 0.;
  std::string bead_where;
  /// a colloid's friction rate from its solvent shell, largest of translation
  /// gamma n_s int_0^rc w(h)^2 4 pi (R + h)^2 dh / M and rotation (2/3) R^2
  /// (...) / I; or (explicit pair friction only) a sphere's surface_friction
  /// with point partners: translation (2/3) gamma n int w^2 4 pi r^2 dr / M,
  /// rotation (2/3) gamma n int w^2 4 pi r^4 dr / I over its shell
  double colloid = 0.;
  std::string colloid_where;
  /// thermal speed sqrt(kT / m_min) of the lightest thermalised particle
  double v_thermal = 0.;
};

/** @p include_pair_dpd: false for the Shardlow integrator (exact pair updates).
 */
FrictionRates friction_rates(System &sys, bool include_pair_dpd);

/** Stability limits of nu = rate * dt with explicit friction (velocity
 * Verlet; doc/stability.md). Solvent DPD pairs (mean-field rate above): blows
 * up between nu = 3.27 and 3.52 (rho = 3, w = 1 - r, dt = 0.01, measured);
 * one-body friction (a colloid in its shell, a bead near a colloid or a
 * wall): v -> (1 - nu) v per step, unstable at nu = 2 (a colloid measured: runs
 * at nu = 1.07, explodes at 3.6). The checks keep a margin below both. */
inline constexpr double kNuDpd = 3.0;
inline constexpr double kNuOneBody = 1.5;
/** Largest thermal displacement per step, in thermal-speed units, that the
 * skin must cover: skin >= kSkinSpeeds * sqrt(kT/m) * dt. */
inline constexpr double kSkinSpeeds = 6.0;

/** Throws Utils::RuntimeError naming the cause and a suggested time step if
 * the scene is beyond the measured explicit stability limit of the selected
 * integrator, or if the thermal motion per step exceeds the skin. */
void check_stability_before_run(System &sys);

/** Largest fraction of the explicit stability limit used by the scene at its
 * time step (> 1: unstable), with where it comes from (for messages). */
double limit_fraction(System &sys, std::string &where);

} // namespace Marble
