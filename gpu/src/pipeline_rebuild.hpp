// SPDX-License-Identifier: MIT
// The CUDA pipeline's rebuild (CudaPipeline's members, pipeline_class.hpp, out of line), as
// CpuPipeline's (cpu/src/cpu_pipeline_lists.cpp, cpu/src/cpu_pipeline_history.cpp): the
// detection and the candidate list, the mesh candidate list, the reordering in Morton order, and
// the contact histories kept by scene index across the rebuild, restored after it and read out
// (readLocalState()). The functors: pipeline_list_fns.hpp, pipeline_reorder_fns.hpp.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "pipeline_class.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// As CpuPipeline::rebuild.
template <class Exec>
void CudaPipeline<Exec>::rebuild() {
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  m_timer.mark(Phase::Reorder, s);
  if (m_listBuilt && (m_history || hasMesh())) {  // by scene index: survives the renumbering
    if (m_history) keepHistory();
    if (hasMesh()) keepMeshHistory();
    m_listBuilt = false;  // until the new lists hold them (a failed rebuild keeps the kept ones)
  }
  if (m_reorder) reorder();

  m_timer.mark(Phase::State, s);
  m_clumps ? launchState<true>() : launchState<false>();
  // Detection input: the positions and the radii grown by skin/2 (and a JKR neck's half,
  // neckReach(); with periodic boundaries by the rounding of a difference across them,
  // periodicGrowth()).
  const float h = 0.5f * (m_skin + m_neck) + m_periodicGrowth;
  Exec::forEach(s, n,
                DetectionInputFn{m_pos[m_cur].data(), h, m_bx.grow(n), m_by.grow(n), m_bz.grow(n), m_br.grow(n),
                                 m_buildPos.data()},
                "detectionInput");

  const BroadphaseInput in{m_bx.data(), m_by.data(), m_bz.data(), m_br.data(), m_bodyOf.data(), n,
                           m_world.maxRadius + h,
                           m_world.sizingRadius > 0.0f ? m_world.sizingRadius + h : 0.0f};
  try {
    if (m_periodic.axes != 0) {  // the sweep over the particles and their ghost images
      m_images.build(in, m_periodic, ghostReach(in.maxRadius, m_periodic), s);
      m_bp.run(m_images.input(), m_world.params.broadphase, s, &m_timer);
    } else {
      m_bp.run(in, m_world.params.broadphase, s, &m_timer);
    }
  } catch (const SimulationError& e) {
    if (e.particle() < 0) throw;
    std::uint32_t o = 0;
    Exec::copyToHost(s, &o, m_orig.data() + e.particle(), 1);
    s.synchronize();
    throw SimulationError(divergenceMessage(m_world, m_world.step + m_steps, o), o);
  }

  m_timer.mark(Phase::List, s);
  const SweepListView sl = m_bp.listView();
  if (m_periodic.axes != 0) {
    m_numCand = m_images.rows(sl, m_orig.data(), m_candOffsets, m_cand, m_candKey, s);
  } else {
    std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
    Exec::forEach(s, std::uint64_t(n) + 1, CandidateCountFn{sl, n, count}, "candidateCount");
    Exec::exclusiveSum(s, m_temp, count, m_candOffsets.data(), n + 1);
    Exec::copyToHost(s, &m_numCand, m_candOffsets.data() + n, 1);
    s.synchronize();
    Exec::forEach(s, n,
                  CandidateFillFn{sl, m_orig.data(), m_candOffsets.data(), m_cand.grow(m_numCand),
                                  m_candKey.grow(m_numCand)},
                  "candidateFill");
  }
  if (m_history) restoreHistory();
  if (hasMesh()) {
    m_numPoses == 0 ? buildMeshList<false>() : buildMeshList<true>();
    restoreMeshHistory();
  }
  m_listBuilt = true;
  m_rebuildTime = m_time;
  m_needRebuild = false;
  ++m_stats.numRebuilds;
  m_stats.numCandidates = m_numCand / 2;
  m_stats.numRecords = m_bp.numRecords();
  m_stats.numCells = m_bp.numCells();
  m_stats.cellSize = m_bp.frame().cellSize;
}

