// DPD integrators that remove most of the kT(dt) drift of plain velocity
// Verlet (doc/stability.md has the measurements):
//
// Shardlow S1 splitting (Shardlow 2003; Nikunen, Karttunen, Vattulainen 2003):
// one step is
//   1. a sweep over the DPD pairs of the main Verlet list, in list order: each
//      pair's relative velocity along e (and, with TRANS_DPD, across e) is
//      advanced over dt by the exact solution of its Ornstein-Uhlenbeck process
//        du = -(gamma M w^2 / mu) u dt + noise,   mu = m_i m_j / (m_i + m_j),
//        u' = a u + sqrt(kT/mu (1 - a^2)) sqrt(12) (e . xi),  a = exp(-gamma M
//        w^2 dt / mu),
//      the momentum mu (u' - u) e going to i and -mu (u' - u) e to j (momentum
//      is conserved pair by pair; the stationary variance of u is exactly kT/mu
//      for any dt, so the friction is unconditionally stable);
//   2. velocity Verlet with the remaining forces (conservative forces, and the
//      colloid pairs and walls with their own explicit friction and noise).
// xi is the DPD pair noise of reference.md section 1 (uniform, variance 1/12,
// Philox keyed by seed, salt dpd, counter, ordered ids, sign by id order), so
// the sweep is reproducible; its result depends on the order of the pair list
// (fixed for a given particle set, decomposition and seed).
//
// DPD-VV (Besold, Vattulainen, Karttunen, Polson 2000): velocity Verlet whose
// forces for the next first half kick carry the DPD friction recomputed from
// the full-step velocities v(t + dt) instead of v(t + dt/2): after the second
// half kick dv = dt/2 F/m, F_i += sum_j -gamma M w^2 (e . (dv_i - dv_j)) e
// (and the transverse analogue): the friction is linear in v, so this is the
// friction of v(t + dt) minus that of v(t + dt/2). Colloid and wall friction
// stay explicit.
#include "integrators/dpd_integrators.hpp"
#include "integrators/stability.hpp"
#include "system/System.hpp"
#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace Marble {

using Utils::Vector3d;

namespace {

[[maybe_unused]] int owner(ParticleStore const &ps, int k) {
  int const nl = ps.n_local();
  return k < nl ? k : ps.ghost_owner[k - nl];
}

#ifdef DPD
// Exact OU factor a and noise amplitude for a friction rate lambda = gamma M
// w^2 / mu.
struct OU {
  double a, s;
  OU(double lambda_dt, double kT_over_mu) {
    a = std::exp(-lambda_dt);
    s = std::sqrt(12. * kT_over_mu *
                  (1. - a * a)); // sqrt(12): xi has variance 1/12
  }
};

// Blocks of pairs as in the force loop (forces/forces.cpp): select the pairs
// within range, draw their noise (independent iterations the CPU overlaps),
// then do the sequential velocity updates in list order.
constexpr int kBlock = 512;

#endif // DPD
} // namespace

