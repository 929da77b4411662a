// Script interface of the observables, accumulators (correlator, time series,
// mean/variance) and the offline FFT correlator (doc/analysis.md). The Python
// wrappers in marble/observables.py and marble/accumulators.py add keyword
// handling; every value is validated here or in the core.
#include "script_interface/bindings.hpp"
#include "script_interface/params.hpp"

#include "analysis/correlator.hpp"
#include "analysis/fft_correlator.hpp"
#include "analysis/observables.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>

namespace ScriptInterface {

using Marble::AutoUpdate;
using Marble::System;
namespace Obs = Marble::Observables;
namespace Acc = Marble::Accumulators;

namespace {

std::vector<int> ids_from(py::handle h) {
  if (py::isinstance<py::str>(h) || !py::hasattr(h, "__iter__"))
    value_error("parameter 'ids' must be a list of particle ids");
  std::vector<int> ids;
  for (auto item : h) {
    auto const v = to_int("ids", item);
    if (v < 0 || v > INT_MAX)
      value_error("parameter 'ids': particle ids are integers >= 0, got " + std::to_string(v));
    ids.push_back(static_cast<int>(v));
  }
  return ids;
}

int int_param(std::string const &name, py::handle h, long long lo) {
  auto const v = to_int(name, h);
  if (v < lo || v > INT_MAX)
    value_error("parameter '" + name + "' must be an integer >= " + std::to_string(lo) + ", got " +
                std::to_string(v));
  return static_cast<int>(v);
}

py::array_t<double> shaped(std::vector<double> const &data, std::vector<std::size_t> shape) {
  std::vector<py::ssize_t> s(shape.begin(), shape.end());
  py::array_t<double> a(s);
  std::copy(data.begin(), data.end(), a.mutable_data());
  return a;
}

std::vector<std::size_t> with_leading(std::size_t n, std::vector<std::size_t> shape) {
  shape.insert(shape.begin(), n);
  return shape;
}

std::shared_ptr<Obs::Observable> as_obs(py::handle h, char const *name) {
  if (h.is_none())
    return nullptr;
  try {
    return h.cast<std::shared_ptr<Obs::Observable>>();
  } catch (py::cast_error &) {
    value_error(std::string("parameter '") + name + "' must be a marble observable");
  }
}

/** (T, n) C-contiguous copy of a time series given as (T, ...) array. */
py::array_t<double> series(py::handle h, char const *name) {
  py::array_t<double> a;
  try {
    a = py::module_::import("numpy").attr("ascontiguousarray")(h, "dtype"_a = "float64");
  } catch (py::error_already_set &) {
    value_error(std::string("parameter '") + name + "' must be a numeric array");
  }
  if (a.ndim() == 0)
    value_error(std::string("parameter '") + name + "' must have a time axis (shape (T, ...))");
  auto const T = a.shape(0);
  py::ssize_t const n = T > 0 ? a.size() / T : 0;
  a = a.attr("reshape")(T, n);
  auto const *p = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(p[i]))
      value_error(std::string("parameter '") + name + "' contains non-finite values");
  return a;
}

} // namespace

