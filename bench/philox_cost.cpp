// Cost of one DPD pair's noise, per pair (CPU time, best of 5 passes over
// 4e6 pairs): the old Philox4x64-10 draw (Utils::noise_uniform, as the pair
// loop drew it before issue 15), the scalar Philox4x32-10 draw
// (Utils::pair_uniform3) and the block draw of the pair loop now
// (Marble::pair_noise_block_soa: 512 pairs at a time in SIMD lanes, with the
// CPU's code path: avx2 or default).
// Build: c++ -O3 -std=c++20 -Isrc/utils/include -Isrc/core bench/philox_cost.cpp
//          src/core/forces/pair_noise.cpp -o philox_cost
#include "forces/pair_noise.hpp"
#include "utils/noise.hpp"
#include "utils/philox4x32.hpp"

#include <cstdio>
#include <ctime>
#include <vector>

namespace {
template <class F> double best_ns_per_pair(int n, F &&pass) {
  double best = 1e30;
  for (int rep = 0; rep < 5; ++rep) {
    std::clock_t const c0 = std::clock();
    pass(rep);
    double const t = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / n * 1e9;
    best = t < best ? t : best;
  }
  return best;
}
} // namespace

int main() {
  constexpr int n = 4000000, blk = 512;
  double acc = 0.;
  double const t64 = best_ns_per_pair(n, [&](int rep) {
    for (int k = 0; k < n; ++k) {
      auto const v = Utils::noise_uniform(42, Utils::RNGSalt::dpd, 7 + rep, static_cast<std::uint64_t>(k),
                                          static_cast<std::uint64_t>(k) + 13);
      acc += v[0] + v[1] + v[2];
    }
  });
  double const t32 = best_ns_per_pair(n, [&](int rep) {
    Utils::PairNoiseKey const key(42, 1, 7 + rep);
    for (int k = 0; k < n; ++k) {
      auto const v = Utils::pair_uniform3(key, static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(k) + 13);
      acc += v[0] + v[1] + v[2];
    }
  });
  std::printf("philox4x64_10_ns_per_pair %.3f\n", t64);
  std::printf("philox4x32_10_scalar_ns_per_pair %.3f\n", t32);
  std::vector<std::uint32_t> lo(blk), hi(blk);
  std::vector<double> sign(blk), x(blk), y(blk), z(blk);
  for (auto const &[name, fn] : Marble::pair_noise_paths()) {
    double const tblk = best_ns_per_pair(n, [&, fn = fn](int rep) {
      Utils::PairNoiseKey const key(42, 1, 7 + rep);
      for (int k0 = 0; k0 < n; k0 += blk) {
        for (int s = 0; s < blk; ++s) {
          lo[s] = static_cast<std::uint32_t>(k0 + s);
          hi[s] = lo[s] + 13;
          sign[s] = (s & 1) ? -1. : 1.;
        }
        fn(key, blk, lo.data(), hi.data(), sign.data(), x.data(), y.data(), z.data());
        acc += x[0] + y[blk - 1] + z[blk / 2];
      }
    });
    std::printf("philox4x32_10_block_%s_ns_per_pair %.3f\n", name, tblk);
  }
  std::printf("pair_loop_path %s\n", Marble::pair_noise_isa());
  return acc == 12345.678 ? 1 : 0; // keep the sums alive
}
