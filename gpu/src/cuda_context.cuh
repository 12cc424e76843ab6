// SPDX-License-Identifier: MIT
// The pipeline's stream, launch checks and per-phase event timers. Internal to tumble::gpu.
#pragma once
#include <cuda_runtime_api.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "cuda_check.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::gpu::detail {

/// Threads per block of every element-wise kernel.
inline constexpr std::uint32_t kBlock = 256;

/// Blocks for n elements (n > 0).
inline unsigned int blocksFor(std::uint64_t n) { return static_cast<unsigned int>((n + kBlock - 1) / kBlock); }

/// One stream per pipeline, plus the launch-check policy.
class StreamContext {
 public:
  StreamContext() {
    TUMBLE_CUDA_CHECK(cudaStreamCreateWithFlags(&m_stream, cudaStreamNonBlocking));
    const char* env = std::getenv("TUMBLE_CUDA_SYNC");
    m_syncEachLaunch = env != nullptr && std::strcmp(env, "1") == 0;
  }
  ~StreamContext() {
    if (m_stream != nullptr) (void)cudaStreamDestroy(m_stream);
  }
  StreamContext(const StreamContext&) = delete;
  StreamContext& operator=(const StreamContext&) = delete;

  cudaStream_t stream() const noexcept { return m_stream; }

  /// After every kernel launch: a launch error (bad configuration, no kernel image for this
  /// device) throws at once. With TUMBLE_CUDA_SYNC=1 the stream is also synchronised, so that
  /// a fault inside the kernel is reported at that kernel rather than at the next copy.
  void afterLaunch(const char* kernel, const char* file, int line) const {
    cudaCheck(cudaGetLastError(), kernel, file, line);
    if (m_syncEachLaunch) cudaCheck(cudaStreamSynchronize(m_stream), kernel, file, line);
  }

  void synchronize() const { TUMBLE_CUDA_CHECK(cudaStreamSynchronize(m_stream)); }

 private:
  cudaStream_t m_stream = nullptr;
  bool m_syncEachLaunch = false;
};

/// Checks the launch just made on `ctx` (see StreamContext::afterLaunch).
#define TUMBLE_CUDA_AFTER_LAUNCH(ctx, kernel) (ctx).afterLaunch(kernel, __FILE__, __LINE__)

/// cudaEvents at the start of each Phase and at the end of the step: StepStats::seconds[p] is the
/// stream time from phase p's event to the next one's (host work in between, such as the PCA
/// eigen-solve, counts towards the phase it belongs to, as on the CPU).
class PhaseTimer {
 public:
  PhaseTimer() {
    try {
      for (auto& e : m_events) TUMBLE_CUDA_CHECK(cudaEventCreate(&e));
    } catch (...) {
      destroy();  // the destructor does not run for a half-built object
      throw;
    }
  }
  ~PhaseTimer() { destroy(); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

  /// Records the start of phase p. Phases must be marked in order, every one of them, each step.
  void mark(Phase p, cudaStream_t stream) { TUMBLE_CUDA_CHECK(cudaEventRecord(m_events[int(p)], stream)); }
  /// Records the end of the step.
  void finish(cudaStream_t stream) { TUMBLE_CUDA_CHECK(cudaEventRecord(m_events[kNumPhases], stream)); }
  /// Waits for the end event and adds each phase's time to seconds[].
  void accumulate(double* seconds) const {
    TUMBLE_CUDA_CHECK(cudaEventSynchronize(m_events[kNumPhases]));
    for (int p = 0; p < kNumPhases; ++p) {
      float ms = 0.0f;
      TUMBLE_CUDA_CHECK(cudaEventElapsedTime(&ms, m_events[p], m_events[p + 1]));
      seconds[p] += 1.0e-3 * static_cast<double>(ms);
    }
  }

 private:
  void destroy() noexcept {
    for (auto& e : m_events)
      if (e != nullptr) (void)cudaEventDestroy(e);
  }

  cudaEvent_t m_events[kNumPhases + 1] = {};
};

}  // namespace tumble::gpu::detail
