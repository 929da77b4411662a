#pragma once
// Per-type-pair parameters of every kernel (nonbonded/registry.hpp), one dense
// table: the pair loop finds a pair's kernels with one index. Pair kernels are
// stored symmetrically; colloid- and wall-surface kernels are ordered
// ([colloid or wall type][partner type]).
#include "nonbonded/registry.hpp"

#include <algorithm>
#include <vector>

namespace Marble {

class InteractionTable {
public:
  static constexpr int max_type = 256; // the tables are dense: n_types^2 entries
  int n_types() const { return m_n; }
  /** Grow the table so that type @p t exists (the one grow step of all kernels). */
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
  /** Types whose pairs are served by the colloid pair list or the walls, not the main list. */
  void set_large_types(std::vector<char> const &large) {
    m_large = large;
    m_large.resize(m_n, 0);
    refresh();
  }
  bool is_large(int t) const { return t < static_cast<int>(m_large.size()) && m_large[t]; }
  IAParams &get(int i, int j) { return m_p[i * m_n + j]; }
  IAParams const &get(int i, int j) const { return m_p[i * m_n + j]; }

  /** Set kernel @p K of types (i, j): both orders for a pair kernel, (i, j) only for an ordered one. */
  template <class K> void set_kernel(int i, int j, typename K::Params const &kp) {
    ensure_type(std::max(i, j));
    get(i, j).template get<K>() = kp;
    get(i, j).update_cutoff();
    if constexpr (!is_ordered(K::role)) {
      get(j, i).template get<K>() = kp;
      get(j, i).update_cutoff();
    }
    refresh();
  }
  /** Switch every kernel of every type pair off. */
  void reset() {
    for (auto &p : m_p)
      p = IAParams{};
    refresh();
  }
  /** Noise prefactors of the dissipative kernels for temperature @p kT and time step @p dt. */
  void refresh_prefactors(double kT, double dt) {
    for (auto &p : m_p)
      for_each_kernel<CompiledKernels>([&]<class K>() {
        if constexpr (requires { K::refresh(p.template get<K>(), kT, dt); })
          K::refresh(p.template get<K>(), kT, dt);
      });
  }
  /** Types that are the first type of an active colloid-surface kernel (colloid types). */
  std::vector<char> colloid_types() const {
    std::vector<char> out(m_n, 0);
    for_each_kernel<CompiledKernels>([&]<class K>() {
      if constexpr (K::role == KernelRole::colloid_surface)
        for (int i = 0; i < m_n; ++i)
          for (int j = 0; j < m_n; ++j)
            out[i] = out[i] || get(i, j).template get<K>().active;
    });
    return out;
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
  /** Pair-loop kernels active for some type pair (bits: pair_loop_bit<K>). */
  unsigned active_pair_kernels() const {
    unsigned mask = 0;
    for (auto const &p : m_p)
      for_each_kernel<PairLoopKernels>([&]<class K>() {
        if (p.template get<K>().active)
          mask |= pair_loop_bit<K>;
      });
    return mask;
  }
  template <class K> bool any_active() const {
    for (auto const &p : m_p)
      if (p.template get<K>().active)
        return true;
    return false;
  }
  std::vector<IAParams> &all() { return m_p; }
  std::vector<IAParams> const &all() const { return m_p; }
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
