// Velocity Verlet: energy conservation of a Lennard-Jones fluid without a
// thermostat, momentum conservation, and free motion under external forces.
#include "config/features.hpp"
#include "system/System.hpp"
#include "utils/errors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using Marble::System;
using Utils::Vector3d;

#ifdef LENNARD_JONES
namespace {
// LJ eps = sigma = 1, cutoff 2.5 between type-0 particles.
void set_lj(System &s, double shift) {
  Marble::LennardJones::Params p;
  p.active = true;
  p.epsilon = 1.;
  p.sigma = 1.;
  p.cutoff = 2.5;
  p.shift = shift;
  s.set_kernel<Marble::LennardJones>(0, 0, p);
}

// N = 4 n^3 particles on an fcc lattice at density rho (no overlaps), with
// random velocities of temperature kT and zero total momentum.
void fcc_lj_fluid(System &s, int n, double rho, double kT, std::uint64_t seed) {
  int const N = 4 * n * n * n;
  double const L = std::cbrt(N / rho);
  s.set_box_l({L, L, L});
  set_lj(s, Marble::LennardJones::auto_shift(1., 2.5));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0., std::sqrt(kT));
  double const a = L / n;
  Vector3d const basis[4] = {{0., 0., 0.}, {0.5, 0.5, 0.}, {0.5, 0., 0.5}, {0., 0.5, 0.5}};
  std::vector<Vector3d> v;
  Vector3d vsum{};
  for (int i = 0; i < N; ++i) {
    v.push_back({g(rng), g(rng), g(rng)});
    vsum += v.back();
  }
  int id = 0;
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y)
      for (int z = 0; z < n; ++z)
        for (auto const &b : basis) {
          Marble::ParticleProperties pp;
          pp.id = id;
          pp.pos = {a * (x + b[0] + 0.25), a * (y + b[1] + 0.25), a * (z + b[2] + 0.25)};
          pp.v = v[id] - (1. / N) * vsum;
          s.add_particle(pp);
          ++id;
        }
}
} // namespace

TEST(VelocityVerlet, LJFluidConservesEnergy) {
  System s({1., 1., 1.});
  fcc_lj_fluid(s, 5, 0.8442, 1.44, 2024); // 500 particles; melts to kT ~ 0.7
  s.set_skin(0.4);
  s.set_time_step(0.005);
  int const n_blocks = 500, steps_per_block = 20; // 10^4 steps
  std::vector<double> E;
  s.run(0);
  E.push_back(s.energies().total());
  double const ekin0 = s.energies().kinetic;
  for (int b = 0; b < n_blocks; ++b) {
    s.run(steps_per_block);
    E.push_back(s.energies().total());
  }
  // The fluid really moved and exchanged energy: not a frozen lattice.
  double const ekin = s.energies().kinetic;
  EXPECT_LT(ekin, 0.8 * ekin0);
  EXPECT_GT(s.cells().n_rebuilds(), 20);
  // Drift: least-squares slope of E(t) times the run length, relative to |E|
  // (the end-point difference would mostly measure the O(dt^2) fluctuation
  // of the shadow energy, which is bounded separately).
  double const n = static_cast<double>(E.size());
  double st = 0., se = 0., stt = 0., ste = 0.;
  for (std::size_t k = 0; k < E.size(); ++k) {
    double const t = static_cast<double>(k);
    st += t, se += E[k], stt += t * t, ste += t * E[k];
  }
  double const slope = (n * ste - st * se) / (n * stt - st * st);
  double const rel_drift = std::abs(slope * (n - 1.)) / std::abs(E.front());
  double max_dev = 0.;
  for (double e : E)
    max_dev = std::max(max_dev, std::abs(e - E.front()));
  std::cout << "E0 = " << E.front() << ", E_end = " << E.back()
            << ", relative drift (fit) = " << rel_drift
            << ", max relative deviation = " << max_dev / std::abs(E.front()) << "\n";
  // Observed with other seeds: 1e-6 .. 5e-5 (a random walk from the force
  // jump at the cutoff); the bound is the project's requirement.
  EXPECT_LT(rel_drift, 1e-4);
  EXPECT_LT(max_dev / std::abs(E.front()), 3e-4);
  // Total momentum stays zero (pair forces are exactly antisymmetric).
  EXPECT_LT(s.linear_momentum().norm(), 1e-10);
}

