#pragma once
// Groot-Warren soft repulsion (espressomd "hat", reference.md section 1):
//   F(r) = F_max (1 - r/r_c) e,  V(r) = F_max (r_c - r)^2 / (2 r_c)  for r < r_c.
#include "nonbonded/kernel.hpp"

namespace Marble {

struct Hat {
  static constexpr char const *name = "hat", *feature = "HAT", *py_class = "HatInteraction",
                              *doc = "Groot-Warren soft repulsion F = F_max (1 - r/cutoff) for r < cutoff.";
  static constexpr KernelRole role = KernelRole::conservative;
  struct Params {
    bool active = false;
    double F_max = 0., cutoff = 0.;
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("F_max", [](P const &p) { return p.F_max; }, [](P &p, double x) { p.F_max = x; }, 0., INFINITY),
          real<P>("cutoff", [](P const &p) { return p.cutoff; }, [](P &p, double x) { p.cutoff = x; }, 0., INFINITY, true)};
      f[0].required = f[1].required = true;
      return f;
    }();
    return f;
  }
  static bool activates(P const &p) { return p.F_max > 0.; }
  static double range(P const &p) { return p.active ? p.cutoff : 0.; }

  static double force_over_r(P const &p, double r) {
    if (r >= p.cutoff || r <= 0.)
      return 0.;
    return p.F_max * (1. - r / p.cutoff) / r;
  }
  static double energy(P const &p, double r) {
    if (r >= p.cutoff)
      return 0.;
    double const x = p.cutoff - r;
    return p.F_max * x * x / (2. * p.cutoff);
  }
};

} // namespace Marble
