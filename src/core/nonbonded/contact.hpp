#pragma once
// Contact force of hard colloids on the surface gap h = r - offset
// (offset = a_i + a_j; seed 004, Jamali & Boromand 2015; doc/suspensions.md):
//   F(h) = f_c (1 - h/delta)^3          0 <= h < delta
//   F(h) = f_c (1 - 3 h/delta)          h < 0 (overlap)
//   F(h) = 0                            h >= delta,      F_i = F e_ij (repulsive).
// Seed 004 prints f_c (1 + h) for h <= 0, which weakens as the overlap grows;
// the linear continuation above matches value and slope (-3 f_c/delta) at
// h = 0, so the force is C^1 and grows with overlap. Energy (F = -dU/dh):
//   U(h) = f_c delta/4 (1 - h/delta)^4                0 <= h < delta
//   U(h) = f_c (delta/4 - h + 3 h^2 / (2 delta))      h < 0.
#include "nonbonded/kernel.hpp"

#include <cmath>

namespace Marble {

struct Contact {
  static constexpr char const *name = "contact", *feature = "CONTACT", *py_class = "ContactInteraction",
                              *doc = "Contact force on the gap h = r - offset: f_contact (1 - h/delta)^3 for 0 <= h < delta, "
                                     "f_contact (1 - 3 h/delta) for h < 0 (C1, grows with overlap); offset = a_i + a_j.";
  static constexpr KernelRole role = KernelRole::conservative;
  struct Params {
    bool active = false;
    double f_contact = 0., delta = 0., offset = 0.;
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("f_contact", [](P const &p) { return p.f_contact; }, [](P &p, double x) { p.f_contact = x; }, 0., INFINITY),
          real<P>("delta", [](P const &p) { return p.delta; }, [](P &p, double x) { p.delta = x; }, 0., INFINITY, true),
          real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., INFINITY)};
      f[0].required = f[1].required = true;
      return f;
    }();
    return f;
  }
  static bool activates(P const &p) { return p.f_contact > 0.; }
  static double range(P const &p) { return p.active ? p.delta + p.offset : 0.; }

  /** Force magnitude along e at gap h. */
  static double force_gap(P const &p, double h) {
    if (h >= p.delta)
      return 0.;
    if (h >= 0.) {
      double const y = 1. - h / p.delta;
      return p.f_contact * y * y * y;
    }
    return p.f_contact * (1. - 3. * h / p.delta);
  }
  static double force_over_r(P const &p, double r) {
    return r > 0. ? force_gap(p, r - p.offset) / r : 0.;
  }
  static double energy(P const &p, double r) {
    double const h = r - p.offset;
    if (h >= p.delta)
      return 0.;
    if (h >= 0.) {
      double const y = 1. - h / p.delta;
      return 0.25 * p.f_contact * p.delta * (y * y) * (y * y);
    }
    return p.f_contact * (0.25 * p.delta - h + 1.5 * h * h / p.delta);
  }
};

} // namespace Marble
