#pragma once
// Tangential ("stick") friction between rotating spheres on the surface gap
// h = r - (a1 + a2) (doc/suspensions.md, "Stick colloids"): the rotational
// DPD of Espanol's fluid particle model (Espanol 1998, PRE 57, 2930, there
// for equal spheres with the lever r/2) with the lever split in proportion to
// the radii. For a pair (i, j), d = r_i - r_j, e = d/r, P = I - e e^T,
// lam_i = a_i/(a_i + a_j) (lam = 1 for a colloid with a point bead, 1/2 for
// two equal spheres),
//   u   = v_i - v_j - (lam_i omega_i + lam_j omega_j) x d
//   F_i = P [ -gamma w^2 u + sqrt(24 kT gamma / dt) w xi ],   F_j = -F_i,
//   T_i = -lam_i d x F_i,   T_j = -lam_j d x F_i,
// w = 1 - max(h, 0)/r_cut for h < r_cut (0 beyond), xi the pair's uniform
// 3-vector (variance 1/12, its own salt). u is the relative velocity of the
// two rigid bodies at the pair's contact point (at -lam_i d from i), so the
// friction drives the solvent near a colloid to the colloid's rigid-body
// velocity v_c + omega_c x (r - r_c): the no-slip condition. The force pair
// acts at that one point: momentum and angular momentum (sum r x F + T) are
// conserved exactly, and the power is F_i . u = -gamma w^2 |P u|^2 <= 0.
// (A lever a_i e instead of lam_i d, i.e. the colloid's surface point for a
// bead at r > a_i, would leave the net torque h e x F_i.) The noise variance
// 2 kT gamma w^2/dt per tangential direction is the fluctuation-dissipation
// partner of the friction for the tangential mode of effective inverse mass
// 1/mu_t = 1/m_i + 1/m_j + r^2 (lam_i^2/I_i + lam_j^2/I_j) (isotropic inertia).
// Hydrodynamic friction: not scaled by DPD_MASS_* factors.
//
// Shared shells (option shared, doc/suspensions.md section 7c): a point j
// inside the friction shells of n > 1 surfaces (a bead in the gap between two
// colloids) is pulled towards every surface's rigid-body velocity, which
// couples the surfaces through it. shared = "full" (default) keeps gamma for
// every pair; "split" uses gamma/n for each of its n pairs (the point's total
// friction stays gamma w^2); "off" drops the pairs of a point shared by n > 1
// surfaces. n counts the active surface_friction pairs of j with a partner of
// radius > 0 and w > 0; it depends on positions only, so each pair keeps the
// fluctuation-dissipation partner of its own friction (noise variance
// 2 kT gamma_pair w^2/dt with gamma_pair = gamma s(n)), and momentum and
// angular momentum stay conserved pair by pair.
//
// The radii are ordered: non_bonded_inter[t1, t2].surface_friction with a1 the
// radius of type t1 and a2 that of t2; the table stores the mirrored
// parameters (a1 <-> a2) for [t2, t1] (mirrored()), so the parameters found
// for a pair (i, j) always have a1 = a_i.
#include "nonbonded/kernel.hpp"
#include "utils/Vector.hpp"
#include "utils/checks.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace Marble {

struct SurfaceFrictionForce {
  Utils::Vector3d f_i{}, torque_i{}, torque_j{};
};

