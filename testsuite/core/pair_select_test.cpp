// The select/gather of the SIMD pair block (forces/pair_simd.cpp): every code
// path this CPU has (AVX2 compare-and-compress, scalar) against a plain loop,
// bit for bit: the pairs within the cutoff in list order, their d = r_i - r_j,
// a NaN distance kept; and the DPD gather (v_i - v_j, ordered ids, sign).
#include "forces/pair_simd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Scene {
  std::vector<Utils::Vector3d> pos, vel;
  std::vector<int> id;
  std::vector<std::array<int, 2>> pairs;
};

/** Particles in a box of 4 and a pair list in runs of one i (as the Verlet
 * list is built), some runs of length 1-3 (mixed i in an AVX2 group). */
Scene make_scene(std::mt19937_64 &g, int n_part, int n_pairs) {
  std::uniform_real_distribution<double> u(0., 4.);
  std::normal_distribution<double> nv(0., 1.);
  Scene s;
  for (int k = 0; k < n_part; ++k) {
    s.pos.push_back({u(g), u(g), u(g)});
    s.vel.push_back({nv(g), nv(g), nv(g)});
    s.id.push_back(k % 2 ? k : 0x40000000 + static_cast<int>(g() % 100000)); // ids in both orders
  }
  s.pos[3][1] = std::numeric_limits<double>::quiet_NaN(); // kept by the select
  while (static_cast<int>(s.pairs.size()) < n_pairs) {
    int const i = static_cast<int>(g() % n_part);
    int const len = static_cast<int>(g() % 3 == 0 ? 1 + g() % 3 : 1 + g() % 40);
    for (int k = 0; k < len && static_cast<int>(s.pairs.size()) < n_pairs; ++k) {
      int j = static_cast<int>(g() % n_part);
      if (j == i)
        j = (j + 1) % n_part;
      s.pairs.push_back({i, j});
    }
  }
  return s;
}

/** A VerletPairs-style list: @p n_rows rows of partners j (empty rows, rows of
 * 1-3 partners and long rows), padded by 8 valid indices (as VerletPairs). */
std::pair<std::vector<int>, std::vector<int>> make_rows(std::mt19937_64 &g, int n_part, int n_rows) {
  std::vector<int> row_start{0}, pj;
  for (int i = 0; i < n_rows; ++i) {
    int const len = static_cast<int>(g() % 4 == 0 ? g() % 4 : g() % 60);
    for (int k = 0; k < len; ++k)
      pj.push_back(static_cast<int>((i + 1 + g() % (n_part - 1)) % n_part));
    row_start.push_back(static_cast<int>(pj.size()));
  }
  pj.insert(pj.end(), {0, 0, 0, 0, 0, 0, 0, 0});
  return {row_start, pj};
}

/** Run a row select block by block from the start (@p select(c, limit, bij,
 * B) returns the number stored), check each stored d = r_i - r_j bit for bit
 * and return the selected pairs in order. */
template <class Select>
std::vector<std::array<int, 2>> collect_rows(Select &&select, Scene const &sc, int n_rows, int limit) {
  std::vector<std::array<int, 2>> got;
  Marble::RowCursor c;
  auto B = std::make_unique<Marble::PairBlockSoA>();
  std::vector<std::array<int, 2>> bij(Marble::kPairBlock);
  int guard = 0;
  while (c.i < n_rows) {
    int const n = select(c, limit, bij.data(), *B);
    EXPECT_LE(n, limit + 8); // the group that crossed the limit: up to 8 listed pairs (AVX-512)
    for (int s = 0; s < n; ++s) {
      auto const [i, j] = bij[s];
      EXPECT_TRUE(same_bits(B->dx[s], sc.pos[i][0] - sc.pos[j][0]));
      EXPECT_TRUE(same_bits(B->dy[s], sc.pos[i][1] - sc.pos[j][1]));
      EXPECT_TRUE(same_bits(B->dz[s], sc.pos[i][2] - sc.pos[j][2]));
      got.push_back(bij[s]);
    }
    if (++guard > 100000) {
      ADD_FAILURE() << "no progress";
      break;
    }
  }
  return got;
}

} // namespace

