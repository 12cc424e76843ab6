// SPDX-License-Identifier: MIT
// The execution layer of the CUDA pipeline (STYLE §2.5): what its orchestration
// (broadphase.hpp, pipeline.hpp) may ask of a machine, and nothing else. Two backends implement
// it with the same static interface, and the orchestration is a template over them:
// - CudaExec (cuda_exec.cuh, nvcc): grid launches on one stream, block trees, CUB, device memory.
// - HostExec (host_exec.hpp, g++): the same operations on oneTBB and host memory, with the
//   stream's order emulated (see host_exec.hpp), so that the CUDA pipeline's own code runs, and
//   is compared bit for bit with the CPU pipeline, on any machine (Backend::CudaHost).
// The models: Jolt's compute backends (Jolt/Compute/CPU runs the shaders as C++), ArborX over
// Kokkos execution spaces (its CI runs the GPU code paths on Serial/OpenMP), Box2D v3's task
// callbacks.
//
// The interface, for a backend E (every call is ordered on the stream, as CUDA's are):
//   E::Stream                       one in-order queue of work; synchronize() waits for it
//   E::Buffer<T>                    a move-only grow-only array in the backend's memory
//                                   (grow(n) discards the contents; upload/download/data)
//   E::Timer                        per-phase times of a step (mark, finish, accumulate)
//   E::forEach(s, n, f, name)       f(i) for every i in [0, n): one writer per element, no order
//   E::reduceChunks(s, n, chunk, op, out, name)
//                                   out[c] = op's fold of the elements [c·chunk, (c+1)·chunk) ∩ [0, n)
//   E::exclusiveSum(s, temp, in, out, n)            the two-phase contract of CUB/cpu::exclusiveSum
//   E::radixSortPairs(s, temp, kIn, kOut, vIn, vOut, n, beginBit, endBit)   stable, as CUB's
//   E::copyToHost / copyToDevice / fillZero         ordered copies (read the host side only after
//                                                   synchronize())
// Functors, not lambdas (STYLE §2.2): trivially copyable structs of views with a TUMBLE_HD
// operator(); the same functor runs in a CUDA thread and in a oneTBB task. The only atomics
// are the integer ones below (exact in any order). No floating-point atomics, anywhere.
#pragma once
#include <cstdint>
#include <exception>
#include <string>

#include "tumble/error.hpp"
#include "tumble/hd.hpp"

/// The inline namespace of the orchestration (pipeline.hpp, broadphase.hpp): its functors are
/// compiled by nvcc in one translation unit and by the host compiler in others, where TUMBLE_HD
/// means different things; each compiler's copy gets its own namespace, so the two never meet at
/// link time (one definition each).
#if defined(__CUDACC__)
#define TUMBLE_EXEC_ABI device
#else
#define TUMBLE_EXEC_ABI host
#endif

