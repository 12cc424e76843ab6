// SPDX-License-Identifier: MIT
// The CUDA pipeline's functors of a rebuild's lists (CudaPipeline::rebuild(), pipeline_rebuild.hpp):
// the detection input, the candidate rows (count → scan → fill, kernels/contact_list.hpp), the
// mesh candidate rows (kernels/mesh.hpp), and the contact histories kept by scene index across
// the rebuild and restored into the new rows (kernels/history.hpp). Internal to tumble::gpu.
#pragma once
#include <cstdint>

#include "exec/exec.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/mesh.hpp"
#include "tumble/math.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// The detection's input columns (radii grown by skin/2) and the build positions.
struct DetectionInputFn {
  const PosRow* pos;
  float halfSkin;
  float *x, *y, *z, *r;
  PosRow* buildPos;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    detectionInput(pos, i, halfSkin, x, y, z, r);
    buildPos[i] = pos[i];
  }
};

// Element n writes the trailing zero of the counts.
struct CandidateCountFn {
  SweepListView s;
  std::uint32_t n;
  std::uint32_t* counts;
  TUMBLE_HD void operator()(std::uint32_t i) const { counts[i] = i < n ? candidateCount(s, i) : 0u; }
};

struct CandidateFillFn {
  SweepListView s;
  const std::uint32_t* orig;
  const std::uint32_t* offsets;
  std::uint32_t* cand;
  std::uint32_t* key;
  TUMBLE_HD void operator()(std::uint32_t i) const { fillCandidates(s, orig, offsets, cand, key, i); }
};

// count[visit.slot(i)] = the number of elements visit(i, f) reports (the count of a count →
// scan → fill); element n writes the trailing zero of the counts.
template <class Visit>
struct VisitCountFn {
  Visit visit;
  std::uint32_t n;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i == n) {
      count[n] = 0;
      return;
    }
    std::uint32_t c = 0;
    visit(i, [&](std::uint32_t) { ++c; });
    count[visit.slot(i)] = c;
  }
};

// The mesh candidate list (forMeshRow(), kernels/mesh.hpp) at a rebuild: count → scan → fill,
// each row sorted by triangle.
template <bool kPosed>
struct MeshRowVisit {
  MeshView mesh;
  const PosRow* pos;
  float grow;
  TUMBLE_HD std::uint32_t slot(std::uint32_t i) const { return i; }
  template <class F>
  TUMBLE_HD void operator()(std::uint32_t i, F&& f) const {
    forMeshRow<kPosed>(mesh, pos[i], grow, f);
  }
};

template <bool kPosed>
struct MeshRowFillFn {
  MeshRowVisit<kPosed> visit;
  const std::uint32_t* offsets;
  std::uint32_t* tri;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    std::uint32_t at = offsets[i];
    visit(i, [&](std::uint32_t t) { tri[at++] = t; });
    tumble::detail::sortRow(tri + offsets[i], nullptr, at - offsets[i]);
  }
};

// The histories across a rebuild (kernels/history.hpp), by scene index: kept from the rows of
// the old list (count → scan → fill: CudaPipeline::takeRows), restored into the rows of the new
// one; the same count → scan → fill reads them out (readLocalState()).
template <class KeyOf, class Take>
struct ListRows {
  const std::uint32_t* offsets;
  const Vec3f* hist;
  KeyOf keyOf;
  Take take;
  const std::uint32_t* orig;
};

// Element n writes the trailing zero of the counts.
template <class KeyOf, class Take>
struct TakenCountFn {
  ListRows<KeyOf, Take> r;
  std::uint32_t n;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    if (i == n) count[n] = 0;
    else count[r.orig[i]] = takenCount(r.offsets, r.hist, r.keyOf, r.take, i, r.orig[i]);
  }
};

template <class KeyOf, class Take>
struct TakeRowFn {
  ListRows<KeyOf, Take> r;
  const std::uint32_t* at;
  std::uint32_t* outKey;
  Vec3f* outHist;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    takeRow(r.offsets, r.hist, r.keyOf, r.take, i, r.orig[i], at[r.orig[i]], outKey, outHist);
  }
};

template <class KeyOf>
struct RestoreRowFn {
  KeptView kept;
  const std::uint32_t* orig;
  const std::uint32_t* offsets;
  KeyOf keyOf;
  Vec3f* hist;
  TUMBLE_HD void operator()(std::uint32_t i) const { restoreRow(kept, orig[i], offsets, keyOf, i, hist); }
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
