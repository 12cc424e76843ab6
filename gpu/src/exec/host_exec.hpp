// SPDX-License-Identifier: MIT
// HostExec: the execution layer (exec.hpp) on oneTBB and host memory, compiled by g++. It runs
// the CUDA pipeline's orchestration, unchanged, on any machine (Backend::CudaHost): for testing,
// and for checking a GPU result without a GPU. It is not a fast path.
//
// Design notes
// - The stream, emulated strictly. Every operation (a forEach, a reduction, a sort, a scan, a
//   copy, a timer mark) is queued on its stream and runs when the stream is synchronised, in
//   order, as on a CUDA stream whose host memory is page-locked (the strictest case: a copy
//   reads or writes the host side only when the stream reaches it). So a host read of a result
//   before synchronize(), or a host array gone before its copy ran, gives a wrong result here
//   (under AddressSanitizer: a use after free) instead of passing by luck.
// - Freeing or regrowing a buffer first runs every stream's queue, as cudaFree synchronises the
//   device.
// - Memory. A buffer that grows is filled with 0xFF bytes (NaN floats, indices out of range), so
//   that a read of an element no operation wrote shows up; under AddressSanitizer everything
//   past the largest size asked of grow() since the allocation is poisoned (the 25 % slack
//   included), so that an index past what the orchestration sized is reported where it happens.
// - Parallelism. forEach runs a oneTBB parallel_for over elements in the stream's task_arena
//   (PipelineOptions::threads); the atomics are GCC's (exec.hpp), so ThreadSanitizer checks the
//   one-writer-per-element rule of every functor. The reductions fold each chunk in index order
//   (the device's block tree gives the same bits: exec.hpp), the sort and scan are the project's
//   own (tumble/cpu/radix_sort.hpp, scan.hpp), with the contract of CUB's.
#pragma once
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <mutex>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#endif

#include "exec.hpp"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::gpu::exec {

/// One in-order queue of work with its oneTBB arena (the host's CUDA stream).
class HostStream {
 public:
  /// threads: PipelineOptions::threads (0: all cores).
  explicit HostStream(int threads = 0);
  ~HostStream();
  HostStream(const HostStream&) = delete;
  HostStream& operator=(const HostStream&) = delete;

  /// Queues op (TUMBLE_CUDA_SYNC=1: and runs the queue at once, as the CUDA stream synchronises
  /// after every launch then).
  void enqueue(std::function<void()> op) const;
  /// Runs the queued work in order and waits for it.
  void synchronize() const;
  /// Drops the queued work unrun (AbandonOnUnwind: an exception left the code that queued it).
  void abandon() const noexcept;
  /// Runs f in this stream's arena (the threads the pipeline was given).
  template <class F>
  void inArena(const F& f) const {
    m_arena.execute(f);
  }

  /// Runs the queues of every live stream (what cudaFree does to the device).
  static void synchronizeAll();
  /// The same where nothing may throw (a buffer's release): a failure aborts with its message.
  static void synchronizeAllBeforeFree() noexcept;

 private:
  void drainLocked() const;

  std::unique_ptr<tbb::global_control> m_allowThreads;  // before the arena: threads above the cores
  mutable tbb::task_arena m_arena;
  mutable std::mutex m_mutex;
  mutable std::vector<std::function<void()>> m_queue;
  bool m_syncEach = false;
};

/// A grow-only array of T in host memory standing in for device memory (exec.hpp's Buffer).
template <class T>
class HostBuffer {
 public:
  HostBuffer() = default;
  ~HostBuffer() { release(); }
  HostBuffer(const HostBuffer&) = delete;
  HostBuffer& operator=(const HostBuffer&) = delete;
  HostBuffer(HostBuffer&& o) noexcept : m_data(o.m_data), m_capacity(o.m_capacity), m_addressable(o.m_addressable) {
    o.m_data = nullptr;
    o.m_capacity = o.m_addressable = 0;
  }
  HostBuffer& operator=(HostBuffer&& o) noexcept {
    if (this != &o) {
      release();
      m_data = o.m_data;
      m_capacity = o.m_capacity;
      m_addressable = o.m_addressable;
      o.m_data = nullptr;
      o.m_capacity = o.m_addressable = 0;
    }
    return *this;
  }

