// SPDX-License-Identifier: MIT
// Golden state hashes (validation/golden/state_hashes.txt): the CPU pipeline's result for each
// scene is fixed bit for bit, on any machine and thread count, and the CUDA pipeline's is the same.
// A change must be deliberate.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tumble/config.hpp"
#include "tumble/factory.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

// Every line of validation/golden/state_hashes.txt run on `backend` with each thread count.
void checkGoldenHashes(Backend backend, std::initializer_list<int> threadCounts) {
  std::ifstream in(sourcePath("validation/golden/state_hashes.txt"));
  ASSERT_TRUE(in) << "cannot open validation/golden/state_hashes.txt";
  std::string line;
  int checked = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string scene, hashText;
    std::uint64_t steps = 0;
    ASSERT_TRUE(ls >> scene >> steps >> hashText) << "bad line: " << line;
    const std::uint64_t want = std::stoull(hashText, nullptr, 16);
    const World w = World::fromScene(readSceneFile(sourcePath(scene)));
    for (int threads : threadCounts) {
      PipelineOptions o;
      o.threads = threads;
      auto p = makePipeline(backend, o);
      p->load(w);
      p->step(steps);
      BodyState s;
      p->readState(s);
      char got[17];
      std::snprintf(got, sizeof got, "%016llx", static_cast<unsigned long long>(stateHash(s)));
      EXPECT_EQ(stateHash(s), want) << toString(backend) << ": " << scene << " after " << steps << " steps, "
                                    << threads << " threads: got " << got;
    }
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

}  // namespace

TEST(Golden, CpuStateHashesMatch) { checkGoldenHashes(Backend::Cpu, {1, 2}); }

// The CUDA pipeline's state is the CPU's bit for bit: the same hashes, on the host backend (with 1
// and 2 threads) and on a GPU (TUMBLE_STRICT_FP: without it nvcc may contract multiply-adds).
class CudaGolden : public ::testing::TestWithParam<Backend> {};

TEST_P(CudaGolden, StateHashesMatch) {
  TUMBLE_NEED_BACKEND(GetParam());
  if (GetParam() == Backend::Cuda) {
    if (!TUMBLE_STRICT_FP) GTEST_SKIP() << "TUMBLE_STRICT_FP=OFF: nvcc may contract multiply-adds";
    checkGoldenHashes(Backend::Cuda, {0});
  } else {
    checkGoldenHashes(GetParam(), {1, 2});
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, CudaGolden, ::testing::ValuesIn(tumble_test::cudaPipelineBackends()),
                         tumble_test::backendName);
