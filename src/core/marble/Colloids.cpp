#include "config/features.hpp"
#ifdef MARBLE
#include "marble/Colloids.hpp"

#include "forces/pair_force.hpp"
#include "forces/pair_traversal.hpp"
#include "thermostats/ou_step.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>

namespace Marble {

using Utils::Vector3d;

namespace {
/** The marble coupling's noise of the pair (colloid c, bead j): the explicit
 * force and the Shardlow update draw the same numbers. */
Vector3d marble_noise(NoiseContext const &noise, ParticleStore const &ps, int c, int j) {
  return Utils::noise_uniform(noise.seed, MarbleSurface::salt, noise.counter, static_cast<std::uint64_t>(ps.id[c]),
                              static_cast<std::uint64_t>(ps.id[j]));
}
} // namespace

void Colloids::set_types(std::vector<char> const &is_colloid) {
  m_is_colloid = is_colloid;
  m_any = std::any_of(is_colloid.begin(), is_colloid.end(), [](char c) { return c != 0; });
}

void Colloids::rebuild(ParticleStore const &ps, BoxGeometry const &box, CellSystem const &cells,
                       InteractionTable const &ia) {
  m_pairs.clear();
  m_members.clear();
  m_copies.clear();
  if (!m_any)
    return;
  find_pairs(ps, box, cells, ia);
  for (auto const &pr : m_pairs)
    for (int k : {pr.colloid, pr.other})
      (k < ps.n_local() ? m_members : m_copies).push_back(k);
  // every local colloid: on several ranks one whose partners are all on other
  // ranks gets its fast forces from there (as a remote colloid ghost)
  for (int k = 0; k < ps.n_local(); ++k)
    if (is_colloid_type(ps.type[k]))
      m_members.push_back(k);
  for (auto *list : {&m_members, &m_copies}) {
    std::sort(list->begin(), list->end());
    list->erase(std::unique(list->begin(), list->end()), list->end());
  }
}

void Colloids::find_pairs(ParticleStore const &ps, BoxGeometry const &box, CellSystem const &cells,
                          InteractionTable const &ia) {
  int const n_local = ps.n_local();
  int const nt = ia.n_types();
  double const skin = cells.skin();
  auto const &L = box.length();
  // the colloids: locals, and copies of other ranks' colloids (their pairs
  // with this rank's locals are found here; the force on the copy goes back
  // to the owner with the ghost forces)
  for (int c = 0; c < ps.size(); ++c) {
    if (c >= n_local && ps.ghost_owner[c - n_local] != kRemoteColloidGhost)
      continue;
    int const tc = ps.type[c];
    if (!is_colloid_type(tc))
      continue;
    // Interaction range of this colloid with any type.
    double range = 0.;
    for (int t = 0; t < nt; ++t)
      range = std::max({range, ia.get(tc, t).max_cut, MarbleSurface::range(ia.get(tc, t).get<MarbleSurface>())});
    if (range <= 0.)
      continue;
    range += skin;
    double const range2 = range * range;
    std::array<int, 3> nimg{};
    for (int d = 0; d < 3; ++d)
      nimg[d] = box.periodic(d) ? static_cast<int>(std::ceil(range / L[d])) : 0;
    for (int sx = -nimg[0]; sx <= nimg[0]; ++sx)
      for (int sy = -nimg[1]; sy <= nimg[1]; ++sy)
        for (int sz = -nimg[2]; sz <= nimg[2]; ++sz) {
          Vector3d const shift{sx * L[0], sy * L[1], sz * L[2]};
          Vector3d const center = ps.pos[c] + shift;
          bool outside = false;
          for (int d = 0; d < 3; ++d)
            outside |= box.periodic(d) && (center[d] + range < 0. || center[d] - range > L[d]);
          if (outside)
            continue;
          bool const self_image_ok = (sx > 0) || (sx == 0 && (sy > 0 || (sy == 0 && sz > 0)));
          cells.for_each_local_near(center, range, [&](int j) {
            if (j == c && !self_image_ok)
              return;
            int const tj = ps.type[j];
            // a pair of two colloids is listed once, by the smaller id
            if (j != c && is_colloid_type(tj) && ps.id[j] < ps.id[c])
              return;
            if ((ps.pos[j] - center).norm2() < range2)
              m_pairs.push_back({c, j, shift});
          });
        }
    // Colloids cover the whole box when range > L/2 in some direction;
    // for_each_local_near may then miss nothing, since it scans every cell overlapping the sphere.
  }
}

// Every colloid pair within range with the forces on the partner j: the
// conservative and the dissipative pair kernels separately (their sum is the
// pair force of forces/pair_force.hpp) and the marble coupling (with the
// torque on the colloid). fn(c, j, d, f_cons, f_diss, marble) with
// d = r_j - r_c(image).
template <class Fn>
void Colloids::for_each_pair_force(ParticleStore const &ps, InteractionTable const &ia,
                                   NoiseContext const &noise, Fn &&fn, bool with_marble) const {
  constexpr unsigned cons_mask = pair_kernels_with_role<KernelRole::conservative>();
  constexpr unsigned diss_mask = pair_kernels_with_role<KernelRole::pair_dissipative>();
  for (auto const &pr : m_pairs) {
    int const c = pr.colloid, j = pr.other;
    int const tc = ps.type[c], tj = ps.type[j];
    // d = r_j - r_c (the partner relative to the colloid image)
    Vector3d const d = ps.pos[j] - (ps.pos[c] + pr.shift);
    double const r2 = d.norm2();
    IAParams const &p = ia.get(tc, tj);
    MarbleParams const &m = p.get<MarbleSurface>();
    double const range = MarbleSurface::range(m);
    if (r2 >= p.max_cut * p.max_cut && !(m.active && r2 < range * range))
      continue;
    double const r = std::sqrt(r2);
    if (!(r > 0.))
      continue;
    // Forces on the partner j (F_i of the pair kernels with i = j); without
    // the thermostat only the conservative kernels act.
    auto vij = [&] { return ps.v[j] - ps.v[c]; };
    auto xi = [&]<class K>() { return pair_noise(noise, K::salt, ps.id[j], ps.id[c]); };
    auto mfac = [&] { return pair_mass_factor(ps, j, c); };
    Vector3d const f_cons = pair_force<cons_mask>(p, d, r, vij, xi, mfac);
    Vector3d const f_diss = noise.on ? pair_force<diss_mask>(p, d, r, vij, xi, mfac) : Vector3d{};
    MarbleForce mf;
    if (with_marble && m.active && noise.on) {
      mf = MarbleSurface::force(m, d, r, ps.v[j], ps.v[c], ps.omega[c], marble_noise(noise, ps, c, j));
    }
    fn(c, j, d, f_cons, f_diss, mf);
  }
}

void Colloids::add_forces(ParticleStore &ps, InteractionTable const &ia, NoiseContext const &noise,
                          bool with_conservative, bool with_marble) const {
  for_each_pair_force(
      ps, ia, noise,
      [&](int c, int j, Vector3d const &, Vector3d const &f_cons, Vector3d const &f_diss, MarbleForce const &mf) {
        // without the conservative part: RESPA's slow forces
        Vector3d f = with_conservative ? f_cons : Vector3d{};
        f += f_diss;
        f += mf.on_bead;
        ps.f[j] += f;
        ps.f[c] -= f;
#ifdef ROTATION
        ps.torque[c] += mf.torque_colloid;
#endif
      },
      with_marble);
}

// The marble coupling's exact pair update (Shardlow; doc/marble.md, "Under
// Shardlow"). Bead j (mass m), colloid c (mass M, inertia I, spin omega),
// contact point A = r_c + R n: an impulse J on j (-J on c at A, torque
// (R n) x (-J)) changes u = v_j - (v_c + omega x R n) by J (1/m + 1/M) along n
// and by J (1/m + 1/M + R^2/I) across n. The coupling's friction -gamma w^2 u
// acts on each part as an Ornstein-Uhlenbeck process with the rate
// gamma w^2 / mu (mu: the part's reduced mass), stepped exactly:
//   u' = a u + sqrt(kT/mu (1 - a^2)) sqrt(12) xi,  a = exp(-gamma w^2 dt / mu),
// with the coupling's own noise xi (uniform, variance 1/12 per component, the
// explicit force's counter-based draw), so the stationary variance is kT/mu at
// any dt. "dpd" keeps the normal part, "transverse" the tangential one,
// "tunable_slip" both. A fixed colloid acts as infinitely heavy.
void Colloids::shardlow_marble_sweep(ParticleStore &ps, InteractionTable const &ia, NoiseContext const &noise,
                                     double kT, double dt, std::vector<char> const *fixed) const {
  for (auto const &pr : m_pairs) {
    int const c = pr.colloid, j = pr.other;
    MarbleParams const &m = ia.get(ps.type[c], ps.type[j]).get<MarbleSurface>();
    if (!m.active || !(m.gamma > 0.))
      continue;
    Vector3d const d = ps.pos[j] - (ps.pos[c] + pr.shift);
    double const r2 = d.norm2();
    double const range = MarbleSurface::range(m);
    if (!(r2 < range * range))
      continue;
    double const r = std::sqrt(r2);
    if (!(r > 0.))
      continue;
    double const w = m.weight(r - m.radius);
    if (w <= 0.)
      continue;
    Vector3d const n = d / r;
    Vector3d const rA = m.radius * n;
    bool const c_fixed = fixed ? (*fixed)[static_cast<std::size_t>(c)] != 0 : c < ps.n_local() && ps.has_fixed(c);
    double const inv_m = 1. / ps.get_mass(j);
    double const inv_M = c_fixed ? 0. : 1. / ps.get_mass(c);
    double inv_I = 0.;
    Vector3d omega{};
#ifdef ROTATION
    if (ps.rotation[c] && !c_fixed)
      inv_I = 1. / ps.rinertia[c];
    omega = ps.omega[c];
#endif
    Vector3d const xi = kT > 0. ? marble_noise(noise, ps, c, j) : Vector3d{};
    Vector3d const u = ps.v[j] - (ps.v[c] + Utils::cross(omega, rA));
    double const g = m.gamma * w * w * dt;
    Vector3d J{};
    if (m.coupling != MarbleCoupling::transverse) { // along n
      double const inv_mu = inv_m + inv_M;
      OU const ou(g * inv_mu, kT * inv_mu);
      double const du = (ou.a - 1.) * (n * u) + ou.s * (n * xi);
      J += (du / inv_mu) * n;
    }
    if (m.coupling != MarbleCoupling::dpd) { // across n
      double const inv_mu = inv_m + inv_M + m.radius * m.radius * inv_I;
      OU const ou(g * inv_mu, kT * inv_mu);
      Vector3d const ut = u - (n * u) * n;
      Vector3d const xt = xi - (n * xi) * n;
      Vector3d const du = (ou.a - 1.) * ut + ou.s * xt;
      J += du / inv_mu;
    }
    ps.v[j] += inv_m * J;
    if (!c_fixed)
      ps.v[c] -= inv_M * J;
#ifdef ROTATION
    if (inv_I > 0.)
      ps.omega[c] += inv_I * Utils::cross(rA, -J);
#endif
  }
}

void Colloids::add_conservative_forces(ParticleStore const &ps, InteractionTable const &ia,
                                       std::vector<Vector3d> &f) const {
  // the pair loop without the thermostat: only the conservative kernels act
  for_each_pair_force(ps, ia, NoiseContext{},
                      [&](int c, int j, Vector3d const &, Vector3d const &f_cons, Vector3d const &,
                          MarbleForce const &) {
                        f[j] += f_cons;
                        f[c] -= f_cons;
                      });
}

void Colloids::dissipative_virial(ParticleStore const &ps, InteractionTable const &ia,
                                  NoiseContext const &noise, std::array<double, 9> &dpd,
                                  std::array<double, 9> &marble) const {
  for_each_pair_force(ps, ia, noise,
                      [&](int, int, Vector3d const &d, Vector3d const &, Vector3d const &f_diss,
                          MarbleForce const &mf) {
                        for (int a = 0; a < 3; ++a)
                          for (int b = 0; b < 3; ++b) {
                            dpd[3 * a + b] += d[a] * f_diss[b];
                            marble[3 * a + b] += d[a] * mf.on_bead[b];
                          }
                      });
}

void Colloids::conservative([[maybe_unused]] ParticleStore const &ps,
                            [[maybe_unused]] InteractionTable const &ia,
                            [[maybe_unused]] std::vector<double> &energy,
                            [[maybe_unused]] std::array<double, 9> &virial) const {
  int const nt = ia.n_types();
  for (auto const &pr : m_pairs) {
    int const c = pr.colloid, j = pr.other;
    int const tc = ps.type[c], tj = ps.type[j];
    Vector3d const d = ps.pos[j] - (ps.pos[c] + pr.shift);
    IAParams const &p = ia.get(tc, tj);
    double const r2 = d.norm2();
    if (r2 >= p.max_cut * p.max_cut)
      continue;
    double const r = std::sqrt(r2);
    auto const cons = conservative_pair(p, r);
    double const fac = cons.force_over_r, u = cons.energy;
    energy[std::min(tc, tj) * nt + std::max(tc, tj)] += u;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        virial[3 * a + b] += fac * d[a] * d[b];
  }
}

std::string Colloids::check_rotation([[maybe_unused]] ParticleStore const &ps,
                                    [[maybe_unused]] InteractionTable const &ia) const {
  if (!m_any)
    return {};
#ifdef ROTATION
  for (int i = 0; i < ps.n_local(); ++i) {
    int const t = ps.type[i];
    if (!is_colloid_type(t) || ps.rotation[i])
      continue;
    for (int s = 0; s < ia.n_types(); ++s) {
      auto const &m = ia.get(t, s).get<MarbleSurface>();
      if (m.active && m.transmits_torque())
        return "particle " + std::to_string(ps.id[i]) + " (type " + std::to_string(t) +
               ") has a marble coupling that exerts torque ('" +
               MarbleSurface::coupling_names[static_cast<int>(m.coupling)] + "' with type " +
               std::to_string(s) + ") but does not rotate: set rotation=True on it (or use coupling='dpd')";
    }
  }
#endif
  return {};
}

} // namespace Marble
#endif // MARBLE