  T* data() noexcept { return m_data; }
  const T* data() const noexcept { return m_data; }
  std::size_t capacity() const noexcept { return m_capacity; }

  /// Room for at least n elements (25 % slack, as the device's); growing discards the contents
  /// (the new memory holds 0xFF bytes). Under ASan only the largest size asked since the array
  /// was allocated is addressable: not less, because work queued before this call may still
  /// use that much (the device's grow() changes nothing then either).
  T* grow(std::size_t n) {
    if (m_capacity < n) {
      // As cudaFree in the device's grow(): the old array's queued work runs first (a failure of
      // it throws here, not in release()). A first allocation, like cudaMalloc, waits for nothing.
      if (m_data != nullptr) HostStream::synchronizeAll();
      release();
      const std::size_t cap = n + n / 4 + 16;
      m_data = static_cast<T*>(::operator new(cap * sizeof(T), std::align_val_t{kAlign}));
      m_capacity = cap;
      m_addressable = 0;
      std::memset(static_cast<void*>(m_data), 0xFF, cap * sizeof(T));
#if defined(__SANITIZE_ADDRESS__)
      ASAN_POISON_MEMORY_REGION(m_data, cap * sizeof(T));
#endif
    }
    if (n > m_addressable) {
#if defined(__SANITIZE_ADDRESS__)
      ASAN_UNPOISON_MEMORY_REGION(m_data, n * sizeof(T));
#endif
      m_addressable = n;
    }
    return m_data;
  }

  /// Exactly host[0..n), ordered on the stream (host must stay as it is until the stream
  /// reaches the copy).
  void upload(const T* host, std::size_t n, const HostStream& s);
  void upload(const std::vector<T>& host, const HostStream& s) { upload(host.data(), host.size(), s); }
  /// The first n elements into host, ordered on the stream (read them after synchronize()).
  void download(T* host, std::size_t n, const HostStream& s) const;

 private:
  static constexpr std::size_t kAlign = alignof(T) > 64 ? alignof(T) : 64;

  void release() noexcept {
    if (m_data == nullptr) return;
    HostStream::synchronizeAllBeforeFree();  // as cudaFree: work still queued may use the array
#if defined(__SANITIZE_ADDRESS__)
    ASAN_UNPOISON_MEMORY_REGION(m_data, m_capacity * sizeof(T));
#endif
    ::operator delete(static_cast<void*>(m_data), std::align_val_t{kAlign});
    m_data = nullptr;
    m_capacity = m_addressable = 0;
  }

  T* m_data = nullptr;
  std::size_t m_capacity = 0;
  std::size_t m_addressable = 0;  // the largest size asked since the allocation
};

/// Per-phase wall time of a step, marked when the stream reaches each mark (as cudaEvents).
class HostTimer {
 public:
  void mark(Phase p, const HostStream& s) { record(static_cast<int>(p), s); }
  void finish(const HostStream& s) { record(kNumPhases, s); }
  /// Waits for the stream and adds each phase's time to seconds[].
  void accumulate(const HostStream& s, double* seconds) const {
    s.synchronize();
    for (int p = 0; p < kNumPhases; ++p)
      seconds[p] += std::chrono::duration<double>(m_at[p + 1] - m_at[p]).count();
  }

 private:
  void record(int k, const HostStream& s) {
    auto* at = &m_at[k];
    s.enqueue([at] { *at = std::chrono::steady_clock::now(); });
  }
  std::chrono::steady_clock::time_point m_at[kNumPhases + 1] = {};
};

/// The host backend of the execution layer (exec.hpp).
struct HostExec {
  using Stream = HostStream;
  template <class T>
  using Buffer = HostBuffer<T>;
  using Timer = HostTimer;

