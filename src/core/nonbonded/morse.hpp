#pragma once
// Morse potential (espressomd "morse"; seed 004 uses it for colloid-colloid
// attraction on the surface gap):
//   V(r) = eps [ exp(-2 alpha (x - rmin)) - 2 exp(-alpha (x - rmin)) ] - V_c,  x = r - offset,
// for x < cutoff, shifted by V_c (V at x = cutoff) so V is continuous there;
// minimum -eps (- V_c) at x = rmin. The optional offset (default 0, as in
// espressomd) measures x from a surface, e.g. offset = a_i + a_j for spheres
// of radii a_i, a_j. Force F = -dV/dr e = 2 alpha eps [e^{-2 alpha (x - rmin)} - e^{-alpha (x - rmin)}] e.
#include "nonbonded/kernel.hpp"

#include <cmath>

namespace Marble {

struct Morse {
  static constexpr char const *name = "morse", *feature = "MORSE", *py_class = "MorseInteraction",
                              *doc = "Morse potential V = eps [exp(-2 alpha (x - rmin)) - 2 exp(-alpha (x - rmin))] "
                                     "- V(cutoff), x = r - offset < cutoff.";
  static constexpr KernelRole role = KernelRole::conservative;
  struct Params {
    bool active = false;
    double eps = 0., alpha = 0., rmin = 0., cutoff = 0., offset = 0.;
    double shift = 0.; // V(cutoff), derived
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("eps", [](P const &p) { return p.eps; }, [](P &p, double x) { p.eps = x; }, 0., INFINITY),
          real<P>("alpha", [](P const &p) { return p.alpha; }, [](P &p, double x) { p.alpha = x; }, 0., INFINITY, true),
          real<P>("rmin", [](P const &p) { return p.rmin; }, [](P &p, double x) { p.rmin = x; }, 0., INFINITY),
          real<P>("cutoff", [](P const &p) { return p.cutoff; }, [](P &p, double x) { p.cutoff = x; }, 0., INFINITY, true),
          real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., INFINITY)};
      for (auto k : {0, 1, 2, 3})
        f[k].required = true;
      return f;
    }();
    return f;
  }
  static double bare(P const &p, double x) {
    double const e = std::exp(-p.alpha * (x - p.rmin));
    return p.eps * (e * e - 2. * e);
  }
  static void finish(P &p) { p.shift = bare(p, p.cutoff); }
  static bool activates(P const &p) { return p.eps > 0.; }
  static double range(P const &p) { return p.active ? p.cutoff + p.offset : 0.; }

  static double force_over_r(P const &p, double r) {
    double const x = r - p.offset;
    if (x >= p.cutoff || r <= 0.)
      return 0.;
    double const e = std::exp(-p.alpha * (x - p.rmin));
    return 2. * p.alpha * p.eps * (e * e - e) / r;
  }
  static double energy(P const &p, double r) {
    double const x = r - p.offset;
    return x >= p.cutoff ? 0. : bare(p, x) - p.shift;
  }
};

} // namespace Marble
