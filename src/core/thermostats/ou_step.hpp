#pragma once
// The exact Ornstein-Uhlenbeck step of a relative velocity over dt (the
// Shardlow pair updates: integrators/shardlow.cpp, marble/Colloids.cpp):
//   u' = a u + s xi,  a = exp(-lambda dt),  s = sqrt(12 kT/mu (1 - a^2)),
// with xi uniform of variance 1/12 (hence sqrt(12)) and lambda the friction
// rate on u (friction / reduced mass mu): the stationary variance is kT/mu at
// any dt.
#include <cmath>

namespace Marble {

struct OU {
  double a, s;
  OU(double lambda_dt, double kT_over_mu) {
    a = std::exp(-lambda_dt);
    s = std::sqrt(12. * kT_over_mu * (1. - a * a)); // sqrt(12): xi has variance 1/12
  }
};

} // namespace Marble
