#pragma once
// Exceptions with a fixed meaning at the script interface:
//   std::invalid_argument / std::domain_error -> Python ValueError
//   Utils::FeaturesError                      -> marble.FeaturesError
//   Utils::RuntimeError                       -> Python RuntimeError
#include <sstream>
#include <stdexcept>
#include <string>

namespace Utils {

struct FeaturesError : std::runtime_error {
  explicit FeaturesError(std::string const &feature, std::string const &what = "")
      : std::runtime_error("missing feature " + feature +
                           (what.empty() ? std::string() : " (needed for " + what + ")")) {}
};

struct RuntimeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/** Format a value for an error message. */
template <typename T> std::string to_str(T const &v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

} // namespace Utils