TEST(PairSelect, PathsAgreeBitForBit) {
  std::mt19937_64 g(42);
  auto const paths = Marble::pair_select_paths();
  ASSERT_GE(paths.size(), 1u);
  for (int nb : {0, 1, 3, 4, 5, 7, 8, 100, 511, 512}) {
    Scene const sc = make_scene(g, 300, nb);
    double const cut2 = 1.2 * 1.2;
    // the plain loop
    std::vector<int> want;
    for (int q = 0; q < nb; ++q) {
      auto const [i, j] = sc.pairs[q];
      double const dx = sc.pos[i][0] - sc.pos[j][0], dy = sc.pos[i][1] - sc.pos[j][1],
                   dz = sc.pos[i][2] - sc.pos[j][2];
      if (!(dx * dx + dy * dy + dz * dz >= cut2))
        want.push_back(q);
    }
    for (auto const &path : paths) {
      auto B = std::make_unique<Marble::PairBlockSoA>();
      std::vector<std::array<int, 2>> bij(Marble::kPairBlock);
      int const n = path.select(sc.pairs.data(), nb, sc.pos.data(), cut2, bij.data(), *B);
      ASSERT_EQ(n, static_cast<int>(want.size())) << path.name << " nb " << nb;
      for (int s = 0; s < n; ++s) {
        auto const [i, j] = sc.pairs[want[s]];
        ASSERT_EQ(bij[s][0], i) << path.name;
        ASSERT_EQ(bij[s][1], j) << path.name;
        ASSERT_TRUE(same_bits(B->dx[s], sc.pos[i][0] - sc.pos[j][0])) << path.name << " pair " << s;
        ASSERT_TRUE(same_bits(B->dy[s], sc.pos[i][1] - sc.pos[j][1])) << path.name << " pair " << s;
        ASSERT_TRUE(same_bits(B->dz[s], sc.pos[i][2] - sc.pos[j][2])) << path.name << " pair " << s;
      }
      // the DPD gather of the selected pairs
      std::vector<std::uint32_t> lo(Marble::kPairBlock), hi(Marble::kPairBlock);
      std::vector<double> sign(Marble::kPairBlock);
      std::vector<Marble::Rec4> vel4(sc.vel.size());
      for (std::size_t k = 0; k < sc.vel.size(); ++k)
        vel4[k] = {{sc.vel[k][0], sc.vel[k][1], sc.vel[k][2], 0.}};
      path.gather_dpd(bij.data(), n, vel4.data(), sc.id.data(), *B, lo.data(), hi.data(), sign.data());
      for (int s = 0; s < n; ++s) {
        auto const [i, j] = bij[s];
        ASSERT_TRUE(same_bits(B->vx[s], sc.vel[i][0] - sc.vel[j][0])) << path.name;
        ASSERT_TRUE(same_bits(B->vy[s], sc.vel[i][1] - sc.vel[j][1])) << path.name;
        ASSERT_TRUE(same_bits(B->vz[s], sc.vel[i][2] - sc.vel[j][2])) << path.name;
        std::uint32_t l, h;
        double sg;
        Marble::order_pair_ids(sc.id[i], sc.id[j], l, h, sg);
        ASSERT_EQ(lo[s], l) << path.name;
        ASSERT_EQ(hi[s], h) << path.name;
        ASSERT_TRUE(same_bits(sign[s], sg)) << path.name << " " << sign[s] << " " << sg;
      }
    }
  }
}

