// SPDX-License-Identifier: MIT
// The pair set of every pipeline equals the brute-force oracle (SPEC §3), on random scenes and
// on every hard case, for every compiled backend and several cell sizes and thread counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/random.hpp"
#include "tumble/sweep_frame.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

class PairsTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

std::string describeDiff(const std::vector<Pair>& got, const std::vector<Pair>& want) {
  std::vector<Pair> missing, extra;
  std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
  std::set_difference(got.begin(), got.end(), want.begin(), want.end(), std::back_inserter(extra));
  std::string s = std::to_string(missing.size()) + " missing, " + std::to_string(extra.size()) + " extra";
  if (!missing.empty()) s += "; first missing (" + std::to_string(missing[0].i) + "," + std::to_string(missing[0].j) + ")";
  if (!extra.empty()) s += "; first extra (" + std::to_string(extra[0].i) + "," + std::to_string(extra[0].j) + ")";
  return s;
}

void expectSamePairs(Pipeline& p, const ParticleCloud& c, const BroadphaseParams& bp, const std::string& what) {
  const auto want = bruteForcePairs(c);
  const auto got = p.findPairs(c, bp);
  EXPECT_TRUE(got == want) << what << ": " << describeDiff(got, want) << " (oracle has " << want.size() << ")";
}

}  // namespace

TEST_P(PairsTest, HardCasesMatchBruteForce) {
  const std::uint64_t seed = 20261122;
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::printf("hard cases seed %llu\n", static_cast<unsigned long long>(seed));
  auto p = makePipeline(GetParam());
  std::size_t withPairs = 0;
  for (const auto& hc : hardCases(seed)) {
    for (float cell : {0.0f, 0.05f, 1.0f, 100.0f}) {
      BroadphaseParams bp;
      bp.cellSize = cell;
      expectSamePairs(*p, hc.cloud, bp, hc.name + " cell " + std::to_string(cell));
    }
    if (!bruteForcePairs(hc.cloud).empty()) ++withPairs;
  }
  EXPECT_GE(withPairs, 8u) << "the hard cases must actually contain contacts";
}

TEST_P(PairsTest, RandomScenesMatchBruteForce) {
  auto p = makePipeline(GetParam());
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::printf("random scene seed %llu\n", static_cast<unsigned long long>(seed));
    Rng rng(seed);
    const std::uint32_t n = 1 + rng.below(6000);
    const float box = rng.uniform(2.0f, 60.0f);
    const float rmin = rng.uniform(0.01f, 0.5f);
    const ParticleCloud c = randomCloud(n, seed, box, rmin, rmin * rng.uniform(1.0f, 20.0f), 1 + rng.below(8));
    BroadphaseParams bp;
    bp.cellSize = (seed % 3 == 0) ? rmin * 0.5f : 0.0f;
    bp.pcaEvery = 1;
    expectSamePairs(*p, c, bp, "random n=" + std::to_string(n));
  }
}

TEST_P(PairsTest, SameResultForAnyThreadCount) {
  const ParticleCloud c = randomCloud(20000, 77, 40.0f, 0.3f, 0.6f, 4);
  std::vector<Pair> first;
  for (int t : {1, 2, 3, 4}) {
    PipelineOptions o;
    o.threads = t;
    auto p = makePipeline(GetParam(), o);
    const auto got = p->findPairs(c, BroadphaseParams{});
    if (t == 1) {
      first = got;
      EXPECT_FALSE(first.empty());
    } else {
      EXPECT_TRUE(got == first) << "threads " << t;
    }
  }
}

