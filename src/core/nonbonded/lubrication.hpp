#pragma once
// Squeeze-mode lubrication between spheres of radii a1, a2 on the surface gap
// h = r - (a1 + a2) (seed 004 after Ball & Melrose 1997; doc/suspensions.md):
//   F_i = [ -a_sq(h) (e . v_ij) + sqrt(24 kT a_sq(h) / dt) w_n(h) (e . xi) ] e   for h < h_cut,
//   a_sq(h) = 6 pi eta [ a_red^2 / h_e  +  c_log ln(a_mean / h_e) ],   h_e = max(h, h_min),
// with a_red = a1 a2/(a1 + a2) and a_mean = (a1 + a2)/2. The first term is the
// exact leading (Reynolds) squeeze term of two unequal spheres (Jeffrey &
// Onishi 1984, X11A = g1/xi, g1 = 2 beta^2/(1 + beta)^3); for equal spheres it
// is (3 pi/2) eta a^2 / h, seed 004's and Ball-Melrose's form. (Seed 004 writes
// ((a1 + a2)/2)^2 for a_red^2 times 4: equal for equal spheres, too large
// otherwise.) The optional log term (log_term="on") is the next Jeffrey-Onishi
// term, c_log = a1 a2 (a1^2 + 7 a1 a2 + a2^2) / (5 (a1 + a2)^3) (9a/40 for
// equal spheres: LAMMPS pair lubricate's squeeze coefficient); a_sq is
// clipped at 0 where the log turns negative (h_e > a_mean).
//
// Noise: xi is the pair's uniform 3-vector (variance 1/12, salt lubrication),
// so the noise variance along e is 2 kT a_sq / dt: fluctuation-dissipation
// holds for the pair's relative normal velocity at every gap. noise="seed"
// instead multiplies the noise by the DPD weight w_n = 1 - max(h, 0)/h_cut, as
// seed 004's combined amplitude sqrt(2 (a_sq + gamma) kT) w does: it misses the
// fraction 1 - w_n^2 of the variance (kept only to show the deficit).
//
// form="shifted" (for a solvent that resolves the squeeze flow above h_cut,
// doc/suspensions.md 7g/7i) subtracts the friction's value at h_cut, so that
// the kernel supplies only what the solvent misses below h_cut and goes
// continuously to zero there:
//   a_sq(h) = 6 pi eta [ a_red^2 (1/h_e - 1/h_cut)  +  c_log ln(h_cut / h_e) ]
// (log part only with log_term="on"); the noise uses the same a_sq, so
// fluctuation-dissipation holds unchanged. form="plain" (default) is the
// form above, bit for bit.
// Hydrodynamic friction: not scaled by DPD_MASS_* factors.
#include "nonbonded/kernel.hpp"
#include "utils/Vector.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>

