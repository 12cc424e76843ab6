// SPDX-License-Identifier: MIT
// The pipelines' hooks for a domain decomposition (HaloPipeline; the CPU pipeline and the CUDA
// pipeline, on the host backend in every build): rows read and written back change no bit, the
// contacts counted per body add up to the run's, and rows that jump (a ghost overwritten by its
// owner's) make the pipeline rebuild its list when they must.
#include <gtest/gtest.h>

#include <numeric>

#include "tumble/factory.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

std::vector<std::uint32_t> allBodies(const World& w) {
  std::vector<std::uint32_t> b(w.numBodies());
  std::iota(b.begin(), b.end(), 0u);
  return b;
}

class HaloPipelineTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { TUMBLE_NEED_BACKEND(GetParam()); }
};

std::vector<Backend> haloBackends() {
  std::vector<Backend> b{Backend::Cpu};
  for (Backend c : tumble_test::cudaPipelineBackends()) b.push_back(c);
  return b;
}

}  // namespace

TEST_P(HaloPipelineTest, RowsWrittenBackChangeNoBit) {
  Scene sc = readSceneFile(sourcePath("scenes/molecules.toml"));
  sc.integrator.rotation = RotationScheme::Splitting;
  const World w = World::fromScene(sc);
  const std::uint64_t steps = 300;
  PipelineOptions o;
  o.threads = 2;
  const BodyState ref = stateAfter(Backend::Cpu, w, steps, o);
  auto p = makeHaloPipeline(GetParam(), o);
  p->load(w);
  const std::vector<std::uint32_t> bodies = allBodies(w);
  std::vector<BodyMotion> rows;
  std::uint64_t touching = 0;
  for (std::uint64_t s = 0; s < steps; ++s) {
    p->step(1);
    p->readMotion(bodies, rows);
    p->writeMotion(bodies, rows);
    const std::uint64_t counted = p->contactsOf(bodies);
    ASSERT_EQ(counted, 2 * p->stats().numPairs) << "step " << s + 1 << ": each contact from both sides";
    touching += counted;
  }
  EXPECT_GT(touching, 0u);
  BodyState got;
  p->readState(got);
  const auto diff = firstDifference(ref, got);
  EXPECT_FALSE(diff) << diff->describe();
}

TEST_P(HaloPipelineTest, RowsThatJumpRebuildTheList) {
  // Clumps flying apart and into each other fast, without ground or gravity (no plane springs,
  // no history: the state is the bodies alone).
  Scene sc = benchScene(4096);
  sc.ground.enabled = false;
  sc.gravity = Vec3f{0.0f, 0.0f, 0.0f};
  for (BodyDef& b : sc.bodies) b.velocity = 10.0f * b.velocity;
  const World w = World::fromScene(sc);
  PipelineOptions o;
  o.threads = 2;
  const std::vector<std::uint32_t> bodies = allBodies(w);
  auto a = makeHaloPipeline(GetParam(), o);
  a->load(w);
  a->step(100);
  std::vector<BodyMotion> later;
  a->readMotion(bodies, later);
  // b's list is built at the start; its rows then jump 99 steps on (0.25 m at 2.5 m/s), farther
  // than the skin: its next step must rebuild the list, or it misses contacts.
  auto b = makeHaloPipeline(GetParam(), o);
  b->load(w);
  b->step(1);
  b->writeMotion(bodies, later);
  ASSERT_GT(a->stats().numPairs, 0u);
  a->step(50);
  b->step(50);
  BodyState sa, sb;
  a->readLocalState(sa);
  b->readLocalState(sb);
  const auto diff = firstDifference(sa, sb);
  EXPECT_FALSE(diff) << diff->describe();
  EXPECT_EQ(a->stats().numPairs, b->stats().numPairs);
}

INSTANTIATE_TEST_SUITE_P(Backends, HaloPipelineTest, ::testing::ValuesIn(haloBackends()), tumble_test::backendName);
