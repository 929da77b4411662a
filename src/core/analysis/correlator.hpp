#pragma once
// Accumulators updated during integration (System::auto_update()):
// the multiple-tau correlator, a time series and a mean/variance calculator.
//
// Multiple-tau scheme (Ramirez, Sinha, Gubbins, J. Chem. Phys. 133, 154103
// (2010); our own formulation, doc/analysis.md): level 0 holds the samples
// x_0[n]; level l holds x_l[j] = compress(x_{l-1}[2j], x_{l-1}[2j+1]), i.e.
// one value per aligned block of 2^l samples, built as soon as the block is
// complete. Level 0 correlates lags k = 0..tau_lin, level l >= 1 lags
// k 2^l for k = tau_lin/2+1..tau_lin, each averaged over every pair of values
// of that level: C(k 2^l) = mean_j op(A_l[j], B_l[j+k]). This is exactly what
// the same compression followed by a direct correlation would give.
#include "analysis/observables.hpp"
#include "system/System.hpp"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace Marble {
struct CheckpointAccess; // io/checkpoint.cpp: accumulator state, bit for bit
}

namespace Marble::Accumulators {

enum class CorrOperation { ScalarProduct, ComponentwiseProduct, SquareDistanceComponentwise };
enum class Compression { Discard1, Discard2, Linear };

/** std::invalid_argument naming the allowed values for unknown names. */
CorrOperation parse_corr_operation(std::string const &name);
Compression parse_compression(std::string const &name, std::string const &param);
std::string to_string(CorrOperation op);
std::string to_string(Compression c);

/** Number of values op(a, b) produces for vectors of n values. */
std::size_t corr_dim(CorrOperation op, std::size_t n);
/** out[...] += op(a, b) for a at the earlier and b at the later time. */
void correlate_add(CorrOperation op, double const *a, double const *b, std::size_t n, double *out);

/** The multiple-tau data structure (no System): push samples, read results. */
class MultipleTau {
  friend struct Marble::CheckpointAccess;

public:
  /** @p tau_max_samples >= 1: the largest lag (in samples) to cover; the
   * number of levels is the smallest H with tau_lin 2^(H-1) >= it. */
  MultipleTau(std::size_t dim_a, std::size_t dim_b, int tau_lin, long long tau_max_samples,
              CorrOperation op, Compression compress_a, Compression compress_b);
  void push(double const *a, double const *b);
  int tau_lin() const { return m_tau_lin; }
  int hierarchy_depth() const { return static_cast<int>(m_levels.size()); }
  std::size_t n_lags() const { return m_lags.size(); }
  std::size_t dim_corr() const { return m_dim_corr; }
  /** Lags in samples. */
  std::vector<long long> const &lags() const { return m_lags; }
  /** n_lags x dim_corr means; NaN where no pair was seen yet. */
  std::vector<double> result() const;
  std::vector<long long> const &sample_sizes() const { return m_count; }
  long long n_samples() const { return m_n_samples; }

private:
  struct Level {
    std::vector<double> a, b; // ring buffers of tau_lin + 1 values
    long long n = 0;          // values received at this level
    std::vector<double> pend_a, pend_b;
    bool pending = false;
  };
  void push_level(std::size_t l, double const *a, double const *b);
  std::size_t lag_index(std::size_t l, int k) const;

  std::size_t m_dim_a, m_dim_b, m_dim_corr;
  int m_tau_lin;
  CorrOperation m_op;
  Compression m_ca, m_cb;
  std::vector<Level> m_levels;
  std::vector<long long> m_lags, m_count;
  std::vector<double> m_sum;
  long long m_n_samples = 0;
};

/** AutoUpdate wrapper: samples obs1 (and obs2) every delta_N steps. */
class Correlator : public AutoUpdate {
  friend struct Marble::CheckpointAccess;

public:
  /** @p dt: time between samples (delta_N * time_step), for lag times and
   * to detect a later change of the time step. Validates everything. */
  Correlator(std::shared_ptr<Observables::Observable> obs1,
             std::shared_ptr<Observables::Observable> obs2, int tau_lin, double tau_max,
             int delta_N, double time_step, CorrOperation op, Compression c1, Compression c2);
  void update(System &system) override;
  /** No more samples are accepted afterwards (the eager compression leaves
   * at most one unpaired value per level, which is discarded). */
  void finalize() { m_finalized = true; }
  bool finalized() const { return m_finalized; }
  MultipleTau const &data() const { return m_data; }
  double dt() const { return m_dt; }
  double tau_max() const { return m_tau_max; }
  std::vector<std::size_t> result_shape() const;
  std::shared_ptr<Observables::Observable> obs1() const { return m_obs1; }
  std::shared_ptr<Observables::Observable> obs2() const { return m_obs2; }
  CorrOperation operation() const { return m_op; }

private:
  std::shared_ptr<Observables::Observable> m_obs1, m_obs2;
  double m_time_step, m_dt, m_tau_max;
  CorrOperation m_op;
  MultipleTau m_data;
  bool m_finalized = false;
};

/** Stores every sample. */
class TimeSeries : public AutoUpdate {
  friend struct Marble::CheckpointAccess;

public:
  TimeSeries(std::shared_ptr<Observables::Observable> obs, int delta_N);
  void update(System &system) override;
  void clear() { m_data.clear(), m_n = 0; }
  std::size_t n_samples() const { return m_n; }
  std::vector<double> const &data() const { return m_data; }
  std::shared_ptr<Observables::Observable> obs() const { return m_obs; }

private:
  std::shared_ptr<Observables::Observable> m_obs;
  std::vector<double> m_data;
  std::size_t m_n = 0;
};

/** Running mean and variance per value (Welford). */
class MeanVarianceCalculator : public AutoUpdate {
  friend struct Marble::CheckpointAccess;

public:
  MeanVarianceCalculator(std::shared_ptr<Observables::Observable> obs, int delta_N);
  void update(System &system) override;
  std::size_t n_samples() const { return m_n; }
  std::vector<double> const &mean() const { return m_mean; }
  /** Sample variance (n - 1 in the denominator); NaN for fewer than 2 samples. */
  std::vector<double> variance() const;
  std::shared_ptr<Observables::Observable> obs() const { return m_obs; }

private:
  std::shared_ptr<Observables::Observable> m_obs;
  std::vector<double> m_mean, m_m2;
  std::size_t m_n = 0;
};

} // namespace Marble::Accumulators
