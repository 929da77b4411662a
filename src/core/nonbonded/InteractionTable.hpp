#pragma once
// Per-type-pair interaction parameters. The table is symmetric and dense in
// the type ids: the pair loop finds a pair's kernels with one index.
#include "config/features.hpp"
#include "nonbonded/hat.hpp"
#include "nonbonded/lennard_jones.hpp"
#include "thermostats/dpd.hpp"

#include <algorithm>
#include <vector>

namespace Marble {

struct IAParams {
#ifdef LENNARD_JONES
  LennardJonesParams lj;
#endif
#ifdef HAT
  HatParams hat;
#endif
#ifdef DPD
  DPDParams dpd;
#endif
  double max_cut = 0.;  // largest cutoff of the active kernels
  double max_cut2 = 0.; // square of the range served by the main Verlet list
                        // (0 for pairs with a large particle type: see Colloids)

  void update_cutoff() {
    max_cut = 0.;
#ifdef LENNARD_JONES
    max_cut = std::max(max_cut, lj.max_cutoff());
#endif
#ifdef HAT
    max_cut = std::max(max_cut, hat.max_cutoff());
#endif
#ifdef DPD
    max_cut = std::max(max_cut, dpd.max_cutoff());
#endif
    max_cut2 = max_cut * max_cut;
  }
};

/** Conservative part of a pair at distance r: force F = force_over_r * d and
 * the energy (all potentials of the pair summed). Used wherever a pair is
 * evaluated outside the main loop (colloid pairs, walls, analysis). */
struct ConservativePair {
  double force_over_r = 0., energy = 0.;
};
inline ConservativePair conservative_pair([[maybe_unused]] IAParams const &p,
                                          [[maybe_unused]] double r) {
  ConservativePair out;
#ifdef LENNARD_JONES
  if (p.lj.active) {
    out.force_over_r += p.lj.force_over_r(r);
    out.energy += p.lj.energy(r);
  }
#endif
#ifdef HAT
  if (p.hat.active) {
    out.force_over_r += p.hat.force_over_r(r);
    out.energy += p.hat.energy(r);
  }
#endif
  return out;
}

/** Which kernels any type pair uses: selects the instantiation of the pair loop. */
struct KernelMask {
  bool lj = false, hat = false, dpd = false;
};

class InteractionTable {
public:
  static constexpr int max_type = 256; // the tables are dense: n_types^2 entries
  int n_types() const { return m_n; }
  /** Grow the table so that type @p t exists. */
  void ensure_type(int t) {
    if (t < m_n)
      return;
    int const n = t + 1;
    std::vector<IAParams> p(static_cast<std::size_t>(n) * n);
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j)
        p[i * n + j] = m_p[i * m_n + j];
    m_p.swap(p);
    m_n = n;
    m_large.resize(n, 0);
  }
  /** Types whose pairs are served by the colloid pair list, not the main one. */
  void set_large_types(std::vector<char> const &large) {
    m_large = large;
    m_large.resize(m_n, 0);
    refresh();
  }
  bool is_large(int t) const { return t < static_cast<int>(m_large.size()) && m_large[t]; }
  IAParams &get(int i, int j) { return m_p[i * m_n + j]; }
  IAParams const &get(int i, int j) const { return m_p[i * m_n + j]; }
  /** Write @p p for (i, j) and (j, i). */
  void set(int i, int j, IAParams p) {
    ensure_type(std::max(i, j));
    p.update_cutoff();
    m_p[i * m_n + j] = p;
    m_p[j * m_n + i] = p;
    refresh();
  }
  /** Range of the main Verlet list: pairs of large types excluded. */
  double max_cutoff() const {
    double c = 0.;
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j)
        if (!is_large(i) && !is_large(j))
          c = std::max(c, m_p[i * m_n + j].max_cut);
    return c;
  }
  KernelMask kernels() const {
    KernelMask k;
    for ([[maybe_unused]] auto const &p : m_p) {
#ifdef LENNARD_JONES
      k.lj |= p.lj.active;
#endif
#ifdef HAT
      k.hat |= p.hat.active;
#endif
#ifdef DPD
      k.dpd |= p.dpd.active;
#endif
    }
    return k;
  }
  std::vector<IAParams> &all() { return m_p; }
  void clear() {
    m_p.clear();
    m_large.clear();
    m_n = 0;
  }

private:
  void refresh() {
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j) {
        auto &p = m_p[i * m_n + j];
        p.max_cut2 = (is_large(i) || is_large(j)) ? 0. : p.max_cut * p.max_cut;
      }
  }
  int m_n = 0;
  std::vector<IAParams> m_p;
  std::vector<char> m_large;
};

} // namespace Marble
