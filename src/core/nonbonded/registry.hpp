#pragma once
// Compile-time views of the kernel list (nonbonded/kernel_list.hpp): the
// compiled kernels, those of the pair loop, and iteration over them.
#include "config/features.hpp"
#include "nonbonded/kernel_list.hpp"

#include <cstddef>
#include <tuple>
#include <type_traits>

namespace Marble {

template <class K> inline constexpr bool compiled = feature_on(K::feature, MARBLE_FEATURES_ACTIVE);

namespace detail {
template <class K, class L> struct Prepend;
template <class K, class... Ks> struct Prepend<K, TypeList<Ks...>> {
  using type = TypeList<K, Ks...>;
};
template <template <class> class Pred, class L> struct Filter;
template <template <class> class Pred> struct Filter<Pred, TypeList<>> {
  using type = TypeList<>;
};
template <template <class> class Pred, class K, class... Ks> struct Filter<Pred, TypeList<K, Ks...>> {
  using rest = typename Filter<Pred, TypeList<Ks...>>::type;
  using type = std::conditional_t<Pred<K>::value, typename Prepend<K, rest>::type, rest>;
};
template <class K> struct IsCompiled : std::bool_constant<compiled<K>> {};
template <class K> struct IsPairLoop : std::bool_constant<compiled<K> && in_pair_loop(K::role)> {};
template <class K> struct IsMainList : std::bool_constant<compiled<K> && in_main_list(K::role)> {};
template <class L> struct ParamTuple;
template <class... Ks> struct ParamTuple<TypeList<Ks...>> {
  using type = std::tuple<typename Ks::Params...>;
};
template <class L> struct Size;
template <class... Ks> struct Size<TypeList<Ks...>> : std::integral_constant<std::size_t, sizeof...(Ks)> {};
template <class K, class L> struct IndexOf;
template <class K, class... Ks> struct IndexOf<K, TypeList<K, Ks...>> : std::integral_constant<std::size_t, 0> {};
template <class K, class J, class... Ks>
struct IndexOf<K, TypeList<J, Ks...>> : std::integral_constant<std::size_t, 1 + IndexOf<K, TypeList<Ks...>>::value> {};
} // namespace detail

using CompiledKernels = typename detail::Filter<detail::IsCompiled, AllKernels>::type;
/** Kernels evaluated in the main Verlet-list loop (conservative and pair-dissipative). */
using PairLoopKernels = typename detail::Filter<detail::IsPairLoop, AllKernels>::type;
/** Kernels whose pairs the main Verlet list serves (the pair loop's and the rotational pair kernels). */
using MainListKernels = typename detail::Filter<detail::IsMainList, AllKernels>::type;
inline constexpr std::size_t n_pair_loop_kernels = detail::Size<PairLoopKernels>::value;
/** Bit of kernel @p K in a pair-loop mask. */
template <class K> inline constexpr unsigned pair_loop_bit = 1u << detail::IndexOf<K, PairLoopKernels>::value;

/** Call f.template operator()<K>() for every kernel K of list @p L, in order. */
template <class L> struct ForEach;
template <class... Ks> struct ForEach<TypeList<Ks...>> {
  template <class F> static constexpr void run(F &&f) { (f.template operator()<Ks>(), ...); }
};
template <class L, class F> constexpr void for_each_kernel(F &&f) { ForEach<L>::run(static_cast<F &&>(f)); }

/** Every kernel's parameters for one (ordered) pair of types. */
struct IAParams {
  typename detail::ParamTuple<CompiledKernels>::type kernels{};
  double max_cut = 0.;  // largest range of the active main-list kernels
  double max_cut2 = 0.; // square of the range served by the main Verlet list
                        // (0 for pairs with a large particle type: see Colloids)

  template <class K> typename K::Params &get() {
    static_assert(compiled<K>, "kernel not compiled in: guard the call by its feature");
    return std::get<typename K::Params>(kernels);
  }
  /** A kernel that is not compiled in reads as switched off. */
  template <class K> typename K::Params const &get() const {
    if constexpr (compiled<K>) {
      return std::get<typename K::Params>(kernels);
    } else {
      static typename K::Params const off{};
      return off;
    }
  }
  void update_cutoff() {
    max_cut = 0.;
    for_each_kernel<MainListKernels>([&]<class K>() {
      double const r = K::range(get<K>());
      max_cut = r > max_cut ? r : max_cut;
    });
    max_cut2 = max_cut * max_cut;
  }
};

/** Sum of the conservative kernels of a pair at distance r: F = force_over_r d. */
struct ConservativePair {
  double force_over_r = 0., energy = 0.;
};
inline ConservativePair conservative_pair(IAParams const &p, double r) {
  ConservativePair out;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if constexpr (K::role == KernelRole::conservative) {
      auto const &kp = p.get<K>();
      if (kp.active) {
        out.force_over_r += K::force_over_r(kp, r);
        out.energy += K::energy(kp, r);
      }
    }
  });
  return out;
}
/** Is any conservative kernel of the pair active? */
inline bool any_conservative(IAParams const &p) {
  bool on = false;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if constexpr (K::role == KernelRole::conservative)
      on = on || p.get<K>().active;
  });
  return on;
}

} // namespace Marble
