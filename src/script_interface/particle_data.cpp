// Script interface of the particle storage: vectorised add / get / set of
// named properties, validated here (ValueError naming the property and range,
// FeaturesError for a property of a feature not compiled in).
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include "system/System.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace ScriptInterface {

using Marble::ParticleProperties;
using Marble::System;
using Utils::Vector3d;

namespace {

struct PropInfo {
  int width;            // 1 (scalar) or 3
  bool writable;
  char const *feature;  // nullptr if always available
  bool compiled;
};

std::map<std::string, PropInfo> const &properties() {
  static std::map<std::string, PropInfo> const props = {
      {"id", {1, false, nullptr, true}},
      {"type", {1, true, nullptr, true}},
      {"pos", {3, true, nullptr, true}},
      {"pos_folded", {3, false, nullptr, true}},
      {"image_box", {3, false, nullptr, true}},
      {"v", {3, true, nullptr, true}},
      {"f", {3, false, nullptr, true}},
#ifdef MASS
      {"mass", {1, true, "MASS", true}},
#else
      {"mass", {1, true, "MASS", false}},
#endif
#ifdef ROTATION
      {"rotation", {1, true, "ROTATION", true}},
      {"rinertia", {1, true, "ROTATION", true}},
      {"omega_lab", {3, true, "ROTATION", true}},
      {"omega_body", {3, true, "ROTATION", true}},
      {"torque_lab", {3, false, "ROTATION", true}},
#else
      {"rotation", {1, true, "ROTATION", false}},
      {"rinertia", {1, true, "ROTATION", false}},
      {"omega_lab", {3, true, "ROTATION", false}},
      {"omega_body", {3, true, "ROTATION", false}},
      {"torque_lab", {3, false, "ROTATION", false}},
#endif
#ifdef EXTERNAL_FORCE
      {"ext_force", {3, true, "EXTERNAL_FORCE", true}},
      {"fix", {3, true, "EXTERNAL_FORCE", true}},
#else
      {"ext_force", {3, true, "EXTERNAL_FORCE", false}},
      {"fix", {3, true, "EXTERNAL_FORCE", false}},
#endif
      // Langevin/Brownian friction of the particle (ESPResSo: THERMOSTAT_PER_PARTICLE,
      // always compiled in here); < 0 (the default, -1) means the thermostat's gamma
      {"gamma", {1, true, nullptr, true}},
#ifdef ROTATION
      {"gamma_rot", {1, true, "ROTATION", true}},
#else
      {"gamma_rot", {1, true, "ROTATION", false}},
#endif
#if defined(EXTERNAL_FORCE) && defined(ROTATION)
      {"ext_torque", {3, true, "EXTERNAL_FORCE and ROTATION", true}},
#else
      {"ext_torque", {3, true, "EXTERNAL_FORCE and ROTATION", false}},
#endif
  };
  return props;
}

// Without MASS every particle has mass 1: reading it is allowed, setting is not.
PropInfo const &lookup(std::string const &name, bool for_read = false) {
  auto const &props = properties();
  auto it = props.find(name);
  if (it == props.end()) {
    std::string list;
    for (auto const &kv : props)
      list += (list.empty() ? "" : ", ") + kv.first;
    value_error("unknown particle property '" + name + "' (known: " + list + ")");
  }
  if (!it->second.compiled && !(for_read && name == "mass"))
    throw Utils::FeaturesError(it->second.feature, "particle property '" + name + "'");
  return it->second;
}

/** Values of one property for n particles as an (n, width) array of doubles. */
py::array_t<double> as_rows(std::string const &name, py::handle value, int width, std::size_t n) {
  py::array_t<double> a;
  try {
    auto np = py::module_::import("numpy");
    // C order: apply() reads each row as width contiguous doubles (a transposed
    // or strided input, e.g. meshgrid(...).reshape(3, -1).T, is copied).
    a = np.attr("asarray")(value, "dtype"_a = "float64", "order"_a = "C");
  } catch (py::error_already_set &) {
    value_error("particle property '" + name + "' must be numeric");
  }
  // Accept one value for all particles or one per particle.
  if (width == 1) {
    if (a.ndim() == 0)
      a = a.attr("reshape")(1).attr("repeat")(n);
    if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
      value_error("particle property '" + name + "' must be a scalar or have " +
                  std::to_string(n) + " entries, got shape " +
                  std::string(py::str(a.attr("shape"))));
    return a.attr("reshape")(n, 1);
  }
  if (a.ndim() == 1 && a.shape(0) == 3)
    a = py::module_::import("numpy").attr("tile")(a, py::make_tuple(n, 1));
  if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != n || a.shape(1) != 3)
    value_error("particle property '" + name + "' must have shape (3,) or (" + std::to_string(n) +
                ", 3), got " + std::string(py::str(a.attr("shape"))));
  return a;
}

