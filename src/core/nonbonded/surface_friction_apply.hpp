#pragma once
// Where the rotational pair kernel (nonbonded/surface_friction.hpp) acts: the
// pairs of the main Verlet list, in its own pass, because the pair loop of
// forces/ carries neither spins nor torques.
//   - explicit forces and torques (velocity Verlet, DPD-VV: System::add_extra_forces);
//   - the exact pair update of the Shardlow sweep (integrators/shardlow.cpp);
//   - the virial sum d (x) F_i for System::dpd_stress() (friction and noise).
// Without ROTATION the spins are zero and the torques are dropped (the kernel
// then acts like a tangential DPD friction on the contact point at rest).
#include "cells/CellSystem.hpp"
#include "config/features.hpp"
#include "forces/pair_traversal.hpp"
#include "nonbonded/InteractionTable.hpp"
#include "nonbonded/surface_friction.hpp"
#include "particles/ParticleStore.hpp"
#include "thermostats/NoiseContext.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace Marble {

#ifdef TRANS_DPD
namespace detail {
inline Utils::Vector3d spin(ParticleStore const &ps, int i) {
#ifdef ROTATION
  return ps.omega[i];
#else
  (void)ps, (void)i;
  return {};
#endif
}
/** 1/I of particle @p i (0 if it does not rotate). */
inline double inv_inertia(ParticleStore const &ps, int i) {
#ifdef ROTATION
  return ps.rotation[i] ? 1. / ps.rinertia[i] : 0.;
#else
  (void)ps, (void)i;
  return 0.;
#endif
}
} // namespace detail

/** Call fn(i, j, d, r, params) for every pair of the main list with an active surface_friction. */
template <class Fn>
void for_each_surface_friction_pair(ParticleStore const &ps, PairList const &pairs, InteractionTable const &ia,
                                    Fn &&fn) {
  for_each_pair(ps, pairs, ia, [&](int i, int j) {
    auto const &p = ia.get(ps.type[i], ps.type[j]).get<SurfaceFriction>();
    if (!p.active)
      return;
    Utils::Vector3d const d = ps.pos[i] - ps.pos[j];
    double const r = std::sqrt(d.norm2());
    if (!(r > 0.) || SurfaceFriction::weight(p, r) <= 0.)
      return;
    fn(i, j, d, r, p);
  });
}

/**
 * Shared shells (surface_friction.hpp, option shared): the number of shells
 * holding each particle (list index), n_k = the active pairs (k, s) with w > 0
 * whose partner s has a radius > 0. Empty (every pair n = 1) unless some
 * active pair has shared != "full". Complete for ghosts too: serially every
 * ghost is an image of a local (counted on the owner); with several ranks the
 * counts go through the ghost exchange (each pair is listed on one rank).
 * Depends on positions only (fixed during a Shardlow sweep and a force pass).
 */
inline std::vector<int> surface_friction_shells(ParticleStore const &ps, CellSystem const &cells, InteractionTable const &ia,
                                                bool parallel) {
  std::vector<int> n;
  bool any_shared = false;
  for (int t1 = 0; t1 < ia.n_types(); ++t1)
    for (int t2 = 0; t2 < ia.n_types(); ++t2) {
      auto const &p = ia.get(t1, t2).get<SurfaceFriction>();
      any_shared = any_shared || (p.active && p.shared != SurfaceFriction::shared_full);
    }
  if (!any_shared)
    return n;
  int const nl = ps.n_local();
  auto owner = [&](int k) { return k < nl ? k : ps.ghost_owner[k - nl]; };
  std::vector<Utils::Vector3d> c(static_cast<std::size_t>(ps.size()));
  for_each_surface_friction_pair(ps, cells.pairs(), ia, [&](int i, int j, Utils::Vector3d const &, double,
                                                            SurfaceFriction::Params const &p) {
    if (p.a1 > 0.)
      c[parallel ? j : owner(j)][0] += 1.;
    if (p.a2 > 0.)
      c[parallel ? i : owner(i)][0] += 1.;
  });
  if (parallel) {
    cells.reduce_ghost_values(ps, c);
    cells.fill_ghost_values(ps, c);
  }
  n.resize(c.size());
  for (std::size_t k = 0; k < c.size(); ++k)
    n[k] = static_cast<int>(std::lround(c[parallel ? k : static_cast<std::size_t>(owner(static_cast<int>(k)))][0]));
  return n;
}

/** The shared-shell factor of the pair (i, j) (1 if @p shells is empty). */
inline double surface_friction_scale(SurfaceFriction::Params const &p, std::vector<int> const &shells, int i, int j) {
  if (shells.empty())
    return 1.;
  return SurfaceFriction::shared_scale(p, SurfaceFriction::pair_shells(p, shells[i], shells[j]));
}

/**
 * Calls fn(i, j, d, r, p, scale, xi) for every surface-friction pair that acts
 * (shared-shell factor scale > 0), with its counter-based noise xi: the one
 * place where the explicit force and its virial take the pair's scale and noise.
 */
template <class F>
void for_each_scaled_surface_friction_pair(ParticleStore const &ps, CellSystem const &cells, InteractionTable const &ia,
                                           NoiseContext const &noise, bool parallel, F &&fn) {
  std::vector<int> const shells = surface_friction_shells(ps, cells, ia, parallel);
  for_each_surface_friction_pair(ps, cells.pairs(), ia, [&](int i, int j, Utils::Vector3d const &d, double r,
                                                            SurfaceFriction::Params const &p) {
    double const scale = surface_friction_scale(p, shells, i, j);
    if (scale <= 0.)
      return;
    fn(i, j, d, r, p, scale, pair_noise(noise, SurfaceFriction::salt, ps.id[i], ps.id[j]));
  });
}

