// SPDX-License-Identifier: MIT
// CPU ≡ CUDA step by step: the CPU pipeline and the CUDA pipeline stepped side by side on
// molecules, spheres, bench-16k and a pour for 1000 steps (and a dense cluster for 200), under
// the report's law and the laws with history, comparing after every step the pair
// lists, every bit of the body state and contact-list state (the contacts and their histories),
// and the debug velocities and forces; a failure names the first differing step, quantity and
// body or particle. Each runs on every backend of the CUDA pipeline: cuda-host (its code on the
// host backend, in every build and every CI run) and cuda (on a GPU). The comparison itself is
// checked on the CPU (StepDifferenceTest): it finds nothing between two CPU runs that must agree,
// and names the first difference of two that must not.
#include <gtest/gtest.h>

#include <string>

#include "tumble/config.hpp"
#include "tumble/pour.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

World sceneWorld(const char* file) { return World::fromScene(readSceneFile(sourcePath(file))); }

// Balls and dimers poured onto the ground under the report's law, a batch every 50 steps
// (interval 0.005 s): the world grows and both pipelines are loaded afresh with it.
const char* kPour = R"(
[scene]
dt = 1e-4
steps = 1000
seed = 7
[ground]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.01
mass = 0.0105
[[shape]]
name = "dimer"
[[shape.sphere]]
radius = 0.01
offset = [-0.006, 0, 0]
mass = 0.0105
[[shape.sphere]]
radius = 0.01
offset = [0.006, 0, 0]
mass = 0.0105
[[fill]]
shape = "dimer"
count = 40
region = "box"
min = [-0.1, -0.1, 0.0]
max = [0.1, 0.1, 0.05]
[[pour]]
shapes = ["ball", "dimer"]
count = 100
rate = 1500
interval = 0.005
region = "box"
min = [-0.08, -0.08, 0.08]
max = [0.08, 0.08, 0.3]
velocity = [0, 0, -1]
scale = [0.8, 1.2]
)";

// A jittered 12 × 12 × 12 lattice of spheres that overlap their neighbours (spacing 1.8 r), no
// gravity: every particle is in contact from the first step on, so that a row, a record or an
// offset lost at any index shows (the last particle of the internal order included, which in
// the scenes above may touch nothing).
World denseCluster(ContactLaw law = ContactLaw::Report) {
  Scene s;
  s.gravity = {0.0f, 0.0f, 0.0f};
  s.dt = 1e-3f;
  s.contact = {1e3f, 0.5f, 0.2f};
  s.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
  Rng rng(2026);
  for (int i = 0; i < 12 * 12 * 12; ++i) {
    BodyDef b;
    b.position = {0.18f * float(i % 12) + rng.uniform(-0.01f, 0.01f),
                  0.18f * float(i / 12 % 12) + rng.uniform(-0.01f, 0.01f),
                  0.18f * float(i / 144) + rng.uniform(-0.01f, 0.01f)};
    s.bodies.push_back(b);
  }
  if (law == ContactLaw::HookeHistory) s = withHookeHistory(s);
  if (law == ContactLaw::HertzMindlin) s = withHertzMindlin(s, 1.0e6f, true);
  return World::fromScene(s);
}

class CudaEqualsCpu : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
    if (GetParam() == Backend::Cuda && !TUMBLE_STRICT_FP)
      GTEST_SKIP() << "TUMBLE_STRICT_FP=OFF: nvcc may contract multiply-adds, so CPU and CUDA "
                      "agree within tolerance only (tumble validate checks that)";
  }

  // Returns the number of bodies at the end (the pours add some).
  std::size_t expectEqual(const World& w, std::uint64_t steps, const char* what, const Pouring* pouring = nullptr) {
    auto cpu = makePipeline(Backend::Cpu);
    auto cuda = makePipeline(GetParam());
    const auto d = firstStepDifference(*cpu, w, *cuda, w, steps, /*debug=*/true, pouring);
    EXPECT_FALSE(d) << what << ", CPU against " << toString(GetParam()) << ": " << d->what;
    BodyState s;
    cpu->readState(s);
    return s.size();
  }
};

}  // namespace

TEST(StepDifferenceTest, NoneBetweenRunsThatMustAgree) {
  PipelineOptions one, two;
  one.threads = 1;
  two.threads = 2;
  two.reorder = false;
  auto a = makePipeline(Backend::Cpu, one);
  auto b = makePipeline(Backend::Cpu, two);
  const World w = sceneWorld("scenes/molecules.toml");
  const auto d = firstStepDifference(*a, w, *b, w, 60, /*debug=*/true);
  EXPECT_FALSE(d) << d->what;
}

TEST(StepDifferenceTest, NamesTheFirstDifference) {
  const World w = sceneWorld("scenes/molecules.toml");
  World nudged = w;
  nudged.state.vx[5] += 1e-3f;
  auto a = makePipeline(Backend::Cpu);
  auto b = makePipeline(Backend::Cpu);
  const auto e = firstStepDifference(*a, w, *b, nudged, 60, /*debug=*/true);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->step, 1u);
  EXPECT_NE(e->what.find("of body 5:"), std::string::npos) << e->what;
}

TEST_P(CudaEqualsCpu, MoleculesStepByStep) { expectEqual(sceneWorld("scenes/molecules.toml"), 1000, "molecules"); }

TEST_P(CudaEqualsCpu, SpheresStepByStep) { expectEqual(sceneWorld("scenes/spheres.toml"), 1000, "spheres"); }

TEST_P(CudaEqualsCpu, Bench16kStepByStep) { expectEqual(sceneWorld("scenes/bench-16k.toml"), 1000, "bench-16k"); }

TEST_P(CudaEqualsCpu, DenseClusterStepByStep) { expectEqual(denseCluster(), 200, "dense cluster"); }

// The laws with a tangential history per contact (the histories compared after every step with
// the state): molecules' clumps falling onto the ground and into each other, and the dense
// cluster's single spheres (which rotate under these laws), where every particle carries
// histories from the first step and each rebuild must carry them all across; hertz-mindlin with
// two materials (a per-pair table, rolling resistance between some pairs: withHertzMindlin).
TEST_P(CudaEqualsCpu, HookeHistoryStepByStep) {
  expectEqual(World::fromScene(withHookeHistory(readSceneFile(sourcePath("scenes/molecules.toml")))), 1000,
              "molecules, hooke-history");
  expectEqual(denseCluster(ContactLaw::HookeHistory), 200, "dense cluster, hooke-history");
}

TEST_P(CudaEqualsCpu, HertzMindlinStepByStep) {
  expectEqual(World::fromScene(withHertzMindlin(readSceneFile(sourcePath("scenes/molecules.toml")), 1.0e6f, true)),
              1000, "molecules, hertz-mindlin");
  expectEqual(denseCluster(ContactLaw::HertzMindlin), 200, "dense cluster, hertz-mindlin");
}

TEST_P(CudaEqualsCpu, PourStepByStep) {
  const Scene s = parseScene(kPour, "pour (cuda_equals_cpu_test.cpp)");
  const Pouring pouring(s);
  const World w = pouring.worldWith(pouring.initialBodies());
  // Every poured body must have entered within the 1000 steps (else the test saw less of it).
  EXPECT_EQ(expectEqual(w, 1000, "pour", &pouring), pouring.finalBodies());
}

INSTANTIATE_TEST_SUITE_P(Backends, CudaEqualsCpu, ::testing::ValuesIn(tumble_test::cudaPipelineBackends()),
                         tumble_test::backendName);
