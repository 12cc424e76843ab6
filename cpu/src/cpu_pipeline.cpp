// SPDX-License-Identifier: MIT
// The CPU reference pipeline (SPEC §2–§4) on oneTBB.
//
// Design notes
// - Contacts as state. Detection runs only at a rebuild of the candidate list (a Verlet list,
//   kernels/contact_list.hpp): on radii grown by skin/2, then turned into one row per particle
//   sorted by the partners' scene indices. Every step the exact predicate filters the rows, so
//   the contacts, and the order in which a particle sums them, are the same for any detection
//   setting, skin or thread count. A rebuild is due when two particles may have closed in by the
//   skin (less a rounding margin) since the last one; with skin 0, every step. Between rebuilds
//   the forces read the near list (a thinner skin, refreshed from the candidate list).
// - Locality. At each rebuild the bodies are renumbered in Morton order of their centres and
//   particles follow their bodies (a body's particles stay contiguous and in scene order), so a
//   row's candidates are near it in memory. Every output and every sum is by scene index, so
//   the numbering changes no bit; PipelineOptions::reorder turns it off (for tests).
// - One pass per step. For each body: its particles' forces (contacts, ground, gravity,
//   pulls), the body totals in particle order, the integration, the particles' rows of the
//   next state (double-buffered: the neighbours still read this step's rows) and the skin
//   test's displacement. The CUDA pipeline runs the same functions as separate kernels.
//   Under the report's law, without the debug capture, a body's contacts are found in one batch
//   (kernels/step.hpp bodyForces(): the body's rows of the compact list the forces read, the
//   near list or without one the candidate list, filtered with no branch per entry, then summed
//   in row order), the same operations as particleForce() in the same order.
// - Determinism: every output element has one writer and every floating-point sum runs in a
//   fixed order. The only reductions across bodies are a max and an integer count, exact in
//   any order. No float atomics, no parallel_reduce on floats that feed the state.
// - A scene pays only for what it uses: single-sphere scenes skip the rotations, torques and
//   couples (kClumps false); scenes without ground or walls skip the plane tests; pulls cost nothing
//   while off; scenes without periodic boundaries run no minimum image (kPeriodic false). Nothing
//   is allocated in a step once the sizes have settled.
// - Periodic boundaries (kernels/periodic.hpp): the step takes differences through the minimum
//   image and wraps the bodies' centres; the detection sweeps the particles and their ghost
//   images (kernels/periodic_images.hpp) and merges each particle's finds into its row, so the candidate
//   list is the same canonical list as without boundaries.
#include "tumble/cpu/cpu_pipeline.hpp"

#include "cpu_pipeline_impl.hpp"

