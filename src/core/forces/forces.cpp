// The force driver: one pass over the Verlet list, with the set of kernels
// (LJ / hat / DPD) fixed at compile time for each instantiation of the loop,
// so a scene pays only for the kernels some type pair uses.
#include "system/System.hpp"
#include "utils/errors.hpp"
#include "utils/noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace Marble {

using Utils::Vector3d;

namespace {

// Per-type-pair data the loop needs for every listed pair, in small dense
// tables (the full IAParams is only read for pairs within range).
struct PairTables {
  int n = 0;
  std::vector<double> cut2;
  std::vector<char> dpd_on;
  explicit PairTables(InteractionTable const &ia) : n(ia.n_types()) {
    cut2.resize(static_cast<std::size_t>(n) * n);
    dpd_on.resize(cut2.size());
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        auto const &p = ia.get(a, b);
        cut2[a * n + b] = p.max_cut2;
#ifdef DPD
        dpd_on[a * n + b] = p.dpd.active;
#else
        dpd_on[a * n + b] = 0;
#endif
      }
  }
};

// The list is processed in blocks of kBlock pairs, in three passes that keep
// the list order (so the force summation order, and the trajectory, are
// bit-for-bit those of a plain one-pass loop):
//   1. select the pairs within their cutoff, without a branch (half to two
//      thirds of the listed pairs are outside: a branch there is mispredicted
//      often);
//   2. draw the Philox noise of the selected pairs: independent iterations
//      that the CPU overlaps (the noise is the single largest cost);
//   3. evaluate the kernels and accumulate the forces.
constexpr int kBlock = 512;

template <bool LJ_ON, bool HAT_ON, bool DPD_ON>
void pair_loop(ParticleStore &ps, std::vector<std::array<int, 2>> const &pairs,
               InteractionTable const &ia, NoiseContext const &th) {
  (void)th;
  auto const *const pos = ps.pos.data();
  [[maybe_unused]] auto const *const vel = ps.v.data();
  auto *const frc = ps.f.data();
  auto const *const typ = ps.type.data();
  [[maybe_unused]] auto const *const pid = ps.id.data();
  PairTables const tab(ia);
  int const nt = tab.n;
  bool const one_type = nt == 1;
  double const cut2_0 = nt > 0 ? tab.cut2[0] : 0.;
  auto const *const pr = pairs.data();
  std::size_t const n_pairs = pairs.size();
  std::array<int, kBlock> sel;
  [[maybe_unused]] std::array<Vector3d, kBlock> xi;
  for (std::size_t b0 = 0; b0 < n_pairs; b0 += kBlock) {
    int const nb = static_cast<int>(std::min<std::size_t>(kBlock, n_pairs - b0));
    auto const *const blk = pr + b0;
    // 1. pairs within range
    int m = 0;
    if (one_type) {
      for (int q = 0; q < nb; ++q) {
        Vector3d const d = pos[blk[q][0]] - pos[blk[q][1]];
        sel[m] = q;
        m += !(d.norm2() >= cut2_0) ? 1 : 0; // (a NaN distance is kept: the force check reports it)
      }
    } else {
      for (int q = 0; q < nb; ++q) {
        int const i = blk[q][0], j = blk[q][1];
        Vector3d const d = pos[i] - pos[j];
        sel[m] = q;
        m += !(d.norm2() >= tab.cut2[typ[i] * nt + typ[j]]) ? 1 : 0;
      }
    }
#ifdef DPD
    // 2. noise of the unordered pair; the sign follows id order so F_j = -F_i
    if constexpr (DPD_ON) {
      for (int s = 0; s < m; ++s) {
        int const i = blk[sel[s]][0], j = blk[sel[s]][1];
        if (!one_type && !tab.dpd_on[typ[i] * nt + typ[j]])
          continue;
        int const a = pid[i], b = pid[j];
        bool const flip = !(a < b);
        Vector3d const x = Utils::noise_uniform(th.seed, Utils::RNGSalt::dpd, th.counter,
                                                static_cast<std::uint64_t>(flip ? b : a),
                                                static_cast<std::uint64_t>(flip ? a : b));
        xi[s] = flip ? -x : x;
      }
    }
#endif
    // 3. kernels
    for (int s = 0; s < m; ++s) {
      int const i = blk[sel[s]][0], j = blk[sel[s]][1];
      IAParams const &p = ia.get(typ[i], typ[j]);
      Vector3d const d = pos[i] - pos[j];
      double const r = std::sqrt(d.norm2());
      double fac = 0.;
#ifdef LENNARD_JONES
      if constexpr (LJ_ON)
        if (p.lj.active)
          fac += p.lj.force_over_r(r);
#endif
#ifdef HAT
      if constexpr (HAT_ON)
        if (p.hat.active)
          fac += p.hat.force_over_r(r);
#endif
      Vector3d force = fac * d;
#ifdef DPD
      if constexpr (DPD_ON) {
        if (p.dpd.active && r > 0.) {
          double mfac = 1.;
#if defined(DPD_MASS_RED) || defined(DPD_MASS_LIN)
          mfac = dpd_mass_factor(ps.mass[i], ps.mass[j]);
#endif
          force += dpd_pair_force(p.dpd, d, r, vel[i] - vel[j], xi[s], mfac);
        }
      }
#endif
      frc[i] += force;
      frc[j] -= force;
    }
  }
}

