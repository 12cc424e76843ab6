// SPDX-License-Identifier: MIT
// The CPU pipeline's lists: the rebuild (reordering, detection, the candidate list and its
// periodic form), the near list's refresh and the skin test's reference, and the mesh rows.
#include "cpu_pipeline_impl.hpp"

namespace tumble::cpu::impl {

// A new candidate list: reorder, particle positions, detection on grown radii, rows sorted by
// scene index, build positions.
void CpuPipeline::rebuild() {
  double* sec = m_stats.seconds;
  const std::uint32_t n = m_world.numParticles();
  auto t0 = Clock::now();
  if (m_listBuilt && (m_history || m_hasMesh)) {  // by scene index: survives the renumbering
    if (m_history) keepHistory();
    if (m_hasMesh) keepMeshHistory();
    m_listBuilt = false;  // until the new lists hold them (a failed rebuild keeps the kept ones)
  }
  if (m_reorder) reorder();
  sec[int(Phase::Reorder)] += since(t0);

  t0 = Clock::now();
  computePositions();
  PosRow* pos = m_pos[m_cur].data();
  // Detection input: the positions and the radii grown by skin/2 (and a JKR neck's half,
  // neckReach(); with periodic boundaries by the rounding of a difference across them,
  // periodicGrowth()).
  const float h = 0.5f * (m_skin + m_neck) + m_periodicGrowth;
  float* bx = tumble::detail::grow(m_bx, n);
  float* by = tumble::detail::grow(m_by, n);
  float* bz = tumble::detail::grow(m_bz, n);
  float* br = tumble::detail::grow(m_br, n);
  forEach(n, kGrain, [&](std::uint32_t i) {
    detectionInput(pos, i, h, bx, by, bz, br);
    m_rebuildPos[i] = pos[i];
    if (!m_perBody) m_buildPos[i] = pos[i];
  });
  if (m_perBody) setBodyReference();
  sec[int(Phase::State)] += since(t0);

  const BroadphaseInput in{bx, by, bz, br, m_bodyOf.data(), n, m_world.maxRadius + h,
                           m_world.sizingRadius > 0.0f ? m_world.sizingRadius + h : 0.0f};
  try {
    if (m_periodic.axes != 0) {  // the sweep over the particles and their ghost images
      m_images.build(in, m_periodic, ghostReach(in.maxRadius, m_periodic));
      m_bp.run(m_images.input(), m_world.params.broadphase, sec);
    } else {
      m_bp.run(in, m_world.params.broadphase, sec);
    }
  } catch (const SimulationError& e) {
    if (e.particle() < 0) throw;
    const std::uint32_t o = m_orig[static_cast<std::uint32_t>(e.particle())];
    throw SimulationError(divergenceMessage(m_world, m_world.step + m_steps, o), o);
  }

  t0 = Clock::now();
  buildList();
  if (m_history) restoreHistory();
  if (m_hasMesh) {
    buildMeshList();
    restoreMeshHistory();
  }
  m_listBuilt = true;
  m_closed = 0.0;
  m_rebuildTime = m_time;
  if (m_nearSkin > 0.0f) {
    fillNearList();
  } else {
    m_owner.resize(m_cand.size());
    forEach(n, kGrain, [&](std::uint32_t i) { ownRow(m_candOffsets, i); });
  }
  sec[int(Phase::List)] += since(t0);
  m_needRebuild = false;
  m_needRefresh = false;
  ++m_stats.numRebuilds;
  m_stats.numCandidates = m_cand.size() / 2;
  m_stats.numRecords = m_bp.numRecords();
  m_stats.numCells = m_bp.numCells();
  m_stats.cellSize = m_bp.frame().cellSize;
}

// The near list from the candidate list at the current positions, which become the reference of
// the drift. What counts against the candidate list from here on: the smaller of the closures
// summed over the near list's intervals and the closure since the rebuild, measured now (the
// latter keeps a particle that moves to and fro from forcing rebuilds).
void CpuPipeline::refreshNear() {
  const auto t0 = Clock::now();
  const Drift sinceRebuild = m_periodic.axes != 0 ? driftSinceRebuild<true>() : driftSinceRebuild<false>();
  if (m_perBody) setBodyReference();
  m_closed = std::min(m_closed + double(m_lastClosure), double(closureFor(sinceRebuild)));
  fillNearList();
  m_needRefresh = false;
  ++m_stats.numNearRefreshes;
  m_stats.seconds[int(Phase::List)] += since(t0);
}

// The bodies where they are now become the reference of the skin test per body (bodyDrift()).
void CpuPipeline::setBodyReference() {
  forEach(static_cast<std::uint32_t>(m_bodies.size()), kGrain,
          [&](std::uint32_t k) { m_bodyRef[k] = BodyRef{m_bodies[k].x, m_bodies[k].q}; });
}

// The displacements of the particles since the rebuild (minimum images with periodic
// boundaries), measured one by one; with the skin test per particle, the positions now become
// its reference.
template <bool kPeriodic>
Drift CpuPipeline::driftSinceRebuild() {
  const std::uint32_t n = m_world.numParticles();
  const PosRow* pos = m_pos[m_cur].data();
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, n, kGrain), noDrift(),
      [&](const auto& rg, Drift d) {
        for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
          addParticleDisplacement<kPeriodic>(d, pos[i], m_rebuildPos[i], m_periodic);
          if (!m_perBody) m_buildPos[i] = pos[i];
        }
        return d;
      },
      [](Drift x, const Drift& y) {
        mergeDrift(x, y);  // min and max: exact in any order
        return x;
      });
}