namespace tumble::cpu {
namespace impl {

void CpuPipeline::load(const World& world) {
  if (world.numParticles() == 0) throw Error("cannot load an empty world");
  requirePeriodsFit(world);  // before any state changes
  m_world = localWorld(world, &m_frame);  // far from the origin: integrate in a local frame
  const World& w = m_world;
  const std::uint32_t n = w.numParticles(), nb = w.numBodies();
  m_clumps = w.hasClumps || w.params.contact.rotatesSpheres();  // the rotating path
  m_planes = kernelWalls(world.params, m_frame);  // from the world's points: as the guard sees them
  m_wallsMove = world.params.wallsMove();
  m_planeDamping = w.planeDamping;
  m_planeHertz = w.planeHertz;
  m_law = w.params.contact.law;
  m_history = w.params.contact.hasHistory();
  tumble::detail::initialRows(w, &m_bodies, &m_bodyStatic, &m_own);
  m_bodiesNext.resize(nb);
  m_radius = w.radius;
  m_mass = w.mass;
  // One material: every particle's is 0 and the kernels need no column.
  m_material = w.params.materials.size() > 1 ? w.material : std::vector<std::uint16_t>{};
  m_orig.resize(n);
  m_bodyOf = w.body;
  for (std::uint32_t i = 0; i < n; ++i) m_orig[i] = i;
  const BodyState& s = w.state;
  m_gtx = s.groundSpringX;  // localWorld sized them: planes × particles
  m_gty = s.groundSpringY;
  for (auto& c : m_pos) c.assign(n, PosRow{});
  // The skin test per body where bodies hold two particles or more on average (clumps: one
  // bound for all of a body's particles is cheaper than measuring each); per particle else.
  m_perBody = m_clumps && n >= 2 * nb;  // only the rotating pass (kClumps) measures bodies
  m_bodyRef.assign(m_perBody ? nb : 0, BodyRef{});
  m_buildPos.assign(m_perBody ? 0 : n, PosRow{});
  m_rebuildPos.assign(n, PosRow{});
  m_touching.assign(n, 0);
  m_candOffsets.assign(std::size_t(n) + 1, 0u);
  m_cur = 0;
  m_skin = effectiveSkin(w);
  m_neck = neckReach(w);
  m_periodic = kernelPeriodic(w.params, m_frame);
  const double periodicReach = periodicRoundingReach(m_periodic);
  m_periodicGrowth = m_periodic.axes != 0 ? periodicGrowth(w.maxRadius + 0.5f * (m_skin + m_neck), m_periodic) : 0.0f;
  m_fullLimit = skinClosureLimit(m_skin, w.maxRadius, periodicReach);
  m_nearSkin = kNearSkinFraction * m_skin;
  m_nearLimit = skinClosureLimit(m_nearSkin, w.maxRadius, periodicReach);
  // Too thin to help: the forces read the candidate list. (Under a law with history the near
  // list's entries find their ξ beside the candidate list, StepView::historySlot.)
  if (!(m_nearLimit > 0.0f)) m_nearSkin = 0.0f;
  m_listBuilt = false;
  if (m_history) keepLoadedHistory(s.contacts);
  m_mesh = kernelMesh(world.params, m_frame);  // from the world's scene and the run's frame, as the guard's
  m_hasMesh = m_mesh.numTriangles() > 0;
  // Moving meshes: their poses at each step's start (setWallMotion()), and their motion in the
  // skin test (MeshMotionBound).
  m_meshMotion = MeshMotionBound(w.params, m_mesh, m_planes, w.maxRadius, m_skin);
  m_meshPoses.assign(m_meshMotion.any() ? m_planes.size() : 0, MeshPose{});
  m_meshOffsets.assign(std::size_t(n) + 1, 0u);
  m_meshTri.clear();
  m_meshHist.clear();
  keepLoadedMeshHistory(s.meshContacts);
  m_closed = 0.0;
  m_needRefresh = false;
  m_needRebuild = true;
  m_pulls = w.params.pulls.active & ~w.params.periodic.conflictingPulls();
  m_time = w.time;
  m_steps = 0;
  m_bp = cpu::detail::Broadphase{};
  m_arena.execute([&] { computePositions(); });  // readLocalPositions() before the first step
  resetStats();
  m_hasDebug = false;
  m_hasFlows = false;
}

void CpuPipeline::step(std::uint64_t n) {
  if (m_bodies.empty()) throw Error("step() before load()");
  m_arena.execute([&] {
    for (std::uint64_t s = 0; s < n; ++s) stepOnce();
  });
}

void CpuPipeline::readState(BodyState& out) const {
  readLocalState(out);
  toWorld(out, m_frame);
}

void CpuPipeline::readLocalState(BodyState& out) const {
  const std::uint32_t nb = static_cast<std::uint32_t>(m_bodies.size());
  out.resize(nb);
  const std::size_t ng = m_gtx.size();
  out.groundSpringX.resize(ng);
  out.groundSpringY.resize(ng);
  out.imageX.resize(m_periodic.on(0) ? nb : 0);
  out.imageY.resize(m_periodic.on(1) ? nb : 0);
  m_arena.execute([&] {
    forEach(nb, kGrain, [&](std::uint32_t k) {
      const BodyRow& b = m_bodies[k];
      const std::uint32_t o = b.orig;
      out.px[o] = b.x.x; out.py[o] = b.x.y; out.pz[o] = b.x.z;
      out.vx[o] = b.v.x; out.vy[o] = b.v.y; out.vz[o] = b.v.z;
      out.qw[o] = b.q.w; out.qx[o] = b.q.x; out.qy[o] = b.q.y; out.qz[o] = b.q.z;
      out.lx[o] = b.l.x; out.ly[o] = b.l.y; out.lz[o] = b.l.z;
      if (m_periodic.on(0)) out.imageX[o] = b.image[0];
      if (m_periodic.on(1)) out.imageY[o] = b.image[1];
    });
    const std::size_t n = m_orig.size();
    forEach(static_cast<std::uint32_t>(ng), kGrain, [&](std::uint32_t s) {
      const std::size_t o = (s / n) * n + m_orig[s % n];  // plane-major
      out.groundSpringX[o] = m_gtx[s];
      out.groundSpringY[o] = m_gty[s];
    });
  });
  readHistory(out.contacts);
  readMeshHistory(out.meshContacts);
}

void CpuPipeline::readLocalPositions(std::vector<float>& out) const {
  const std::uint32_t n = m_world.numParticles();
  out.resize(3 * std::size_t(n));
  const PosRow* pos = m_pos[m_cur].data();
  m_arena.execute([&] {
    forEach(n, kGrain, [&](std::uint32_t i) {
      const std::size_t o = 3 * std::size_t(m_orig[i]);
      out[o] = pos[i].x; out[o + 1] = pos[i].y; out[o + 2] = pos[i].z;
    });
  });
}

std::vector<Pair> CpuPipeline::pairs() const {
  if (m_steps == 0) return {};
  const std::uint32_t n = m_world.numParticles();
  const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
  const std::uint32_t* orig = m_orig.data();
  const CandidateListView list = contactListView();
  // One pass of the exact test over fixed chunks of particles, each appending its pairs
  // (scene indices, ascending j within a particle's row) to its own buffers; the buffers are
  // joined in chunk order and sorted by i with a stable radix sort, which gives (i, j) order.
  // Scratch kept between calls (the guards call this every few steps).
  const std::uint32_t numChunks = (n + kGrain - 1) / kGrain;
  if (m_pairChunks.size() < numChunks) m_pairChunks.resize(numChunks);
  std::vector<Pair> out;
  m_arena.execute([&] {
    tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
      PairChunk& buf = m_pairChunks[c];
      const std::uint32_t begin = c * kGrain, end = std::min(n, (c + 1) * kGrain);
      // Room: the contacts each particle had in the last step (the same list and positions),
      // its whole row where that count was capped.
      std::size_t room = 0;
      for (std::uint32_t p = begin; p < end; ++p)
        room += m_touching[p] < 255 ? m_touching[p] : list.end[p] - list.begin[p];
      buf.i.resize(room);
      buf.j.resize(room);
      std::uint32_t k = 0;
      for (std::uint32_t p = begin; p < end; ++p) {
        if (m_touching[p] == 0) continue;  // the last step saw it touch nothing
        k += emitContactsAbove(pos, orig, list, p, k, buf.i.data(), buf.j.data(), m_periodic);
      }
      buf.i.resize(k);
      buf.j.resize(k);
    });
    std::vector<std::size_t> start(numChunks + 1, 0);
    for (std::uint32_t c = 0; c < numChunks; ++c) start[c + 1] = start[c] + m_pairChunks[c].i.size();
    const std::size_t total = start[numChunks];
    std::uint32_t* keys = tumble::detail::grow(m_pairI, total);
    std::uint32_t* vals = tumble::detail::grow(m_pairJ, total);
    tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
      std::copy(m_pairChunks[c].i.begin(), m_pairChunks[c].i.end(), keys + start[c]);
      std::copy(m_pairChunks[c].j.begin(), m_pairChunks[c].j.end(), vals + start[c]);
    });
    std::uint32_t* skeys = tumble::detail::grow(m_pairSortedI, total);
    std::uint32_t* svals = tumble::detail::grow(m_pairSortedJ, total);
    const int bits = std::max(1, static_cast<int>(std::bit_width(n - 1)));
    std::size_t bytes = 0;
    radixSortPairs<std::uint32_t, std::uint32_t>(nullptr, bytes, keys, skeys, vals, svals, total, 0, bits);
    radixSortPairs<std::uint32_t, std::uint32_t>(tumble::detail::grow(m_pairTemp, bytes), bytes, keys, skeys, vals,
                                                 svals, total, 0, bits);
    out.resize(total);
    for (std::size_t k = 0; k < total; ++k) out[k] = Pair{skeys[k], svals[k]};
  });
  return out;
}