using LoopFn = void (*)(ParticleStore &, std::vector<std::array<int, 2>> const &,
                        InteractionTable const &, NoiseContext const &);

template <int Mask> constexpr LoopFn loop_for() {
  return &pair_loop<(Mask & 1) != 0, (Mask & 2) != 0, (Mask & 4) != 0>;
}

constexpr LoopFn loops[8] = {loop_for<0>(), loop_for<1>(), loop_for<2>(), loop_for<3>(),
                             loop_for<4>(), loop_for<5>(), loop_for<6>(), loop_for<7>()};

} // namespace

void System::compute_forces(bool with_thermostat) {
  ensure_lists();
  for (auto &f : m_ps.f)
    f = {};
#ifdef ROTATION
  for (auto &t : m_ps.torque)
    t = {};
#endif
  KernelMask const k = m_ia.kernels();
  NoiseContext const th = noise_context(with_thermostat);
  int const mask =
      (k.lj ? 1 : 0) | (k.hat ? 2 : 0) | ((k.dpd && th.on && m_dpd_in_pair_loop) ? 4 : 0);
  loops[mask](m_ps, m_cells.pairs(), m_ia, th);
  add_extra_forces(with_thermostat); // colloid pairs, constraints
  m_cells.reduce_ghost_forces(m_ps);
#ifdef EXTERNAL_FORCE
  for (int i = 0; i < m_ps.n_local(); ++i) {
    m_ps.f[i] += m_ps.ext_force[i];
#ifdef ROTATION
    m_ps.torque[i] += m_ps.ext_torque[i];
#endif
  }
#endif
  m_forces_valid = true;
}

void System::check_forces_finite() const {
  std::string msg;
  for (int i = 0; i < m_ps.n_local(); ++i) {
    bool bad = !Utils::isfinite(m_ps.f[i]);
#ifdef ROTATION
    bad = bad || !Utils::isfinite(m_ps.torque[i]);
#endif
    if (bad) {
      msg = "non-finite force on particle " + std::to_string(m_ps.id[i]) + " at step " +
            std::to_string(m_step) +
            ": likely cause: overlapping particles (a singular potential at r -> 0) or a "
            "time step too large for the interactions; remove overlaps with "
            "integrator.set_steepest_descent() or reduce time_step";
      break;
    }
  }
  m_comm.throw_if_any(msg); // on every rank, so none waits in a collective call
}

} // namespace Marble
