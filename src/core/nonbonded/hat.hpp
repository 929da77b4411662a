#pragma once
// Groot-Warren soft repulsion (espressomd "hat", reference.md section 1):
//   F(r) = F_max (1 - r/r_c) e,  V(r) = F_max (r_c - r)^2 / (2 r_c)  for r < r_c.
namespace Marble {

struct HatParams {
  bool active = false;
  double F_max = 0., cutoff = 0.;

  double max_cutoff() const { return active ? cutoff : 0.; }
  double force_over_r(double r) const {
    if (r >= cutoff || r <= 0.)
      return 0.;
    return F_max * (1. - r / cutoff) / r;
  }
  double energy(double r) const {
    if (r >= cutoff)
      return 0.;
    double const x = cutoff - r;
    return F_max * x * x / (2. * cutoff);
  }
};

} // namespace Marble
