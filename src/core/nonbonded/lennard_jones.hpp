#pragma once
// Lennard-Jones with offset (espressomd convention, reference.md section 3):
//   V(r) = 4 eps [ (s/(r-r0))^12 - (s/(r-r0))^6 + shift ]  for  min < r - r0 < cutoff.
// The cutoff is measured from the offset; shift "auto" makes V(r0 + cutoff) = 0.
#include "nonbonded/kernel.hpp"

#include <cmath>

namespace Marble {

struct LennardJones {
  static constexpr char const *name = "lennard_jones", *feature = "LENNARD_JONES",
                              *py_class = "LennardJonesInteraction",
                              *doc = "V = 4 eps [(s/(r-offset))^12 - (s/(r-offset))^6 + shift] for min < r - offset < cutoff (cutoff measured from the offset; shift \"auto\" makes V continuous).";
  static constexpr KernelRole role = KernelRole::conservative;
  struct Params {
    bool active = false;
    double epsilon = 0., sigma = 0., cutoff = 0., shift = 0., offset = 0., min = 0.;
  };
  using P = Params;
  static double auto_shift(double sigma, double cutoff) {
    double const q6 = std::pow(sigma / cutoff, 6);
    return -(q6 * q6 - q6);
  }
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("epsilon", [](P const &p) { return p.epsilon; }, [](P &p, double x) { p.epsilon = x; }, 0., INFINITY),
          real<P>("sigma", [](P const &p) { return p.sigma; }, [](P &p, double x) { p.sigma = x; }, 0., INFINITY, true),
          real<P>("cutoff", [](P const &p) { return p.cutoff; }, [](P &p, double x) { p.cutoff = x; }, 0., INFINITY, true),
          real<P>("shift", [](P const &p) { return p.shift; }, [](P &p, double x) { p.shift = x; }, -INFINITY, INFINITY),
          real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., INFINITY),
          real<P>("min", [](P const &p) { return p.min; }, [](P &p, double x) { p.min = x; }, 0., INFINITY)};
      for (auto k : {0, 1, 2})
        f[k].required = true;
      f[3].keyword = "auto";
      f[3].hint = "sigma and cutoff";
      f[3].keyword_value = [](P const &p) { return auto_shift(p.sigma, p.cutoff); };
      return f;
    }();
    return f;
  }
  static void finish(P &p) { Utils::check_double("min", p.min, 0., p.cutoff, false, true); }
  static bool activates(P const &p) { return p.epsilon > 0.; }
  static double range(P const &p) { return p.active ? p.cutoff + p.offset : 0.; }

  /** Force magnitude divided by r (F = fac * d) at distance r. */
  static double force_over_r(P const &p, double r) {
    double const roff = r - p.offset;
    if (roff >= p.cutoff || roff <= p.min)
      return 0.;
    double const q2 = (p.sigma * p.sigma) / (roff * roff);
    double const q6 = q2 * q2 * q2;
    return 48. * p.epsilon * q6 * (q6 - 0.5) / (roff * r);
  }
  static double energy(P const &p, double r) {
    double const roff = r - p.offset;
    if (roff >= p.cutoff || roff <= p.min)
      return 0.;
    double const q2 = (p.sigma * p.sigma) / (roff * roff);
    double const q6 = q2 * q2 * q2;
    return 4. * p.epsilon * (q6 * q6 - q6 + p.shift);
  }
};

} // namespace Marble
