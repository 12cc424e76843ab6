// SPDX-License-Identifier: MIT
// CPU ≡ CUDA step by step (issue 10, item 2): both pipelines stepped side by side on molecules,
// spheres and bench-16k for 1000 steps, comparing after every step the pair lists, every bit of
// the body state and contact-list state (the contacts and their histories), and the debug
// velocities and forces; a failure names the first differing step, quantity and body or
// particle. The comparison itself is checked on the CPU (StepDifferenceTest): it finds nothing
// between two CPU runs that must agree, and names the first difference of two that must not.
#include <gtest/gtest.h>

#include <string>

#include "tumble/config.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

World sceneWorld(const char* file) { return World::fromScene(readSceneFile(sourcePath(file))); }

void expectCudaEqualsCpu(const char* file, std::uint64_t steps) {
  if (!TUMBLE_STRICT_FP) GTEST_SKIP() << "TUMBLE_STRICT_FP=OFF: nvcc may contract multiply-adds, so CPU and CUDA "
                                         "agree within tolerance only (tumble validate checks that)";
  auto cpu = makePipeline(Backend::Cpu);
  auto cuda = makePipeline(Backend::Cuda);
  const World w = sceneWorld(file);
  const auto d = firstStepDifference(*cpu, w, *cuda, w, steps, /*debug=*/true);
  EXPECT_FALSE(d) << file << ", CPU against CUDA: " << d->what;
}

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

TEST(CudaEqualsCpu, MoleculesStepByStep) {
  TUMBLE_NEED_CUDA(cudaStatus());
  expectCudaEqualsCpu("scenes/molecules.toml", 1000);
}

TEST(CudaEqualsCpu, SpheresStepByStep) {
  TUMBLE_NEED_CUDA(cudaStatus());
  expectCudaEqualsCpu("scenes/spheres.toml", 1000);
}

TEST(CudaEqualsCpu, Bench16kStepByStep) {
  TUMBLE_NEED_CUDA(cudaStatus());
  expectCudaEqualsCpu("scenes/bench-16k.toml", 1000);
}