std::vector<MeshContact> CpuPipeline::meshContacts() const {
  if (m_steps == 0 || !m_hasMesh) return {};
  const std::uint32_t n = m_world.numParticles();
  const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used, with its mesh rows
  const MeshView mv = m_mesh.view(m_meshPoses);  // and its poses
  const auto forHits = [&](std::uint32_t i, auto&& f) {
    forMeshHits(mv, m_meshOffsets.data(), m_meshTri.data(), pos[i], i, f);
  };
  std::vector<std::uint32_t> start(std::size_t(n) + 1, 0u);
  m_arena.execute([&] {
    forEach(n, kGrain, [&](std::uint32_t i) {
      std::uint32_t c = 0;
      forHits(i, [&](std::uint32_t) { ++c; });
      start[m_orig[i] + 1] = c;
    });
  });
  for (std::uint32_t o = 0; o < n; ++o) start[o + 1] += start[o];
  std::vector<MeshContact> out(start[n]);
  m_arena.execute([&] {
    forEach(n, kGrain, [&](std::uint32_t i) {
      std::uint32_t at = start[m_orig[i]];
      forHits(i, [&](std::uint32_t t) { out[at++] = MeshContact{m_orig[i], t}; });
    });
  });
  return out;
}

// The pairs() set walked where it lies: per body, its particles' rows (the contacts of the
// last step, decided on that step's positions as pairs() does), the terms at the current
// positions; one write per body, at its scene index.
bool CpuPipeline::contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const {
  const std::uint32_t nb = static_cast<std::uint32_t>(m_bodies.size());
  if (m_steps == 0) {  // no contacts yet, as pairs()
    out.assign(nb, ContactSums{});
    return true;
  }
  out.resize(nb);
  const PosRow* was = m_pos[1 - m_cur].data();  // the rows the last step used
  const PosRow* now = m_pos[m_cur].data();
  const std::uint32_t* orig = m_orig.data();
  const CandidateListView list = contactListView();
  m_arena.execute([&] {
    forEach(nb, kBodyGrain, [&](std::uint32_t b) {
      out[m_bodies[b].orig] = bodyContactSums(m_bodies.data(), m_bodyOf.data(), m_touching.data(), was, now, orig,
                                              list, law, m_periodic, b);
    });
  });
  return true;
}

