// SPDX-License-Identifier: MIT
// CudaExec: the execution layer (exec.hpp) on one CUDA device, compiled by nvcc. The only code of
// the CUDA pipeline that calls the CUDA runtime (with cub_primitives.cu and device_status.cu).
//
// Design notes
// - One stream per pipeline. Every launch is checked at once (a bad configuration, no kernel
//   image for this device); with TUMBLE_CUDA_SYNC=1 the stream is also synchronised after it,
//   so that a fault inside a kernel is reported at that kernel (STYLE §5).
// - forEach: one thread per element, kBlock threads per block.
// - reduceChunks: an op exact in any grouping folds each chunk with one block, each thread taking
//   chunk/kBlock contiguous elements in order and the block combining them as a tree of
//   contiguous ranges, the lower on the left; any other op (a floating-point sum) folds each
//   chunk with one thread in index order. Either way the chunk's value is its elements folded in
//   index order, bit for bit (exec.hpp).
// - Sort and scan: CUB, instantiated in one translation unit (cub_primitives.cu).
// - Buffers: DeviceBuffer, grow-only (never cudaMalloc in a step once sizes have settled).
#pragma once
#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "../cub_primitives.cuh"
#include "../cuda_check.hpp"
#include "exec.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::gpu::exec {

/// One CUDA stream, plus the launch-check policy.
class CudaStream {
 public:
  /// threads: PipelineOptions::threads, which only the host backend uses.
  explicit CudaStream(int threads = 0) {
    (void)threads;
    TUMBLE_CUDA_CHECK(cudaStreamCreateWithFlags(&m_stream, cudaStreamNonBlocking));
    const char* env = std::getenv("TUMBLE_CUDA_SYNC");
    m_syncEach = env != nullptr && std::strcmp(env, "1") == 0;
  }
  ~CudaStream() {
    if (m_stream != nullptr) (void)cudaStreamDestroy(m_stream);
  }
  CudaStream(const CudaStream&) = delete;
  CudaStream& operator=(const CudaStream&) = delete;

  cudaStream_t get() const noexcept { return m_stream; }
  void synchronize() const { TUMBLE_CUDA_CHECK(cudaStreamSynchronize(m_stream)); }
  /// AbandonOnUnwind: waits for the work in flight, ignoring its errors (copies from pageable
  /// host memory were staged when queued, so none reads a local that is gone).
  void abandon() const noexcept {
    (void)cudaStreamSynchronize(m_stream);
    (void)cudaGetLastError();
  }

  /// After every launch: a launch error throws at once; TUMBLE_CUDA_SYNC=1 also synchronises.
  void afterLaunch(const char* what) const {
    gpu::detail::cudaCheck(cudaGetLastError(), what, __FILE__, __LINE__);
    if (m_syncEach) gpu::detail::cudaCheck(cudaStreamSynchronize(m_stream), what, __FILE__, __LINE__);
  }

 private:
  cudaStream_t m_stream = nullptr;
  bool m_syncEach = false;
};