/** Explicit forces and torques (with the noise of @p noise) on locals and ghosts. */
inline void add_surface_friction_forces(ParticleStore &ps, CellSystem const &cells, InteractionTable const &ia,
                                        NoiseContext const &noise, bool parallel) {
  for_each_scaled_surface_friction_pair(
      ps, cells, ia, noise, parallel,
      [&](int i, int j, Utils::Vector3d const &d, double r, SurfaceFriction::Params const &p, double scale,
          Utils::Vector3d const &xi) {
        auto const out =
            SurfaceFriction::force(p, d, r, ps.v[i] - ps.v[j], detail::spin(ps, i), detail::spin(ps, j), xi, scale);
        ps.f[i] += out.f_i;
        ps.f[j] -= out.f_i;
#ifdef ROTATION
        ps.torque[i] += out.torque_i;
        ps.torque[j] += out.torque_j;
#endif
      });
}

/** Virial sums d (x) F_i / V of the friction and the noise (added to @p fric, @p nse). */
inline void surface_friction_virial(ParticleStore const &ps, CellSystem const &cells, InteractionTable const &ia,
                                    NoiseContext const &noise, double V, bool parallel, std::array<double, 9> &fric,
                                    std::array<double, 9> &nse) {
  Utils::Vector3d const zero{};
  for_each_scaled_surface_friction_pair(
      ps, cells, ia, noise, parallel,
      [&](int i, int j, Utils::Vector3d const &d, double r, SurfaceFriction::Params const &p, double scale,
          Utils::Vector3d const &xi) {
        auto const ff =
            SurfaceFriction::force(p, d, r, ps.v[i] - ps.v[j], detail::spin(ps, i), detail::spin(ps, j), zero, scale);
        auto const fn = SurfaceFriction::force(p, d, r, zero, zero, zero, xi, scale);
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            fric[3 * a + b] += d[a] * ff.f_i[b] / V;
            nse[3 * a + b] += d[a] * fn.f_i[b] / V;
          }
      });
}

/**
 * The exact Shardlow update of one pair's tangential contact velocity over dt
 * (Ornstein-Uhlenbeck, as the DPD pair update of integrators/shardlow.cpp):
 * with 1/mu_t = 1/m_i + 1/m_j + r^2 (lam_i^2/I_i + lam_j^2/I_j) an impulse J
 * (perpendicular to e) on i changes the tangential contact velocity by J/mu_t,
 * so u_t' = a u_t + sqrt(kT/mu_t (1 - a^2)) sqrt(12) P xi, a = exp(-gamma w^2
 * dt/mu_t), and J = mu_t (u_t' - u_t) goes to i (-J to j) with the torques
 * -lam d x J. @p oi, @p oj are the owners (locals) of list entries i, j;
 * @p scale the shared-shell factor of gamma (surface_friction_scale());
 * @p v_jump (Lees-Edwards) the velocity jump of v_i - v_j across the
 * shear plane (the owners' velocity difference plus it is the entries').
 */
inline void surface_friction_pair_update(ParticleStore &ps, SurfaceFriction::Params const &p, int i, int j, int oi,
                                         int oj, double kT, double dt, NoiseContext const &noise, double scale = 1.,
                                         Utils::Vector3d const *v_jump = nullptr) {
  if (scale <= 0.)
    return;
  Utils::Vector3d const d = ps.pos[i] - ps.pos[j];
  double const r2 = d.norm2();
  if (!(r2 > 0.))
    return;
  double const r = std::sqrt(r2);
  double const w = SurfaceFriction::weight(p, r);
  if (w <= 0.)
    return;
  double const mi = ps.get_mass(oi), mj = ps.get_mass(oj);
  double const inv_mu =
      1. / mi + 1. / mj + r2 * (p.lam1 * p.lam1 * detail::inv_inertia(ps, oi) + p.lam2 * p.lam2 * detail::inv_inertia(ps, oj));
  double const mu = 1. / inv_mu;
  Utils::Vector3d const e = d / r;
  Utils::Vector3d const vij = v_jump ? ps.v[oi] - ps.v[oj] + *v_jump : ps.v[oi] - ps.v[oj];
  Utils::Vector3d const u = SurfaceFriction::contact_velocity(p, d, vij, detail::spin(ps, oi), detail::spin(ps, oj));
  Utils::Vector3d const ut = u - (e * u) * e;
  double const a = std::exp(-p.gamma * scale * w * w * dt * inv_mu);
  Utils::Vector3d du = (a - 1.) * ut;
  if (kT > 0.) {
    Utils::Vector3d const xi = pair_noise(noise, SurfaceFriction::salt, ps.id[i], ps.id[j]);
    du += std::sqrt(12. * kT * inv_mu * (1. - a * a)) * (xi - (e * xi) * e);
  }
  Utils::Vector3d const J = mu * du;
  ps.v[oi] += J / mi;
  ps.v[oj] -= J / mj;
#ifdef ROTATION
  Utils::Vector3d const dxj = Utils::cross(d, J);
  if (ps.rotation[oi])
    ps.omega[oi] -= (p.lam1 / ps.rinertia[oi]) * dxj;
  if (ps.rotation[oj])
    ps.omega[oj] -= (p.lam2 / ps.rinertia[oj]) * dxj;
#endif
}
#endif // TRANS_DPD

} // namespace Marble
