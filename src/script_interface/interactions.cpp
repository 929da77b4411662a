// Script interface of the non-bonded interactions (marble.interactions): one
// generic set / get / deactivate for every kernel of the kernel list
// (nonbonded/kernel_list.hpp), driven by the kernels' field lists, and the
// list itself, from which the Python classes are generated.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include "nonbonded/registry.hpp"

#include <pybind11/stl.h>

#include <string>

namespace ScriptInterface {

using Marble::System;

namespace {

void check_types(int i, int j) {
  for (int t : {i, j})
    if (t < 0 || t >= Marble::InteractionTable::max_type)
      value_error("particle type must be an integer in [0, " +
                  std::to_string(Marble::InteractionTable::max_type) + "), got " + std::to_string(t));
}

/** A Python value as handed to the core's field validation. */
Marble::FieldValue field_value(py::handle h) {
  Marble::FieldValue v;
  std::string const type_name = py::str(py::type::of(h).attr("__name__"));
  if (py::isinstance<py::str>(h)) {
    v.kind = Marble::FieldValue::Kind::text;
    v.text = h.cast<std::string>();
  } else if (h.is_none() || py::isinstance<py::bool_>(h)) {
    v.kind = Marble::FieldValue::Kind::other;
    v.text = type_name;
  } else {
    try {
      v.number = py::float_(py::reinterpret_borrow<py::object>(h)).cast<double>();
    } catch (py::error_already_set &) {
      v.kind = Marble::FieldValue::Kind::other;
      v.text = type_name;
    }
  }
  return v;
}

Marble::FieldValues field_values(py::dict const &kw) {
  Marble::FieldValues out;
  for (auto const &item : kw)
    out.emplace_back(py::str(item.first).cast<std::string>(), field_value(item.second));
  return out;
}

/** Call fn.template operator()<K>() for the kernel named @p name (compiled
 * or not); ValueError for an unknown name. */
template <class Fn> void with_kernel(std::string const &name, Fn &&fn) {
  bool found = false;
  Marble::for_each_kernel<Marble::AllKernels>([&]<class K>() {
    if (!found && name == K::name) {
      found = true;
      fn.template operator()<K>();
    }
  });
  if (!found)
    value_error("unknown non-bonded interaction '" + name + "'");
}

template <class K> py::object field_to_py(Marble::Field<typename K::Params> const &f, typename K::Params const &p) {
  double const x = f.get(p);
  switch (f.type) {
  case Marble::FieldType::integer:
    return py::int_(static_cast<long long>(x));
  case Marble::FieldType::choice:
    return py::str(f.choices.at(static_cast<std::size_t>(x)));
  case Marble::FieldType::real:
    break;
  }
  return py::float_(x);
}

char const *role_name(Marble::KernelRole r) {
  switch (r) {
  case Marble::KernelRole::conservative:
    return "conservative";
  case Marble::KernelRole::pair_dissipative:
    return "pair_dissipative";
  case Marble::KernelRole::colloid_surface:
    return "colloid_surface";
  case Marble::KernelRole::wall_surface:
    return "wall_surface";
  case Marble::KernelRole::srd_boundary:
    return "srd_boundary";
  case Marble::KernelRole::rotational_pair:
    return "rotational_pair";
  }
  return "?";
}

/** Name, feature, role and field list of every kernel (for Python and docs). */
py::list kernel_descriptions() {
  py::list out;
  Marble::for_each_kernel<Marble::AllKernels>([&]<class K>() {
    py::list fields;
    for (auto const &f : K::fields()) {
      py::dict d;
      d["key"] = f.key;
      d["type"] = f.type == Marble::FieldType::real      ? "real"
                  : f.type == Marble::FieldType::integer ? "integer"
                                                         : "choice";
      d["required"] = f.required;
      d["default"] = f.type == Marble::FieldType::choice && !f.choices.empty()
                         ? py::object(py::str(f.choices.at(static_cast<std::size_t>(f.default_value))))
                         : py::object(py::float_(f.default_value));
      d["range"] = f.type == Marble::FieldType::integer && f.hint ? std::string(f.hint)
                   : f.type == Marble::FieldType::choice          ? std::string()
                                                                  : range_str(f.lo, f.lo_open, f.hi, f.hi_open);
      py::list choices;
      for (auto c : f.choices)
        choices.append(c);
      d["choices"] = choices;
      d["keyword"] = f.keyword ? py::object(py::str(f.keyword)) : py::object(py::none());
      d["feature"] = f.missing_feature ? py::object(py::str(f.missing_feature)) : py::object(py::none());
      fields.append(d);
    }
    py::dict k;
    k["name"] = K::name;
    k["feature"] = K::feature;
    k["py_class"] = K::py_class;
    k["doc"] = K::doc;
    k["compiled"] = Marble::compiled<K>;
    k["role"] = role_name(K::role);
    k["ordered"] = Marble::is_ordered(K::role);
    k["fields"] = fields;
    out.append(k);
  });
  return out;
}

} // namespace

void bind_interactions(py::class_<System> &cls) {
  cls.def_static("nonbonded_kernels", &kernel_descriptions);
  cls.def("set_nonbonded", [](System &s, int i, int j, std::string const &kind, py::dict kw) {
    check_types(i, j);
    with_kernel(kind, [&]<class K>() {
      if constexpr (!Marble::compiled<K>) {
        throw Utils::FeaturesError(K::feature, K::name);
      } else {
        auto p = Marble::parse_fields(K::name, K::fields(), field_values(kw));
        if constexpr (requires { K::finish(p); })
          K::finish(p);
        p.active = K::activates(p);
        if constexpr (requires { K::check_pair(s, i, j, p); })
          K::check_pair(s, i, j, p);
        s.set_kernel<K>(i, j, p);
      }
    });
  });
  cls.def("get_nonbonded", [](System &s, int i, int j, std::string const &kind) {
    check_types(i, j);
    py::dict d;
    with_kernel(kind, [&]<class K>() {
      if constexpr (!Marble::compiled<K>) {
        throw Utils::FeaturesError(K::feature, K::name);
      } else {
        if (std::max(i, j) >= s.interactions().n_types())
          return;
        auto const &p = s.interactions().get(i, j).get<K>();
        if (!p.active)
          return;
        for (auto const &f : K::fields())
          d[f.key] = field_to_py<K>(f, p);
      }
    });
    return d;
  });
  cls.def("deactivate_nonbonded", [](System &s, int i, int j, std::string const &kind) {
    check_types(i, j);
    with_kernel(kind, [&]<class K>() {
      if constexpr (!Marble::compiled<K>)
        throw Utils::FeaturesError(K::feature, K::name);
      else
        s.set_kernel<K>(i, j, typename K::Params{});
    });
  });
  cls.def("reset_nonbonded", &System::reset_interactions);
}

} // namespace ScriptInterface
