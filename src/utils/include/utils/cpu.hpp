#pragma once
// Run-time CPU feature checks for the code paths chosen at load (the default
// build has no -march: one binary uses AVX2 where the CPU has it).

#include <cstdlib>
#include <string_view>

namespace Utils {

/** True if this CPU runs AVX2 (x86-64 with GCC/Clang; checked once). */
inline bool cpu_has_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static bool const has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

/** True where the pair loop's 512-bit (zmm) forms run (the AVX-512 row
 * select and the block forces' avx512f build; doc/benchmarks.md, session 31):
 * the CPU has AVX-512 F and VL and is an AMD one (Zen 4 runs zmm code at its
 * full clock; on the Intel AVX-512 cores of earlier sessions zmm code measured
 * slower), or the environment variable MARBLE_SIMD is "avx512"; never where
 * MARBLE_SIMD is "avx2" (the benchmarks' switch). Read once per process. */
inline bool cpu_prefers_zmm() {
#if defined(__x86_64__) && defined(__GNUC__)
  static bool const has = [] {
    char const *const e = std::getenv("MARBLE_SIMD");
    std::string_view const v = e != nullptr ? e : "";
    if (v == "avx2")
      return false;
    bool const isa = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                     __builtin_cpu_supports("avx2");
    return isa && (v == "avx512" || __builtin_cpu_is("amd"));
  }();
  return has;
#else
  return false;
#endif
}

} // namespace Utils
