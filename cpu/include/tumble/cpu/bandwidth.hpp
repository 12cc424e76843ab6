// SPDX-License-Identifier: MIT
/// @file bandwidth.hpp
/// The streaming bandwidth of this machine, measured in the calling process (issue 32, item 3):
/// the denominator of the memory floor of a step (Pipeline::stepTraffic(), `tumble bench`).
#pragma once
#include <cstddef>

namespace tumble::cpu {

struct Bandwidth {
  double bytesPerSecond = 0.0;  ///< bytes read plus bytes written per second, the best copy
  std::size_t bufferBytes = 0;  ///< the size of each of the two buffers
  int threads = 0;              ///< the threads that copied
};

/// The best of `repeats` copies of one buffer into another on `threads` threads (0: all cores),
/// each buffer at least 256 MiB and twice the last-level cache (sysconf), so that both stream
/// from memory (but both within a quarter of the memory available); counted as the bytes read plus the bytes written (2 × the buffer), as
/// Pipeline::stepTraffic() counts a step's. The buffers are touched first by the threads that
/// copy them (their pages where those threads run).
Bandwidth streamingBandwidth(int threads, int repeats = 5);

}  // namespace tumble::cpu
