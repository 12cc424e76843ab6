// SPDX-License-Identifier: MIT
// A step allocates nothing once the sizes have settled (scratch is grow-only; the candidate list
// and the detection keep their capacity across rebuilds). This file replaces the global
// operator new of the test binary with a counting one (the count is all it changes).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include <unistd.h>

#include "tumble/factory.hpp"
#include "tumble/recording.hpp"

#include "tumble/validation/scenes.hpp"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<long> g_allocatedBytes{0};
}  // namespace

// The sanitizers bring their own operator new; replacing it under them mismatches allocations
// made by their other forms (the sanitizer build skips this test; the plain build runs it).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TUMBLE_COUNT_ALLOCATIONS 0
#else
#define TUMBLE_COUNT_ALLOCATIONS 1
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  g_allocatedBytes.fetch_add(static_cast<long>(n), std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif

TEST(Allocation, StepsAllocateNothingOnceSizesHaveSettled) {
  if (!TUMBLE_COUNT_ALLOCATIONS) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
  using namespace tumble;
  const World w = World::fromScene(validation::benchScene(16000));
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  p->step(1500);  // the pile lands: the list and the detection reach their sizes
  const std::uint64_t rebuilds = p->stats().numRebuilds;
  const long before = g_allocations.load();
  p->step(500);
  const long allocations = g_allocations.load() - before;
  std::printf("500 steps with %llu rebuilds: %ld allocations\n",
              static_cast<unsigned long long>(p->stats().numRebuilds - rebuilds), allocations);
  EXPECT_GT(p->stats().numRebuilds, rebuilds) << "the window must contain rebuilds for the test to mean something";
  EXPECT_EQ(allocations, 0);
}

// Reading a recording frame by frame reuses the frame's storage: after the first frame, reading
// the other 199 allocates less than one frame's worth of bytes in all (the whole-recording read
// holds all of them), so render and play need one frame of memory whatever the file's length.
TEST(Allocation, ReadingARecordingFrameByFrameReusesTheFrame) {
  if (!TUMBLE_COUNT_ALLOCATIONS) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
  using namespace tumble;
  const World w = World::fromScene(validation::benchScene(2000));
  const std::string path = ::testing::TempDir() + "tumble_allocation_" + std::to_string(::getpid()) + ".bin";
  {
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    RecordingWriter rec(path, w, /*debug=*/false, 1);
    BodyState s;
    for (int f = 0; f < 200; ++f) {
      p->step(1);
      p->readState(s);
      rec.writeFrame(p->stepCount(), p->time(), 0, s);
    }
  }
  RecordingReader reader(path);
  ASSERT_EQ(reader.numFrames(), 200u);
  RecordedFrame f;
  reader.readFrame(0, f);
  const long frameBytes = static_cast<long>(28 * w.numBodies());
  const long before = g_allocatedBytes.load();
  for (std::size_t k = 1; k < reader.numFrames(); ++k) reader.readFrame(k, f);
  const long bytes = g_allocatedBytes.load() - before;
  std::printf("199 frames of %ld bytes read: %ld bytes allocated\n", frameBytes, bytes);
  EXPECT_LT(bytes, frameBytes);
  std::remove(path.c_str());
}
