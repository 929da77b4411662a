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
  double max_cut = 0.; // largest cutoff of the active kernels
  double max_cut2 = 0.;

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

/** Which kernels any type pair uses: selects the instantiation of the pair loop. */
struct KernelMask {
  bool lj = false, hat = false, dpd = false;
};

class InteractionTable {
public:
  static constexpr int max_type = 1000;
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
  }
  IAParams &get(int i, int j) { return m_p[i * m_n + j]; }
  IAParams const &get(int i, int j) const { return m_p[i * m_n + j]; }
  /** Write @p p for (i, j) and (j, i). */
  void set(int i, int j, IAParams p) {
    ensure_type(std::max(i, j));
    p.update_cutoff();
    m_p[i * m_n + j] = p;
    m_p[j * m_n + i] = p;
  }
  double max_cutoff() const {
    double c = 0.;
    for (auto const &p : m_p)
      c = std::max(c, p.max_cut);
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
    m_n = 0;
  }

private:
  int m_n = 0;
  std::vector<IAParams> m_p;
};

} // namespace Marble
