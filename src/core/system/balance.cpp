// Load balance of the domain decomposition (doc/parallel.md "Load balance").
//
// The domains are boxes between cut planes along each axis of the node grid
// (cells/CellSystem.hpp set_domain_fractions); by default the planes split
// the box into equal parts. balance_domains() moves the planes of every split
// axis so that each slab of ranks (the ranks at one node coordinate along the
// axis) holds a share of the particles proportional to its speed:
//   - BalanceBy::Particles: every slab the same speed, i.e. equal particle
//     counts (deterministic: a function of the positions only);
//   - BalanceBy::Pairs: the same with each particle weighted by 1 + the
//     pairs of its row of the Verlet list (LAMMPS's `weight neigh`): a
//     denser region, whose particles have more pairs, gets fewer particles
//     (deterministic);
//   - BalanceBy::Time: a slab's speed is its particles per second of its
//     ranks' own work since the last balance (wall time less the wall time
//     inside MPI calls, where a rank waits for its partners). A slab on a
//     slower core, or with costlier particles (colloids, a denser region),
//     then gets fewer particles. The cuts depend on the machine's timing, so
//     a run's last bits are not reproducible from run to run (as with
//     LAMMPS's `balance ... weight time`); the physics is unchanged.
// The new plane j lies where the particles' cumulative count along the axis
// reaches the slabs' cumulative speed share (a histogram of the folded
// positions, 64 bins per slab, interpolated linearly within a bin), then
// moved by `damping` of the way from the old plane, and kept at least one
// pair range (cutoff + skin; twice that under the Shardlow integrator, whose
// sweep needs it) from its neighbours. The planes are computed on every
// rank from reduced sums and then broadcast from rank 0, so that every rank
// holds the same bits.
#include "system/System.hpp"
#ifdef SRD
#include "srd/Fluid.hpp"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>

