// SPDX-License-Identifier: MIT
// The decomposition of the domain among the ranks (tumble/mpi/decomposition.hpp): balanced by
// particle count, slabs contiguous, fewer bodies than ranks, and a halo that holds every
// particle within reach of a rank's own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "tumble/error.hpp"
#include "tumble/mpi/decomposition.hpp"
#include "tumble/random.hpp"

using namespace tumble;
using namespace tumble::mpi;

namespace {

struct Bodies {
  std::vector<Vec3f> centres;
  std::vector<std::uint32_t> count, first;
  std::vector<float> pos;  // 3 per particle: the centre plus a jitter of up to 0.3
};

Bodies randomBodies(std::uint32_t nb, std::uint64_t seed, float lx, float ly, float lz) {
  Rng rng(seed);
  Bodies b;
  for (std::uint32_t k = 0; k < nb; ++k) {
    const Vec3f c{lx * rng.uniform(), ly * rng.uniform(), lz * rng.uniform()};
    b.centres.push_back(c);
    b.first.push_back(static_cast<std::uint32_t>(b.pos.size() / 3));
    b.count.push_back(1 + rng.below(8));
    for (std::uint32_t i = 0; i < b.count.back(); ++i) {
      b.pos.push_back(c.x + 0.6f * (rng.uniform() - 0.5f));
      b.pos.push_back(c.y + 0.6f * (rng.uniform() - 0.5f));
      b.pos.push_back(c.z + 0.6f * (rng.uniform() - 0.5f));
    }
  }
  return b;
}

float coord(const Vec3f& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

}  // namespace

TEST(DecompositionTest, SharesTheParticlesEvenly) {
  const Bodies b = randomBodies(2000, 7, 10.0f, 4.0f, 2.0f);
  std::uint64_t total = 0;
  for (auto c : b.count) total += c;
  for (const Decomposition how : {Decomposition::Rcb, Decomposition::Slabs})
    for (int ranks = 1; ranks <= 9; ++ranks) {
      SCOPED_TRACE(std::string(toString(how)) + ", " + std::to_string(ranks) + " ranks");
      const std::vector<int> owner = decompose(b.centres, b.count, ranks, how);
      std::vector<std::uint64_t> share(static_cast<std::size_t>(ranks), 0);
      for (std::size_t k = 0; k < owner.size(); ++k) {
        ASSERT_GE(owner[k], 0);
        ASSERT_LT(owner[k], ranks);
        share[static_cast<std::size_t>(owner[k])] += b.count[k];
      }
      // Each cut is within one body (8 particles) of its share; the levels add up.
      const double levels = std::ceil(std::log2(double(ranks))) + 1.0;
      for (const std::uint64_t s : share) EXPECT_NEAR(double(s), double(total) / ranks, 8.0 * levels);
      EXPECT_EQ(owner, decompose(b.centres, b.count, ranks, how)) << "the same answer every time";
    }
}

TEST(DecompositionTest, SlabsAreContiguousAlongTheLongestExtent) {
  const Bodies b = randomBodies(500, 11, 2.0f, 12.0f, 3.0f);  // longest along y
  const int ranks = 5;
  const std::vector<int> owner = decompose(b.centres, b.count, ranks, Decomposition::Slabs);
  std::vector<float> lo(ranks, 1e30f), hi(ranks, -1e30f);
  for (std::size_t k = 0; k < owner.size(); ++k) {
    lo[owner[k]] = std::min(lo[owner[k]], coord(b.centres[k], 1));
    hi[owner[k]] = std::max(hi[owner[k]], coord(b.centres[k], 1));
  }
  for (int r = 0; r + 1 < ranks; ++r) EXPECT_LE(hi[r], lo[r + 1]) << "slab " << r;
}

TEST(DecompositionTest, FewerBodiesThanRanksLeavesRanksEmpty) {
  const std::vector<Vec3f> centres{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<std::uint32_t> count{1, 1, 1};
  for (const Decomposition how : {Decomposition::Rcb, Decomposition::Slabs}) {
    const std::vector<int> owner = decompose(centres, count, 4, how);
    std::vector<int> bodies(4, 0);
    for (int o : owner) ++bodies[o];
    EXPECT_EQ(std::count(bodies.begin(), bodies.end(), 0), 1) << "one rank without a body";
    EXPECT_EQ(std::count(bodies.begin(), bodies.end(), 1), 3);
  }
}

TEST(DecompositionTest, EqualCoordinatesAreCutByIndex) {
  // Every centre on one plane x = 1: the cut along x falls between bodies of the same coordinate.
  std::vector<Vec3f> centres;
  for (int k = 0; k < 10; ++k) centres.push_back(Vec3f{1.0f, 0.0f, 0.0f});
  centres.push_back(Vec3f{0.0f, 0.0f, 0.0f});
  centres.push_back(Vec3f{2.0f, 0.0f, 0.0f});
  const std::vector<std::uint32_t> count(centres.size(), 1);
  const std::vector<int> owner = decompose(centres, count, 2, Decomposition::Slabs);
  EXPECT_EQ(owner[10], 0);
  EXPECT_EQ(owner[11], 1);
  int below = 0;
  for (int k = 0; k < 10; ++k) below += owner[k] == 0;
  EXPECT_EQ(below, 5) << "the lower indices of the equal ones below the cut";
  for (int k = 0; k < 10; ++k) EXPECT_EQ(owner[k], k < 5 ? 0 : 1);
}

TEST(DecompositionTest, GhostsHoldEveryParticleWithinReach) {
  const Bodies b = randomBodies(600, 3, 8.0f, 8.0f, 2.0f);
  const double reach = 0.7;
  for (int ranks = 2; ranks <= 6; ++ranks) {
    const std::vector<int> owner = decompose(b.centres, b.count, ranks, Decomposition::Rcb);
    const auto ghosts = ghostsOf(owner, b.pos, b.first, b.count, ranks, reach);
    const std::size_t np = b.pos.size() / 3;
    std::vector<std::uint32_t> bodyOf(np);
    for (std::uint32_t k = 0; k < b.first.size(); ++k)
      for (std::uint32_t i = b.first[k]; i < b.first[k] + b.count[k]; ++i) bodyOf[i] = k;
    std::size_t held = 0, total = 0;
    for (int r = 0; r < ranks; ++r) {
      const auto& g = ghosts[static_cast<std::size_t>(r)];
      ASSERT_TRUE(std::is_sorted(g.begin(), g.end()));
      for (const std::uint32_t k : g) ASSERT_NE(owner[k], r) << "a rank's own body is no ghost";
      for (std::size_t p = 0; p < np; ++p) {
        if (owner[bodyOf[p]] != r) continue;
        for (std::size_t q = 0; q < np; ++q) {
          if (owner[bodyOf[q]] == r) continue;
          double d2 = 0.0;
          for (int a = 0; a < 3; ++a) d2 += std::pow(double(b.pos[3 * p + a]) - b.pos[3 * q + a], 2);
          if (d2 < reach * reach) {
            ASSERT_TRUE(std::binary_search(g.begin(), g.end(), bodyOf[q]))
                << "rank " << r << " lacks body " << bodyOf[q] << " near its particle " << p;
          }
        }
      }
      held += g.size();
      total += owner.size();
    }
    EXPECT_LT(held, total) << "a halo, not everything";
  }
}

TEST(DecompositionTest, NamesParse) {
  EXPECT_EQ(decompositionFromString("rcb"), Decomposition::Rcb);
  EXPECT_EQ(decompositionFromString("slabs"), Decomposition::Slabs);
  EXPECT_THROW(decompositionFromString("cubes"), Error);
}