void check_finite(std::string const &name, double x) {
  if (!std::isfinite(x))
    value_error("particle property '" + name + "' must be finite, got " + Utils::to_str(x));
}

/** Apply @p name = @p row to a properties record (validated). */
void apply(System const &sys, ParticleProperties &p, std::string const &name, double const *row) {
  auto vec = [&](char const *nm) {
    Vector3d v{row[0], row[1], row[2]};
    for (int d = 0; d < 3; ++d)
      check_finite(nm, v[d]);
    return v;
  };
  if (name == "type") {
    double const t = row[0];
    if (!(t >= 0 && t < Marble::InteractionTable::max_type && t == std::floor(t)))
      value_error("particle property 'type' must be an integer in [0, " +
                  std::to_string(Marble::InteractionTable::max_type) + "), got " + Utils::to_str(t));
    p.type = static_cast<int>(t);
  } else if (name == "pos") {
    Vector3d const x = vec("pos");
    for (int d = 0; d < 3; ++d)
      if (std::abs(x[d]) > 1e9 * sys.box().length()[d])
        value_error("particle property 'pos' is too far outside the box (|x| > 1e9 box_l)");
    p.pos = x;
    p.image = {};
  } else if (name == "v") {
    p.v = vec("v");
  } else if (name == "mass") {
    check_double("mass", row[0], 0., INFINITY, true);
    p.mass = row[0];
  } else if (name == "rotation") {
    if (row[0] != 0. && row[0] != 1.)
      value_error("particle property 'rotation' must be a bool");
    p.rotation = row[0] != 0.;
  } else if (name == "rinertia") {
    check_double("rinertia", row[0], 0., INFINITY, true);
    p.rinertia = row[0];
  } else if (name == "omega_lab" || name == "omega_body") {
    p.omega = vec(name.c_str());
  } else if (name == "gamma" || name == "gamma_rot") {
    double const g = row[0];
    if (!(std::isfinite(g) && (g >= 0. || g == -1.)))
      value_error("particle property '" + name + "' must be a finite number >= 0, or -1 for the "
                  "thermostat's global value, got " + Utils::to_str(g));
    (name == "gamma" ? p.gamma : p.gamma_rot) = g;
  } else if (name == "ext_force") {
    p.ext_force = vec("ext_force");
  } else if (name == "ext_torque") {
    p.ext_torque = vec("ext_torque");
  } else if (name == "fix") {
    std::uint8_t bits = 0;
    for (int d = 0; d < 3; ++d) {
      if (row[d] != 0. && row[d] != 1.)
        value_error("particle property 'fix' must be 3 bools");
      bits |= static_cast<std::uint8_t>((row[d] != 0.) << d);
    }
    p.fix = bits;
  } else {
    value_error("particle property '" + name + "' is read-only");
  }
}

/** rotation and rinertia accept per-axis values for espressomd compatibility, if all equal. */
py::object normalise_isotropic(std::string const &name, py::object value) {
  auto np = py::module_::import("numpy");
  py::array a;
  try {
    a = np.attr("asarray")(value, "dtype"_a = "float64");
  } catch (py::error_already_set &) {
    value_error("particle property '" + name + "' must be numeric");
  }
  if (a.ndim() >= 1 && a.shape(a.ndim() - 1) == 3 && (a.ndim() == 2 || a.ndim() == 1)) {
    py::array first = a.attr("__getitem__")(py::make_tuple(py::ellipsis(), 0));
    py::array maxv = a.attr("max")("axis"_a = -1), minv = a.attr("min")("axis"_a = -1);
    if (!np.attr("array_equal")(maxv, minv).cast<bool>())
      value_error("particle property '" + name +
                  "': only isotropic values (three equal components) are supported");
    return first;
  }
  return value;
}

std::vector<int> ids_from(py::handle ids) {
  return ids.cast<std::vector<int>>();
}

std::vector<int> global_ids(System const &s) {
  auto ids = s.comm().allgatherv(s.particles().ids_sorted());
  std::sort(ids.begin(), ids.end());
  return ids;
}

// IndexError naming the first id that no rank holds (collective).
void check_exist_globally(System const &s, std::vector<int> const &ids) {
  if (auto const missing = s.first_missing_particle(ids))
    throw py::index_error("particle " + std::to_string(*missing) + " does not exist");
}

} // namespace