// The scatter into the Rec4 force buffer: every path against the plain loop
// f_i += f, f_j -= f in list order, bit for bit (runs of one i of length 1-40,
// j of one pair the i of the next, lengths not a multiple of 4).
TEST(PairSelect, ScatterPathsAgreeBitForBit) {
  std::mt19937_64 g(5);
  std::normal_distribution<double> nf(0., 10.);
  for (int n : {0, 1, 3, 4, 5, 7, 8, 100, 511, 512}) {
    Scene const sc = make_scene(g, 60, n);
    auto B = std::make_unique<Marble::PairBlockSoA>();
    for (int s = 0; s < n; ++s)
      B->fx[s] = nf(g), B->fy[s] = nf(g), B->fz[s] = nf(g);
    std::vector<Marble::Force4> start(60);
    for (auto &r : start)
      r = {{nf(g), nf(g), nf(g), 0.}};
    std::vector<Marble::Force4> want = start;
    for (int s = 0; s < n; ++s) {
      auto const [i, j] = sc.pairs[s];
      want[i].v[0] += B->fx[s], want[i].v[1] += B->fy[s], want[i].v[2] += B->fz[s];
      want[j].v[0] -= B->fx[s], want[j].v[1] -= B->fy[s], want[j].v[2] -= B->fz[s];
    }
    for (auto const &path : Marble::pair_scatter_paths()) {
      std::vector<Marble::Force4> got = start;
      path.scatter(sc.pairs.data(), n, *B, got.data());
      for (int k = 0; k < 60; ++k)
        for (int c = 0; c < 4; ++c)
          ASSERT_TRUE(same_bits(got[k].v[c], want[k].v[c])) << path.name << " n " << n << " particle " << k;
    }
  }
}

TEST(PairSelect, DispatchedCallMatchesScalar) {
  std::mt19937_64 g(7);
  Scene const sc = make_scene(g, 200, 512);
  double const cut2_table[1] = {1.0};
  auto A = std::make_unique<Marble::PairBlockSoA>(), C = std::make_unique<Marble::PairBlockSoA>();
  std::vector<std::array<int, 2>> a(Marble::kPairBlock), c(Marble::kPairBlock);
  int const na = Marble::pair_block_select(sc.pairs.data(), 512, sc.pos.data(), nullptr, cut2_table, 1, a.data(), *A);
  int const nc = Marble::pair_select_paths()[0].select(sc.pairs.data(), 512, sc.pos.data(), 1.0, c.data(), *C);
  ASSERT_EQ(na, nc);
  for (int s = 0; s < na; ++s) {
    ASSERT_EQ(a[s], c[s]);
    ASSERT_TRUE(same_bits(A->dx[s], C->dx[s]) && same_bits(A->dy[s], C->dy[s]) && same_bits(A->dz[s], C->dz[s]));
  }
}

// The row select (pair_rows_select on a VerletPairs-style list: rows of
// partners j, padded by 4 valid indices), every path and several block
// limits, resumed block by block: the same pairs, in list order, with the
// same d bits, as the plain loop over the expanded (i, j) pairs; empty rows,
// rows of 1-3 partners and long rows included.
TEST(PairSelect, RowPathsAgreeBitForBit) {
  std::mt19937_64 g(11);
  int const n_part = 300;
  Scene const sc = make_scene(g, n_part, 0);
  for (int n_rows : {0, 1, 5, 120}) {
    auto const [row_start, pj] = make_rows(g, n_part, n_rows);
    double const cut2 = 1.2 * 1.2;
    std::vector<std::array<int, 2>> want;
    for (int i = 0; i < n_rows; ++i)
      for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
        int const j = pj[k];
        double const dx = sc.pos[i][0] - sc.pos[j][0], dy = sc.pos[i][1] - sc.pos[j][1],
                     dz = sc.pos[i][2] - sc.pos[j][2];
        if (!(dx * dx + dy * dy + dz * dz >= cut2))
          want.push_back({i, j});
      }
    for (auto const &path : Marble::pair_rows_select_paths())
      for (int limit : {0, 5, 192, Marble::kPairBlock - 8}) {
        auto sel = [&](Marble::RowCursor &c, int lim, std::array<int, 2> *bij, Marble::PairBlockSoA &B) {
          return path.select(row_start.data(), pj.data(), n_rows, c, lim, sc.pos.data(), cut2, bij, B);
        };
        ASSERT_EQ(collect_rows(sel, sc, n_rows, limit), want) << path.name << " limit " << limit << " rows " << n_rows;
      }
  }
}