// The near list, compact (its rows one after the other), with each entry's particle
// (StepView::listOwner) and, under a law with history, its candidate entry (historySlot; the
// entries left out forget their ξ, fillNear()): first at the candidate rows' offsets, then
// compacted.
void CpuPipeline::fillNearList() {
  const std::uint32_t n = m_world.numParticles();
  std::uint32_t* room = tumble::detail::grow(m_nearRoom, m_cand.size());
  std::uint32_t* slotRoom = m_history ? tumble::detail::grow(m_nearSlotRoom, m_cand.size()) : nullptr;
  Vec3f* hist = m_history ? m_hist.data() : nullptr;
  std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(n) + 1);
  const CandidateListView full = compactList(m_candOffsets.data(), m_cand.data());
  const PosRow* pos = m_pos[m_cur].data();
  if (m_periodic.axes != 0)
    forEach(n, kGrain, [&](std::uint32_t i) {
      count[i] = fillNear<true>(pos, full, m_nearSkin + m_neck, room, i, m_periodic, hist, slotRoom) - m_candOffsets[i];
    });
  else
    forEach(n, kGrain, [&](std::uint32_t i) {
      count[i] = fillNear(pos, full, m_nearSkin + m_neck, room, i, PeriodicBox{}, hist, slotRoom) - m_candOffsets[i];
    });
  count[n] = 0;
  m_nearOffsets.resize(std::size_t(n) + 1);
  scanCounts(count, std::size_t(n) + 1, m_nearOffsets.data());
  m_near.resize(m_nearOffsets[n]);
  m_owner.resize(m_nearOffsets[n]);
  m_nearSlot.resize(m_history ? m_nearOffsets[n] : 0);
  forEach(n, kGrain, [&](std::uint32_t i) {
    const std::uint32_t from = m_candOffsets[i], to = m_nearOffsets[i];
    std::copy(room + from, room + from + count[i], m_near.data() + to);
    if (slotRoom != nullptr) std::copy(slotRoom + from, slotRoom + from + count[i], m_nearSlot.data() + to);
    ownRow(m_nearOffsets, i);
  });
}

// The particle of each entry of the compact list at `offsets` (StepView::listOwner): row i's.
void CpuPipeline::ownRow(const std::vector<std::uint32_t>& offsets, std::uint32_t i) {
  std::fill(m_owner.data() + offsets[i], m_owner.data() + offsets[i + 1], i);
}