  template <class F>
  static void forEach(const Stream& s, std::uint64_t n, const F& f, const char* /*name*/) {
    if (n == 0) return;
    s.enqueue([&s, n, f] {
      s.inArena([&] {
        tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, n, kHostGrain), [&](const auto& r) {
          for (std::uint64_t i = r.begin(); i != r.end(); ++i) f(static_cast<std::uint32_t>(i));
        });
      });
    });
  }

  // Each chunk folded as the device folds it: an op exact in any grouping as the block's tree
  // (threadShare for each of kBlock threads, then treeStep level by level), any other in index
  // order.
  template <class Op>
  static void reduceChunks(const Stream& s, std::uint32_t n, std::uint32_t chunk, const Op& op,
                           typename Op::Value* out, const char* /*name*/) {
    checkChunk<Op>(chunk);
    const std::uint32_t numChunks = (n + chunk - 1) / chunk;
    if (numChunks == 0) return;
    s.enqueue([&s, n, chunk, numChunks, op, out] {
      s.inArena([&] {
        tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
          if constexpr (Op::kAnyGrouping) {
            typename Op::Value part[kBlock];
            for (std::uint32_t t = 0; t < kBlock; ++t) part[t] = threadShare(op, n, chunk, c, t);
            for (std::uint32_t d = 1; d < kBlock; d <<= 1)
              for (std::uint32_t t = 0; t < kBlock; t += 2 * d) treeStep(op, part, t, d);
            out[c] = part[0];
          } else {
            const std::uint32_t begin = c * chunk;
            out[c] = foldRange(op, begin, n - begin < chunk ? n : begin + chunk);
          }
        });
      });
    });
  }

  static void exclusiveSum(const Stream& s, Buffer<unsigned char>& temp, const std::uint32_t* in, std::uint32_t* out,
                           std::uint32_t n) {
    std::size_t bytes = 0;
    cpu::exclusiveSum<std::uint32_t>(nullptr, bytes, in, out, n);
    unsigned char* t = temp.grow(bytes);
    s.enqueue([&s, t, bytes, in, out, n] {
      s.inArena([&] {
        std::size_t b = bytes;
        cpu::exclusiveSum(t, b, in, out, std::size_t{n});
      });
    });
  }

  template <class K>
  static void radixSortPairs(const Stream& s, Buffer<unsigned char>& temp, const K* keysIn, K* keysOut,
                             const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                             int endBit) {
    std::size_t bytes = 0;
    cpu::radixSortPairs<K, std::uint32_t>(nullptr, bytes, keysIn, keysOut, valuesIn, valuesOut, n);
    unsigned char* t = temp.grow(bytes);
    s.enqueue([&s, t, bytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit, endBit] {
      s.inArena([&] {
        std::size_t b = bytes;
        cpu::radixSortPairs(t, b, keysIn, keysOut, valuesIn, valuesOut, std::size_t{n}, beginBit, endBit);
      });
    });
  }

  template <class T>
  static void copyToHost(const Stream& s, T* host, const T* dev, std::size_t n) {
    if (n == 0) return;
    s.enqueue([host, dev, n] { std::memcpy(static_cast<void*>(host), dev, n * sizeof(T)); });
  }
  template <class T>
  static void copyToDevice(const Stream& s, T* dev, const T* host, std::size_t n) {
    if (n == 0) return;
    s.enqueue([host, dev, n] { std::memcpy(static_cast<void*>(dev), host, n * sizeof(T)); });
  }
  template <class T>
  static void fillZero(const Stream& s, T* dev, std::size_t n) {
    if (n == 0) return;
    s.enqueue([dev, n] { std::memset(static_cast<void*>(dev), 0, n * sizeof(T)); });
  }
};

template <class T>
void HostBuffer<T>::upload(const T* host, std::size_t n, const HostStream& s) {
  grow(n);
  HostExec::copyToDevice(s, m_data, host, n);
}

template <class T>
void HostBuffer<T>::download(T* host, std::size_t n, const HostStream& s) const {
  HostExec::copyToHost(s, host, m_data, n);
}

}  // namespace tumble::gpu::exec