void bind_particle_data(py::class_<System> &cls) {
  // SPMD: every rank calls these with the same arguments; reads gather over the ranks.
  cls.def("n_part", [](System const &s) { return s.n_particles(); });
  cls.def("particle_ids", [](System const &s) { return global_ids(s); });
  cls.def("particle_exists", [](System const &s, int pid) { return s.comm().any(s.particles().exists(pid)); });
  cls.def("highest_particle_id", [](System const &s) {
    auto ids = s.particles().ids_sorted();
    return s.comm().max(ids.empty() ? -1 : ids.back());
  });

  cls.def("add_particles", [](System &s, int n, py::dict props) {
    if (n <= 0)
      value_error("number of particles to add must be > 0");
    std::vector<ParticleProperties> parts(n);
    // ids
    std::vector<int> ids(n);
    if (props.contains("id")) {
      auto rows = as_rows("id", props["id"], 1, n);
      auto r = rows.unchecked<2>();
      for (int k = 0; k < n; ++k) {
        double const x = r(k, 0);
        if (!(x >= 0 && x < 1e8 && x == std::floor(x))) // the id map is dense
          value_error("particle property 'id' must be an integer in [0, 1e8), got " + Utils::to_str(x));
        ids[k] = static_cast<int>(x);
      }
    } else {
      auto const local = s.particles().ids_sorted();
      int next = s.comm().max(local.empty() ? -1 : local.back()) + 1;
      for (int k = 0; k < n; ++k)
        ids[k] = next++;
    }
    {
      std::set<int> seen;
      std::vector<int> taken; // ids that exist on this rank
      for (int pid : ids) {
        if (!seen.insert(pid).second)
          value_error("particle id " + std::to_string(pid) + " already exists");
        if (s.particles().exists(pid))
          taken.push_back(pid);
      }
      taken = s.comm().allgatherv(taken);
      if (!taken.empty())
        value_error("particle id " + std::to_string(*std::min_element(taken.begin(), taken.end())) +
                    " already exists");
    }
    if (!props.contains("pos"))
      value_error("particle property 'pos' is required to add particles");
    for (int k = 0; k < n; ++k)
      parts[k].id = ids[k];
    // Validate everything before adding anything.
    for (auto const &item : props) {
      auto const name = py::str(item.first).cast<std::string>();
      if (name == "id")
        continue;
      auto const &info = lookup(name);
      if (!info.writable)
        value_error("particle property '" + name + "' is read-only");
      py::object value = py::reinterpret_borrow<py::object>(item.second);
      if (name == "rotation" || name == "rinertia")
        value = normalise_isotropic(name, value);
      auto rows = as_rows(name, value, info.width, n);
      for (int k = 0; k < n; ++k)
        apply(s, parts[k], name, rows.data(k, 0));
    }
    for (auto const &p : parts)
      s.add_particle(p);
    return ids;
  });

  cls.def("get_property", [](System &s, std::string const &name, py::object ids_obj) {
    auto const &info = lookup(name, true);
    auto const ids = ids_from(ids_obj);
    auto const &ps = s.particles();
    auto const n = static_cast<py::ssize_t>(ids.size());
    bool const is_int = name == "id" || name == "type" || name == "image_box";
    bool const is_bool = name == "rotation" || name == "fix";
    std::vector<py::ssize_t> shape = {n};
    if (info.width == 3)
      shape.push_back(3);
    py::array_t<double> out(shape);
    double *o = out.mutable_data();
    std::fill(o, o + n * info.width, 0.);
    std::vector<double> found(static_cast<std::size_t>(n), 0.);
    for (py::ssize_t k = 0; k < n; ++k) {
      int const i = ps.index_of(ids[k]);
      if (i < 0)
        continue; // on another rank (or nowhere: checked below)
      found[k] = 1.;
      double *row = o + k * info.width;
      auto put = [&](Vector3d const &v) { row[0] = v[0], row[1] = v[1], row[2] = v[2]; };
      if (name == "id") row[0] = ps.id[i];
      else if (name == "type") row[0] = ps.type[i];
      else if (name == "pos") put(s.box().unfolded(ps.pos[i], ps.image[i]));
      else if (name == "pos_folded") {
        Vector3d p = ps.pos[i];
        Utils::Vector3i img{};
        s.box().fold(p, img);
        put(p);
      } else if (name == "image_box") {
        Vector3d p = ps.pos[i];
        Utils::Vector3i img = ps.image[i];
        s.box().fold(p, img);
        put({double(img[0]), double(img[1]), double(img[2])});
      } else if (name == "v") put(s.folded_velocity(i)); // Lees-Edwards: frame of pos_folded
      else if (name == "f") put(ps.f[i]);
      else if (name == "mass") row[0] = ps.get_mass(i);
      else if (name == "gamma") row[0] = ps.gamma[i];
      else if (name == "gamma_rot") row[0] = ps.gamma_rot[i];
#ifdef ROTATION
      else if (name == "rotation") row[0] = ps.rotation[i];
      else if (name == "rinertia") row[0] = ps.rinertia[i];
      else if (name == "omega_lab" || name == "omega_body") put(ps.omega[i]);
      else if (name == "torque_lab") put(ps.torque[i]);
#endif
#ifdef EXTERNAL_FORCE
      else if (name == "ext_force") put(ps.ext_force[i]);
      else if (name == "fix") put({double(ps.fix[i] & 1), double((ps.fix[i] >> 1) & 1), double((ps.fix[i] >> 2) & 1)});
#ifdef ROTATION
      else if (name == "ext_torque") put(ps.ext_torque[i]);
#endif
#endif
    }
    if (s.comm().parallel()) { // each particle lives on one rank: the sum gathers
      s.comm().sum_inplace(o, static_cast<int>(n * info.width));
      s.comm().sum_inplace(found.data(), static_cast<int>(n));
    }
    for (py::ssize_t k = 0; k < n; ++k)
      if (found[k] != 1.)
        throw py::index_error("particle " + std::to_string(ids[k]) + " does not exist");
    if (is_int)
      return py::object(out.attr("astype")("int64"));
    if (is_bool)
      return py::object(out.attr("astype")("bool"));
    return py::object(out);
  });

  cls.def("set_property", [](System &s, std::string const &name, py::object ids_obj, py::object value) {
    auto const &info = lookup(name);
    if (!info.writable)
      value_error("particle property '" + name + "' is read-only");
    auto const ids = ids_from(ids_obj);
    auto &ps = s.particles();
    check_exist_globally(s, ids);
    if (name == "rotation" || name == "rinertia")
      value = normalise_isotropic(name, value);
    auto rows = as_rows(name, value, info.width, ids.size());
    // Validate all rows first: a bad value changes nothing.
    std::vector<ParticleProperties> recs(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) {
      if (ps.exists(ids[k]))
        recs[k] = ps.get(ids[k]); // else: on another rank; the row is still validated
      apply(s, recs[k], name, rows.data(k, 0));
    }
    bool const keeps_lists = name == "ext_force" || name == "ext_torque" || name == "fix" ||
                             name == "gamma" || name == "gamma_rot";
    if (!keeps_lists)
      ps.clear_ghosts();
    for (std::size_t k = 0; k < ids.size(); ++k) {
      int const i = ps.index_of(ids[k]);
      if (name == "type")
        s.interactions().ensure_type(recs[k].type);
      if (i < 0)
        continue;
      auto const &p = recs[k];
      if (name == "type") {
        s.interactions().ensure_type(p.type);
        ps.type[i] = p.type;
      } else if (name == "pos") {
        Vector3d x = p.pos;
        Utils::Vector3i img{};
        s.box().fold(x, img);
        ps.pos[i] = x;
        ps.image[i] = img;
      } else if (name == "v") {
        ps.v[i] = p.v;
        // Lees-Edwards: p.v is in the frame of the folded position; the
        // next fold applies the jump of a pending shear-plane crossing
        if (s.box().lees_edwards().active())
          ps.v[i] += p.v - s.folded_velocity(i);
      }
      else if (name == "gamma") ps.gamma[i] = p.gamma;
      else if (name == "gamma_rot") ps.gamma_rot[i] = p.gamma_rot;
#ifdef MASS
      else if (name == "mass") ps.mass[i] = p.mass;
#endif
#ifdef ROTATION
      else if (name == "rotation") ps.rotation[i] = p.rotation;
      else if (name == "rinertia") ps.rinertia[i] = p.rinertia;
      else if (name == "omega_lab" || name == "omega_body") ps.omega[i] = p.omega;
#endif
#ifdef EXTERNAL_FORCE
      // External force/torque: the stored force already holds the old value,
      // so it is corrected in place; the pair forces, the Verlet list and the
      // thermostat noise of the last step stay valid (re-setting ext_force
      // between runs, e.g. in reverse Poiseuille, then changes nothing else).
      else if (name == "ext_force") {
        ps.f[i] += p.ext_force - ps.ext_force[i];
        ps.ext_force[i] = p.ext_force;
      } else if (name == "fix") ps.fix[i] = p.fix;
#ifdef ROTATION
      else if (name == "ext_torque") {
        ps.torque[i] += p.ext_torque - ps.ext_torque[i];
        ps.ext_torque[i] = p.ext_torque;
      }
#endif
#endif
    }
    if (name == "gamma" || name == "gamma_rot") {
      s.on_change(); // the thermostat forces of the last step used the old value
      return;
    }
    if (keeps_lists)
      return; // no particle moved and no pair force changed
    s.on_particle_change();
  });

  cls.def("remove_particles", [](System &s, std::vector<int> const &ids) {
    check_exist_globally(s, ids);
    for (int pid : ids)
      s.remove_particle(pid);
  });
  cls.def("clear_particles", &System::clear_particles);
  cls.def_static("property_names", [] {
    std::vector<std::string> out;
    for (auto const &kv : properties())
      if (kv.second.compiled)
        out.push_back(kv.first);
    return out;
  });
}

} // namespace ScriptInterface