std::vector<Pair> CpuPipeline::findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) {
  const float maxR = checkCloud(cloud);
  const std::size_t n = cloud.size();
  cpu::detail::Broadphase b;
  double sec[kNumPhases] = {};
  const BroadphaseInput in{cloud.x.data(), cloud.y.data(),    cloud.z.data(),
                           cloud.r.data(), cloud.body.data(), static_cast<std::uint32_t>(n),
                           maxR,           tumble::detail::sizingRadius(cloud.r.data(), n)};
  std::vector<Pair> out;
  m_arena.execute([&] {
    if (cloud.periodic.axes != 0) {
      out = findPeriodicPairs(cloud, in, bp, b);
      return;
    }
    b.run(in, bp, sec);
    out = b.sortedPairs(static_cast<std::uint32_t>(n));
  });
  return out;
}

void CpuPipeline::readDebug(ParticleDebug& out) const {
  if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
  const std::uint32_t n = m_world.numParticles();
  out.v.resize(3 * std::size_t(n));
  for (auto& f : out.force) f.resize(3 * std::size_t(n));
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t o = 3 * std::size_t(m_orig[i]), s = 3 * std::size_t(i);
    for (int c = 0; c < 3; ++c) out.v[o + c] = m_dbgVel[s + c];
    for (int k = 0; k < 5; ++k)
      for (int c = 0; c < 3; ++c) out.force[k][o + c] = m_dbg[k][s + c];
  }
  out.contacts = pairs();
  out.contactForces = capturedContacts(m_dbgContact.data(), contactListView().begin[n]);
}

