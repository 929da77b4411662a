#include "analysis/correlator.hpp"

#include "utils/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace Marble::Accumulators {

CorrOperation parse_corr_operation(std::string const &name) {
  if (name == "scalar_product")
    return CorrOperation::ScalarProduct;
  if (name == "componentwise_product")
    return CorrOperation::ComponentwiseProduct;
  if (name == "square_distance_componentwise")
    return CorrOperation::SquareDistanceComponentwise;
  throw std::invalid_argument("parameter 'corr_operation' must be one of scalar_product, "
                              "componentwise_product, square_distance_componentwise; got '" +
                              name + "'");
}

Compression parse_compression(std::string const &name, std::string const &param) {
  if (name == "discard1")
    return Compression::Discard1;
  if (name == "discard2")
    return Compression::Discard2;
  if (name == "linear")
    return Compression::Linear;
  throw std::invalid_argument("parameter '" + param +
                              "' must be one of discard1, discard2, linear; got '" + name + "'");
}

std::string to_string(CorrOperation op) {
  switch (op) {
  case CorrOperation::ScalarProduct:
    return "scalar_product";
  case CorrOperation::ComponentwiseProduct:
    return "componentwise_product";
  default:
    return "square_distance_componentwise";
  }
}

std::string to_string(Compression c) {
  switch (c) {
  case Compression::Discard1:
    return "discard1";
  case Compression::Discard2:
    return "discard2";
  default:
    return "linear";
  }
}

std::size_t corr_dim(CorrOperation op, std::size_t n) {
  return op == CorrOperation::ScalarProduct ? 1 : n;
}

void correlate_add(CorrOperation op, double const *a, double const *b, std::size_t n, double *out) {
  switch (op) {
  case CorrOperation::ScalarProduct: {
    double s = 0.;
    for (std::size_t i = 0; i < n; ++i)
      s += a[i] * b[i];
    out[0] += s;
    break;
  }
  case CorrOperation::ComponentwiseProduct:
    for (std::size_t i = 0; i < n; ++i)
      out[i] += a[i] * b[i];
    break;
  case CorrOperation::SquareDistanceComponentwise:
    for (std::size_t i = 0; i < n; ++i)
      out[i] += (b[i] - a[i]) * (b[i] - a[i]);
    break;
  }
}

namespace {
// discard1 keeps the second (newer) value, discard2 the first, linear averages.
void compress(Compression c, std::vector<double> const &older, double const *newer,
              std::vector<double> &out) {
  std::size_t const n = older.size();
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = c == Compression::Discard1   ? newer[i]
             : c == Compression::Discard2 ? older[i]
                                          : 0.5 * (older[i] + newer[i]);
}
} // namespace

MultipleTau::MultipleTau(std::size_t dim_a, std::size_t dim_b, int tau_lin,
                         long long tau_max_samples, CorrOperation op, Compression compress_a,
                         Compression compress_b)
    : m_dim_a(dim_a), m_dim_b(dim_b), m_dim_corr(corr_dim(op, dim_a)), m_tau_lin(tau_lin), m_op(op),
      m_ca(compress_a), m_cb(compress_b) {
  if (tau_lin < 2 || tau_lin % 2)
    throw std::invalid_argument("parameter 'tau_lin' must be an even integer >= 2, got " +
                                std::to_string(tau_lin));
  if (tau_max_samples < 1)
    throw std::invalid_argument("parameter 'tau_max' must cover at least one sample interval");
  if (dim_a == 0 || dim_b == 0)
    throw std::invalid_argument("correlator: observables must have at least one value");
  if (dim_a != dim_b)
    throw std::invalid_argument("correlator: obs1 and obs2 must have the same number of values "
                                "for corr_operation '" +
                                to_string(op) + "' (got " + std::to_string(dim_a) + " and " +
                                std::to_string(dim_b) + ")");
  std::size_t depth = 1;
  while (static_cast<long long>(tau_lin) << (depth - 1) < tau_max_samples)
    ++depth;
  m_levels.resize(depth);
  for (auto &lev : m_levels) {
    lev.a.resize((tau_lin + 1) * dim_a);
    lev.b.resize((tau_lin + 1) * dim_b);
  }
  for (int k = 0; k <= tau_lin; ++k)
    m_lags.push_back(k);
  for (std::size_t l = 1; l < depth; ++l)
    for (int k = tau_lin / 2 + 1; k <= tau_lin; ++k)
      m_lags.push_back(static_cast<long long>(k) << l);
  m_count.assign(m_lags.size(), 0);
  m_sum.assign(m_lags.size() * m_dim_corr, 0.);
}

std::size_t MultipleTau::lag_index(std::size_t l, int k) const {
  if (l == 0)
    return static_cast<std::size_t>(k);
  return m_tau_lin + 1 + (l - 1) * (m_tau_lin / 2) + (k - m_tau_lin / 2 - 1);
}

void MultipleTau::push(double const *a, double const *b) {
  ++m_n_samples;
  push_level(0, a, b);
}

