#include "config/features.hpp"
#ifdef MARBLE
#include "marble/Colloids.hpp"

#include "utils/noise.hpp"

#include <algorithm>
#include <cmath>

namespace Marble {

using Utils::Vector3d;

void Colloids::grow(int n) {
  if (n <= m_n)
    return;
  std::vector<MarbleParams> t(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < m_n; ++i)
    for (int j = 0; j < m_n; ++j)
      t[i * n + j] = m_table[i * m_n + j];
  m_table.swap(t);
  m_is_colloid.resize(n, 0);
  m_n = n;
}

void Colloids::set(int c, int s, MarbleParams const &p) {
  grow(std::max(c, s) + 1);
  m_table[c * m_n + s] = p;
  m_any = false;
  std::fill(m_is_colloid.begin(), m_is_colloid.end(), 0);
  for (int i = 0; i < m_n; ++i)
    for (int j = 0; j < m_n; ++j)
      if (m_table[i * m_n + j].active) {
        m_is_colloid[i] = 1;
        m_any = true;
      }
}

MarbleParams const &Colloids::get(int c, int s) const {
  static MarbleParams const none{};
  if (c >= m_n || s >= m_n)
    return none;
  return m_table[c * m_n + s];
}

bool Colloids::is_solvent_type(int t) const {
  for (int c = 0; c < m_n; ++c)
    if (t < m_n && m_table[c * m_n + t].active)
      return true;
  return false;
}

void Colloids::update_prefactors(double kT, double dt) {
  for (auto &p : m_table)
    p.pref_noise = (dt > 0. && kT > 0. && p.gamma > 0.) ? std::sqrt(24. * kT * p.gamma / dt) : 0.;
}

void Colloids::rebuild(ParticleStore const &ps, BoxGeometry const &box, CellSystem const &cells,
                       InteractionTable const &ia) {
  m_pairs.clear();
  if (!m_any)
    return;
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
      range = std::max({range, ia.get(tc, t).max_cut, get(tc, t).range()});
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

void Colloids::add_forces(ParticleStore &ps, InteractionTable const &ia, NoiseContext const &noise) const {
  for (auto const &pr : m_pairs) {
    int const c = pr.colloid, j = pr.other;
    int const tc = ps.type[c], tj = ps.type[j];
    // d = r_j - r_c (the partner relative to the colloid image)
    Vector3d const d = ps.pos[j] - (ps.pos[c] + pr.shift);
    double const r2 = d.norm2();
    IAParams const &p = ia.get(tc, tj);
    MarbleParams const &m = get(tc, tj);
    if (r2 >= p.max_cut * p.max_cut && !(m.active && r2 < m.range() * m.range()))
      continue;
    double const r = std::sqrt(r2);
    if (!(r > 0.))
      continue;
    // Force on the partner j (F_i of the pair kernels with i = j).
    Vector3d f = conservative_pair(p, r).force_over_r * d;
    Vector3d torque{};
#ifdef DPD
    if (noise.on && p.dpd.active) {
      int const a = ps.id[j], b = ps.id[c];
      Vector3d const xi =
          a < b ? Utils::noise_uniform(noise.seed, Utils::RNGSalt::dpd, noise.counter,
                                       static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b))
                : -Utils::noise_uniform(noise.seed, Utils::RNGSalt::dpd, noise.counter,
                                        static_cast<std::uint64_t>(b), static_cast<std::uint64_t>(a));
      double mfac = 1.;
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
      mfac = dpd_mass_factor(ps.mass[j], ps.mass[c]);
#endif
      f += dpd_pair_force(p.dpd, d, r, ps.v[j] - ps.v[c], xi, mfac);
    }
#endif
    if (m.active && noise.on) {
      Vector3d const xi = Utils::noise_uniform(noise.seed, Utils::RNGSalt::marble, noise.counter,
                                               static_cast<std::uint64_t>(ps.id[c]),
                                               static_cast<std::uint64_t>(ps.id[j]));
      auto const mf = marble_force(m, d, r, ps.v[j], ps.v[c], ps.omega[c], xi);
      f += mf.on_bead;
      torque = mf.torque_colloid;
    }
    ps.f[j] += f;
    ps.f[c] -= f;
#ifdef ROTATION
    ps.torque[c] += torque;
#endif
  }
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

std::string Colloids::check_rotation([[maybe_unused]] ParticleStore const &ps) const {
  if (!m_any)
    return {};
#ifdef ROTATION
  for (int i = 0; i < ps.n_local(); ++i) {
    int const t = ps.type[i];
    if (!is_colloid_type(t) || ps.rotation[i])
      continue;
    for (int s = 0; s < m_n; ++s)
      if (get(t, s).active && get(t, s).transmits_torque())
        return "particle " + std::to_string(ps.id[i]) + " (type " + std::to_string(t) +
               ") has a marble coupling that exerts torque ('" +
               (get(t, s).coupling == MarbleCoupling::tunable_slip ? "tunable_slip" : "transverse") +
               "' with type " + std::to_string(s) +
               ") but does not rotate: set rotation=True on it (or use coupling='dpd')";
  }
#endif
  return {};
}

} // namespace Marble
#endif // MARBLE