// Scenes of several types (nt = 3; one type pair with cutoff 0, i.e. never
// selected, as the colloid pairs a separate list serves): every typed path
// of the block and the row select against the plain loop with the table's
// cutoff per pair, bit for bit, and the dispatched calls against scalar.
TEST(PairSelect, TypedPathsAgreeBitForBit) {
  std::mt19937_64 g(23);
  int const n_part = 300, nt = 3;
  Scene const sc = make_scene(g, n_part, 600);
  std::vector<int> typ(n_part);
  for (auto &t : typ)
    t = static_cast<int>(g() % nt);
  double const cut2_table[9] = {1.44, 0.81, 0., 0.81, 2.25, 1.0, 0., 1.0, 0.49};
  auto in_range = [&](int i, int j) {
    double const dx = sc.pos[i][0] - sc.pos[j][0], dy = sc.pos[i][1] - sc.pos[j][1], dz = sc.pos[i][2] - sc.pos[j][2];
    return !(dx * dx + dy * dy + dz * dz >= cut2_table[typ[i] * nt + typ[j]]);
  };
  auto const paths = Marble::pair_typed_select_paths();
  ASSERT_GE(paths.size(), 1u);
  // the block select
  for (int nb : {0, 1, 3, 4, 5, 7, 8, 100, 511, 512}) {
    std::vector<std::array<int, 2>> want;
    for (int q = 0; q < nb; ++q)
      if (in_range(sc.pairs[q][0], sc.pairs[q][1]))
        want.push_back(sc.pairs[q]);
    for (auto const &path : paths) {
      auto B = std::make_unique<Marble::PairBlockSoA>();
      std::vector<std::array<int, 2>> bij(Marble::kPairBlock);
      int const n = path.select(sc.pairs.data(), nb, sc.pos.data(), typ.data(), cut2_table, nt, bij.data(), *B);
      ASSERT_EQ(n, static_cast<int>(want.size())) << path.name << " nb " << nb;
      for (int s = 0; s < n; ++s) {
        ASSERT_EQ(bij[s], want[s]) << path.name;
        auto const [i, j] = bij[s];
        ASSERT_TRUE(same_bits(B->dx[s], sc.pos[i][0] - sc.pos[j][0])) << path.name;
        ASSERT_TRUE(same_bits(B->dy[s], sc.pos[i][1] - sc.pos[j][1])) << path.name;
        ASSERT_TRUE(same_bits(B->dz[s], sc.pos[i][2] - sc.pos[j][2])) << path.name;
      }
    }
    // the dispatched call equals the scalar path
    auto A = std::make_unique<Marble::PairBlockSoA>();
    std::vector<std::array<int, 2>> a(Marble::kPairBlock);
    int const na = Marble::pair_block_select(sc.pairs.data(), nb, sc.pos.data(), typ.data(), cut2_table, nt,
                                             a.data(), *A);
    ASSERT_EQ(na, static_cast<int>(want.size()));
    for (int s = 0; s < na; ++s)
      ASSERT_EQ(a[s], want[s]);
  }
  // the row select, resumed block by block
  for (int n_rows : {0, 1, 5, 120}) {
    auto const [row_start, pj] = make_rows(g, n_part, n_rows);
    std::vector<std::array<int, 2>> want;
    for (int i = 0; i < n_rows; ++i)
      for (int k = row_start[i]; k < row_start[i + 1]; ++k)
        if (in_range(i, pj[k]))
          want.push_back({i, pj[k]});
    auto run = [&](auto &&select, int limit) {
      auto sel = [&](Marble::RowCursor &c, int lim, std::array<int, 2> *bij, Marble::PairBlockSoA &B) {
        return select(row_start.data(), pj.data(), n_rows, c, lim, sc.pos.data(), typ.data(), cut2_table, nt, bij, B);
      };
      return collect_rows(sel, sc, n_rows, limit);
    };
    for (auto const &path : paths)
      for (int limit : {0, 5, 192, Marble::kPairBlock - 8})
        ASSERT_EQ(run(path.rows_select, limit), want) << path.name << " limit " << limit << " rows " << n_rows;
    ASSERT_EQ(run(&Marble::pair_rows_select, 192), want) << "dispatched";
  }
  // the typed paths exist beside the one-type ones on this CPU
  ASSERT_EQ(paths.size(), Marble::pair_rows_select_paths().size());
}
