#pragma once
// The force of the pair-loop kernels on particle i of a pair (i, j), d = r_i - r_j:
// the conservative kernels' force_over_r summed (in list order) times d, then
// each pair-dissipative kernel's force. Shared by the main loop
// (forces/forces.cpp) and the colloid pair list (marble/Colloids.cpp), so a
// kernel is written once. @p Mask selects the kernels (pair_loop_bit<K>);
// @p vij_of() gives v_i - v_j, @p xi_of.template operator()<K>() kernel K's
// (signed) pair noise and @p mfac_of() the pair mass factor, each only called
// where a dissipative kernel needs it.
#include "nonbonded/registry.hpp"
#include "utils/Vector.hpp"

namespace Marble {

/** Mask bits of the kernels with role @p R. */
template <KernelRole R> constexpr unsigned pair_kernels_with_role() {
  unsigned m = 0;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if (K::role == R)
      m |= pair_loop_bit<K>;
  });
  return m;
}

template <unsigned Mask, class VijOf, class XiOf, class MfacOf>
Utils::Vector3d pair_force(IAParams const &p, Utils::Vector3d const &d, double r, VijOf &&vij_of,
                           XiOf &&xi_of, MfacOf &&mfac_of) {
  double fac = 0.;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if constexpr (K::role == KernelRole::conservative && (Mask & pair_loop_bit<K>) != 0) {
      auto const &kp = p.get<K>();
      if (kp.active)
        fac += K::force_over_r(kp, r);
    }
  });
  Utils::Vector3d force = fac * d;
  for_each_kernel<PairLoopKernels>([&]<class K>() {
    if constexpr (K::role == KernelRole::pair_dissipative && (Mask & pair_loop_bit<K>) != 0) {
      auto const &kp = p.get<K>();
      if (kp.active && r > 0.)
        force += K::force(kp, d, r, vij_of(), xi_of.template operator()<K>(), mfac_of());
    }
  });
  return force;
}

} // namespace Marble
