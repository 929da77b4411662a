#pragma once
// DPD pair thermostat, reference.md section 1:
//   F_i = P [ -g_par w_par^2 v + s_par w_par xi ] + (I - P)[ -g_perp w_perp^2 v + s_perp w_perp xi ]
// with P = e e^T, s = sqrt(24 kT g / dt) (uniform noise of variance 1/12),
// w = 1 (weight_function 0) or 1 - (r/r_cut)^k (weight_function 1).
#include "config/features.hpp"
#include "utils/Vector.hpp"

#include <cmath>

namespace Marble {

struct DPDWeight {
  int weight_function = 0; // 0: w = 1; 1: w = 1 - (r/r_cut)^k
  double gamma = 0., k = 1., r_cut = 0.;
  double pref_noise = 0.; // sqrt(24 kT gamma M / dt), kept up to date by the System

  double weight(double r) const {
    if (r >= r_cut)
      return 0.;
    if (weight_function == 0)
      return 1.;
    double const x = r / r_cut;
    return 1. - (k == 1. ? x : std::pow(x, k));
  }
};

struct DPDParams {
  bool active = false;
  DPDWeight radial;
#ifdef TRANS_DPD
  DPDWeight trans;
#endif
  double max_cutoff() const {
    if (!active)
      return 0.;
#ifdef TRANS_DPD
    return radial.r_cut > trans.r_cut ? radial.r_cut : trans.r_cut;
#else
    return radial.r_cut;
#endif
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

/**
 * DPD force on particle i.
 * @param d     r_i - r_j, @param r |d| (> 0)
 * @param vij   v_i - v_j
 * @param xi    noise vector for the unordered pair, already multiplied by the
 *              id-order sign (+1 if id_i < id_j, else -1) so that F_j = -F_i.
 * @param mfac  M_ij (1 without DPD_MASS_*); scales gamma by M, noise by sqrt(M).
 */
inline Utils::Vector3d dpd_pair_force(DPDParams const &p, Utils::Vector3d const &d, double r,
                                      Utils::Vector3d const &vij, Utils::Vector3d const &xi,
                                      double mfac) {
  Utils::Vector3d const e = d / r;
  double const ev = e * vij;
  double const exi = e * xi;
  double const sq_m = (mfac == 1.) ? 1. : std::sqrt(mfac);
  Utils::Vector3d force{};
  double const w = p.radial.weight(r);
  if (w > 0.) {
    double const mag = -p.radial.gamma * mfac * w * w * ev + p.radial.pref_noise * sq_m * w * exi;
    force = mag * e;
  }
#ifdef TRANS_DPD
  double const wt = p.trans.weight(r);
  if (wt > 0. && p.trans.gamma > 0.) {
    // (I - P) applied to -g w^2 v + s w xi
    Utils::Vector3d const v_perp = vij - ev * e;
    Utils::Vector3d const xi_perp = xi - exi * e;
    force += (-p.trans.gamma * mfac * wt * wt) * v_perp + (p.trans.pref_noise * sq_m * wt) * xi_perp;
  }
#endif
  return force;
}

} // namespace Marble
