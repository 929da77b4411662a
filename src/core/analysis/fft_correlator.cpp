#include "analysis/fft_correlator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#ifdef MARBLE_HAVE_FFTW
#include <fftw3.h>
#endif

namespace Marble::Analysis {

using Accumulators::CorrOperation;

namespace {

void check_sizes(std::size_t T, std::size_t n, std::size_t max_lag) {
  if (T == 0 || n == 0)
    throw std::invalid_argument("correlate: the time series is empty");
  if (max_lag >= T)
    throw std::invalid_argument("correlate: max_lag must be < the number of samples (" +
                                std::to_string(T) + "), got " + std::to_string(max_lag));
}

#ifdef MARBLE_HAVE_FFTW
/** Smallest 2^a 3^b 5^c >= n (sizes FFTW handles fastest). */
std::size_t good_size(std::size_t n) {
  std::size_t best = 1;
  while (best < n)
    best *= 2;
  for (std::size_t p5 = 1; p5 < best; p5 *= 5)
    for (std::size_t p35 = p5; p35 < best; p35 *= 3) {
      std::size_t m = p35;
      while (m < n)
        m *= 2;
      if (m < best)
        best = m;
    }
  return best;
}

/** RAII owner of the FFTW buffers and plans for one padded length. */
class FFTWorkspace {
public:
  explicit FFTWorkspace(std::size_t N) : m_N(N) {
    m_real = fftw_alloc_real(N);
    m_fx = fftw_alloc_complex(N / 2 + 1);
    m_fy = fftw_alloc_complex(N / 2 + 1);
    if (!m_real || !m_fx || !m_fy)
      throw std::bad_alloc();
    m_r2c = fftw_plan_dft_r2c_1d(static_cast<int>(N), m_real, m_fx, FFTW_ESTIMATE);
    m_c2r = fftw_plan_dft_c2r_1d(static_cast<int>(N), m_fx, m_real, FFTW_ESTIMATE);
  }
  ~FFTWorkspace() {
    fftw_destroy_plan(m_r2c);
    fftw_destroy_plan(m_c2r);
    fftw_free(m_real);
    fftw_free(m_fx);
    fftw_free(m_fy);
  }
  FFTWorkspace(FFTWorkspace const &) = delete;
  FFTWorkspace &operator=(FFTWorkspace const &) = delete;

  /** cross[k] = sum_t x[t] y[t+k] for k = 0..max_lag (component @p c of rows of n). */
  void cross(double const *x, double const *y, std::size_t T, std::size_t n, std::size_t c,
             double shift, std::size_t max_lag, std::vector<double> &out) {
    load(x, T, n, c, shift);
    fftw_execute_dft_r2c(m_r2c, m_real, m_fx);
    std::size_t const nc = m_N / 2 + 1;
    if (y != x) {
      load(y, T, n, c, shift);
      fftw_execute_dft_r2c(m_r2c, m_real, m_fy);
    }
    fftw_complex const *fy = y != x ? m_fy : m_fx;
    // conj(X) Y: the inverse transform is sum_t x[t] y[t+k] (circular, no
    // wrap-around for k < T since N >= 2T - 1)
    for (std::size_t i = 0; i < nc; ++i) {
      double const re = m_fx[i][0] * fy[i][0] + m_fx[i][1] * fy[i][1];
      double const im = m_fx[i][0] * fy[i][1] - m_fx[i][1] * fy[i][0];
      m_fx[i][0] = re;
      m_fx[i][1] = im;
    }
    fftw_execute_dft_c2r(m_c2r, m_fx, m_real);
    out.resize(max_lag + 1);
    for (std::size_t k = 0; k <= max_lag; ++k)
      out[k] = m_real[k] / static_cast<double>(m_N);
  }

private:
  void load(double const *x, std::size_t T, std::size_t n, std::size_t c, double shift) {
    for (std::size_t t = 0; t < T; ++t)
      m_real[t] = x[t * n + c] - shift;
    for (std::size_t t = T; t < m_N; ++t)
      m_real[t] = 0.;
  }
  std::size_t m_N;
  double *m_real;
  fftw_complex *m_fx, *m_fy;
  fftw_plan m_r2c, m_c2r;
};
#endif

} // namespace

bool have_fftw() {
#ifdef MARBLE_HAVE_FFTW
  return true;
#else
  return false;
#endif
}

std::vector<double> direct_correlate(double const *x, double const *y, std::size_t T, std::size_t n,
                                     std::size_t max_lag, CorrOperation op) {
  check_sizes(T, n, max_lag);
  if (!y)
    y = x;
  std::size_t const dc = Accumulators::corr_dim(op, n);
  std::vector<double> out((max_lag + 1) * dc, 0.);
  for (std::size_t k = 0; k <= max_lag; ++k) {
    double *row = out.data() + k * dc;
    for (std::size_t t = 0; t + k < T; ++t)
      Accumulators::correlate_add(op, x + t * n, y + (t + k) * n, n, row);
    for (std::size_t d = 0; d < dc; ++d)
      row[d] /= static_cast<double>(T - k);
  }
  return out;
}

std::vector<double> fft_correlate(double const *x, double const *y, std::size_t T, std::size_t n,
                                  std::size_t max_lag, CorrOperation op) {
#ifndef MARBLE_HAVE_FFTW
  return direct_correlate(x, y, T, n, max_lag, op);
#else
  check_sizes(T, n, max_lag);
  if (!y)
    y = x;
  std::size_t const dc = Accumulators::corr_dim(op, n);
  std::vector<double> out((max_lag + 1) * dc, 0.);
  FFTWorkspace ws(good_size(2 * T));
  std::vector<double> cr;
  for (std::size_t c = 0; c < n; ++c) {
    double shift = 0.;
    if (op == CorrOperation::SquareDistanceComponentwise) {
      // (y - x)^2 does not change under a common shift: centring on the mean
      // of x keeps the FFT's round-off relative to the fluctuations
      for (std::size_t t = 0; t < T; ++t)
        shift += x[t * n + c];
      shift /= static_cast<double>(T);
    }
    ws.cross(x, y, T, n, c, shift, max_lag, cr);
    if (op == CorrOperation::SquareDistanceComponentwise) {
      // sum_{t<T-k} x[t]^2 + sum_{t>=k} y[t]^2 - 2 sum_t x[t] y[t+k]
      std::vector<double> px(T + 1, 0.), py(T + 1, 0.);
      for (std::size_t t = 0; t < T; ++t) {
        double const a = x[t * n + c] - shift, b = y[t * n + c] - shift;
        px[t + 1] = px[t] + a * a;
        py[t + 1] = py[t] + b * b;
      }
      for (std::size_t k = 0; k <= max_lag; ++k)
        out[k * dc + c] = (px[T - k] + (py[T] - py[k]) - 2. * cr[k]) / static_cast<double>(T - k);
    } else {
      std::size_t const d = op == CorrOperation::ScalarProduct ? 0 : c;
      for (std::size_t k = 0; k <= max_lag; ++k)
        out[k * dc + d] += cr[k] / static_cast<double>(T - k);
    }
  }
  if (op == CorrOperation::SquareDistanceComponentwise) {
    for (auto &v : out) // round-off can leave tiny negative values
      v = std::max(v, 0.);
    if (y == x) // and a nonzero lag 0
      std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(dc), 0.);
  }
  return out;
#endif
}

} // namespace Marble::Analysis
