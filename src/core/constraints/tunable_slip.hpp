#pragma once
// Tunable-slip wall friction (Smiatek, Allen, Schmid 2008; reference.md
// section 4) of a wall's particle type with a fluid type, registered as
// non_bonded_inter[wall type, fluid type].tunable_slip. A bead at distance z
// from the wall feels
//   F = -gamma w(z) (v - v_wall) + sqrt(24 kT gamma / dt) sqrt(w(z)) xi,
//   w(z) = 1 - (z - offset)/r_cut for offset <= z < offset + r_cut (w = 1 below offset).
// The wall traversal (constraints/Constraints.cpp) applies it.
#include "nonbonded/kernel.hpp"
#include "utils/noise.hpp"

namespace Marble {

struct TunableSlip {
  static constexpr char const *name = "tunable_slip", *feature = "TUNABLE_SLIP",
                              *py_class = "TunableSlipInteraction",
                              *doc = "Tunable-slip wall friction (Smiatek et al.) between a wall particle type i and fluid type j: F = -gamma w(z) (v - v_wall) + noise, w = 1 - (z - offset)/r_cut; thermalised by the DPD thermostat.";
  static constexpr KernelRole role = KernelRole::wall_surface;
  static constexpr Utils::RNGSalt salt = Utils::RNGSalt::tunable_slip_wall;
  struct Params {
    bool active = false;
    double gamma = 0., r_cut = 0., offset = 0.;
    double pref_noise = 0.; // sqrt(24 kT gamma / dt)
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("gamma", [](P const &p) { return p.gamma; }, [](P &p, double x) { p.gamma = x; }, 0., INFINITY),
          real<P>("r_cut", [](P const &p) { return p.r_cut; }, [](P &p, double x) { p.r_cut = x; }, 0., 1e6, true),
          real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., 1e6)};
      f[0].required = f[1].required = true;
      return f;
    }();
    return f;
  }
  static bool activates(P const &) { return true; }
  static double range(P const &p) { return p.active ? p.offset + p.r_cut : 0.; }
  static void refresh(P &p, double kT, double dt) { p.pref_noise = noise_prefactor(kT, p.gamma, dt); }
};

using TunableSlipParams = TunableSlip::Params;

} // namespace Marble