namespace Marble {

namespace {
double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
} // namespace

void System::reset_balance_clock() {
  m_balance_wall = wall_now();
  m_balance_mpi = m_comm.stats().wall_seconds;
}

void System::set_domain_cuts(std::array<std::vector<double>, 3> const &cuts) {
  std::array<std::vector<double>, 3> f;
  auto const &L = m_box.length();
  for (int d = 0; d < 3; ++d) {
    auto const &c = cuts[static_cast<std::size_t>(d)];
    if (c.empty())
      continue;
    auto &fd = f[static_cast<std::size_t>(d)];
    fd.resize(c.size());
    for (std::size_t k = 0; k < c.size(); ++k)
      fd[k] = k == 0 ? 0. : k + 1 == c.size() ? 1. : c[k] / L[d];
  }
  m_cells.set_domain_fractions(std::move(f));
}

System::BalanceResult System::balance_domains(BalanceBy by, double damping, double threshold) {
  BalanceResult res;
  if (!m_comm.parallel()) {
    reset_balance_clock();
    return res;
  }
  int const size = m_comm.size(), me = m_comm.rank();
  // each local's weight: 1, or 1 + its listed pairs (the lists of the current positions)
  std::vector<double> weight;
  if (by == BalanceBy::Pairs) {
    ensure_lists();
    auto const &pl = m_cells.pairs();
    weight.assign(static_cast<std::size_t>(m_ps.n_local()), 1.);
    int const rows = std::min(pl.n_rows(), m_ps.n_local());
    for (int i = 0; i < rows; ++i)
      weight[static_cast<std::size_t>(i)] += pl.row_start[i + 1] - pl.row_start[i];
    for (auto const &ij : pl.extra)
      for (int k : ij)
        if (k < m_ps.n_local())
          weight[static_cast<std::size_t>(k)] += 0.5;
  }
  int const n_md = m_ps.n_local();
  // SRD particles (srd/Fluid.hpp) count as particles of weight 1 (they have no pairs)
  int n_srd = 0;
#ifdef SRD
  if (srd)
    n_srd = srd->size();
#endif
  int const n_local = n_md + n_srd;
  auto position = [&](int i) -> Utils::Vector3d const & {
#ifdef SRD
    if (i >= n_md)
      return srd->pos[static_cast<std::size_t>(i - n_md)];
#endif
    return m_ps.pos[i];
  };
  // this rank's cost: its own work since the last balance, or its (weighted) particles
  double busy = static_cast<double>(n_local);
  if (by == BalanceBy::Pairs) {
    busy = n_srd;
    for (double w : weight)
      busy += w;
  }
  if (by == BalanceBy::Time) {
    double const mpi = m_comm.stats().wall_seconds;
    double const mpi_since = mpi >= m_balance_mpi ? mpi - m_balance_mpi : mpi; // (stats reset since)
    busy = std::max(0., wall_now() - m_balance_wall - mpi_since);
  }
  double cmax = busy, csum = busy;
  m_comm.max_inplace(&cmax, 1);
  m_comm.sum_inplace(&csum, 1);
  reset_balance_clock();
  res.imbalance = csum > 0. ? cmax / (csum / size) : 1.;
  if (!(csum > 0.) || res.imbalance <= 1. + threshold)
    return res;

  auto const g = m_cells.node_grid(m_box);
  auto const &L = m_box.length();
  auto const me_at = CellSystem::coords_at(g, me);
  // the narrowest domain allowed: the pair range, twice that under Shardlow
  double r = std::max({m_cells.range(), m_cells.range_ll(), m_cells.range_ls()});
  if (r <= 0.)
    r = max_cutoff() + m_cells.skin();
  if (m_integrator == IntegratorKind::Shardlow)
    r *= 2.;
  std::array<std::vector<double>, 3> frac = m_cells.domain_fractions();
  bool any = false;
  for (int d = 0; d < 3; ++d) {
    int const p = g[d];
    auto &fd = frac[static_cast<std::size_t>(d)];
    if (p < 2) {
      fd.clear();
      continue;
    }
    auto const old = m_cells.domain_cuts(m_box, d);
    double const w_min = std::min(r, L[d] / p);
    // slab sums: particles and work
    std::vector<double> slab(2 * static_cast<std::size_t>(p), 0.);
    slab[static_cast<std::size_t>(me_at[d])] += n_local;
    slab[static_cast<std::size_t>(p + me_at[d])] += busy;
    // the particles' histogram along d (folded positions; weighted by Pairs)
    int const nb = 64 * p;
    std::vector<double> hist(static_cast<std::size_t>(nb), 0.);
    double const inv = nb / L[d];
    for (int i = 0; i < n_local; ++i) {
      double x = position(i)[d];
      if (m_box.periodic(d))
        x -= L[d] * std::floor(x / L[d]);
      int const b = std::clamp(static_cast<int>(std::floor(x * inv)), 0, nb - 1);
      hist[static_cast<std::size_t>(b)] += i < n_md && !weight.empty() ? weight[static_cast<std::size_t>(i)] : 1.;
    }
    m_comm.sum_inplace(slab.data(), 2 * p);
    m_comm.sum_inplace(hist.data(), nb);
    double n_total = 0.;
    for (double h : hist)
      n_total += h;
    if (!(n_total > 0.))
      continue;
    // each slab's speed (particles per second of work; equal by particles or pairs)
    std::vector<double> speed(static_cast<std::size_t>(p), 1.);
    if (by == BalanceBy::Time) {
      double mean = 0.;
      int n_known = 0;
      for (int k = 0; k < p; ++k)
        if (slab[k] > 0. && slab[p + k] > 0.) {
          speed[k] = slab[k] / slab[p + k];
          mean += speed[k], ++n_known;
        } else {
          speed[k] = -1.;
        }
      mean = n_known ? mean / n_known : 1.;
      for (auto &s : speed)
        if (s < 0.)
          s = mean; // a slab without particles or work: the mean speed
    }
    double s_total = 0.;
    for (double s : speed)
      s_total += s;
    // the new planes: the cumulative count (or weight) reaches the cumulative speed share
    std::vector<double> cut(static_cast<std::size_t>(p) + 1);
    cut[0] = 0., cut[static_cast<std::size_t>(p)] = L[d];
    double share = 0., cum = 0.;
    int b = 0;
    for (int j = 1; j < p; ++j) {
      share += speed[static_cast<std::size_t>(j - 1)];
      double const target = n_total * share / s_total;
      while (b < nb && cum + hist[static_cast<std::size_t>(b)] < target)
        cum += hist[static_cast<std::size_t>(b++)];
      double const h = b < nb ? hist[static_cast<std::size_t>(b)] : 0.;
      double const t = h > 0. ? (target - cum) / h : 0.;
      double const y = (b + std::clamp(t, 0., 1.)) / inv;
      cut[static_cast<std::size_t>(j)] = old[static_cast<std::size_t>(j)] +
                                         damping * (y - old[static_cast<std::size_t>(j)]);
    }
    // at least w_min apart (forward, then backward from the top)
    for (int j = 1; j < p; ++j)
      cut[j] = std::max(cut[j], cut[j - 1] + w_min);
    for (int j = p - 1; j >= 1; --j)
      cut[j] = std::min(cut[j], cut[j + 1] - w_min);
    bool ok = true;
    for (int j = 1; j <= p; ++j)
      ok = ok && cut[j] - cut[j - 1] >= w_min * (1. - 1e-12) && std::isfinite(cut[j]);
    if (!ok)
      continue; // (the range does not fit: keep the planes)
    fd.assign(static_cast<std::size_t>(p) + 1, 0.);
    for (int j = 1; j < p; ++j)
      fd[static_cast<std::size_t>(j)] = cut[static_cast<std::size_t>(j)] / L[d];
    fd[static_cast<std::size_t>(p)] = 1.;
    any = true;
  }
  if (!any)
    return res;
  for (auto &fd : frac) // the same bits on every rank
    if (!fd.empty())
      m_comm.bcast_bytes(fd.data(), fd.size() * sizeof(double), 0);
  m_cells.set_domain_fractions(std::move(frac));
  res.moved = true;
  ++m_n_balances;
  return res;
}

} // namespace Marble