/// A move-only owner of one device array (STYLE §2.1; DEM-Engine's DataMigrationHelper says why
/// GPU arrays must not be copyable: a copy would double-free), grow-only like the CPU pipeline's
/// columns.
template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : m_data(o.m_data), m_capacity(o.m_capacity) {
    o.m_data = nullptr;
    o.m_capacity = 0;
  }
  DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
    if (this != &o) {
      release();
      m_data = o.m_data;
      m_capacity = o.m_capacity;
      o.m_data = nullptr;
      o.m_capacity = 0;
    }
    return *this;
  }

  T* data() noexcept { return m_data; }
  const T* data() const noexcept { return m_data; }
  std::size_t capacity() const noexcept { return m_capacity; }

  /// Makes room for at least n elements (25 % slack) and returns the data. Growing discards the
  /// contents; never shrinks. cudaFree synchronises the device, so work still in flight on the
  /// old array is finished first.
  T* grow(std::size_t n) {
    if (m_capacity < n) {
      release();
      void* p = nullptr;
      const std::size_t cap = n + n / 4 + 16;
      TUMBLE_CUDA_CHECK(cudaMalloc(&p, cap * sizeof(T)));
      m_data = static_cast<T*>(p);
      m_capacity = cap;
    }
    return m_data;
  }

  /// Exactly host[0..n), ordered on the stream (host must stay as it is until the stream has
  /// reached the copy).
  void upload(const T* host, std::size_t n, const CudaStream& s) {
    grow(n);
    if (n > 0)
      TUMBLE_CUDA_CHECK(cudaMemcpyAsync(m_data, host, n * sizeof(T), cudaMemcpyHostToDevice, s.get()));
  }
  void upload(const std::vector<T>& host, const CudaStream& s) { upload(host.data(), host.size(), s); }
  /// The first n elements into host, ordered on the stream (read them after synchronize()).
  void download(T* host, std::size_t n, const CudaStream& s) const {
    if (n > 0)
      TUMBLE_CUDA_CHECK(cudaMemcpyAsync(host, m_data, n * sizeof(T), cudaMemcpyDeviceToHost, s.get()));
  }

 private:
  void release() noexcept {
    if (m_data != nullptr) (void)cudaFree(m_data);  // never throws from a destructor
    m_data = nullptr;
    m_capacity = 0;
  }

  T* m_data = nullptr;
  std::size_t m_capacity = 0;
};

/// cudaEvents at the start of each Phase and at the end of the step: a phase's time is the
/// stream time from its event to the next one's (host work in between, such as the PCA solve,
/// counts towards the phase it belongs to, as on the CPU).
class CudaTimer {
 public:
  CudaTimer() {
    try {
      for (auto& e : m_events) TUMBLE_CUDA_CHECK(cudaEventCreate(&e));
    } catch (...) {
      destroy();  // the destructor does not run for a half-built object
      throw;
    }
  }
  ~CudaTimer() { destroy(); }
  CudaTimer(const CudaTimer&) = delete;
  CudaTimer& operator=(const CudaTimer&) = delete;

  /// Records the start of phase p. Phases must be marked in order, every one of them, each step.
  void mark(Phase p, const CudaStream& s) { TUMBLE_CUDA_CHECK(cudaEventRecord(m_events[int(p)], s.get())); }
  /// Records the end of the step.
  void finish(const CudaStream& s) { TUMBLE_CUDA_CHECK(cudaEventRecord(m_events[kNumPhases], s.get())); }
  /// Waits for the end event and adds each phase's time to seconds[].
  void accumulate(const CudaStream& s, double* seconds) const {
    (void)s;
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

namespace detail {

inline unsigned int blocksFor(std::uint64_t n) { return static_cast<unsigned int>((n + kBlock - 1) / kBlock); }

template <class F>
__global__ void __launch_bounds__(kBlock) forEachKernel(std::uint64_t n, F f) {
  const std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < n) f(static_cast<std::uint32_t>(i));
}

// One block per chunk: each thread's share, then the tree (threadShare, treeStep: exec.hpp).
template <class Op>
__global__ void __launch_bounds__(kBlock) reduceTreeKernel(std::uint32_t n, std::uint32_t chunk, Op op,
                                                           typename Op::Value* out) {
  __shared__ typename Op::Value part[kBlock];
  const std::uint32_t t = threadIdx.x;
  part[t] = threadShare(op, n, chunk, blockIdx.x, t);
  __syncthreads();
  for (std::uint32_t d = 1; d < kBlock; d <<= 1) {
    treeStep(op, part, t, d);
    __syncthreads();
  }
  if (t == 0) out[blockIdx.x] = part[0];
}

// One thread per chunk, in index order (an op whose merge is not exact), in blocks of
// kOrderedBlock threads: a cloud's few hundred chunks spread over many multiprocessors.
inline constexpr std::uint32_t kOrderedBlock = 32;

template <class Op>
__global__ void __launch_bounds__(kOrderedBlock) reduceOrderedKernel(std::uint32_t n, std::uint32_t chunk,
                                                              std::uint32_t numChunks, Op op,
                                                              typename Op::Value* out) {
  const std::uint32_t c = blockIdx.x * blockDim.x + threadIdx.x;
  if (c >= numChunks) return;
  const std::uint32_t begin = c * chunk;
  out[c] = foldRange(op, begin, n - begin < chunk ? n : begin + chunk);
}

}  // namespace detail

/// The CUDA backend of the execution layer (exec.hpp).
struct CudaExec {
  using Stream = CudaStream;
  template <class T>
  using Buffer = DeviceBuffer<T>;
  using Timer = CudaTimer;

