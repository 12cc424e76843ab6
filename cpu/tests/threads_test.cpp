// SPDX-License-Identifier: MIT
// --threads above the number of cores is honoured (issue 34, item 10): without the control
// oneTBB runs an arena of more threads than cores on as many threads as cores, and warns.
#include <gtest/gtest.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "tumble/cpu/threads.hpp"

namespace {

std::size_t threadsUsed(tbb::task_arena& arena) {
  std::set<std::thread::id> ids;
  std::mutex m;
  arena.execute([&] {
    tbb::parallel_for(0, 2000, [&](int) {
      {
        const std::lock_guard<std::mutex> lock(m);
        ids.insert(std::this_thread::get_id());
      }
      std::this_thread::sleep_for(std::chrono::microseconds(500));  // long enough for every worker to join
    });
  });
  return ids.size();
}

}  // namespace

TEST(Threads, MoreThanTheCoresAreHonoured) {
  const int cores = tbb::info::default_concurrency();
  const int want = cores + 2;
  const auto allow = tumble::cpu::allowThreads(want);
  ASSERT_NE(allow, nullptr);
  tbb::task_arena arena(want);
  EXPECT_EQ(threadsUsed(arena), std::size_t(want)) << cores << " cores";
}

TEST(Threads, NoControlUpToTheCores) {
  EXPECT_EQ(tumble::cpu::allowThreads(0), nullptr);
  EXPECT_EQ(tumble::cpu::allowThreads(1), nullptr);
  EXPECT_EQ(tumble::cpu::allowThreads(tbb::info::default_concurrency()), nullptr);
}
