// SPDX-License-Identifier: MIT
// Determinism (SPEC §4): the same scene gives bit-identical state for any thread count and on
// repetition.
#include <gtest/gtest.h>

#include <cstdio>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

class DeterminismTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

std::uint64_t runHash(Backend b, const World& w, int threads, std::uint64_t steps, std::uint64_t* pairs) {
  PipelineOptions o;
  o.threads = threads;
  auto p = makePipeline(b, o);
  p->load(w);
  p->step(steps);
  BodyState s;
  p->readState(s);
  *pairs = p->stats().numPairs;
  return stateHash(s);
}

}  // namespace

TEST_P(DeterminismTest, MoleculesBitIdenticalForAnyThreadCount) {
  const World w = World::fromScene(readSceneFile(sourcePath("scenes/molecules.toml")));
  std::uint64_t pairs = 0;
  const std::uint64_t ref = runHash(GetParam(), w, 1, 300, &pairs);
  std::printf("molecules, 300 steps, 1 thread: hash %016llx, %llu pairs\n", static_cast<unsigned long long>(ref),
              static_cast<unsigned long long>(pairs));
  EXPECT_GT(pairs, 0u) << "the test needs contacts to mean something";
  for (int t : {2, 4, 1, 2}) {
    std::uint64_t pp = 0;
    EXPECT_EQ(runHash(GetParam(), w, t, 300, &pp), ref) << "threads " << t;
  }
}

TEST_P(DeterminismTest, StepSplitDoesNotMatter) {
  // step(300) and 300 × step(1) are the same computation.
  const World w = World::fromScene(benchScene(16000));
  auto a = makePipeline(GetParam());
  auto b = makePipeline(GetParam());
  a->load(w);
  b->load(w);
  a->step(300);
  for (int i = 0; i < 300; ++i) b->step(1);
  BodyState sa, sb;
  a->readState(sa);
  b->readState(sb);
  EXPECT_EQ(stateHash(sa), stateHash(sb));
  EXPECT_GT(a->stats().numPairs, 0u);
}

TEST(PipelineOptionsTest, ThreadCountOutOfRangeIsAnError) {
  // oneTBB crashes in its arena's destructor beyond 65536 threads: rejected before it is asked.
  for (int threads : {-1, kMaxThreads + 1, 65537}) {
    PipelineOptions o;
    o.threads = threads;
    EXPECT_THROW(makePipeline(Backend::Cpu, o), Error) << threads << " threads";
  }
  PipelineOptions o;
  o.threads = kMaxThreads;
  EXPECT_NO_THROW(makePipeline(Backend::Cpu, o));
}

INSTANTIATE_TEST_SUITE_P(Backends, DeterminismTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);
