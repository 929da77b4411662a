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
      // a symmetric kernel with per-type parameters (radii) stores them mirrored for (j, i)
      if constexpr (requires { K::mirrored(kp); })
        get(j, i).template get<K>() = K::mirrored(kp);
      else
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
  /** Range (largest cutoff) of type pair (i, j) in the main Verlet list; 0
   * for pairs of large types (served by the colloid list or the walls). */
  double pair_range(int i, int j) const {
    return (is_large(i) || is_large(j)) ? 0. : m_p[i * m_n + j].max_cut;
  }
  /** A split of the main list's types into small and large-range ones
   * (cells/CellSystem.hpp): the largest cutoff among small types, among
   * large-range types, and between the two. */
  struct RangeSplit {
    std::vector<char> large; // empty: no split
    double cut_small = 0., cut_ll = 0., cut_ls = 0.;
  };
  /** The ranges of the split with large-range types @p large. */
  RangeSplit range_split(std::vector<char> const &large) const {
    RangeSplit r;
    r.large = large;
    r.large.resize(m_n, 0);
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j) {
        double const c = pair_range(i, j);
        bool const li = r.large[i] != 0, lj = r.large[j] != 0;
        double &dst = (li && lj) ? r.cut_ll : ((li || lj) ? r.cut_ls : r.cut_small);
        dst = std::max(dst, c);
      }
    return r;
  }
  /** The types auto_range_split may make large-range, before their counts
   * are known: with b the smallest positive pair range, those whose own pairs
   * reach farther than 2 b (or, without pairs of their own, whose pairs with
   * another type do). None (every scene of one range scale): no split, and no
   * need to count the particles of each type. */
  std::vector<char> range_split_candidates() const {
    double b = 0.;
    for (int i = 0; i < m_n; ++i)
      for (int j = 0; j < m_n; ++j) {
        double const c = pair_range(i, j);
        if (c > 0. && (b == 0. || c < b))
          b = c;
      }
    std::vector<char> cand(m_n, 0);
    for (int t = 0; t < m_n && b > 0.; ++t) {
      if (is_large(t))
        continue;
      double reach = 0.;
      for (int j = 0; j < m_n; ++j)
        reach = std::max(reach, pair_range(t, j));
      double const self = pair_range(t, t);
      cand[t] = (self > 2. * b || (self == 0. && reach > 2. * b)) ? 1 : 0;
    }
    return cand;
  }
  /** The automatic split (doc/architecture.md, "Two cell grids"), given
   * range_split_candidates() (@p large, taken over) and the
   * number of particles of each type (@p count, all ranks): with b the
   * smallest positive pair range, a type is large-range if its own pairs
   * reach farther than 2 b (or, without pairs of its own, its pairs with
   * another type do) and it holds at most a quarter of the particles; the
   * split is kept only if the small types' range stays positive and the
   * large-range ranges exceed it by more than 1.5 times. Otherwise (and
   * for every scene of one range scale) no split: an empty @c large. */
  RangeSplit auto_range_split(std::vector<char> large, std::vector<double> const &count) const {
    double total = 0.;
    for (double c : count)
      total += c;
    large.resize(static_cast<std::size_t>(m_n), 0);
    bool any = false;
    for (int t = 0; t < m_n; ++t) {
      double const n_t = t < static_cast<int>(count.size()) ? count[t] : 0.;
      large[t] = large[t] && n_t <= 0.25 * total;
      any = any || large[t];
    }
    RangeSplit r;
    if (!any)
      return r;
    r = range_split(large);
    if (!(r.cut_small > 0. && std::max(r.cut_ll, r.cut_ls) > 1.5 * r.cut_small))
      return RangeSplit{};
    return r;
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
