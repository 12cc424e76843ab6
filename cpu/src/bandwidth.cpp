// SPDX-License-Identifier: MIT
#include "tumble/cpu/bandwidth.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>

#include "tumble/memory.hpp"

namespace tumble::cpu {

Bandwidth streamingBandwidth(int threads, int repeats) {
  std::size_t bytes = std::size_t{256} << 20;
#ifdef _SC_LEVEL3_CACHE_SIZE
  if (const long llc = sysconf(_SC_LEVEL3_CACHE_SIZE); llc > 0) bytes = std::max(bytes, 2 * static_cast<std::size_t>(llc));
#endif
  // Both buffers within a quarter of what the machine has available.
  if (const auto have = availableMemory()) bytes = std::min<std::size_t>(bytes, std::max<std::size_t>(*have / 8, 16u << 20));
  constexpr std::size_t kChunk = std::size_t{1} << 20;  // bytes per task: whole pages, few tasks
  const std::size_t chunks = (bytes + kChunk - 1) / kChunk;
  bytes = chunks * kChunk;
  const std::unique_ptr<unsigned char[]> from(new unsigned char[bytes]), to(new unsigned char[bytes]);
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  const auto copy = [&](bool first) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks), [&](const auto& r) {
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          if (first) {
            std::memset(from.get() + c * kChunk, int(c & 0xFF), kChunk);
            std::memset(to.get() + c * kChunk, 0, kChunk);
          } else {
            std::memcpy(to.get() + c * kChunk, from.get() + c * kChunk, kChunk);
          }
        }
      }, tbb::static_partitioner());
    });
  };
  copy(true);  // first touch, by the threads that copy
  double best = 0.0;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    copy(false);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > 0.0) best = std::max(best, 2.0 * double(bytes) / s);
  }
  return Bandwidth{best, bytes, arena.max_concurrency()};
}

}  // namespace tumble::cpu