// As CpuPipeline::buildMeshList: the mesh candidate list at the rebuild's positions.
template <class Exec>
template <bool kPosed>
void CudaPipeline<Exec>::buildMeshList() {
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  const MeshView mv = meshView();
  const PosRow* pos = m_pos[m_cur].data();
  const float grow = tumble::detail::meshRowGrowth(m_skin, m_world.maxRadius);
  std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
  const MeshRowVisit<kPosed> rows{mv, pos, grow};
  Exec::forEach(s, std::uint64_t(n) + 1, VisitCountFn<MeshRowVisit<kPosed>>{rows, n, count}, "meshRowCount");
  Exec::exclusiveSum(s, m_temp, count, m_meshOffsets.data(), n + 1);
  Exec::copyToHost(s, &m_numMeshCand, m_meshOffsets.data() + n, 1);
  s.synchronize();
  Exec::forEach(s, n, MeshRowFillFn<kPosed>{rows, m_meshOffsets.data(), m_meshTri.grow(m_numMeshCand)}, "meshRowFill");
}

// As CpuPipeline::reorder.
template <class Exec>
void CudaPipeline<Exec>::reorder() {
  const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
  if (nb < 2) return;
  const Stream& s = m_ctx;
  const std::uint32_t numChunks = (nb + exec::kBlock - 1) / exec::kBlock;
  Exec::reduceChunks(s, nb, exec::kBlock, BodyBoundsOp{m_bodies.data()}, m_boundsPart.grow(numChunks), "bodyBounds");
  m_hostBounds.resize(numChunks);
  m_boundsPart.download(m_hostBounds.data(), numChunks, s);
  s.synchronize();
  const MortonGrid g = tumble::detail::mortonGridOf(tumble::detail::combineBounds(m_hostBounds.data(), numChunks));
  std::uint32_t* keys = m_mKeys.grow(nb);
  std::uint32_t* vals = m_mVals.grow(nb);
  std::uint32_t* skeys = m_mSortedKeys.grow(nb);
  std::uint32_t* perm = m_perm.grow(nb);
  Exec::forEach(s, nb, MortonKeyFn{m_bodies.data(), g, keys, vals}, "mortonKey");
  Exec::radixSortPairs(s, m_temp, keys, skeys, vals, perm, nb, 0, 30);
  std::uint32_t* count = m_count.grow(std::size_t(nb) + 1);
  std::uint32_t* first = m_first.grow(std::size_t(nb) + 1);
  Exec::forEach(s, std::uint64_t(nb) + 1, PermutedCountFn{m_bodies.data(), perm, nb, count}, "permutedCount");
  Exec::exclusiveSum(s, m_temp, count, first, nb + 1);
  const bool springs = m_numSprings > 0, damping = m_numPlanes > 1;
  const ReorderColumns from{m_own.data(),  m_radius.data(), m_mass.data(),
                            m_hasMaterial ? m_material.data() : nullptr,
                            m_orig.data(), m_bodyOf.data(), springs ? m_tx.data() : nullptr,
                            springs ? m_ty.data() : nullptr, damping ? m_planeDamping.data() : nullptr};
  const ReorderColumns to{m_ownTmp.grow(n),  m_radiusTmp.grow(n), m_massTmp.grow(n),
                          m_hasMaterial ? m_materialTmp.grow(n) : nullptr, m_origTmp.grow(n),
                          m_bodyOfTmp.grow(n), springs ? m_txTmp.grow(m_numSprings) : nullptr,
                          springs ? m_tyTmp.grow(m_numSprings) : nullptr,
                          damping ? m_planeDampingTmp.grow(std::size_t(m_numPlanes - 1) * n) : nullptr};
  Exec::forEach(s, nb,
                MoveBodiesFn{m_bodies.data(), m_bodyStatic.data(), perm, first, n, m_numPlanes, from,
                             m_bodiesNext.data(), m_bodyStaticTmp.grow(nb), to},
                "moveBodies");
  std::swap(m_bodies, m_bodiesNext);
  std::swap(m_bodyStatic, m_bodyStaticTmp);
  std::swap(m_own, m_ownTmp);
  std::swap(m_radius, m_radiusTmp);
  std::swap(m_mass, m_massTmp);
  std::swap(m_orig, m_origTmp);
  std::swap(m_bodyOf, m_bodyOfTmp);
  if (m_hasMaterial) std::swap(m_material, m_materialTmp);
  if (springs) {
    std::swap(m_tx, m_txTmp);
    std::swap(m_ty, m_tyTmp);
  }
  if (damping) std::swap(m_planeDamping, m_planeDampingTmp);
}

