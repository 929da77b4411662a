#pragma once
// Range checks with the project's standard message (ValueError at the script
// interface): "parameter 'x' must be a finite number in [lo, hi), got v".
#include "utils/errors.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace Utils {

[[noreturn]] inline void value_error(std::string const &msg) { throw std::invalid_argument(msg); }

/** Interval description for messages, e.g. "[0, inf)". */
inline std::string range_str(double lo, bool lo_open, double hi, bool hi_open) {
  auto num = [](double x) {
    if (std::isinf(x))
      return std::string(x > 0 ? "inf" : "-inf");
    return to_str(x);
  };
  return (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + (hi_open ? ")" : "]");
}

/** A finite double in [lo, hi] (or open ends), else ValueError naming @p name. */
inline double check_double(std::string const &name, double x, double lo = -INFINITY,
                           double hi = INFINITY, bool lo_open = false, bool hi_open = false) {
  bool ok = std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  if (!ok)
    value_error("parameter '" + name + "' must be a finite number in " +
                range_str(lo, lo_open, hi, hi_open) + ", got " + to_str(x));
  return x;
}

} // namespace Utils
