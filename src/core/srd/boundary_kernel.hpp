#pragma once
// The boundary of an SRD colloid (seed 003): colloid type c is a hard sphere
// of `radius` for SRD type s, with a boundary rule applied while the SRD
// particles stream (srd/Fluid.cpp). Registered as
// non_bonded_inter[c, s].srd_boundary; it exerts no pair force (SRD particles
// take no part in pair lists), so it is its own role.
#include "nonbonded/kernel.hpp"

namespace Marble {
namespace Srd {
// stochastic: seed 003 eqs. (1), (2) (diffuse, thermalising, stick);
// bounce_back: relative velocity reversed (stick); slip: specular;
// rough: Enskog's rough-sphere collision on average (normal reversed, a
// fraction 2K, K = chi/(1 + chi), chi = 2/5, of the relative tangential
// velocity reversed, the rest thermal noise): the collision behind seed
// 003's Enskog frictions (doc/srd.md).
enum class BoundaryRule { stochastic, bounce_back, slip, rough };
// How a bounce is coupled to the colloid (doc/srd.md, "Finite colloid mass"):
// pair: the rule acts on the relative velocity at the contact point with the
//   effective masses of the pair (particle, colloid); the bounces of a step
//   are events at the crossing times of the relative motion, processed in
//   time order, each impulse applied to the colloid at once (detailed balance
//   for the pair, no detection lag; the default);
// fixed_surface: the rule in the frame of an infinitely heavy surface (seed
//   003), impulses applied at once in id order;
// seed003: seed 003 literally: infinitely heavy surface, all impulses of a
//   step summed and applied at its end (runs warm at small M/m; comparison only).
enum class Coupling { pair, fixed_surface, seed003 };
} // namespace Srd

struct SRDBoundary {
  static constexpr char const *name = "srd_boundary", *feature = "SRD",
                              *py_class = "SRDBoundaryInteraction",
                              *doc = "Boundary of an SRD colloid (seed 003): colloid type i is a hard sphere of "
                                     "radius for SRD type j, with the rule 'stochastic' (stick, thermalising), "
                                     "'bounce_back' (stick), 'slip' (specular) or 'rough' (Enskog's rough sphere); coupling 'pair' (default: reduced-mass rule, "
                                     "bounces as events in time order), 'fixed_surface' or 'seed003' (comparison only).";
  static constexpr KernelRole role = KernelRole::srd_boundary;
  struct Params {
    bool active = false;
    double radius = 0.;
    Srd::BoundaryRule rule = Srd::BoundaryRule::stochastic;
    Srd::Coupling coupling = Srd::Coupling::pair;
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("radius", [](P const &p) { return p.radius; }, [](P &p, double x) { p.radius = x; }, 0., 1e6, true)};
      f[0].required = true;
      Field<P> r{"rule", FieldType::choice, [](P const &p) { return double(int(p.rule)); },
                 [](P &p, double x) { p.rule = Srd::BoundaryRule(int(x)); }};
      r.choices = {"stochastic", "bounce_back", "slip", "rough"};
      f.push_back(r);
      Field<P> c{"coupling", FieldType::choice, [](P const &p) { return double(int(p.coupling)); },
                 [](P &p, double x) { p.coupling = Srd::Coupling(int(x)); }};
      c.choices = {"pair", "fixed_surface", "seed003"};
      f.push_back(c);
      return f;
    }();
    return f;
  }
  static bool activates(P const &) { return true; }
  static double range(P const &) { return 0.; } // no pair force
  template <class Sys> static void check_pair(Sys const &, int c, int s, P const &) {
    if (c == s)
      Utils::value_error("srd_boundary: the colloid type and the SRD type must differ (got " +
                         std::to_string(c) + " for both)");
  }
};

} // namespace Marble