namespace Marble {

struct Lubrication {
  static constexpr char const *name = "lubrication", *feature = "LUBRICATION", *py_class = "LubricationInteraction",
                              *doc = "Squeeze lubrication of spheres a1, a2 on the gap h = r - a1 - a2 < h_cut (needs the DPD "
                                     "thermostat for kT): friction a_sq = 6 pi eta [a_red^2/max(h, h_min) (+ log term)] "
                                     "along e (form='shifted': minus its value at h_cut), noise of variance 2 kT a_sq/dt (noise='seed': seed 004's, times w = 1 - h/h_cut).";
  static constexpr KernelRole role = KernelRole::pair_dissipative;
  static constexpr Utils::RNGSalt salt = Utils::RNGSalt::lubrication;
  static constexpr char const *log_names[] = {"off", "on"};
  static constexpr char const *noise_names[] = {"fdt", "seed"};
  static constexpr char const *form_names[] = {"plain", "shifted"};
  struct Params {
    bool active = false;
    double eta = 0., a1 = 0., a2 = 0., h_cut = 0., h_min = 1e-3;
    int log_term = 0, noise = 0, form = 0;
    // derived (finish / refresh)
    double offset = 0., a_red2 = 0., a_mean = 0., c_log = 0.;
    double pref_noise = 0.; // sqrt(24 kT / dt)
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      auto choice = [](char const *key, auto get, auto set, char const *const *names) {
        Field<P> x{key, FieldType::choice, get, set};
        x.choices = {names[0], names[1]};
        return x;
      };
      std::vector<Field<P>> f{
          real<P>("eta", [](P const &p) { return p.eta; }, [](P &p, double x) { p.eta = x; }, 0., INFINITY, true),
          real<P>("a1", [](P const &p) { return p.a1; }, [](P &p, double x) { p.a1 = x; }, 0., INFINITY, true),
          real<P>("a2", [](P const &p) { return p.a2; }, [](P &p, double x) { p.a2 = x; }, 0., INFINITY, true),
          real<P>("h_cut", [](P const &p) { return p.h_cut; }, [](P &p, double x) { p.h_cut = x; }, 0., INFINITY, true),
          real<P>("h_min", [](P const &p) { return p.h_min; }, [](P &p, double x) { p.h_min = x; }, 0., INFINITY, true),
          choice("log_term", [](P const &p) { return double(p.log_term); }, [](P &p, double x) { p.log_term = int(x); },
                 log_names),
          choice("noise", [](P const &p) { return double(p.noise); }, [](P &p, double x) { p.noise = int(x); },
                 noise_names),
          choice("form", [](P const &p) { return double(p.form); }, [](P &p, double x) { p.form = int(x); },
                 form_names)};
      for (auto k : {0, 1, 2, 3})
        f[k].required = true;
      f[4].default_value = 1e-3;
      return f;
    }();
    return f;
  }
  static void finish(P &p) {
    Utils::check_double("h_min", p.h_min, 0., p.h_cut, true, true); // 0 < h_min < h_cut
    double const s = p.a1 + p.a2;
    p.offset = s;
    p.a_red2 = (p.a1 * p.a2 / s) * (p.a1 * p.a2 / s);
    p.a_mean = 0.5 * s;
    p.c_log = p.a1 * p.a2 * (p.a1 * p.a1 + 7. * p.a1 * p.a2 + p.a2 * p.a2) / (5. * s * s * s);
  }
  static bool activates(P const &p) { return p.eta > 0.; }
  static double range(P const &p) { return p.active ? p.offset + p.h_cut : 0.; }
  static void refresh(P &p, double kT, double dt) {
    p.pref_noise = (dt > 0. && kT > 0.) ? std::sqrt(24. * kT / dt) : 0.;
  }

  /** Squeeze friction coefficient a_sq at gap h (h < h_cut). */
  static double friction(P const &p, double h) {
    double const he = std::max(h, p.h_min);
    if (p.form == 1) { // shifted: zero at h_cut (h_e <= h < h_cut here, so both terms are >= 0)
      double a = p.a_red2 * (1. / he - 1. / p.h_cut);
      if (p.log_term)
        a += p.c_log * std::log(p.h_cut / he);
      return a > 0. ? 6. * M_PI * p.eta * a : 0.;
    }
    double a = p.a_red2 / he;
    if (p.log_term)
      a += p.c_log * std::log(p.a_mean / he);
    return a > 0. ? 6. * M_PI * p.eta * a : 0.;
  }
  /** Factor of the noise amplitude: 1 (fdt) or seed 004's weight 1 - max(h, 0)/h_cut. */
  static double noise_weight(P const &p, double h) {
    return p.noise == 0 ? 1. : 1. - std::max(h, 0.) / p.h_cut;
  }

  static Utils::Vector3d force(P const &p, Utils::Vector3d const &d, double r, Utils::Vector3d const &vij,
                               Utils::Vector3d const &xi, double /* mfac */) {
    double const h = r - p.offset;
    if (h >= p.h_cut)
      return {};
    Utils::Vector3d const e = d / r;
    double const a = friction(p, h);
    double const mag = -a * (e * vij) + p.pref_noise * std::sqrt(a) * noise_weight(p, h) * (e * xi);
    return mag * e;
  }
};

} // namespace Marble