void MultipleTau::push_level(std::size_t l, double const *a, double const *b) {
  Level &lev = m_levels[l];
  auto const cap = static_cast<long long>(m_tau_lin + 1);
  long long const n = lev.n;
  std::size_t const slot = static_cast<std::size_t>(n % cap);
  std::copy(a, a + m_dim_a, lev.a.begin() + slot * m_dim_a);
  std::copy(b, b + m_dim_b, lev.b.begin() + slot * m_dim_b);
  double const *b_now = lev.b.data() + slot * m_dim_b;
  int const k_min = l == 0 ? 0 : m_tau_lin / 2 + 1;
  for (int k = k_min; k <= m_tau_lin && n - k >= 0; ++k) {
    std::size_t const s = static_cast<std::size_t>((n - k) % cap);
    std::size_t const idx = lag_index(l, k);
    correlate_add(m_op, lev.a.data() + s * m_dim_a, b_now, m_dim_a,
                  m_sum.data() + idx * m_dim_corr);
    ++m_count[idx];
  }
  lev.n = n + 1;
  if (l + 1 == m_levels.size())
    return;
  if (!lev.pending) {
    lev.pend_a.assign(a, a + m_dim_a);
    lev.pend_b.assign(b, b + m_dim_b);
    lev.pending = true;
    return;
  }
  lev.pending = false;
  std::vector<double> ca, cb;
  compress(m_ca, lev.pend_a, a, ca);
  compress(m_cb, lev.pend_b, b, cb);
  push_level(l + 1, ca.data(), cb.data());
}

std::vector<double> MultipleTau::result() const {
  std::vector<double> out(m_sum.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < m_lags.size(); ++i)
    if (m_count[i] > 0)
      for (std::size_t d = 0; d < m_dim_corr; ++d)
        out[i * m_dim_corr + d] = m_sum[i * m_dim_corr + d] / static_cast<double>(m_count[i]);
  return out;
}

namespace {
long long tau_max_in_samples(double tau_max, double dt) {
  if (!(std::isfinite(tau_max) && tau_max > 0.))
    throw std::invalid_argument("parameter 'tau_max' must be a finite number > 0, got " +
                                Utils::to_str(tau_max));
  double const r = tau_max / dt;
  if (!(r < 1e15))
    throw std::invalid_argument("parameter 'tau_max' is too large for the sampling interval");
  return std::max(1LL, static_cast<long long>(std::ceil(r * (1. - 1e-12))));
}

double sampling_interval(int delta_N, double time_step) {
  if (delta_N < 1)
    throw std::invalid_argument("parameter 'delta_N' must be an integer >= 1, got " +
                                std::to_string(delta_N));
  if (!(std::isfinite(time_step) && time_step > 0.))
    throw std::invalid_argument(
        "the correlator needs the system's time_step: set system.time_step > 0 first");
  return delta_N * time_step;
}

void check_obs(std::shared_ptr<Observables::Observable> const &obs, char const *name) {
  if (!obs)
    throw std::invalid_argument(std::string("parameter '") + name + "' must be an observable");
}
} // namespace

Correlator::Correlator(std::shared_ptr<Observables::Observable> obs1,
                       std::shared_ptr<Observables::Observable> obs2, int tau_lin, double tau_max,
                       int delta_N, double time_step, CorrOperation op, Compression c1,
                       Compression c2)
    : m_obs1((check_obs(obs1, "obs1"), std::move(obs1))), m_obs2(obs2 ? std::move(obs2) : m_obs1),
      m_time_step(time_step), m_dt(sampling_interval(delta_N, time_step)), m_tau_max(tau_max),
      m_op(op), m_data(m_obs1->n_values(), m_obs2->n_values(), tau_lin,
                       tau_max_in_samples(tau_max, m_dt), op, c1, c2) {
  this->delta_N = delta_N;
}

void Correlator::update(System &system) {
  if (m_finalized)
    throw Utils::RuntimeError("Correlator: finalize() was called, it accepts no more samples "
                              "(remove it from system.auto_update_accumulators)");
  if (std::abs(system.time_step() - m_time_step) > 1e-12 * m_time_step)
    throw Utils::RuntimeError(
        "Correlator: the time step changed from " + Utils::to_str(m_time_step) + " to " +
        Utils::to_str(system.time_step()) + " since it was created: its lag times would be wrong");
  auto const a = (*m_obs1)(system);
  if (m_obs2 == m_obs1) {
    m_data.push(a.data(), a.data());
  } else {
    auto const b = (*m_obs2)(system);
    m_data.push(a.data(), b.data());
  }
}

std::vector<std::size_t> Correlator::result_shape() const {
  std::vector<std::size_t> shape{m_data.n_lags()};
  if (m_op == CorrOperation::ScalarProduct) {
    shape.push_back(1);
  } else {
    for (auto s : m_obs1->shape())
      shape.push_back(s);
  }
  return shape;
}

TimeSeries::TimeSeries(std::shared_ptr<Observables::Observable> obs, int delta_N)
    : m_obs((check_obs(obs, "obs"), std::move(obs))) {
  sampling_interval(delta_N, 1.);
  this->delta_N = delta_N;
}

void TimeSeries::update(System &system) {
  auto const x = (*m_obs)(system);
  m_data.insert(m_data.end(), x.begin(), x.end());
  ++m_n;
}

MeanVarianceCalculator::MeanVarianceCalculator(std::shared_ptr<Observables::Observable> obs,
                                               int delta_N)
    : m_obs((check_obs(obs, "obs"), std::move(obs))) {
  sampling_interval(delta_N, 1.);
  this->delta_N = delta_N;
  m_mean.assign(m_obs->n_values(), 0.);
  m_m2.assign(m_obs->n_values(), 0.);
}

void MeanVarianceCalculator::update(System &system) {
  auto const x = (*m_obs)(system);
  ++m_n;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double const d = x[i] - m_mean[i];
    m_mean[i] += d / static_cast<double>(m_n);
    m_m2[i] += d * (x[i] - m_mean[i]);
  }
}

std::vector<double> MeanVarianceCalculator::variance() const {
  std::vector<double> v(m_m2.size(), std::numeric_limits<double>::quiet_NaN());
  if (m_n > 1)
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = m_m2[i] / static_cast<double>(m_n - 1);
  return v;
}

} // namespace Marble::Accumulators
