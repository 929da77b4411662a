#pragma once
// Offline correlation of a stored time series, averaged over every time origin:
//   C(k) = 1/(T-k) sum_{t=0}^{T-k-1} op(x[t], y[t+k]),  k = 0..max_lag,
// with the operations of the multiple-tau correlator. With FFTW (compile
// definition MARBLE_HAVE_FFTW) the products come from zero-padded FFTs in
// O(T log T) per component (square distances via prefix sums of squares);
// without it, and on request, from the direct O(T max_lag) sum.
#include "analysis/correlator.hpp"

#include <cstddef>
#include <vector>

namespace Marble::Analysis {

/** True if this build has the FFTW path. */
bool have_fftw();

/** @p x, @p y: T rows of n values (row-major); @p y may be nullptr (= x).
 * Returns (max_lag + 1) rows of corr_dim(op, n) values. Throws
 * std::invalid_argument if T == 0 or max_lag >= T. */
std::vector<double> fft_correlate(double const *x, double const *y, std::size_t T, std::size_t n,
                                  std::size_t max_lag, Accumulators::CorrOperation op);
std::vector<double> direct_correlate(double const *x, double const *y, std::size_t T, std::size_t n,
                                     std::size_t max_lag, Accumulators::CorrOperation op);

} // namespace Marble::Analysis
