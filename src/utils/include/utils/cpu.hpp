#pragma once
// Run-time CPU feature checks for the code paths chosen at load (the default
// build has no -march: one binary uses AVX2 where the CPU has it).

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

} // namespace Utils
