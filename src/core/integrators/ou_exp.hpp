#pragma once
// The Shardlow pair sweep's vector helpers (integrators/shardlow.cpp), 4
// lanes at a time with AVX2 where the CPU has it: exp(x) for x <= 0 (the OU
// factors a = exp(-lambda dt)) and the OU noise amplitudes. Every path
// (AVX2, scalar) performs the same IEEE operations in the same order (no
// FMA; ou_exp.cpp is compiled with -ffp-contract=off), so all give the same
// bits, and exp_neg(x) gives the bits of one lane. Within 1 ulp of the exact value on [-inf, 0]
// (testsuite/core/ou_exp_test.cpp): exp(-0) = exp(0) = 1 exactly, subnormal
// results for x in about [-745.13, -708.4], 0 below, exp(-inf) = 0, NaN -> NaN.
// x > 0 is outside the domain: it is treated as 0 (result 1).
#include <utility>
#include <vector>

namespace Marble {

/** exp(x) for x <= 0 (the bits of one lane of exp_neg_block). */
double exp_neg(double x);

/** out[l] = exp_neg(x[l]) for l < n (n >= 0; @p out may be @p x). */
void exp_neg_block(double const *x, double *out, int n);

using ExpNegBlockFn = void (*)(double const *x, double *out, int n);
/** The code paths this CPU runs ("scalar", and "avx2" where the CPU has it),
 * for the tests: each must give the bits of exp_neg. */
std::vector<std::pair<char const *, ExpNegBlockFn>> exp_neg_paths();

/** The OU step's noise amplitude and damping for l < n, from its factor
 * a[l] and kT/mu: sd[l] = sqrt(12 kT_mu[l] (1 - a[l]^2)) (evaluated as
 * (12 kT_mu) (1 - a a)) and am1[l] = a[l] - 1 (@p am1 may be @p a). The
 * bits of the scalar expressions on every path. */
void ou_amplitude_block(double const *a, double const *kT_mu, int n, double *sd, double *am1);

using OUAmplitudeBlockFn = void (*)(double const *, double const *, int, double *, double *);
/** Its code paths on this CPU (as exp_neg_paths), for the tests. */
std::vector<std::pair<char const *, OUAmplitudeBlockFn>> ou_amplitude_paths();

} // namespace Marble
