// SPDX-License-Identifier: MIT
// Smoke tests of the CUDA pipeline on its own, on each backend of its execution layer (cuda-host
// everywhere, cuda where built): the broadphase against an O(N²) loop over the shared predicate,
// and a few steps of a clump scene with ground. The cross-backend tests (the CPU pipeline and
// the CUDA pipeline stepped side by side) live in validation/. The cuda instances skip without a
// device; nothing here touches CUDA before a test body runs (gtest_discover_tests lists the
// tests at build time, possibly on a machine without a GPU).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/factory.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/random.hpp"
#include "tumble/world.hpp"

using namespace tumble;

namespace {

class GpuSmokeTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { TUMBLE_NEED_BACKEND(GetParam()); }
  std::unique_ptr<Pipeline> make() const { return makePipeline(GetParam()); }
};

std::vector<Pair> bruteForce(const ParticleCloud& c) {
  std::vector<Pair> out;
  const auto n = static_cast<std::uint32_t>(c.size());
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j)
      if (c.body[i] != c.body[j] && spheresOverlap(c.x[i], c.y[i], c.z[i], c.r[i], c.x[j], c.y[j], c.z[j], c.r[j]))
        out.push_back({i, j});
  return out;  // generated in (i, j) order: already sorted
}

ParticleCloud randomCloud(std::uint32_t n, std::uint64_t seed, float offset, float rMin, float rMax) {
  Rng rng(seed);
  ParticleCloud c;
  const float side = std::cbrt(static_cast<float>(n)) * 0.5f * (rMin + rMax);
  for (std::uint32_t i = 0; i < n; ++i) {
    c.x.push_back(offset + rng.uniform(-side, side));
    c.y.push_back(offset + rng.uniform(-side, side));
    c.z.push_back(-offset + rng.uniform(-side, side));
    c.r.push_back(rng.uniform(rMin, rMax));
    c.body.push_back(i / 3);  // some pairs lie within one body and must be skipped
  }
  return c;
}

}  // namespace

TEST_P(GpuSmokeTest, FindPairsMatchesBruteForce) {
  auto p = make();
  ASSERT_EQ(p->backend(), GetParam());
  struct Case {
    std::uint32_t n;
    float offset, rMin, rMax;
  };
  const Case cases[] = {{1, 0.0f, 0.1f, 0.2f},     {2, 0.0f, 0.5f, 0.5f},      {33, 0.0f, 0.1f, 0.3f},
                        {1025, 0.0f, 0.05f, 0.2f}, {3000, 100.0f, 0.01f, 0.5f}, {4097, -5.0f, 0.1f, 0.1f}};
  std::uint64_t seed = 1;
  for (const Case& k : cases) {
    SCOPED_TRACE("n = " + std::to_string(k.n) + ", seed = " + std::to_string(seed));
    const ParticleCloud c = randomCloud(k.n, seed++, k.offset, k.rMin, k.rMax);
    BroadphaseParams bp;
    const std::vector<Pair> got = p->findPairs(c, bp);
    EXPECT_EQ(got, bruteForce(c));
  }
}

TEST_P(GpuSmokeTest, FindPairsRejectsNonFinite) {
  auto p = make();
  ParticleCloud c = randomCloud(100, 7, 0.0f, 0.1f, 0.2f);
  c.y[42] = std::nanf("");
  c.x[77] = INFINITY;
  try {
    p->findPairs(c, BroadphaseParams{});
    FAIL() << "expected tumble::SimulationError";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("particle 42 "), std::string::npos) << e.what();
  }
}

TEST_P(GpuSmokeTest, StepRunsOnAClumpSceneWithGround) {
  Scene s;
  s.dt = 1.0e-4f;
  s.ground.enabled = true;
  s.shapes = {ShapeDef{"pair", {SphereDef{{-0.1f, 0, 0}, 0.1f, 1.0f, 0.5f}, SphereDef{{0.1f, 0, 0}, 0.12f, 1.5f, 0.7f}}},
              ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.15f, 1.0f, 0.5f}}}};
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    BodyDef b;
    b.shape = static_cast<std::uint32_t>(i % 2);
    b.position = {rng.uniform(-1.5f, 1.5f), rng.uniform(-1.5f, 1.5f), rng.uniform(0.2f, 3.0f)};
    b.velocity = {rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), 0.0f};
    b.angularVelocity = {rng.uniform(-3.0f, 3.0f), 0.0f, rng.uniform(-3.0f, 3.0f)};
    s.bodies.push_back(b);
  }
  const World w = World::fromScene(s);
  auto p = make();
  p->load(w);
  p->setDebugCapture(true);
  p->step(50);
  EXPECT_EQ(p->stats().steps, 50u);
  EXPECT_GT(p->stats().numRecords, 0u);
  EXPECT_NEAR(p->time(), 50 * 1.0e-4, 1e-9);
  BodyState st;
  p->readState(st);
  ASSERT_EQ(st.size(), w.numBodies());
  for (std::size_t k = 0; k < st.size(); ++k) {
    ASSERT_TRUE(std::isfinite(st.px[k]) && std::isfinite(st.py[k]) && std::isfinite(st.pz[k])) << "body " << k;
    EXPECT_NEAR(st.qw[k] * st.qw[k] + st.qx[k] * st.qx[k] + st.qy[k] * st.qy[k] + st.qz[k] * st.qz[k], 1.0f, 1e-5f);
  }
  ParticleDebug dbg;
  p->readDebug(dbg);
  EXPECT_EQ(dbg.v.size(), 3 * std::size_t(w.numParticles()));
  EXPECT_EQ(dbg.contacts, p->pairs());
  for (const Pair& q : p->pairs()) EXPECT_LT(q.i, q.j);
}

// A pipeline loaded again after an odd number of steps (a pour's reload, a resumed run) has the
// new world's positions at once, before any step: as the CPU pipeline's, bit for bit.
TEST_P(GpuSmokeTest, ReloadedPositionsAreTheNewWorlds) {
  Scene s;
  s.dt = 1.0e-4f;
  s.ground.enabled = true;
  s.shapes = {ShapeDef{"pair", {SphereDef{{-0.1f, 0, 0}, 0.1f, 1.0f, 0.5f}, SphereDef{{0.1f, 0, 0}, 0.12f, 1.5f, 0.7f}}}};
  for (int i = 0; i < 20; ++i) {
    BodyDef b;
    b.position = {0.5f * float(i % 5), 0.5f * float(i / 5), 0.3f};
    b.angularVelocity = {1.0f, 2.0f, float(i)};
    s.bodies.push_back(b);
  }
  const World first = World::fromScene(s);
  for (BodyDef& b : s.bodies) b.position.z += 1.0f;
  s.bodies.resize(17);
  const World second = World::fromScene(s);
  auto p = make();
  auto cpu = makePipeline(Backend::Cpu);
  std::vector<float> got, want;
  for (Pipeline* q : {p.get(), cpu.get()}) {
    q->load(first);
    q->step(1);
    q->load(second);
    q->readLocalPositions(q == p.get() ? got : want);
  }
  ASSERT_EQ(got.size(), 3 * std::size_t(second.numParticles()));
  EXPECT_EQ(got, want);
}

INSTANTIATE_TEST_SUITE_P(Backends, GpuSmokeTest, ::testing::ValuesIn(tumble_test::cudaPipelineBackends()),
                         tumble_test::backendName);