// The list the forces (and pairs()) iterate: the near list when there is one; under JKR with
// the entries' springs (CandidateListView::held), which say which pairs the force stage held.
CandidateListView CpuPipeline::contactListView() const {
  const bool near = m_nearSkin > 0.0f;
  CandidateListView l = near ? compactList(m_nearOffsets.data(), m_near.data())
                             : compactList(m_candOffsets.data(), m_cand.data());
  if (m_world.params.contact.cohesion == Cohesion::Jkr) {
    l.held = m_hist.data();
    l.heldSlot = near ? m_nearSlot.data() : nullptr;
  }
  return l;
}

// Stage 1: the particle positions of the current body state (after a reordering, and at load).
void CpuPipeline::computePositions() {
  PosRow* pos = m_pos[m_cur].data();
  forEach(static_cast<std::uint32_t>(m_bodies.size()), kBodyGrain, [&](std::uint32_t k) {
    if (m_clumps)
      bodyParticles<true>(m_bodies[k], m_own.data(), m_radius.data(), nullptr, pos, nullptr);
    else
      bodyParticles<false>(m_bodies[k], m_own.data(), m_radius.data(), nullptr, pos, nullptr);
  });
}

// The sweep's forward and backward lists → one row per particle, sorted by scene index.
void CpuPipeline::buildList() {
  const std::uint32_t n = m_world.numParticles();
  const SweepListView s{m_bp.recFirst.data(), m_bp.inv.data(),         m_bp.nbrOffsets.data(),
                        m_bp.nbr.data(),      m_bp.backOffsets.data(), m_bp.back.data()};
  if (m_periodic.axes != 0) {
    buildPeriodicList(s);
    return;
  }
  std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(n) + 1);
  forEach(n, kGrain, [&](std::uint32_t i) { count[i] = candidateCount(s, i); });
  count[n] = 0;
  scanCounts(count, std::size_t(n) + 1, m_candOffsets.data());
  const std::uint32_t total = m_candOffsets[n];
  m_cand.resize(total);  // keeps its capacity: no allocation once the size has settled
  std::uint32_t* key = tumble::detail::grow(m_candKey, total);
  forEach(n, kGrain, [&](std::uint32_t i) {
    fillCandidates(s, m_orig.data(), m_candOffsets.data(), m_cand.data(), key, i);
  });
}

// buildList() with periodic boundaries: each particle's row gathers what it and its ghosts
// found (fillPeriodicRow(), sorted by scene index, each partner once), first at room for
// every image's candidates, then compacted.
void CpuPipeline::buildPeriodicList(const SweepListView& s) {
  const std::uint32_t n = m_world.numParticles();
  std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(n) + 1);
  const PeriodicImagesView images = m_images.view();
  forEach(n, kGrain, [&](std::uint32_t i) { count[i] = periodicRowBound(s, images, i); });
  count[n] = 0;
  m_roomOffsets.resize(std::size_t(n) + 1);
  scanCounts(count, std::size_t(n) + 1, m_roomOffsets.data());
  const std::uint32_t room = m_roomOffsets[n];
  std::uint32_t* rows = tumble::detail::grow(m_roomCand, room);
  std::uint32_t* key = tumble::detail::grow(m_candKey, room);
  forEach(n, kGrain, [&](std::uint32_t i) {
    count[i] = fillPeriodicRow(s, images, m_orig.data(), i, rows + m_roomOffsets[i], key + m_roomOffsets[i]);
  });
  scanCounts(count, std::size_t(n) + 1, m_candOffsets.data());
  m_cand.resize(m_candOffsets[n]);
  forEach(n, kGrain, [&](std::uint32_t i) {
    std::copy(rows + m_roomOffsets[i], rows + m_roomOffsets[i] + count[i], m_cand.data() + m_candOffsets[i]);
  });
}