void bind_accumulators(py::module_ &m, py::class_<System> &cls) {
  // --- observables ---
  py::class_<Obs::Observable, std::shared_ptr<Obs::Observable>>(m, "Observable")
      .def("calculate",
           [](Obs::Observable const &o, System const &s) { return shaped(o(s), o.shape()); })
      .def("shape", [](Obs::Observable const &o) { return py::tuple(py::cast(o.shape())); })
      .def_property_readonly("name", &Obs::Observable::name);

  auto pid_obs =
      py::class_<Obs::PidObservable, Obs::Observable, std::shared_ptr<Obs::PidObservable>>(
          m, "PidObservable");
  pid_obs.def_property_readonly("ids", &Obs::PidObservable::ids);
  py::class_<Obs::ParticlePositions, Obs::PidObservable, std::shared_ptr<Obs::ParticlePositions>>(
      m, "ParticlePositions")
      .def(py::init([](System const &s, py::object ids) {
        return std::make_shared<Obs::ParticlePositions>(s, ids_from(ids));
      }));
  py::class_<Obs::ParticleVelocities, Obs::PidObservable, std::shared_ptr<Obs::ParticleVelocities>>(
      m, "ParticleVelocities")
      .def(py::init([](System const &s, py::object ids) {
        return std::make_shared<Obs::ParticleVelocities>(s, ids_from(ids));
      }));
  py::class_<Obs::ParticleAngularVelocities, Obs::PidObservable,
             std::shared_ptr<Obs::ParticleAngularVelocities>>(m, "ParticleAngularVelocities")
      .def(py::init([](System const &s, py::object ids) {
        return std::make_shared<Obs::ParticleAngularVelocities>(s, ids_from(ids));
      }));
  py::class_<Obs::ComVelocity, Obs::Observable, std::shared_ptr<Obs::ComVelocity>>(m, "ComVelocity")
      .def(py::init([](System const &s, py::object ids) {
        return std::make_shared<Obs::ComVelocity>(s, ids_from(ids));
      }))
      .def_property_readonly("ids", &Obs::ComVelocity::ids);

  // --- accumulators ---
  py::class_<AutoUpdate, std::shared_ptr<AutoUpdate>>(m, "AutoUpdate")
      .def_property_readonly("delta_N", [](AutoUpdate const &a) { return a.delta_N; })
      .def("update", [](AutoUpdate &a, System &s) { a.update(s); });

  py::class_<Acc::Correlator, AutoUpdate, std::shared_ptr<Acc::Correlator>>(m, "Correlator")
      .def(py::init([](py::object obs1, py::object obs2, py::object tau_lin, py::object tau_max,
                       py::object delta_N, double time_step, std::string const &op,
                       std::string const &c1, std::string const &c2) {
             auto o1 = as_obs(obs1, "obs1");
             if (!o1)
               value_error("parameter 'obs1' is required");
             return std::make_shared<Acc::Correlator>(
                 o1, as_obs(obs2, "obs2"), int_param("tau_lin", tau_lin, 2),
                 check_double("tau_max", to_double("tau_max", tau_max), 0., INFINITY, true),
                 int_param("delta_N", delta_N, 1), time_step, Acc::parse_corr_operation(op),
                 Acc::parse_compression(c1, "compress1"), Acc::parse_compression(c2, "compress2"));
           }),
           "obs1"_a, "obs2"_a, "tau_lin"_a, "tau_max"_a, "delta_N"_a, "time_step"_a,
           "corr_operation"_a, "compress1"_a, "compress2"_a)
      .def("result",
           [](Acc::Correlator const &c) { return shaped(c.data().result(), c.result_shape()); })
      .def("lag_times",
           [](Acc::Correlator const &c) {
             std::vector<double> t;
             for (auto k : c.data().lags())
               t.push_back(static_cast<double>(k) * c.dt());
             return shaped(t, {t.size()});
           })
      .def("lag_samples", [](Acc::Correlator const &c) { return c.data().lags(); })
      .def("sample_sizes", [](Acc::Correlator const &c) { return c.data().sample_sizes(); })
      .def("finalize", &Acc::Correlator::finalize)
      .def_property_readonly("finalized", &Acc::Correlator::finalized)
      .def_property_readonly("n_samples",
                             [](Acc::Correlator const &c) { return c.data().n_samples(); })
      .def_property_readonly("tau_lin", [](Acc::Correlator const &c) { return c.data().tau_lin(); })
      .def_property_readonly("tau_max", &Acc::Correlator::tau_max)
      .def_property_readonly("dt", &Acc::Correlator::dt)
      .def_property_readonly("hierarchy_depth",
                             [](Acc::Correlator const &c) { return c.data().hierarchy_depth(); })
      .def_property_readonly("corr_operation",
                             [](Acc::Correlator const &c) { return Acc::to_string(c.operation()); })
      .def_property_readonly("obs1", &Acc::Correlator::obs1)
      .def_property_readonly("obs2", &Acc::Correlator::obs2);

  py::class_<Acc::TimeSeries, AutoUpdate, std::shared_ptr<Acc::TimeSeries>>(m, "TimeSeries")
      .def(py::init([](py::object obs, py::object delta_N) {
             auto o = as_obs(obs, "obs");
             if (!o)
               value_error("parameter 'obs' is required");
             return std::make_shared<Acc::TimeSeries>(o, int_param("delta_N", delta_N, 1));
           }),
           "obs"_a, "delta_N"_a)
      .def("time_series",
           [](Acc::TimeSeries const &t) {
             return shaped(t.data(), with_leading(t.n_samples(), t.obs()->shape()));
           })
      .def("clear", &Acc::TimeSeries::clear)
      .def_property_readonly("n_samples", &Acc::TimeSeries::n_samples)
      .def_property_readonly("obs", &Acc::TimeSeries::obs);

  py::class_<Acc::MeanVarianceCalculator, AutoUpdate, std::shared_ptr<Acc::MeanVarianceCalculator>>(
      m, "MeanVarianceCalculator")
      .def(py::init([](py::object obs, py::object delta_N) {
             auto o = as_obs(obs, "obs");
             if (!o)
               value_error("parameter 'obs' is required");
             return std::make_shared<Acc::MeanVarianceCalculator>(o,
                                                                  int_param("delta_N", delta_N, 1));
           }),
           "obs"_a, "delta_N"_a)
      .def("mean",
           [](Acc::MeanVarianceCalculator const &c) {
             std::vector<double> mean = c.mean();
             if (c.n_samples() == 0)
               std::fill(mean.begin(), mean.end(), std::nan(""));
             return shaped(mean, c.obs()->shape());
           })
      .def("variance",
           [](Acc::MeanVarianceCalculator const &c) {
             return shaped(c.variance(), c.obs()->shape());
           })
      .def_property_readonly("n_samples", &Acc::MeanVarianceCalculator::n_samples)
      .def_property_readonly("obs", &Acc::MeanVarianceCalculator::obs);

  // --- the System's list of automatically updated accumulators ---
  cls.def("auto_update_add", [](System &s, std::shared_ptr<AutoUpdate> a) {
    auto &v = s.auto_update();
    if (std::find(v.begin(), v.end(), a) != v.end())
      value_error("this accumulator is already in auto_update_accumulators");
    v.push_back(std::move(a));
  });
  cls.def("auto_update_remove", [](System &s, std::shared_ptr<AutoUpdate> a) {
    auto &v = s.auto_update();
    auto it = std::find(v.begin(), v.end(), a);
    if (it == v.end())
      value_error("this accumulator is not in auto_update_accumulators");
    v.erase(it);
  });
  cls.def("auto_update_clear", [](System &s) { s.auto_update().clear(); });
  cls.def("auto_update_size", [](System &s) { return s.auto_update().size(); });

  // --- offline correlation of stored series ---
  m.def("have_fftw", &Marble::Analysis::have_fftw);
  m.def(
      "correlate",
      [](py::object x, py::object y, std::string const &op_name, py::object max_lag, bool direct) {
        auto const op = Acc::parse_corr_operation(op_name);
        auto const xa = series(x, "x");
        py::array_t<double> ya;
        if (!y.is_none()) {
          ya = series(y, "y");
          if (ya.shape(0) != xa.shape(0) || ya.shape(1) != xa.shape(1))
            value_error("parameters 'x' and 'y' must have the same shape");
        }
        auto const T = static_cast<std::size_t>(xa.shape(0));
        auto const n = static_cast<std::size_t>(xa.shape(1));
        if (T == 0 || n == 0)
          value_error("parameter 'x' is empty");
        std::size_t lag = T - 1;
        if (!max_lag.is_none()) {
          auto const l = to_int("max_lag", max_lag);
          if (l < 0 || static_cast<std::size_t>(l) >= T)
            value_error("parameter 'max_lag' must be in [0, " + std::to_string(T - 1) + "], got " +
                        std::to_string(l));
          lag = static_cast<std::size_t>(l);
        }
        double const *py_ = y.is_none() ? nullptr : ya.data();
        std::vector<double> out;
        {
          py::gil_scoped_release release;
          out = direct ? Marble::Analysis::direct_correlate(xa.data(), py_, T, n, lag, op)
                       : Marble::Analysis::fft_correlate(xa.data(), py_, T, n, lag, op);
        }
        return shaped(out, {lag + 1, Acc::corr_dim(op, n)});
      },
      "x"_a, "y"_a, "operation"_a, "max_lag"_a, "direct"_a);
}

} // namespace ScriptInterface
