#pragma once
// Parameter validation at the script interface: every value that enters the
// core passes through here, so errors name the parameter and its allowed range.
#include "utils/Vector.hpp"
#include "utils/checks.hpp"
#include "utils/errors.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ScriptInterface {

namespace py = pybind11;

using Utils::check_double;
using Utils::range_str;
using Utils::value_error;

/** Convert a Python object to a double, rejecting bools/strings/None. */
inline double to_double(std::string const &name, py::handle h) {
  if (h.is_none() || py::isinstance<py::str>(h) || py::isinstance<py::bool_>(h))
    value_error("parameter '" + name + "' must be a number, got " +
                std::string(py::str(py::type::of(h).attr("__name__"))));
  try {
    return py::float_(py::reinterpret_borrow<py::object>(h)).cast<double>();
  } catch (py::error_already_set &) {
    value_error("parameter '" + name + "' must be a number, got " +
                std::string(py::str(py::type::of(h).attr("__name__"))));
  }
}

inline long long to_int(std::string const &name, py::handle h) {
  if (py::isinstance<py::bool_>(h) || py::isinstance<py::float_>(h) || h.is_none() ||
      py::isinstance<py::str>(h)) {
    // integral floats (e.g. 3.0) are accepted, others are not
    if (py::isinstance<py::float_>(h)) {
      double const x = h.cast<double>();
      if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9e15)
        return static_cast<long long>(x);
    }
    value_error("parameter '" + name + "' must be an integer");
  }
  try {
    return py::int_(py::reinterpret_borrow<py::object>(h)).cast<long long>();
  } catch (py::error_already_set &) {
    value_error("parameter '" + name + "' must be an integer");
  } catch (py::cast_error &) {
    value_error("parameter '" + name + "' is out of the integer range");
  }
}

inline Utils::Vector3d to_vec3(std::string const &name, py::handle h) {
  py::array_t<double> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  } catch (...) {
  }
  if (!a || a.ndim() != 1 || a.shape(0) != 3)
    value_error("parameter '" + name + "' must be a sequence of 3 numbers");
  Utils::Vector3d v{a.at(0), a.at(1), a.at(2)};
  for (int d = 0; d < 3; ++d)
    if (!std::isfinite(v[d]))
      value_error("parameter '" + name + "' must be finite, got [" + Utils::to_str(v[0]) + ", " +
                  Utils::to_str(v[1]) + ", " + Utils::to_str(v[2]) + "]");
  return v;
}

/** Reject keys not in @p allowed. */
inline void check_keys(std::string const &what, py::dict const &kw,
                       std::vector<std::string> const &allowed) {
  for (auto const &item : kw) {
    auto const key = py::str(item.first).cast<std::string>();
    bool found = false;
    for (auto const &a : allowed)
      found |= (a == key);
    if (!found) {
      std::string list;
      for (auto const &a : allowed)
        list += (list.empty() ? "" : ", ") + a;
      value_error("unknown parameter '" + key + "' for " + what + " (allowed: " + list + ")");
    }
  }
}

inline bool has(py::dict const &kw, char const *key) { return kw.contains(key); }

/** A 3-vector as a numpy array of shape (3,). */
inline py::array_t<double> vec_to_array(Utils::Vector3d const &v) {
  py::array_t<double> a(3);
  auto *p = a.mutable_data();
  p[0] = v[0], p[1] = v[1], p[2] = v[2];
  return a;
}

/** A row-major 3x3 tensor as a numpy array of shape (3, 3). */
inline py::array_t<double> mat_to_array(std::array<double, 9> const &m) {
  py::array_t<double> a({3, 3});
  std::copy(m.begin(), m.end(), a.mutable_data());
  return a;
}

} // namespace ScriptInterface