// findPairs() of a cloud in a periodic box: the sweep over its images on radii grown by the
// rounding margin of a difference across the boundary, then the exact predicate (the minimum
// image, as the oracle) on each particle's merged row.
std::vector<Pair> CpuPipeline::findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in, const BroadphaseParams& bp,
                                                 cpu::detail::Broadphase& b) {
  const std::uint32_t n = in.n;
  const PeriodicBox& box = cloud.periodic;
  const float g = periodicGrowth(in.maxRadius, box);
  std::vector<float> grown(n);
  for (std::uint32_t i = 0; i < n; ++i) grown[i] = cloud.r[i] + g;
  const BroadphaseInput gin{in.x, in.y, in.z, grown.data(), in.body, n, in.maxRadius + g,
                            in.cellRadius > 0.0f ? in.cellRadius + g : 0.0f};
  cpu::detail::PeriodicImages images;
  images.build(gin, box, ghostReach(gin.maxRadius, box));
  double sec[kNumPhases] = {};
  b.run(images.input(), bp, sec);
  const SweepListView s{b.recFirst.data(), b.inv.data(),         b.nbrOffsets.data(),
                        b.nbr.data(),      b.backOffsets.data(), b.back.data()};
  const PeriodicImagesView iv = images.view();
  std::vector<std::uint32_t> orig(n), roomOffsets(std::size_t(n) + 1, 0u);
  for (std::uint32_t i = 0; i < n; ++i) {
    orig[i] = i;
    roomOffsets[i + 1] = roomOffsets[i] + periodicRowBound(s, iv, i);
  }
  std::vector<std::uint32_t> rows(roomOffsets[n]), key(roomOffsets[n]), len(n);
  forEach(n, kGrain, [&](std::uint32_t i) {
    len[i] = fillPeriodicRow(s, iv, orig.data(), i, rows.data() + roomOffsets[i], key.data() + roomOffsets[i]);
  });
  std::vector<Pair> out;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t t = roomOffsets[i]; t < roomOffsets[i] + len[i]; ++t) {
      const std::uint32_t j = rows[t];
      if (j > i && spheresOverlap(box, cloud.x[i], cloud.y[i], cloud.z[i], cloud.r[i], cloud.x[j], cloud.y[j],
                                  cloud.z[j], cloud.r[j]))
        out.push_back(Pair{i, j});
    }
  return out;
}

// The mesh candidate list at the current positions (those of the rebuild): per particle the
// triangles whose grown box comes within r + skin/2 + margin (forTrianglesNear(); with moving
// meshes forPosedTrianglesNear(), each mesh where this step's pose puts it), sorted by
// triangle (so that the rows do not depend on the hierarchy), count → scan → fill. A particle
// that has moved less than skin/2 − margin since, relative to the mesh (the skin test with
// wallClosureOf() and the meshes' motion, MeshMotionBound), cannot touch a triangle outside
// its row.
void CpuPipeline::buildMeshList() { m_meshPoses.empty() ? buildMeshRows<false>() : buildMeshRows<true>(); }

template <bool kPosed>
void CpuPipeline::buildMeshRows() {
  const std::uint32_t n = m_world.numParticles();
  const MeshView mv = m_mesh.view(m_meshPoses);
  const PosRow* pos = m_pos[m_cur].data();
  const float grow = tumble::detail::meshRowGrowth(m_skin, m_world.maxRadius);
  const auto near = [&](std::uint32_t i, auto&& f) { forMeshRow<kPosed>(mv, pos[i], grow, f); };
  std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(n) + 1);
  forEach(n, kGrain, [&](std::uint32_t i) {
    std::uint32_t c = 0;
    near(i, [&](std::uint32_t) { ++c; });
    count[i] = c;
  });
  count[n] = 0;
  m_meshOffsets.resize(std::size_t(n) + 1);
  scanCounts(count, std::size_t(n) + 1, m_meshOffsets.data());
  m_meshTri.resize(m_meshOffsets[n]);
  forEach(n, kGrain, [&](std::uint32_t i) {
    std::uint32_t at = m_meshOffsets[i];
    near(i, [&](std::uint32_t t) { m_meshTri[at++] = t; });
    tumble::detail::sortRow(m_meshTri.data() + m_meshOffsets[i], nullptr, at - m_meshOffsets[i]);
  });
}

// out[k] = count[0] + … + count[k − 1] for k < len (the project's scan, scratch in m_temp):
// the offsets of every CSR list the pipeline builds.
void CpuPipeline::scanCounts(const std::uint32_t* count, std::size_t len, std::uint32_t* out) {
  std::size_t bytes = 0;
  exclusiveSum<std::uint32_t>(nullptr, bytes, count, out, len);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, bytes), bytes, count, out, len);
}

