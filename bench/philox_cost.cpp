// Cost of one DPD pair's noise: Philox4x64-10 (Random123) -> 3 uniforms, as
// Utils::noise_uniform draws it in the pair loop. Independent calls, as in
// the loop's noise pass. Prints ns per call (CPU time).
// Build: c++ -O3 -std=c++20 -Isrc/utils/include bench/philox_cost.cpp -o philox_cost
#include "utils/noise.hpp"

#include <cstdio>
#include <ctime>

int main() {
  constexpr int n = 4000000;
  double acc = 0.;
  double best = 1e30;
  for (int rep = 0; rep < 5; ++rep) {
    std::clock_t const c0 = std::clock();
    for (int k = 0; k < n; ++k) {
      auto const v =
          Utils::noise_uniform(42, Utils::RNGSalt::dpd, 7 + rep, static_cast<std::uint64_t>(k),
                               static_cast<std::uint64_t>(k) + 13);
      acc += v[0] + v[1] + v[2];
    }
    double const t = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC / n * 1e9;
    best = t < best ? t : best;
  }
  std::printf("philox4x64_10_ns_per_pair %.3f\n", best);
  return acc == 12345.678 ? 1 : 0; // keep the sum alive
}