namespace tumble::gpu::exec {

/// Threads per block of every CUDA launch; reduceChunks' chunks are multiples of it when their op
/// is exact in any grouping (the device splits a chunk evenly over one block).
inline constexpr std::uint32_t kBlock = 256;

/// A reduction over fixed chunks (E::reduceChunks). An op is a trivially copyable struct with:
///   using Value = …;                       trivially copyable
///   static constexpr bool kAnyGrouping;    merge() is exact and associative (min, max, integer
///                                          sums): the device may fold a chunk as a tree of
///                                          contiguous ranges. false: the chunk is folded by one
///                                          thread in index order (floating-point sums).
///   TUMBLE_HD Value identity() const;
///   TUMBLE_HD void add(Value& acc, std::uint32_t i) const;          element i, in index order
///   TUMBLE_HD void merge(Value& left, const Value& right) const;    right: the higher indices
/// Either way each chunk's value is its elements folded in index order, bit for bit, so the
/// partials (combined on the host in chunk order) are the same on every backend. Both backends
/// group an op exact in any grouping as the device's block does (threadShare, then treeStep), so
/// that a merge that is not in fact exact shows on the host backend too; its chunk must be a
/// multiple of kBlock (checkChunk).
template <class Op>
TUMBLE_HD_INLINE typename Op::Value foldRange(const Op& op, std::uint32_t begin, std::uint32_t end) {
  typename Op::Value v = op.identity();
  for (std::uint32_t i = begin; i < end; ++i) op.add(v, i);
  return v;
}

/// The device's fold of a chunk for an op exact in any grouping, in two shared steps (the CUDA
/// backend's block runs them; a test runs them thread by thread on the host): thread t of the
/// chunk's block first folds its contiguous share of chunk/kBlock elements in order ...
template <class Op>
TUMBLE_HD_INLINE typename Op::Value threadShare(const Op& op, std::uint32_t n, std::uint32_t chunk, std::uint32_t c,
                                                std::uint32_t t) {
  const std::uint32_t share = chunk / kBlock;
  const std::uint64_t begin = std::uint64_t(c) * chunk + std::uint64_t(t) * share;
  const std::uint64_t end = begin + share < n ? begin + share : n;  // beyond n: an empty share
  return foldRange(op, static_cast<std::uint32_t>(begin < end ? begin : end), static_cast<std::uint32_t>(end));
}

/// The chunk of an op exact in any grouping splits evenly over one block (each thread takes
/// chunk / kBlock elements): throws tumble::Error otherwise, on both backends.
template <class Op>
inline void checkChunk(std::uint32_t chunk) {
  if (Op::kAnyGrouping && (chunk == 0 || chunk % kBlock != 0))
    throw Error("reduceChunks: a chunk of " + std::to_string(chunk) + " elements does not split over a block of " +
                std::to_string(kBlock) + " threads");
}

/// ... then the block merges the shares as a tree, level d = 1, 2, 4, … < kBlock: after a level,
/// part[t] (t a multiple of 2d) covers threads [t, t + 2d), so every merge joins two contiguous
/// ranges, the lower on the left, and part[0] is the chunk's fold in index order, bit for bit.
template <class Op>
TUMBLE_HD_INLINE void treeStep(const Op& op, typename Op::Value* part, std::uint32_t t, std::uint32_t d) {
  if ((t & (2 * d - 1)) == 0) op.merge(part[t], part[t + d]);
}

// --- Integer atomics (the skin test's max and min, the contact count) -----------------------
// Exact in any order. On the device CUDA's; on the host GCC's __atomic builtins (which
// ThreadSanitizer understands), so that the host backend runs the same read-modify-writes.

TUMBLE_HD_INLINE void atomicMaxU32(unsigned int* p, unsigned int v) {
#if defined(__CUDA_ARCH__)
  atomicMax(p, v);
#else
  unsigned int cur = __atomic_load_n(p, __ATOMIC_RELAXED);
  while (cur < v && !__atomic_compare_exchange_n(p, &cur, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

TUMBLE_HD_INLINE void atomicMinU32(unsigned int* p, unsigned int v) {
#if defined(__CUDA_ARCH__)
  atomicMin(p, v);
#else
  unsigned int cur = __atomic_load_n(p, __ATOMIC_RELAXED);
  while (v < cur && !__atomic_compare_exchange_n(p, &cur, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

TUMBLE_HD_INLINE void atomicAddU64(unsigned long long* p, unsigned long long v) {
#if defined(__CUDA_ARCH__)
  atomicAdd(p, v);
#else
  __atomic_fetch_add(p, v, __ATOMIC_RELAXED);
#endif
}

/// Elements per task of the host backend's forEach (the device runs one per thread).
inline constexpr std::uint32_t kHostGrain = 1024;

/// Declared first in a function that queues work on stream s (copies to or from its locals
/// among it): when an exception leaves the function, the work still queued is abandoned
/// (Stream::abandon()), so that it never runs on locals that are gone. The pipeline is then in
/// an unspecified, destructible state, as after any error.
template <class Stream>
class AbandonOnUnwind {
 public:
  explicit AbandonOnUnwind(const Stream& s) : m_stream(s), m_exceptions(std::uncaught_exceptions()) {}
  ~AbandonOnUnwind() {
    if (std::uncaught_exceptions() > m_exceptions) m_stream.abandon();
  }
  AbandonOnUnwind(const AbandonOnUnwind&) = delete;
  AbandonOnUnwind& operator=(const AbandonOnUnwind&) = delete;

 private:
  const Stream& m_stream;
  int m_exceptions;
};

}  // namespace tumble::gpu::exec
