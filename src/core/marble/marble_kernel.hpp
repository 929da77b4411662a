#pragma once
// The marble colloid's surface coupling (Zhou & Schmid, seed 000; conventions
// of reference.md section 3). A solvent bead i at r_i couples to the surface
// point A = r_O + R n of a colloid at r_O, n = (r_i - r_O)/|r_i - r_O|,
// h = |r_i - r_O| - R, active for h < r_cut, weight w = w_DPD(max(h, 0)).
// With u = v_i - (v_O + omega x R n) and s = sqrt(24 kT gamma / dt):
//   dpd          F_i = [ -gamma w^2 (n.u) + s w (n.xi) ] n
//   transverse   F_i = (I - n n^T) [ -gamma w^2 u + s w xi ]
//   tunable_slip F_i = -gamma w^2 u + s w xi
// Reaction: force -F_i on the colloid and torque (R n) x (-F_i).
#include "utils/Vector.hpp"

#include <cmath>

namespace Marble {

enum class MarbleCoupling { dpd = 0, transverse = 1, tunable_slip = 2 };

struct MarbleParams {
  bool active = false;
  double radius = 0., gamma = 0., r_cut = 0., k = 1.;
  int weight_function = 1;
  MarbleCoupling coupling = MarbleCoupling::tunable_slip;
  double pref_noise = 0.; // sqrt(24 kT gamma / dt), kept up to date by the System

  /** Largest centre-centre distance at which the coupling acts. */
  double range() const { return active ? radius + r_cut : 0.; }
  bool transmits_torque() const { return coupling != MarbleCoupling::dpd; }
  double weight(double h) const {
    if (h >= r_cut)
      return 0.;
    if (weight_function == 0)
      return 1.;
    double const x = (h > 0. ? h : 0.) / r_cut;
    return 1. - (k == 1. ? x : std::pow(x, k));
  }
};

struct MarbleForce {
  Utils::Vector3d on_bead{};        // F_i
  Utils::Vector3d torque_colloid{}; // (R n) x (-F_i)
};

/**
 * @param d   r_i - r_O (bead minus colloid centre, minimum image), |d| > 0
 * @param v_bead, v_colloid, omega  velocities
 * @param xi  noise 3-vector (uniform, variance 1/12 per component), or zero
 */
inline MarbleForce marble_force(MarbleParams const &p, Utils::Vector3d const &d, double dist,
                                Utils::Vector3d const &v_bead, Utils::Vector3d const &v_colloid,
                                Utils::Vector3d const &omega, Utils::Vector3d const &xi) {
  MarbleForce out;
  double const h = dist - p.radius;
  double const w = p.weight(h);
  if (w <= 0.)
    return out;
  Utils::Vector3d const n = d / dist;
  Utils::Vector3d const rA = p.radius * n; // r_OA
  Utils::Vector3d const u = v_bead - (v_colloid + Utils::cross(omega, rA));
  double const fric = -p.gamma * w * w;
  double const noise = p.pref_noise * w;
  Utils::Vector3d f;
  switch (p.coupling) {
  case MarbleCoupling::dpd:
    f = (fric * (n * u) + noise * (n * xi)) * n;
    break;
  case MarbleCoupling::transverse: {
    Utils::Vector3d const g = fric * u + noise * xi;
    f = g - (n * g) * n;
    break;
  }
  case MarbleCoupling::tunable_slip:
    f = fric * u + noise * xi;
    break;
  }
  out.on_bead = f;
  out.torque_colloid = Utils::cross(rA, -f);
  return out;
}

} // namespace Marble
