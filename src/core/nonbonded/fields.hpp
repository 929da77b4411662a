#pragma once
// A kernel's parameters as data (doc/adding-an-interaction.md). Every kernel
// lists its user-visible parameters once, as Fields: key, type, allowed range,
// required or default, and how to read/write it in the kernel's Params struct.
// That one list drives validation and its error texts (set_params), get_params,
// checkpoints and the Python documentation; nothing else names the keys.
#include "utils/checks.hpp"
#include "utils/errors.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace Marble {

enum class FieldType { real, integer, choice };

/** A value handed over by the script interface, before validation. */
struct FieldValue {
  enum class Kind { number, text, other } kind = Kind::number;
  double number = 0.;
  std::string text; // the string (Kind::text) or the Python type name (Kind::other)
};
using FieldValues = std::vector<std::pair<std::string, FieldValue>>;

template <class P> struct Field {
  char const *key;
  FieldType type;
  double (*get)(P const &);
  void (*set)(P &, double);
  bool required = false;
  double default_value = 0.;
  double lo = -INFINITY, hi = INFINITY;
  bool lo_open = false, hi_open = false;
  /** integer: text of the allowed values for the message; keyword: what it is computed from;
   * choice: the names of 0, 1, ... */
  std::vector<char const *> choices = {};
  char const *hint = nullptr;
  /** real: a keyword (e.g. "auto") whose value is computed from the fields before it */
  char const *keyword = nullptr;
  double (*keyword_value)(P const &) = nullptr;
  /** a field of a feature that is not compiled in: accepted only at its default (0) */
  char const *missing_feature = nullptr;
};

/** Field helpers: a real number in a range, an integer in a set, a named choice. */
template <class P>
Field<P> real(char const *key, double (*get)(P const &), void (*set)(P &, double), double lo,
              double hi, bool lo_open = false, bool hi_open = false) {
  Field<P> f{key, FieldType::real, get, set};
  f.lo = lo, f.hi = hi, f.lo_open = lo_open, f.hi_open = hi_open;
  return f;
}

namespace detail {
inline std::string choice_list(std::vector<char const *> const &c) {
  std::string s;
  for (std::size_t k = 0; k < c.size(); ++k)
    s += (k ? ", '" : "'") + std::string(c[k]) + "'";
  return s;
}
} // namespace detail

/** Validate @p v for field @p f and return the stored number. */
template <class P> double field_number(Field<P> const &f, FieldValue const &v, P const &sofar) {
  std::string const key = f.key;
  switch (f.type) {
  case FieldType::choice: {
    if (v.kind != FieldValue::Kind::text)
      Utils::value_error("parameter '" + key + "' must be one of " + detail::choice_list(f.choices));
    for (std::size_t k = 0; k < f.choices.size(); ++k)
      if (v.text == f.choices[k])
        return static_cast<double>(k);
    Utils::value_error("parameter '" + key + "' must be one of " + detail::choice_list(f.choices) +
                       ", got '" + v.text + "'");
  }
  case FieldType::integer: {
    bool const integral = v.kind == FieldValue::Kind::number && std::isfinite(v.number) &&
                          v.number == std::floor(v.number);
    if (!integral)
      Utils::value_error("parameter '" + key + "' must be an integer");
    if (v.number < f.lo || v.number > f.hi)
      Utils::value_error("parameter '" + key + "' must be " + (f.hint ? f.hint : "") + ", got " +
                         Utils::to_str(static_cast<long long>(v.number)));
    return v.number;
  }
  case FieldType::real:
    break;
  }
  if (v.kind == FieldValue::Kind::text) {
    if (f.keyword && v.text == f.keyword) {
      double const x = f.keyword_value(sofar);
      if (!std::isfinite(x))
        Utils::value_error("parameter '" + key + "' = \"" + f.keyword + "\" computed from " +
                           (f.hint ? f.hint : "the other parameters") + " is not finite (" +
                           Utils::to_str(x) + ")");
      return x;
    }
    if (f.keyword)
      Utils::value_error("parameter '" + key + "' must be a number or \"" + f.keyword + "\"");
    Utils::value_error("parameter '" + key + "' must be a number, got str");
  }
  if (v.kind == FieldValue::Kind::other)
    Utils::value_error("parameter '" + key + "' must be a number, got " + v.text);
  return Utils::check_double(key, v.number, f.lo, f.hi, f.lo_open, f.hi_open);
}

/**
 * Parameters from user values: unknown keys, missing required keys, types and
 * ranges are checked in the order of the field list (a keyword value such as
 * LJ's shift "auto" sees the fields before it); absent fields take their
 * default. Throws std::invalid_argument (ValueError) or Utils::FeaturesError.
 */
template <class P>
P parse_fields(std::string const &what, std::vector<Field<P>> const &fields,
               FieldValues const &values) {
  for (auto const &kv : values) {
    bool found = false;
    for (auto const &f : fields)
      found |= kv.first == f.key;
    if (!found) {
      std::string list;
      for (auto const &f : fields)
        list += (list.empty() ? "" : ", ") + std::string(f.key);
      Utils::value_error("unknown parameter '" + kv.first + "' for " + what + " (allowed: " + list +
                         ")");
    }
  }
  auto find = [&](char const *key) -> FieldValue const * {
    for (auto const &kv : values)
      if (kv.first == key)
        return &kv.second;
    return nullptr;
  };
  for (auto const &f : fields)
    if (f.required && !find(f.key))
      Utils::value_error("parameter '" + std::string(f.key) + "' is required for " + what);
  P p{};
  for (auto const &f : fields) {
    FieldValue const *v = find(f.key);
    if (f.missing_feature) {
      if (v && !(v->kind == FieldValue::Kind::number && v->number == 0.))
        throw Utils::FeaturesError(f.missing_feature, what + " parameter '" + f.key + "'");
      continue;
    }
    f.set(p, v ? field_number(f, *v, p) : f.default_value);
  }
  return p;
}

} // namespace Marble
