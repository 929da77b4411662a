// ParticleStore: adding, removing and permuting particles keeps the
// id -> index map and every per-particle array consistent, checked against a
// reference map after each of many random operations.
#include "config/features.hpp"
#include "particles/ParticleStore.hpp"
#include "system/System.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <random>
#include <vector>

using Marble::ParticleProperties;
using Marble::ParticleStore;
using Utils::Vector3d;

namespace {

ParticleProperties random_particle(int pid, std::mt19937_64 &rng) {
  std::uniform_real_distribution<double> u(0., 1.);
  ParticleProperties p;
  p.id = pid;
  p.type = pid % 5;
  p.pos = {u(rng), u(rng), u(rng)};
  p.v = {u(rng), u(rng), u(rng)};
  p.image = {pid % 3, -(pid % 2), 0};
#ifdef MASS
  p.mass = 1. + u(rng);
#endif
#ifdef ROTATION
  p.rotation = (pid % 2) == 0;
  p.rinertia = 0.5 + u(rng);
  p.omega = {u(rng), 0., -u(rng)};
#endif
#ifdef EXTERNAL_FORCE
  p.ext_force = {0., u(rng), 0.};
  p.ext_torque = {u(rng), 0., 0.};
  p.fix = static_cast<std::uint8_t>(pid % 8);
#endif
  return p;
}

void expect_same(ParticleProperties const &a, ParticleProperties const &b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.pos, b.pos);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.image, b.image);
  EXPECT_EQ(a.mass, b.mass);
#ifdef ROTATION
  EXPECT_EQ(a.rotation, b.rotation);
  EXPECT_EQ(a.rinertia, b.rinertia);
  EXPECT_EQ(a.omega, b.omega);
#endif
#ifdef EXTERNAL_FORCE
  EXPECT_EQ(a.ext_force, b.ext_force);
  EXPECT_EQ(a.ext_torque, b.ext_torque);
  EXPECT_EQ(a.fix, b.fix);
#endif
}

void check_consistent(ParticleStore const &ps, std::map<int, ParticleProperties> const &ref) {
  ASSERT_EQ(ps.n_local(), static_cast<int>(ref.size()));
  ASSERT_EQ(ps.size(), ps.n_local()); // no ghosts here
  // every stored index maps back to its id
  for (int i = 0; i < ps.n_local(); ++i)
    ASSERT_EQ(ps.index_of(ps.id[i]), i);
  // every reference particle is found with its data
  for (auto const &kv : ref) {
    ASSERT_TRUE(ps.exists(kv.first));
    expect_same(ps.get(kv.first), kv.second);
  }
  // ids not in the reference do not exist
  int const top = ref.empty() ? -1 : ref.rbegin()->first;
  EXPECT_EQ(ps.max_id(), top);
  for (int pid = -3; pid < top + 5; ++pid)
    EXPECT_EQ(ps.exists(pid), ref.count(pid) == 1) << "id " << pid;
  std::vector<int> ids;
  for (auto const &kv : ref)
    ids.push_back(kv.first);
  EXPECT_EQ(ps.ids_sorted(), ids);
}

} // namespace

TEST(ParticleStore, RandomAddRemovePermute) {
  std::mt19937_64 rng(5);
  ParticleStore ps;
  std::map<int, ParticleProperties> ref;
  std::uniform_int_distribution<int> op(0, 9), idd(0, 300);
  for (int it = 0; it < 2000; ++it) {
    int const o = op(rng);
    if (o < 5) { // add a new id
      int pid = idd(rng);
      if (ref.count(pid))
        continue;
      auto const p = random_particle(pid, rng);
      ps.add(p);
      ref[pid] = p;
    } else if (o < 8) { // remove an existing id
      if (ref.empty())
        continue;
      auto itr = ref.begin();
      std::advance(itr, std::uniform_int_distribution<int>(0, ref.size() - 1)(rng));
      ps.remove(itr->first);
      ref.erase(itr);
    } else { // random permutation (what the cell sort does)
      std::vector<int> order(ps.n_local());
      std::iota(order.begin(), order.end(), 0);
      std::shuffle(order.begin(), order.end(), rng);
      ps.permute_locals(order);
    }
    check_consistent(ps, ref);
    if (HasFatalFailure() || HasFailure())
      FAIL() << "after operation " << it << " (kind " << o << ")";
  }
  // remove everything, largest id last: the map shrinks to nothing
  while (!ref.empty()) {
    ps.remove(ref.begin()->first);
    ref.erase(ref.begin());
    check_consistent(ps, ref);
  }
  EXPECT_EQ(ps.max_id(), -1);
}

TEST(ParticleStore, GhostsDoNotDisturbLocals) {
  std::mt19937_64 rng(11);
  ParticleStore ps;
  std::map<int, ParticleProperties> ref;
  for (int pid : {4, 0, 9, 2}) {
    ref[pid] = random_particle(pid, rng);
    ps.add(ref[pid]);
  }
  int const i9 = ps.index_of(9);
  ps.add_ghost(i9, {1., 0., 0.});
  ps.add_ghost(ps.index_of(0), {0., -1., 0.});
  EXPECT_EQ(ps.n_ghost(), 2);
  EXPECT_EQ(ps.size(), 6);
  EXPECT_EQ(ps.id[4], 9);
  EXPECT_EQ(ps.pos[4], (ps.pos[i9] + Vector3d{1., 0., 0.}));
  EXPECT_EQ(ps.index_of(9), i9); // a ghost never becomes the particle's index
  ps.clear_ghosts();
  check_consistent(ps, ref);
  ps.clear();
  ref.clear();
  check_consistent(ps, ref);
}

TEST(ParticleStore, SystemKeepsIdsThroughRebuilds) {
#if !defined(LENNARD_JONES) && !defined(HAT) && !defined(DPD)
  GTEST_SKIP() << "no pair interaction compiled into this build";
#endif
  // Add/remove through the System, with cell sorts (permutations) and ghost
  // layers in between: every particle keeps its data under its id.
  std::mt19937_64 rng(3);
  Marble::System s({4., 4., 4.});
#if defined(HAT)
  Marble::Hat::Params p;
  p.active = true;
  p.F_max = 1.;
  p.cutoff = 1.;
  s.set_kernel<Marble::Hat>(0, 4, p);
#elif defined(DPD)
  Marble::DPDParams p;
  p.active = true;
  p.radial.gamma = 1.;
  p.radial.r_cut = 1.;
  s.set_kernel<Marble::DPDPair>(0, 4, p);
#else
  s.interactions().ensure_type(4);
#endif
  std::map<int, ParticleProperties> ref;
  std::uniform_int_distribution<int> idd(0, 500);
  for (int round = 0; round < 20; ++round) {
    for (int k = 0; k < 30; ++k) {
      int const pid = idd(rng);
      if (ref.count(pid))
        continue;
      auto q = random_particle(pid, rng);
      q.pos = 4. * q.pos; // inside the box: stored unchanged
      q.image = {};
      s.add_particle(q);
      ref[pid] = q;
    }
    for (int k = 0; k < 10 && !ref.empty(); ++k) {
      auto itr = ref.begin();
      std::advance(itr, std::uniform_int_distribution<int>(0, ref.size() - 1)(rng));
      s.remove_particle(itr->first);
      ref.erase(itr);
    }
    s.ensure_lists(); // sorts by cell and makes ghosts
    EXPECT_GT(s.particles().n_ghost(), 0);
    s.particles().clear_ghosts();
    s.on_particle_change();
    check_consistent(s.particles(), ref);
    if (HasFailure())
      FAIL() << "round " << round;
  }
}