  template <class F>
  static void forEach(const Stream& s, std::uint64_t n, const F& f, const char* name) {
    if (n == 0) return;  // a grid of no blocks is a launch error
    detail::forEachKernel<F><<<detail::blocksFor(n), kBlock, 0, s.get()>>>(n, f);
    s.afterLaunch(name);
  }

  template <class Op>
  static void reduceChunks(const Stream& s, std::uint32_t n, std::uint32_t chunk, const Op& op,
                           typename Op::Value* out, const char* name) {
    checkChunk<Op>(chunk);
    const std::uint32_t numChunks = (n + chunk - 1) / chunk;
    if (numChunks == 0) return;
    if constexpr (Op::kAnyGrouping) {
      detail::reduceTreeKernel<Op><<<numChunks, kBlock, 0, s.get()>>>(n, chunk, op, out);
    } else {
      const unsigned int blocks = (numChunks + detail::kOrderedBlock - 1) / detail::kOrderedBlock;
      detail::reduceOrderedKernel<Op><<<blocks, detail::kOrderedBlock, 0, s.get()>>>(n, chunk, numChunks, op, out);
    }
    s.afterLaunch(name);
  }

  static void exclusiveSum(const Stream& s, Buffer<unsigned char>& temp, const std::uint32_t* in, std::uint32_t* out,
                           std::uint32_t n) {
    std::size_t bytes = 0;
    TUMBLE_CUDA_CHECK(gpu::detail::exclusiveSum(nullptr, bytes, in, out, n, s.get()));
    TUMBLE_CUDA_CHECK(gpu::detail::exclusiveSum(temp.grow(bytes), bytes, in, out, n, s.get()));
    s.afterLaunch("exclusiveSum");
  }

  template <class K>
  static void radixSortPairs(const Stream& s, Buffer<unsigned char>& temp, const K* keysIn, K* keysOut,
                             const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                             int endBit) {
    std::size_t bytes = 0;
    TUMBLE_CUDA_CHECK(gpu::detail::radixSortPairs(nullptr, bytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit,
                                                  endBit, s.get()));
    TUMBLE_CUDA_CHECK(gpu::detail::radixSortPairs(temp.grow(bytes), bytes, keysIn, keysOut, valuesIn, valuesOut, n,
                                                  beginBit, endBit, s.get()));
    s.afterLaunch("radixSortPairs");
  }

  template <class T>
  static void copyToHost(const Stream& s, T* host, const T* dev, std::size_t n) {
    if (n > 0) TUMBLE_CUDA_CHECK(cudaMemcpyAsync(host, dev, n * sizeof(T), cudaMemcpyDeviceToHost, s.get()));
  }
  template <class T>
  static void copyToDevice(const Stream& s, T* dev, const T* host, std::size_t n) {
    if (n > 0) TUMBLE_CUDA_CHECK(cudaMemcpyAsync(dev, host, n * sizeof(T), cudaMemcpyHostToDevice, s.get()));
  }
  template <class T>
  static void fillZero(const Stream& s, T* dev, std::size_t n) {
    if (n > 0) TUMBLE_CUDA_CHECK(cudaMemsetAsync(dev, 0, n * sizeof(T), s.get()));
  }
};

}  // namespace tumble::gpu::exec
