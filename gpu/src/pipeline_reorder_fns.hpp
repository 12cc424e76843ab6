// SPDX-License-Identifier: MIT
// The CUDA pipeline's functors of the reordering at a rebuild (CudaPipeline::reorder(),
// pipeline_rebuild.hpp): the bounds of the body centres, their Morton keys, and the gathers of
// every column in the sorted order (moveBody(), kernels/contact_list.hpp). Internal to
// tumble::gpu.
#pragma once
#include <cstdint>

#include "exec/exec.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// The reordering: the bounds of the body centres, Morton keys, then gathers in the sorted order.
struct BodyBoundsOp {
  const BodyRow* bodies;
  using Value = tumble::detail::BoundsPartial;
  static constexpr bool kAnyGrouping = true;  // min and max: exact in any grouping
  TUMBLE_HD Value identity() const { return tumble::detail::emptyBounds(); }
  TUMBLE_HD void add(Value& b, std::uint32_t k) const {
    tumble::detail::addParticle(b, k, bodies[k].x.x, bodies[k].x.y, bodies[k].x.z, 1.0f);
  }
  TUMBLE_HD void merge(Value& left, const Value& right) const { tumble::detail::mergeBounds(left, right); }
};

struct MortonKeyFn {
  const BodyRow* bodies;
  MortonGrid g;
  std::uint32_t* keys;
  std::uint32_t* vals;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    keys[k] = mortonKey(g, bodies[k].x);
    vals[k] = k;
  }
};

// Element numBodies writes the trailing zero of the counts.
struct PermutedCountFn {
  const BodyRow* bodies;
  const std::uint32_t* perm;
  std::uint32_t numBodies;
  std::uint32_t* counts;
  TUMBLE_HD void operator()(std::uint32_t k) const { counts[k] = k < numBodies ? bodies[perm[k]].count : 0u; }
};

// The reordering's gathers (moveBody, kernels/contact_list.hpp), one body per element.
struct MoveBodiesFn {
  const BodyRow* bodies;
  const BodyStatic* bodyStatic;
  const std::uint32_t* perm;
  const std::uint32_t* first;
  std::uint32_t n, numPlanes;
  ReorderColumns from;
  BodyRow* outBodies;
  BodyStatic* outStatic;
  ReorderColumns to;
  TUMBLE_HD void operator()(std::uint32_t k) const {
    moveBody(bodies, bodyStatic, perm, first, k, n, numPlanes, from, outBodies, outStatic, to);
  }
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