// The non-zero ξ of the rows that `rows.take` accepts (kernels/history.hpp), by scene index
// with their keys: count → scan → fill into out (offsets of n + 1). Returns their number.
template <class Exec>
template <class KeyOf, class Take>
std::uint32_t CudaPipeline<Exec>::takeRows(const ListRows<KeyOf, Take>& rows, Buffer<std::uint32_t>& count,
                                          Buffer<unsigned char>& temp, KeptBuffers& out) const {
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  std::uint32_t* at = out.offsets.grow(std::size_t(n) + 1);
  Exec::forEach(s, std::uint64_t(n) + 1, TakenCountFn<KeyOf, Take>{rows, n, count.grow(std::size_t(n) + 1)},
                "takenCount");
  Exec::exclusiveSum(s, temp, count.data(), at, n + 1);
  std::uint32_t total = 0;
  Exec::copyToHost(s, &total, at + n, 1);
  s.synchronize();
  Exec::forEach(s, n, TakeRowFn<KeyOf, Take>{rows, at, out.key.grow(total), out.hist.grow(total)}, "takeRow");
  return total;
}

// As CpuPipeline::keepHistory/keepMeshHistory: every non-zero ξ of a list, kept for the rebuild.
template <class Exec>
void CudaPipeline<Exec>::keepHistory() {
  takeRows(partnerRows(TakeAll{}), m_count, m_temp, m_kept);
}

template <class Exec>
void CudaPipeline<Exec>::keepMeshHistory() {
  takeRows(meshRows(), m_count, m_temp, m_meshKept);
}

// As CpuPipeline::restoreHistory/restoreMeshHistory: each row of the new list takes its kept ξ.
template <class Exec>
template <class KeyOf>
void CudaPipeline<Exec>::restoreRows(const KeptBuffers& kept, const std::uint32_t* offsets, KeyOf keyOf,
                                     Vec3f* hist) {
  Exec::forEach(m_ctx, m_world.numParticles(), RestoreRowFn<KeyOf>{kept.view(), m_orig.data(), offsets, keyOf, hist},
                "restoreRow");
}

template <class Exec>
void CudaPipeline<Exec>::restoreHistory() {
  restoreRows(m_kept, m_candOffsets.data(), PartnerKey{m_orig.data(), m_cand.data()}, m_hist.grow(m_numCand));
}

template <class Exec>
void CudaPipeline<Exec>::restoreMeshHistory() {
  restoreRows(m_meshKept, m_meshOffsets.data(), TriangleKey{m_meshTri.data()}, m_meshHist.grow(m_numMeshCand));
}

// As CpuPipeline::readRows: the entries of `rows` with a non-zero ξ that rows.take accepts,
// as make(scene index, key, ξ), sorted by (scene index, key); taken out of the list's rows
// (count → scan → fill by scene index), or before the first rebuild from the kept ones.
template <class Exec>
template <class Out, class KeyOf, class Take, class Make>
std::vector<Out> CudaPipeline<Exec>::readRows(const KeptBuffers& kept, const ListRows<KeyOf, Take>& rows,
                                              const Make& make) const {
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  std::vector<std::uint32_t> at(std::size_t(n) + 1);
  std::vector<std::uint32_t> key;
  std::vector<Vec3f> hist;
  const KeptBuffers* from = &kept;
  if (m_listBuilt) {
    takeRows(rows, m_read.count, m_read.temp, m_read.out);
    from = &m_read.out;
  }
  from->offsets.download(at.data(), at.size(), s);
  s.synchronize();
  key.resize(at[n]);
  hist.resize(at[n]);
  from->key.download(key.data(), key.size(), s);
  from->hist.download(hist.data(), hist.size(), s);
  s.synchronize();
  return tumble::detail::readRows<Out>(n, at.data(), key.data(), hist.data(), rows.take, make);
}

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
