#pragma once
// Groot-Warren soft repulsion (espressomd "hat", reference.md section 1):
//   F(r) = F_max (1 - x/r_c) e,  V(r) = F_max (r_c - x)^2 / (2 r_c)  for x = r - offset < r_c.
// The optional offset (default 0: espressomd's hat) measures x from a surface,
// e.g. offset = R for the colloid-solvent repulsion of seed 004 on the gap
// (doc/suspensions.md); with offset 0 the arithmetic is that of the plain hat.
#include "nonbonded/kernel.hpp"

namespace Marble {

struct Hat {
  static constexpr char const *name = "hat", *feature = "HAT", *py_class = "HatInteraction",
                              *doc = "Groot-Warren soft repulsion F = F_max (1 - x/cutoff) for x = r - offset < cutoff (offset default 0).";
  static constexpr KernelRole role = KernelRole::conservative;
  struct Params {
    bool active = false;
    double F_max = 0., cutoff = 0., offset = 0.;
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("F_max", [](P const &p) { return p.F_max; }, [](P &p, double x) { p.F_max = x; }, 0., INFINITY),
          real<P>("cutoff", [](P const &p) { return p.cutoff; }, [](P &p, double x) { p.cutoff = x; }, 0., INFINITY, true),
          real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., INFINITY)};
      f[0].required = f[1].required = true;
      return f;
    }();
    return f;
  }
  static bool activates(P const &p) { return p.F_max > 0.; }
  static double range(P const &p) { return p.active ? p.cutoff + p.offset : 0.; }

  // x = r - 0. is r exactly: offset 0 keeps the plain hat's results bit for bit
  static double force_over_r(P const &p, double r) {
    double const x = r - p.offset;
    if (x >= p.cutoff || r <= 0.)
      return 0.;
    return p.F_max * (1. - x / p.cutoff) / r;
  }
  static double energy(P const &p, double r) {
    double const x = r - p.offset;
    if (x >= p.cutoff)
      return 0.;
    double const y = p.cutoff - x;
    return p.F_max * y * y / (2. * p.cutoff);
  }
};

} // namespace Marble