TEST_P(PairsTest, RejectsBadInput) {
  auto p = makePipeline(GetParam());
  ParticleCloud c = randomCloud(10, 3, 1.0f, 0.1f, 0.2f);
  c.x[4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(p->findPairs(c, BroadphaseParams{}), Error);
  c = randomCloud(10, 3, 1.0f, 0.1f, 0.2f);
  c.z[2] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(p->findPairs(c, BroadphaseParams{}), Error);
  c = randomCloud(10, 3, 1.0f, 0.1f, 0.2f);
  c.r[7] = 0.0f;
  EXPECT_THROW(p->findPairs(c, BroadphaseParams{}), Error);
}

// Inputs whose detection would need more records than the 32-bit scans hold (issue 14): a cell
// size far below the radii. Refused with an error, not a wrap, on both backends (the totals are
// summed in 64 bits before the 32-bit scans: checkRecordTotal, sweep_frame.hpp).
TEST_P(PairsTest, HugeRecordCountsAreRefused) {
  auto p = makePipeline(GetParam());
  ParticleCloud c;
  auto add = [&](float x, std::uint32_t body) {
    c.x.push_back(x);
    c.y.push_back(0.0f);
    c.z.push_back(0.0f);
    c.r.push_back(1.0f);
    c.body.push_back(body);
  };
  for (std::uint32_t i = 0; i < 9; ++i) add(0.0f, i);
  EXPECT_EQ(p->findPairs(c, BroadphaseParams{}).size(), 36u);
  BroadphaseParams tiny;
  tiny.cellSize = 8.4e-6f;
  try {
    p->findPairs(c, tiny);
    ADD_FAILURE() << "a cell size of 8.4e-6 for unit spheres must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("detection would need"), std::string::npos) << e.what();
  }
}

// Coordinates spread beyond what a float projection holds (±2.5e38): refused, not pairs
// silently dropped (the sweep compared inf − inf).
TEST(BroadphaseBoundsTest, CoordinatesBeyondSinglePrecisionAreRefused) {
  auto p = makePipeline(Backend::Cpu);
  ParticleCloud c;
  for (const float v : {2.5e38f, 2.5e38f, -2.5e38f}) {
    c.x.push_back(v), c.y.push_back(v), c.z.push_back(0.0f), c.r.push_back(1.0f);
    c.body.push_back(static_cast<std::uint32_t>(c.body.size()));
  }
  try {
    p->findPairs(c, BroadphaseParams{});
    ADD_FAILURE() << "a cloud spread over 5e38 m must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("single precision"), std::string::npos) << e.what();
  }
}

// One particle 1e30 m away: the rounding margin spans 10^24 m, so the automatic cell is a few
// margins wide (at least 8) instead of a few radii, and the detection finds the oracle's pairs
// instead of needing 10^14 cell records per particle (it was refused; before the bound, the
// 32-bit record scan wrapped and the emission wrote past its buffers).
TEST_P(PairsTest, OneFarParticle) {
  ParticleCloud c;
  for (std::uint32_t i = 0; i < 125; ++i) {
    c.x.push_back(i < 124 ? 1.9f * float(i) : 1e30f);
    c.y.push_back(0.0f);
    c.z.push_back(0.01f * float(i % 3));
    c.r.push_back(1.0f);
    c.body.push_back(i);
  }
  auto p = makePipeline(GetParam());
  expectSamePairs(*p, c, BroadphaseParams{}, "124 on a line, one 1e30 m away");
  EXPECT_EQ(bruteForcePairs(c).size(), 123u);
}

// The same with a cell size given: 258 spheres in a 3 m box and one 2e7 m away along z (the
// particle CSV fuzz target's timeout). The margin is 19 m; cells of 0.6 m made each particle
// cover 4000 cells and the sweep test every pair in each. The given cell is raised to 8 margins
// (speed only: the same pairs).
TEST_P(PairsTest, OneFarParticleWithAGivenCellSize) {
  const std::uint64_t seed = 20261203;
  std::printf("cloud seed %llu\n", static_cast<unsigned long long>(seed));
  const ParticleCloud c = randomCloud(259, seed, 3.0f, 0.05f, 0.15f, 1);
  ParticleCloud far = c;
  far.z[104] = 2.0e7f;
  auto p = makePipeline(GetParam());
  BroadphaseParams bp;
  bp.cellSize = 0.6f;
  expectSamePairs(*p, c, bp, "259 in a box");
  expectSamePairs(*p, far, bp, "258 in a box, one 2e7 m away");
  tumble::detail::BoundsPartial b = tumble::detail::emptyBounds();
  for (std::uint32_t i = 0; i < far.size(); ++i) tumble::detail::addParticle(b, i, far.x[i], far.y[i], far.z[i], far.r[i]);
  SweepFrame f;
  tumble::detail::computeFrame(b, Vec3f{0.0f, 0.0f, 1.0f}, 0.15f, 0.0f, bp, &f);
  EXPECT_GT(f.slack, 10.0f);
  EXPECT_GE(f.cellSize, 8.0f * f.slack) << "a given cell size below 8 rounding margins is raised to them";
  bp.cellSize = 1.0e4f;
  tumble::detail::computeFrame(b, Vec3f{0.0f, 0.0f, 1.0f}, 0.15f, 0.0f, bp, &f);
  EXPECT_EQ(f.cellSize, 1.0e4f) << "a cell size above 8 margins is kept";
}

// A coordinate near the float limit makes v / M infinite or beyond the int32 range; the cell
// index is clamped before the conversion (found by the particle CSV fuzz target, UBSan).
TEST(BroadphaseBoundsTest, CellIndexOfOverflowedCoordinates) {
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(cellIndex(3.0e38f, 10.0f, -5, 10), 4);
  EXPECT_EQ(cellIndex(inf, 1.0f, -5, 10), 4);
  EXPECT_EQ(cellIndex(-3.0e38f, 10.0f, -5, 10), -5);
  EXPECT_EQ(cellIndex(-inf, 1.0f, -5, 10), -5);
  EXPECT_EQ(cellIndex(std::numeric_limits<float>::quiet_NaN(), 1.0f, -5, 10), -5);
  EXPECT_EQ(cellIndex(3.0e9f, 1.0f, 0, 4), 3);
  EXPECT_EQ(cellIndex(-3.0e9f, 1.0f, -2147483647, 4), -2147483647);
  EXPECT_EQ(cellIndex(2.5f, 1.0f, -5, 10), 2);
  EXPECT_EQ(cellIndex(-0.5f, 1.0f, -5, 10), -1);
}

// Radii below the rounding margin's floor (1e-30): the automatic cell is at least 8 margins
// wide, or every particle covers millions of cells and the detection is refused.
TEST_P(PairsTest, RadiiBelowTheSlackFloor) {
  ParticleCloud c;
  for (std::uint32_t i = 0; i < 200; ++i) {
    c.x.push_back(1.5e-33f * float(i % 20));
    c.y.push_back(1.5e-33f * float(i / 20));
    c.z.push_back(0.0f);
    c.r.push_back(1e-33f);
    c.body.push_back(i);
  }
  auto p = makePipeline(GetParam());
  // (No pairs: the squared distances and radii underflow to 0 in the shared predicate.)
  expectSamePairs(*p, c, BroadphaseParams{}, "radii of 1e-33");
}

TEST_P(PairsTest, StepPairsMatchBruteForceOnTheBenchScene) {
  World w = World::fromScene(benchScene(16000));
  auto p = makePipeline(GetParam());
  p->load(w);
  p->step(400);  // let the lattice fall and pack so that there are many contacts
  BodyState s;
  p->readState(s);
  // The pairs of the last step were found at the particle state of its start; re-run one step
  // from a copy of the state so that the positions are known exactly.
  World w2 = w;
  w2.state = s;
  auto q = makePipeline(GetParam());
  q->load(w2);
  q->step(1);
  const auto want = bruteForcePairs(cloudOf(w2, s));
  const auto got = q->pairs();
  EXPECT_GT(want.size(), 500u);
  EXPECT_TRUE(got == want) << describeDiff(got, want);
}

// One large sphere among many small ones: the automatic skin and cells are sized from the
// 99th-percentile radius (World::sizingRadius), not the largest, or every cell holds hundreds of
// small spheres (a step took 4 s at 100k). The pairs stay those of the oracle, in findPairs and
// at every step of a run, and the run's bits do not depend on it (the skin test covers any skin).
TEST_P(PairsTest, OneLargeSphereAmongManySmall) {
  ParticleCloud c = randomCloud(5000, 11, 4.0f, 0.04f, 0.06f);
  c.x.push_back(2.0f), c.y.push_back(2.0f), c.z.push_back(2.0f), c.r.push_back(1.0f);
  c.body.push_back(static_cast<std::uint32_t>(c.body.size()));
  auto p = makePipeline(GetParam());
  expectSamePairs(*p, c, BroadphaseParams{}, "one large sphere among 5000 small");

  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = true;
  s.shapes = {ShapeDef{"small", {SphereDef{{0, 0, 0}, 0.05f, 0.01f, 0.5f}}},
              ShapeDef{"big", {SphereDef{{0, 0, 0}, 1.0f, 10.0f, 0.5f}}}};
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 4; ++k) {
        BodyDef b;
        b.shape = 0;
        b.position = {0.098f * float(i), 0.098f * float(j), 0.05f + 0.098f * float(k)};
        s.bodies.push_back(b);
      }
  BodyDef big;
  big.shape = 1;
  big.position = {1.0f, 1.0f, 1.415f};  // 0.02 above the top layer (0.394), thrown down at 1 m/s
  big.velocity = {0.0f, 0.0f, -1.0f};
  s.bodies.push_back(big);
  const World w = World::fromScene(s);
  EXPECT_EQ(w.sizingRadius, 0.05f);
  auto q = makePipeline(GetParam());
  q->load(w);
  std::size_t touching = 0;
  for (int c2 = 0; c2 < 4; ++c2) {
    q->step(100);
    // The contacts of one more step from this state (as StepPairsMatchBruteForceOnTheBenchScene).
    World w2 = w;
    q->readState(w2.state);
    auto r = makePipeline(GetParam());
    r->load(w2);
    r->step(1);
    const auto want = bruteForcePairs(cloudOf(w2, w2.state));
    const auto got = r->pairs();
    EXPECT_TRUE(got == want) << "after " << q->stepCount() << " steps: " << describeDiff(got, want);
    touching += want.size();
  }
  EXPECT_GT(touching, 100u) << "the big sphere must land on the small ones for this to mean anything";
  EXPECT_FLOAT_EQ(q->stats().skin, 0.025f) << "half the small radius, not the large one";
  EXPECT_LT(q->stats().cellSize, 1.0f) << "cells sized from the small spheres";
}

