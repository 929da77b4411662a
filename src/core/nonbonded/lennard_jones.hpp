#pragma once
// Lennard-Jones with offset (espressomd convention, reference.md section 3):
//   V(r) = 4 eps [ (s/(r-r0))^12 - (s/(r-r0))^6 + shift ]  for  min < r - r0 < cutoff.
// The cutoff is measured from the offset; shift "auto" makes V(r0 + cutoff) = 0.
#include <cmath>

namespace Marble {

struct LennardJonesParams {
  bool active = false;
  double epsilon = 0., sigma = 0., cutoff = 0., shift = 0., offset = 0., min = 0.;

  double max_cutoff() const { return active ? cutoff + offset : 0.; }
  static double auto_shift(double sigma, double cutoff) {
    double const q6 = std::pow(sigma / cutoff, 6);
    return -(q6 * q6 - q6);
  }
  /** Force magnitude divided by r (F = fac * d) for distance r (r^2 = r2). */
  double force_over_r(double r) const {
    double const roff = r - offset;
    if (roff >= cutoff || roff <= min)
      return 0.;
    double const q2 = (sigma * sigma) / (roff * roff);
    double const q6 = q2 * q2 * q2;
    return 48. * epsilon * q6 * (q6 - 0.5) / (roff * r);
  }
  double energy(double r) const {
    double const roff = r - offset;
    if (roff >= cutoff || roff <= min)
      return 0.;
    double const q2 = (sigma * sigma) / (roff * roff);
    double const q6 = q2 * q2 * q2;
    return 4. * epsilon * (q6 * q6 - q6 + shift);
  }
};

} // namespace Marble