#ifdef DPD
void shardlow_sweep(System &sys) {
  auto &ps = sys.particles();
  auto const &ia = sys.interactions();
  auto const &th = sys.thermostat().dpd;
  double const dt = sys.time_step();
  double const kT = th.kT;
  auto const &pairs = sys.cells().pairs();
  std::size_t const n_pairs = pairs.size();
  std::array<int, kBlock> sel;
  std::array<Vector3d, kBlock> xi;
  for (std::size_t b0 = 0; b0 < n_pairs; b0 += kBlock) {
    int const nb =
        static_cast<int>(std::min<std::size_t>(kBlock, n_pairs - b0));
    auto const *const blk = pairs.data() + b0;
    // 1. DPD pairs within range
    int m = 0;
    for (int q = 0; q < nb; ++q) {
      int const i = blk[q][0], j = blk[q][1];
      IAParams const &p = ia.get(ps.type[i], ps.type[j]);
      double const r2 = (ps.pos[i] - ps.pos[j]).norm2();
      sel[m] = q;
      m += (p.dpd.active && r2 < p.max_cut2 && r2 > 0.) ? 1 : 0;
    }
    // 2. noise of the unordered pair, sign by id order (reference.md section 1)
    if (kT > 0.) {
      for (int s = 0; s < m; ++s) {
        int const a = ps.id[blk[sel[s]][0]], b = ps.id[blk[sel[s]][1]];
        bool const flip = !(a < b);
        Vector3d const x = Utils::noise_uniform(
            th.seed, Utils::RNGSalt::dpd, th.philox_counter,
            static_cast<std::uint64_t>(flip ? b : a),
            static_cast<std::uint64_t>(flip ? a : b));
        xi[s] = flip ? -x : x;
      }
    } else {
      for (int s = 0; s < m; ++s)
        xi[s] = {};
    }
    // 3. exact pair updates, one after the other
    for (int s = 0; s < m; ++s) {
      int const i = blk[sel[s]][0], j = blk[sel[s]][1];
      IAParams const &p = ia.get(ps.type[i], ps.type[j]);
      Vector3d const d = ps.pos[i] - ps.pos[j];
      double const r = std::sqrt(d.norm2());
      double const w = p.dpd.radial.weight(r);
#ifdef TRANS_DPD
      double const wt = p.dpd.trans.weight(r);
      if (w <= 0. && wt <= 0.)
        continue;
#else
      if (w <= 0.)
        continue;
#endif
      int const oi = owner(ps, i), oj = owner(ps, j);
      double const mi = ps.get_mass(oi), mj = ps.get_mass(oj);
      double const mu = mi * mj / (mi + mj);
      double mfac = 1.;
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
      mfac = dpd_mass_factor(mi, mj);
#endif
      Vector3d const e = d / r;
      Vector3d const vij = ps.v[oi] - ps.v[oj];
      double const u = e * vij;
      Vector3d du{};
      if (w > 0. && p.dpd.radial.gamma > 0.) {
        OU const ou(p.dpd.radial.gamma * mfac * w * w * dt / mu, kT / mu);
        du = ((ou.a - 1.) * u + ou.s * (e * xi[s])) * e;
      }
#ifdef TRANS_DPD
      if (wt > 0. && p.dpd.trans.gamma > 0.) {
        OU const ou(p.dpd.trans.gamma * mfac * wt * wt * dt / mu, kT / mu);
        Vector3d const u_perp = vij - u * e;
        Vector3d const xi_perp = xi[s] - (e * xi[s]) * e;
        du += (ou.a - 1.) * u_perp + ou.s * xi_perp;
      }
#endif
      Vector3d const dp = mu * du;
      ps.v[oi] += dp / mi;
      ps.v[oj] -= dp / mj;
    }
  }
}

// F_i += friction of the velocity change dv (pairs of the main list only):
// the DPD pair force without noise (thermostats/dpd.hpp), with the relative
// velocity change in place of the relative velocity. @p dv_of(k) gives the
// velocity change of list index k, @p add(k, f) books the force on it.
namespace {
template <typename DV, typename Add> void friction_of_dv_pairs(System &sys, DV dv_of, Add add) {
  auto const &ps = sys.particles();
  auto const &ia = sys.interactions();
  Vector3d const no_noise{};
  for (auto const &pr : sys.cells().pairs()) {
    int const i = pr[0], j = pr[1];
    IAParams const &p = ia.get(ps.type[i], ps.type[j]);
    if (!p.dpd.active)
      continue;
    Vector3d const d = ps.pos[i] - ps.pos[j];
    double const r2 = d.norm2();
    if (!(r2 < p.max_cut2) || !(r2 > 0.))
      continue;
    double mfac = 1.;
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
    mfac = dpd_mass_factor(ps.get_mass(i), ps.get_mass(j)); // ghosts carry their owner's mass
#endif
    Vector3d const f = dpd_pair_force(p.dpd, d, std::sqrt(r2), dv_of(i) - dv_of(j), no_noise, mfac);
    add(i, f);
    add(j, -f);
  }
}
} // namespace

void add_friction_of_dv(System &sys, std::vector<Vector3d> const &dv) {
  auto &ps = sys.particles();
  if (!sys.comm().parallel()) { // every ghost is an image of a local: book on the owner
    friction_of_dv_pairs(
        sys, [&](int k) { return dv[owner(ps, k)]; },
        [&](int k, Vector3d const &f) { ps.f[owner(ps, k)] += f; });
    return;
  }
  // Several ranks: dv of the ghosts from the ghost exchange, the friction on
  // other ranks' particles accumulated per particle and sent back.
  int const n = ps.n_local();
  std::vector<Vector3d> dva(static_cast<std::size_t>(ps.size())), df(dva.size());
  std::copy(dv.begin(), dv.begin() + n, dva.begin());
  sys.cells().fill_ghost_values(ps, dva);
  friction_of_dv_pairs(
      sys, [&](int k) { return dva[k]; }, [&](int k, Vector3d const &f) { df[k] += f; });
  sys.cells().reduce_ghost_values(ps, df);
  for (int i = 0; i < n; ++i)
    ps.f[i] += df[i];
}
#endif // DPD


} // namespace Marble
