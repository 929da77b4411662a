#pragma once
// DPD pair thermostat, reference.md section 1:
//   F_i = P [ -g_par w_par^2 v + s_par w_par xi ] + (I - P)[ -g_perp w_perp^2 v + s_perp w_perp xi ]
// with P = e e^T, s = sqrt(24 kT g / dt) (uniform noise of variance 1/12),
// w = 1 (weight_function 0) or 1 - (r/r_cut)^k (weight_function 1).
// The optional offset (default 0, not in espressomd) evaluates the weights at
// the gap x = max(r - offset, 0) (r_cut measured from the offset), e.g.
// offset = R for the colloid-solvent DPD of seed 004 (doc/suspensions.md);
// max(r - 0., 0.) is r exactly, so offset 0 keeps the plain DPD bit for bit.
#include "config/features.hpp"
#include "nonbonded/kernel.hpp"
#include "utils/Vector.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>

namespace Marble {

struct DPDWeight {
  int weight_function = 0; // 0: w = 1; 1: w = 1 - (r/r_cut)^k
  double gamma = 0., k = 1., r_cut = 0.;
  double pref_noise = 0.; // sqrt(24 kT gamma M / dt), kept up to date by refresh()

  double weight(double r) const {
    if (r >= r_cut)
      return 0.;
    if (weight_function == 0)
      return 1.;
    double const x = r / r_cut;
    return 1. - (k == 1. ? x : std::pow(x, k));
  }
};

/** Pair mass factor M_ij for DPD_MASS_RED / DPD_MASS_LIN, 1 otherwise. */
inline double dpd_mass_factor(double mi, double mj) {
#if defined(DPD_MASS_RED)
  return 2. * mi * mj / (mi + mj);
#elif defined(DPD_MASS_LIN)
  return 0.5 * (mi + mj);
#else
  (void)mi;
  (void)mj;
  return 1.;
#endif
}

struct DPDPair {
  static constexpr char const *name = "dpd", *feature = "DPD", *py_class = "DPDInteraction",
                              *doc = "DPD pair friction and noise (needs system.thermostat.set_dpd): weight_function 0: w = 1, 1: w = 1 - (r/r_cut)^k; transverse part with TRANS_DPD.";
  static constexpr KernelRole role = KernelRole::pair_dissipative;
  static constexpr Utils::RNGSalt salt = Utils::RNGSalt::dpd;
  struct Params {
    bool active = false;
    double offset = 0.;
    DPDWeight radial;
#ifdef TRANS_DPD
    DPDWeight trans;
#endif
  };
  using P = Params;

  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f;
      auto wf = [](char const *key, auto get, auto set) {
        Field<P> x{key, FieldType::integer, get, set};
        x.lo = 0., x.hi = 1.;
        x.hint = "0 (w = 1) or 1 (w = 1 - (r/r_cut)^k)";
        return x;
      };
      f.push_back(wf("weight_function", [](P const &p) { return double(p.radial.weight_function); },
                     [](P &p, double x) { p.radial.weight_function = int(x); }));
      f.push_back(real<P>("gamma", [](P const &p) { return p.radial.gamma; }, [](P &p, double x) { p.radial.gamma = x; }, 0., INFINITY));
      f.push_back(real<P>("k", [](P const &p) { return p.radial.k; }, [](P &p, double x) { p.radial.k = x; }, 0., INFINITY, true));
      f.back().default_value = 1.;
      f.push_back(real<P>("r_cut", [](P const &p) { return p.radial.r_cut; }, [](P &p, double x) { p.radial.r_cut = x; }, 0., INFINITY));
#ifdef TRANS_DPD
      f.push_back(wf("trans_weight_function", [](P const &p) { return double(p.trans.weight_function); },
                     [](P &p, double x) { p.trans.weight_function = int(x); }));
      f.push_back(real<P>("trans_gamma", [](P const &p) { return p.trans.gamma; }, [](P &p, double x) { p.trans.gamma = x; }, 0., INFINITY));
      f.push_back(real<P>("trans_r_cut", [](P const &p) { return p.trans.r_cut; }, [](P &p, double x) { p.trans.r_cut = x; }, 0., INFINITY));
#else
      for (auto key : {"trans_weight_function", "trans_gamma", "trans_r_cut"}) {
        Field<P> x{key, std::string_view(key) == "trans_weight_function" ? FieldType::integer : FieldType::real,
                   [](P const &) { return 0.; }, [](P &, double) {}};
        x.missing_feature = "TRANS_DPD";
        f.push_back(x);
      }
#endif
      f.push_back(real<P>("offset", [](P const &p) { return p.offset; }, [](P &p, double x) { p.offset = x; }, 0., INFINITY));
      return f;
    }();
    return f;
  }
  /** Where the weights are evaluated: the gap max(r - offset, 0). */
  static double gap(P const &p, double r) { return std::max(r - p.offset, 0.); }
  static void finish([[maybe_unused]] P &p) {
#ifdef TRANS_DPD
    p.trans.k = p.radial.k; // espressomd: one exponent k for both weights
#endif
  }
  static bool activates(P const &p) {
#ifdef TRANS_DPD
    return (p.radial.gamma > 0. && p.radial.r_cut > 0.) || (p.trans.gamma > 0. && p.trans.r_cut > 0.);
#else
    return p.radial.gamma > 0. && p.radial.r_cut > 0.;
#endif
  }
  static double range(P const &p) {
    if (!p.active)
      return 0.;
#ifdef TRANS_DPD
    return (p.radial.r_cut > p.trans.r_cut ? p.radial.r_cut : p.trans.r_cut) + p.offset;
#else
    return p.radial.r_cut + p.offset;
#endif
  }
  static void refresh(P &p, double kT, double dt) {
    p.radial.pref_noise = noise_prefactor(kT, p.radial.gamma, dt);
#ifdef TRANS_DPD
    p.trans.pref_noise = noise_prefactor(kT, p.trans.gamma, dt);
#endif
  }

  /**
   * DPD force on particle i.
   * @param d     r_i - r_j, @param r |d| (> 0)
   * @param vij   v_i - v_j
   * @param xi    noise vector for the unordered pair, already multiplied by the
   *              id-order sign (+1 if id_i < id_j, else -1) so that F_j = -F_i.
   * @param mfac  M_ij (1 without DPD_MASS_*); scales gamma by M, noise by sqrt(M).
   */
  static Utils::Vector3d force(P const &p, Utils::Vector3d const &d, double r,
                               Utils::Vector3d const &vij, Utils::Vector3d const &xi, double mfac) {
    Utils::Vector3d const e = d / r;
    double const ev = e * vij;
    double const exi = e * xi;
    double const sq_m = (mfac == 1.) ? 1. : std::sqrt(mfac);
    Utils::Vector3d force{};
    double const x = gap(p, r);
    double const w = p.radial.weight(x);
    if (w > 0.) {
      double const mag = -p.radial.gamma * mfac * w * w * ev + p.radial.pref_noise * sq_m * w * exi;
      force = mag * e;
    }
#ifdef TRANS_DPD
    double const wt = p.trans.weight(x);
    if (wt > 0. && p.trans.gamma > 0.) {
      // (I - P) applied to -g w^2 v + s w xi
      Utils::Vector3d const v_perp = vij - ev * e;
      Utils::Vector3d const xi_perp = xi - exi * e;
      force += (-p.trans.gamma * mfac * wt * wt) * v_perp + (p.trans.pref_noise * sq_m * wt) * xi_perp;
    }
#endif
    return force;
  }
};

using DPDParams = DPDPair::Params;

} // namespace Marble