TEST(VelocityVerlet, LJEnergyDriftGrowsWithTimeStep) {
  // The same test fails with a too-large time step: the bound above has teeth.
  System s({1., 1., 1.});
  fcc_lj_fluid(s, 3, 0.8442, 1.44, 7); // 108 particles
  s.set_skin(0.4);
  s.set_time_step(0.02);
  s.run(0);
  double const e0 = s.energies().total();
  s.run(1000);
  double const e1 = s.energies().total();
  EXPECT_GT(std::abs(e1 - e0) / std::abs(e0), 1e-4);
}

TEST(VelocityVerlet, RefusesBlowUpAndStaysUsable) {
  // Two LJ particles almost on top of each other: the step is refused with an
  // error naming the step and the particle; the positions are kept.
  System s({10., 10., 10.});
  set_lj(s, 0.);
  Marble::ParticleProperties a, b;
  a.id = 3;
  a.pos = {5., 5., 5.};
  b.id = 8;
  b.pos = {5.05, 5., 5.};
  s.add_particle(a);
  s.add_particle(b);
  s.set_time_step(0.01);
  try {
    s.run(10);
    FAIL() << "no error for overlapping particles";
  } catch (Utils::RuntimeError const &e) {
    std::string const what = e.what();
    EXPECT_NE(what.find("step 1"), std::string::npos) << what;
    EXPECT_TRUE(what.find("particle 3") != std::string::npos ||
                what.find("particle 8") != std::string::npos)
        << what;
  }
  EXPECT_EQ(s.step(), 0u);
  auto const &ps = s.particles();
  EXPECT_NEAR(ps.pos[ps.index_of(3)][0], 5., 1e-12);
  EXPECT_NEAR(ps.pos[ps.index_of(8)][0], 5.05, 1e-12);
  for (int i = 0; i < ps.n_local(); ++i)
    EXPECT_TRUE(Utils::isfinite(ps.v[i]));
  // remove the overlap: runs again
  s.particles().pos[s.particles().index_of(8)] = {7., 5., 5.};
  s.on_particle_change();
  EXPECT_EQ(s.run(100), 100);
  EXPECT_EQ(s.step(), 100u);
}

TEST(VelocityVerlet, NonFiniteForceIsReported) {
  // r = 1e-25: the LJ force overflows to inf before any step is made.
  System s({10., 10., 10.});
  set_lj(s, 0.);
  Marble::ParticleProperties a, b;
  a.id = 0;
  a.pos = {0., 1., 1.};
  b.id = 1;
  b.pos = {1e-25, 1., 1.};
  s.add_particle(a);
  s.add_particle(b);
  s.set_time_step(0.01);
  try {
    s.run(5);
    FAIL() << "no error for a non-finite force";
  } catch (Utils::RuntimeError const &e) {
    std::string const what = e.what();
    EXPECT_NE(what.find("non-finite force on particle"), std::string::npos) << what;
  }
  EXPECT_EQ(s.step(), 0u);
  auto &ps = s.particles();
  for (int i = 0; i < ps.n_local(); ++i) {
    EXPECT_TRUE(Utils::isfinite(ps.pos[i]));
    EXPECT_TRUE(Utils::isfinite(ps.v[i]));
  }
  ps.pos[ps.index_of(1)] = {2.2, 1., 1.};
  s.on_particle_change();
  EXPECT_EQ(s.run(10), 10);
}
#endif

#ifdef EXTERNAL_FORCE
TEST(VelocityVerlet, ConstantForceIsExact) {
  // x = x0 + v0 t + F t^2 / (2m) is integrated exactly by velocity Verlet.
  System s({10., 10., 10.});
  Marble::ParticleProperties p;
  p.id = 0;
  p.pos = {1., 2., 3.};
  p.v = {0.1, -0.2, 0.};
  p.ext_force = {0.5, 0.25, -1.};
#ifdef MASS
  p.mass = 2.5;
#endif
  s.add_particle(p);
  s.set_time_step(0.01);
  s.run(500);
  double const t = 5., m = s.particles().get_mass(0);
  auto const q = s.particles().get(0);
  auto const x = s.box().unfolded(q.pos, q.image);
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(q.v[d], p.v[d] + p.ext_force[d] * t / m, 1e-12);
    EXPECT_NEAR(x[d], p.pos[d] + p.v[d] * t + 0.5 * p.ext_force[d] * t * t / m, 1e-10);
  }
}
#endif

TEST(VelocityVerlet, RequiresTimeStep) {
  System s({5., 5., 5.});
  Marble::ParticleProperties p;
  p.id = 0;
  s.add_particle(p);
  EXPECT_THROW(s.run(1), Utils::RuntimeError);
  EXPECT_EQ(s.step(), 0u);
}
