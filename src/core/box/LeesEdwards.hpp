#pragma once
// Lees-Edwards boundary conditions (simple shear; Lees & Edwards, J. Phys. C 5,
// 1921 (1972)), shaped like ESPResSo 4.2's espressomd.lees_edwards
// (doc/lees-edwards.md).
//
// The periodic images across the shear plane (normal n) move along the shear
// direction s: the image one box length above (+L_n e_n) is displaced by
// +pos_offset e_s and moves with +shear_velocity e_s relative to the primary
// box. A particle leaving the box through the upper n face re-enters at the
// lower one with its s coordinate shifted by -pos_offset and its s velocity by
// -shear_velocity (the opposite going down).
#include <cmath>

namespace Marble {

/** The current Lees-Edwards state of the box (shear_direction < 0: off). */
struct LeesEdwardsBC {
  int shear_direction = -1;
  int shear_plane_normal = -1;
  double pos_offset = 0.;
  double shear_velocity = 0.;
  bool active() const { return shear_direction >= 0; }
};

/** A time protocol of the offset (ESPResSo's Off, LinearShear, OscillatoryShear). */
struct LeesEdwardsProtocol {
  enum Kind : int { Off = 0, Linear = 1, Oscillatory = 2 };
  int kind = Off;
  double initial_pos_offset = 0.;
  double shear_velocity = 0.; // Linear
  double amplitude = 0.;      // Oscillatory
  double omega = 0.;          // Oscillatory
  double time_0 = 0.;

  /** offset(t): Linear: initial + v (t - t0); Oscillatory: initial + A sin(omega (t - t0)). */
  double pos_offset(double t) const {
    switch (kind) {
    case Linear:
      return initial_pos_offset + shear_velocity * (t - time_0);
    case Oscillatory:
      return initial_pos_offset + amplitude * std::sin(omega * (t - time_0));
    default:
      return initial_pos_offset;
    }
  }
  /** d offset / dt. */
  double velocity(double t) const {
    switch (kind) {
    case Linear:
      return shear_velocity;
    case Oscillatory:
      return amplitude * omega * std::cos(omega * (t - time_0));
    default:
      return 0.;
    }
  }
};

} // namespace Marble