INSTANTIATE_TEST_SUITE_P(Backends, PairsTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);

// Issue 34, item 7: at the ends of the range the readers accept (radii in [2^-60, 2^60] m, each
// coordinate plus radius within ±2^60 m: exact_range.hpp) the pipeline's pairs agree with an
// oracle in double precision that shares no code with the float predicate: every pair the
// double oracle is sure of is found, and every pair found is sure or within the rounding band
// (1e-5 of the squared radii sum). Beyond the range the float predicate itself fails, which is
// why the readers refuse it: coincident spheres of 2^-76 m underflow, spheres of 1.5e19 m at
// 2e19 m overflow (issue 34's cases).
TEST_P(PairsTest, TheEndsOfTheExactRangeAgreeWithADoubleOracle) {
  const std::uint64_t seed = 20261207;
  std::printf("cloud seed %llu\n", static_cast<unsigned long long>(seed));
  auto p = makePipeline(GetParam());
  // A cloud of radii 0.05-0.15 in a 3 m box, scaled by s and moved by `offset` along x.
  struct Case {
    const char* name;
    double scale, offset;
  };
  const Case cases[] = {{"radii from 2^-60 m", 0x1p-60 / 0.05, 0.0},
                        {"near the origin, 2^-40", 0x1p-40, 0.0},
                        {"unit", 1.0, 0.0},
                        {"radii to 2^53 m, 2^59 m from the origin", 0x1p56, 0x1p59},
                        {"radii to 2^53 m, -2^59 m from the origin", 0x1p56, -0x1p59 - 0x1p58}};
  for (const Case& k : cases) {
    const ParticleCloud unit = randomCloud(600, seed, 3.0f, 0.05f, 0.15f, 1);
    ParticleCloud c = unit;
    for (std::uint32_t i = 0; i < c.size(); ++i) {
      c.x[i] = static_cast<float>(double(unit.x[i]) * k.scale + k.offset);
      c.y[i] = static_cast<float>(double(unit.y[i]) * k.scale);
      c.z[i] = static_cast<float>(double(unit.z[i]) * k.scale);
      c.r[i] = static_cast<float>(double(unit.r[i]) * k.scale);
      ASSERT_TRUE(c.r[i] >= kMinRadius && std::fabs(double(c.x[i])) + c.r[i] <= kMaxCoordinate) << k.name << " " << i;
    }
    const DoublePairs want = doublePrecisionPairs(c, 1e-5);
    const std::vector<Pair> got = p->findPairs(c, BroadphaseParams{});
    std::vector<Pair> missed, extra;
    std::set_difference(want.sure.begin(), want.sure.end(), got.begin(), got.end(), std::back_inserter(missed));
    std::set_difference(got.begin(), got.end(), want.sure.begin(), want.sure.end(), std::back_inserter(extra));
    std::vector<Pair> unexplained;
    std::set_difference(extra.begin(), extra.end(), want.unsure.begin(), want.unsure.end(),
                        std::back_inserter(unexplained));
    EXPECT_GT(want.sure.size(), 100u) << k.name << ": the cloud must have contacts";
    EXPECT_TRUE(missed.empty()) << k.name << ": " << missed.size() << " pairs the double oracle is sure of are missing";
    EXPECT_TRUE(unexplained.empty()) << k.name << ": " << unexplained.size() << " pairs found that do not overlap";
  }
  // Two coincident spheres of the smallest radius; two of nearly 2^58 m overlapping by 5 %, one
  // reaching 2.85 · 2^58 m from the origin: found.
  ParticleCloud ends;
  const float big = 0x1p58f * 0.99f;
  for (const auto& [x, z, r] : {std::tuple<float, float, float>{1.0f, 0x1p59f, 0x1p-60f}, {1.0f, 0x1p59f, 0x1p-60f},
                                {-0x1p59f + 2.0f * big, 0.0f, big}, {-0x1p59f + 3.9f * big, 0.0f, big}}) {
    ends.x.push_back(x);
    ends.y.push_back(0.0f);
    ends.z.push_back(z);
    ends.r.push_back(r);
    ends.body.push_back(static_cast<std::uint32_t>(ends.body.size()));
  }
  EXPECT_EQ(p->findPairs(ends, BroadphaseParams{}), (std::vector<Pair>{{0, 1}, {2, 3}}));
  EXPECT_EQ(doublePrecisionPairs(ends, 1e-5).sure, (std::vector<Pair>{{0, 1}, {2, 3}}));
  // Outside the range the shared predicate misses pairs the double oracle finds.
  EXPECT_FALSE(spheresOverlap(0.0f, 0.0f, 0.0f, 0x1p-76f, 0.0f, 0.0f, 0.0f, 0x1p-76f)) << "(2 r)^2 underflows";
  EXPECT_FALSE(spheresOverlap(0.0f, 0.0f, 0.0f, 1.5e19f, 2e19f, 0.0f, 0.0f, 1.5e19f)) << "d^2 overflows";
}
