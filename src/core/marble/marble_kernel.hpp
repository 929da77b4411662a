#pragma once
// The marble colloid's surface coupling (Zhou & Schmid, seed 000; conventions
// of reference.md section 3). A solvent bead i at r_i couples to the surface
// point A = r_O + R n of a colloid at r_O, n = (r_i - r_O)/|r_i - r_O|,
// h = |r_i - r_O| - R, active for h < r_cut, weight w = w_DPD(max(h, 0)).
// With u = v_i - (v_O + omega x R n) and s = sqrt(24 kT gamma / dt):
//   dpd          F_i = [ -gamma w^2 (n.u) + s w (n.xi) ] n
//   transverse   F_i = (I - n n^T) [ -gamma w^2 u + s w xi ]
//   tunable_slip F_i = -gamma w^2 u + s w xi
// Reaction: force -F_i on the colloid and torque (R n) x (-F_i).
// Registered as non_bonded_inter[colloid type, solvent type].marble.
#include "nonbonded/kernel.hpp"
#include "utils/Vector.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

namespace Marble {

enum class MarbleCoupling { dpd = 0, transverse = 1, tunable_slip = 2 };

struct MarbleForce {
  Utils::Vector3d on_bead{};        // F_i
  Utils::Vector3d torque_colloid{}; // (R n) x (-F_i)
};

struct MarbleSurface {
  static constexpr char const *name = "marble", *feature = "MARBLE", *py_class = "MarbleInteraction",
                              *doc = "Marble colloid surface coupling (Zhou & Schmid) of colloid type i with solvent type j, acting on the gap h = r - radius; thermalised by the DPD thermostat. The order of the types matters.";
  static constexpr KernelRole role = KernelRole::colloid_surface;
  static constexpr Utils::RNGSalt salt = Utils::RNGSalt::marble;
  struct Params {
    bool active = false;
    double radius = 0., gamma = 0., r_cut = 0., k = 1.;
    int weight_function = 1;
    MarbleCoupling coupling = MarbleCoupling::tunable_slip;
    double pref_noise = 0.; // sqrt(24 kT gamma / dt), kept up to date by refresh()

    bool transmits_torque() const { return coupling != MarbleCoupling::dpd; }
    double weight(double h) const {
      if (h >= r_cut)
        return 0.;
      if (weight_function == 0)
        return 1.;
      double const x = (h > 0. ? h : 0.) / r_cut;
      return 1. - (k == 1. ? x : std::pow(x, k));
    }
  };
  using P = Params;
  static constexpr char const *coupling_names[] = {"dpd", "transverse", "tunable_slip"};

  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("radius", [](P const &p) { return p.radius; }, [](P &p, double x) { p.radius = x; }, 0., 1e6, true),
          real<P>("gamma", [](P const &p) { return p.gamma; }, [](P &p, double x) { p.gamma = x; }, 0., INFINITY),
          real<P>("r_cut", [](P const &p) { return p.r_cut; }, [](P &p, double x) { p.r_cut = x; }, 0., 1e6, true)};
      f[0].required = f[1].required = true;
      f[2].default_value = 1.;
      Field<P> wf{"weight_function", FieldType::integer,
                  [](P const &p) { return double(p.weight_function); },
                  [](P &p, double x) { p.weight_function = int(x); }};
      wf.lo = 0., wf.hi = 1., wf.default_value = 1.;
      wf.hint = "0 (w = 1) or 1 (w = 1 - (h/r_cut)^k)";
      f.push_back(wf);
      f.push_back(real<P>("k", [](P const &p) { return p.k; }, [](P &p, double x) { p.k = x; }, 0., INFINITY, true));
      f.back().default_value = 1.;
      Field<P> c{"coupling", FieldType::choice, [](P const &p) { return double(int(p.coupling)); },
                 [](P &p, double x) { p.coupling = MarbleCoupling(int(x)); }};
      c.choices = {"dpd", "transverse", "tunable_slip"};
      c.default_value = double(int(MarbleCoupling::tunable_slip));
      f.push_back(c);
      return f;
    }();
    return f;
  }
  static bool activates(P const &) { return true; }
  /** Scene checks when non_bonded_inter[c, s].marble is set (System is a
   * template parameter: this header does not depend on it). */
  template <class Sys> static void check_pair(Sys const &sys, int c, int s, P const &p) {
    auto const &ia = sys.interactions();
    if (c == s)
      Utils::value_error("marble: the colloid type and the solvent type must differ (got " +
                         std::to_string(c) + " for both)");
    auto coupled = [&](int a, int b) {
      return a < ia.n_types() && b < ia.n_types() && ia.get(a, b).template get<MarbleSurface>().active;
    };
    for (int t = 0; t < ia.n_types(); ++t) {
      if (coupled(s, t))
        Utils::value_error("marble: type " + std::to_string(s) +
                           " is already a colloid type; it cannot also be the solvent of a coupling");
      if (coupled(t, c))
        Utils::value_error("marble: type " + std::to_string(c) +
                           " is already the solvent of a coupling; it cannot also be a colloid type");
    }
    // a coupling that exerts torque needs rotating colloids
    if (p.transmits_torque()) {
      auto const &ps = sys.particles();
      int bad = INT_MAX;
      for (int i = 0; i < ps.n_local(); ++i)
        if (ps.type[i] == c && !ps.rotation[i])
          bad = std::min(bad, ps.id[i]);
      bad = sys.comm().min(bad);
      if (bad != INT_MAX)
        Utils::value_error("marble: particle " + std::to_string(bad) + " of colloid type " +
                           std::to_string(c) + " does not rotate, but coupling '" +
                           coupling_names[static_cast<int>(p.coupling)] +
                           "' exerts torque: add it with rotation=True (or use coupling='dpd')");
    }
  }
  /** Largest centre-centre distance at which the coupling acts. */
  static double range(P const &p) { return p.active ? p.radius + p.r_cut : 0.; }
  static void refresh(P &p, double kT, double dt) { p.pref_noise = noise_prefactor(kT, p.gamma, dt); }

  /**
   * @param d   r_i - r_O (bead minus colloid centre, minimum image), |d| > 0
   * @param v_bead, v_colloid, omega  velocities
   * @param xi  noise 3-vector (uniform, variance 1/12 per component), or zero
   */
  static MarbleForce force(P const &p, Utils::Vector3d const &d, double dist,
                           Utils::Vector3d const &v_bead, Utils::Vector3d const &v_colloid,
                           Utils::Vector3d const &omega, Utils::Vector3d const &xi) {
    MarbleForce out;
    double const h = dist - p.radius;
    double const w = p.weight(h);
    if (w <= 0.)
      return out;
    Utils::Vector3d const n = d / dist;
    Utils::Vector3d const rA = p.radius * n; // r_OA
    Utils::Vector3d const u = v_bead - (v_colloid + Utils::cross(omega, rA));
    double const fric = -p.gamma * w * w;
    double const noise = p.pref_noise * w;
    Utils::Vector3d f;
    switch (p.coupling) {
    case MarbleCoupling::dpd:
      f = (fric * (n * u) + noise * (n * xi)) * n;
      break;
    case MarbleCoupling::transverse: {
      Utils::Vector3d const g = fric * u + noise * xi;
      f = g - (n * g) * n;
      break;
    }
    case MarbleCoupling::tunable_slip:
      f = fric * u + noise * xi;
      break;
    }
    out.on_bead = f;
    out.torque_colloid = Utils::cross(rA, -f);
    return out;
  }
};

using MarbleParams = MarbleSurface::Params;

} // namespace Marble