struct SurfaceFriction {
  static constexpr char const *name = "surface_friction", *feature = "TRANS_DPD",
                              *py_class = "SurfaceFrictionInteraction",
                              *doc = "Stick (tangential) friction between rotating spheres of radii a1 (type i) and a2 "
                                     "(type j) on the gap h = r - a1 - a2 < r_cut (needs the DPD thermostat for kT, and "
                                     "ROTATION for the torques): F_i = (1 - e e) [-gamma w^2 u + noise], u = v_ij - "
                                     "(lam_i omega_i + lam_j omega_j) x d, lam = a/(a1 + a2), w = 1 - h/r_cut, noise "
                                     "variance 2 kT gamma w^2/dt; torques -lam d x F. shared: 'full' (default), 'split' (gamma/n) or 'off' "
                                     "(0) for the pairs of a point inside n > 1 surfaces' shells.";
  static constexpr KernelRole role = KernelRole::rotational_pair;
  static constexpr Utils::RNGSalt salt = Utils::RNGSalt::surface_friction;
  static constexpr char const *shared_names[] = {"full", "split", "off"};
  enum Shared : int { shared_full = 0, shared_split = 1, shared_off = 2 };
  struct Params {
    bool active = false;
    double gamma = 0., r_cut = 0., a1 = 0., a2 = 0.;
    int shared = shared_full;
    // derived (finish / check_pair / refresh)
    double offset = 0., lam1 = 0.5, lam2 = 0.5;
    double pref_noise = 0.; // sqrt(24 kT gamma / dt)
  };
  using P = Params;
  static std::vector<Field<P>> const &fields() {
    static std::vector<Field<P>> const f = [] {
      std::vector<Field<P>> f{
          real<P>("gamma", [](P const &p) { return p.gamma; }, [](P &p, double x) { p.gamma = x; }, 0., INFINITY),
          real<P>("r_cut", [](P const &p) { return p.r_cut; }, [](P &p, double x) { p.r_cut = x; }, 0., INFINITY, true),
          real<P>("a1", [](P const &p) { return p.a1; }, [](P &p, double x) { p.a1 = x; }, 0., INFINITY),
          real<P>("a2", [](P const &p) { return p.a2; }, [](P &p, double x) { p.a2 = x; }, 0., INFINITY)};
      Field<P> sh{"shared", FieldType::choice, [](P const &p) { return double(p.shared); },
                  [](P &p, double x) { p.shared = int(x); }};
      sh.choices = {shared_names[0], shared_names[1], shared_names[2]};
      f.push_back(sh);
      f[0].required = f[1].required = true;
      return f;
    }();
    return f;
  }
  static void finish(P &p) {
    double const s = p.a1 + p.a2;
    p.offset = s;
    // two points: the lever split is a convention (Espanol's r/2)
    p.lam1 = s > 0. ? p.a1 / s : 0.5;
    p.lam2 = s > 0. ? p.a2 / s : 0.5;
  }
  /** Scene check at set_params: one type has one radius. */
  template <class Sys> static void check_pair(Sys const &, int t1, int t2, P const &p) {
    if (t1 == t2 && p.a1 != p.a2)
      Utils::value_error("surface_friction: a pair of one type (" + std::to_string(t1) +
                         ") needs a1 == a2 (got a1 = " + std::to_string(p.a1) + ", a2 = " + std::to_string(p.a2) + ")");
  }
  /** The parameters of the reversed type pair (InteractionTable::set_kernel). */
  static P mirrored(P const &p) {
    P q = p;
    std::swap(q.a1, q.a2);
    std::swap(q.lam1, q.lam2);
    return q;
  }
  static bool activates(P const &p) { return p.gamma > 0.; }
  static double range(P const &p) { return p.active ? p.offset + p.r_cut : 0.; }
  static void refresh(P &p, double kT, double dt) { p.pref_noise = noise_prefactor(kT, p.gamma, dt); }

  /** The factor s of gamma for a pair whose point partner lies in @p n >= 1 shells (see the header). */
  static double shared_scale(P const &p, int n) {
    if (n <= 1 || p.shared == shared_full)
      return 1.;
    return p.shared == shared_split ? 1. / n : 0.;
  }
  /** The multiplicity n of the pair (i, j): the shells holding the partner of a surface (>= 1). */
  static int pair_shells(P const &p, int n_i, int n_j) {
    int n = 1;
    if (p.a1 > 0.)
      n = std::max(n, n_j);
    if (p.a2 > 0.)
      n = std::max(n, n_i);
    return n;
  }
  static double weight(P const &p, double r) {
    double const h = r - p.offset;
    if (h >= p.r_cut)
      return 0.;
    return 1. - std::max(h, 0.) / p.r_cut;
  }
  /** Relative contact-point velocity u of the pair (i, j) whose parameters @p p are (see the header). */
  static Utils::Vector3d contact_velocity(P const &p, Utils::Vector3d const &d, Utils::Vector3d const &vij,
                                          Utils::Vector3d const &omega_i, Utils::Vector3d const &omega_j) {
    return vij - Utils::cross(p.lam1 * omega_i + p.lam2 * omega_j, d);
  }
  /**
   * Force on i and the torques on i and j; @p p are the parameters of (type_i, type_j) (a1 = a_i).
   * @param d r_i - r_j, @param r |d| > 0, @param vij v_i - v_j
   * @param xi pair noise signed by id order (F_j = -F_i), or zero
   * @param scale the shared-shell factor s of gamma (shared_scale(); noise sqrt(s))
   */
  static SurfaceFrictionForce force(P const &p, Utils::Vector3d const &d, double r, Utils::Vector3d const &vij, Utils::Vector3d const &omega_i,
                                    Utils::Vector3d const &omega_j, Utils::Vector3d const &xi, double scale = 1.) {
    SurfaceFrictionForce out;
    double const w = weight(p, r);
    if (w <= 0. || scale <= 0.)
      return out;
    Utils::Vector3d const e = d / r;
    Utils::Vector3d const u = contact_velocity(p, d, vij, omega_i, omega_j);
    Utils::Vector3d const g = (-p.gamma * scale * w * w) * u + (p.pref_noise * std::sqrt(scale) * w) * xi;
    Utils::Vector3d const f = g - (e * g) * e;
    Utils::Vector3d const dxf = Utils::cross(d, f);
    out.f_i = f;
    out.torque_i = -p.lam1 * dxf;
    out.torque_j = -p.lam2 * dxf;
    return out;
  }
};

} // namespace Marble