void CpuPipeline::resetStats() {
  m_stats = StepStats{};
  m_stats.skin = m_skin;
  m_tally.clear();
}

// The hooks of a domain decomposition (HaloPipeline; tumble::mpi).
void CpuPipeline::readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const {
  const std::vector<std::uint32_t>& at = internalBodies();
  out.resize(bodies.size());
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    out[k] = motionOf(m_bodies[at[bodies[k]]]);
  }
}

void CpuPipeline::writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) {
  const std::vector<std::uint32_t>& at = internalBodies();
  PosRow* pos = m_pos[m_cur].data();
  m_arena.execute([&] {
    forEach(static_cast<std::uint32_t>(bodies.size()), kBodyGrain, [&](std::uint32_t k) {
      BodyRow& b = m_bodies[at[bodies[k]]];
      setMotion(b, motion[k]);
      if (m_clumps)
        bodyParticles<true>(b, m_own.data(), m_radius.data(), nullptr, pos, nullptr);
      else
        bodyParticles<false>(b, m_own.data(), m_radius.data(), nullptr, pos, nullptr);
    });
  });
  if (m_steps == 0) return;  // the first step rebuilds anyway
  // The skin test of the step just taken, again, on the positions as they are now: per body
  // against bodyRef (bodyDrift()), or per particle against buildPos.
  const std::uint32_t n = m_perBody ? static_cast<std::uint32_t>(m_bodies.size()) : m_world.numParticles();
  const StepView view = stepView();
  const Drift d = m_arena.execute([&] {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::uint32_t>(0, n, kGrain), noDrift(),
        [&](const auto& rg, Drift acc) {
          for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
            if (m_perBody) {
              if (m_periodic.axes != 0)
                bodyDrift<true>(view, m_bodies[i], m_bodyStatic[i].reach, m_bodyRef[i], &acc);
              else
                bodyDrift<false>(view, m_bodies[i], m_bodyStatic[i].reach, m_bodyRef[i], &acc);
              continue;
            }
            if (m_periodic.axes != 0)
              addParticleDisplacement<true>(acc, pos[i], m_buildPos[i], m_periodic);
            else
              addParticleDisplacement<false>(acc, pos[i], m_buildPos[i], m_periodic);
          }
          return acc;
        },
        [](Drift x, const Drift& y) {
          mergeDrift(x, y);  // min and max: exact in any order
          return x;
        });
  });
  decideList(d, m_time);  // the step just taken has advanced m_time
}

std::uint64_t CpuPipeline::contactsOf(const std::vector<std::uint32_t>& bodies) const {
  if (m_steps == 0) return 0;
  const std::vector<std::uint32_t>& at = internalBodies();
  const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
  const CandidateListView list = contactListView();
  std::uint64_t total = 0;
  for (const std::uint32_t body : bodies)
    total += bodyContactCount(m_bodies[at[body]], m_touching.data(), pos, list, m_periodic);
  return total;
}

EnergyLimbs CpuPipeline::energyOf(const std::vector<std::uint32_t>& bodies) const {
  EnergyLimbs l = noLimbs();
  if (!m_hasFlows) return l;
  const std::vector<std::uint32_t>& at = internalBodies();
  for (const std::uint32_t body : bodies) addEnergy(l, m_bodyFlows[at[body]], m_world.params.dt);
  return l;
}

// Scene index → internal index of every body (the hooks' names for bodies).
const std::vector<std::uint32_t>& CpuPipeline::internalBodies() const {
  m_internal.resize(m_bodies.size());
  for (std::uint32_t k = 0; k < m_bodies.size(); ++k) m_internal[m_bodies[k].orig] = k;
  return m_internal;
}

}  // namespace impl

using impl::CpuPipeline;

std::unique_ptr<Pipeline> makeCpuPipeline(const PipelineOptions& options) {
  return std::make_unique<CpuPipeline>(options);
}

std::unique_ptr<HaloPipeline> makeCpuHaloPipeline(const PipelineOptions& options) {
  return std::make_unique<CpuPipeline>(options);
}

}  // namespace tumble::cpu