// Renumbers the bodies in Morton order of their centres; particles follow their bodies.
void CpuPipeline::reorder() {
  const std::uint32_t nb = static_cast<std::uint32_t>(m_bodies.size());
  if (nb < 2) return;
  // Bounding box of the finite body centres (min and max: exact in any order).
  tumble::detail::BoundsPartial box = tumble::detail::emptyBounds();
  for (std::uint32_t k = 0; k < nb; ++k)
    tumble::detail::addParticle(box, k, m_bodies[k].x.x, m_bodies[k].x.y, m_bodies[k].x.z, 1.0f);
  const MortonGrid g = tumble::detail::mortonGridOf(box);
  std::uint32_t* keys = tumble::detail::grow(m_mKeys, nb);
  std::uint32_t* vals = tumble::detail::grow(m_mVals, nb);
  std::uint32_t* skeys = tumble::detail::grow(m_mSortedKeys, nb);
  std::uint32_t* perm = tumble::detail::grow(m_perm, nb);
  forEach(nb, kGrain, [&](std::uint32_t k) {
    keys[k] = mortonKey(g, m_bodies[k].x);
    vals[k] = k;
  });
  std::size_t bytes = 0;
  radixSortPairs<std::uint32_t, std::uint32_t>(nullptr, bytes, keys, skeys, vals, perm, nb, 0, 30);
  radixSortPairs<std::uint32_t, std::uint32_t>(tumble::detail::grow(m_temp, bytes), bytes, keys, skeys, vals, perm,
                                               nb, 0, 30);
  // New first particles: a scan of the counts in the new order.
  std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(nb) + 1);
  std::uint32_t* first = tumble::detail::grow(m_first, std::size_t(nb) + 1);
  forEach(nb, kGrain, [&](std::uint32_t k) { count[k] = m_bodies[perm[k]].count; });
  count[nb] = 0;
  scanCounts(count, std::size_t(nb) + 1, first);
  const std::uint32_t n = m_world.numParticles();
  m_bodiesNext.resize(nb);  // scratch between steps
  m_bodyStaticTmp.resize(nb);
  m_ownTmp.resize(n);
  m_radiusTmp.resize(n);
  m_massTmp.resize(n);
  m_materialTmp.resize(m_material.size());
  m_origTmp.resize(n);
  m_bodyOfTmp.resize(n);
  m_gtxTmp.resize(m_gtx.size());
  m_gtyTmp.resize(m_gty.size());
  m_planeDampingTmp.resize(m_planeDamping.size());
  auto orNull = [](auto& v) { return v.empty() ? nullptr : v.data(); };
  const ReorderColumns from{m_own.data(),    m_radius.data(), m_mass.data(), orNull(m_material),
                            m_orig.data(),   m_bodyOf.data(), orNull(m_gtx), orNull(m_gty),
                            orNull(m_planeDamping)};
  const ReorderColumns to{m_ownTmp.data(),  m_radiusTmp.data(), m_massTmp.data(), orNull(m_materialTmp),
                          m_origTmp.data(), m_bodyOfTmp.data(), orNull(m_gtxTmp), orNull(m_gtyTmp),
                          orNull(m_planeDampingTmp)};
  const auto numPlanes = static_cast<std::uint32_t>(m_planes.size());
  forEach(nb, kBodyGrain, [&](std::uint32_t k) {
    moveBody(m_bodies.data(), m_bodyStatic.data(), perm, first, k, n, numPlanes, from, m_bodiesNext.data(),
             m_bodyStaticTmp.data(), to);
  });
  m_bodies.swap(m_bodiesNext);
  m_bodyStatic.swap(m_bodyStaticTmp);
  m_own.swap(m_ownTmp);
  m_radius.swap(m_radiusTmp);
  m_mass.swap(m_massTmp);
  m_material.swap(m_materialTmp);
  m_orig.swap(m_origTmp);
  m_bodyOf.swap(m_bodyOfTmp);
  m_gtx.swap(m_gtxTmp);
  m_gty.swap(m_gtyTmp);
  m_planeDamping.swap(m_planeDampingTmp);
}

}  // namespace tumble::cpu::impl
