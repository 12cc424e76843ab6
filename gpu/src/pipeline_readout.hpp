// SPDX-License-Identifier: MIT
// The CUDA pipeline's read-outs (CudaPipeline's members, pipeline_class.hpp, out of line), as
// CpuPipeline's (cpu/src/cpu_pipeline.cpp): the state, the positions, the contacts and the mesh
// contacts, the guard's contact sums and the debug capture; the hooks of a domain decomposition
// (HaloPipeline: readMotion(), writeMotion(), contactsOf()); and findPairs(), the detection on
// its own, with its periodic form. The functors: pipeline_readout_fns.hpp.
#pragma once
#include <cstdint>
#include <vector>

#include "pipeline_class.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

template <class Exec>
void CudaPipeline<Exec>::readLocalState(BodyState& out) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  if (!m_loaded) {
    out = BodyState{};  // as the CPU pipeline's empty state before load()
    return;
  }
  const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
  const Stream& s = m_ctx;
  std::vector<BodyRow> bodies(nb);
  std::vector<std::uint32_t> orig(n);
  std::vector<float> tx(m_numSprings), ty(m_numSprings);
  m_bodies.download(bodies.data(), nb, s);
  m_orig.download(orig.data(), n, s);
  m_tx.download(tx.data(), tx.size(), s);
  m_ty.download(ty.data(), ty.size(), s);
  s.synchronize();
  out.resize(nb);
  out.imageX.resize(m_periodic.on(0) ? nb : 0);
  out.imageY.resize(m_periodic.on(1) ? nb : 0);
  for (const BodyRow& b : bodies) {
    const std::uint32_t o = b.orig;
    out.px[o] = b.x.x; out.py[o] = b.x.y; out.pz[o] = b.x.z;
    out.vx[o] = b.v.x; out.vy[o] = b.v.y; out.vz[o] = b.v.z;
    out.qw[o] = b.q.w; out.qx[o] = b.q.x; out.qy[o] = b.q.y; out.qz[o] = b.q.z;
    out.lx[o] = b.l.x; out.ly[o] = b.l.y; out.lz[o] = b.l.z;
    if (m_periodic.on(0)) out.imageX[o] = b.image[0];
    if (m_periodic.on(1)) out.imageY[o] = b.image[1];
  }
  out.contacts = m_history ? readRows<ContactHistory>(m_kept, partnerRows(TakeAbove{}), tumble::detail::MakeContact{})
                           : std::vector<ContactHistory>{};
  out.meshContacts = hasMesh() ? readRows<MeshContactHistory>(m_meshKept, meshRows(), tumble::detail::MakeMeshContact{})
                               : std::vector<MeshContactHistory>{};
  out.groundSpringX.resize(tx.size());
  out.groundSpringY.resize(ty.size());
  for (std::size_t k = 0; k < tx.size(); ++k) {
    const std::size_t o = (k / n) * n + orig[k % n];  // plane-major
    out.groundSpringX[o] = tx[k];
    out.groundSpringY[o] = ty[k];
  }
}

// As CpuPipeline::readLocalPositions.
template <class Exec>
void CudaPipeline<Exec>::readLocalPositions(std::vector<float>& out) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  const std::uint32_t n = m_world.numParticles();
  std::vector<PosRow> pos(n);
  std::vector<std::uint32_t> orig(n);
  m_pos[m_cur].download(pos.data(), n, m_ctx);
  m_orig.download(orig.data(), n, m_ctx);
  m_ctx.synchronize();
  out.resize(3 * std::size_t(n));
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t o = 3 * std::size_t(orig[i]);
    out[o] = pos[i].x;
    out[o + 1] = pos[i].y;
    out[o + 2] = pos[i].z;
  }
}

// As CpuPipeline::pairs.
template <class Exec>
std::vector<Pair> CudaPipeline<Exec>::pairs() const {
  if (m_steps == 0) return {};
  const CandidateListView list = readoutList();
  const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
  return contactsOf(pos, m_orig.data(), list, m_touching.data(), m_periodic, m_world.numParticles());
}

// As CpuPipeline::meshContacts: the (particle, triangle) contacts of the last step, at its
// positions and poses, sorted.
template <class Exec>
std::vector<MeshContact> CudaPipeline<Exec>::meshContacts() const {
  if (m_steps == 0 || !hasMesh()) return {};
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used, with its mesh rows
  const MeshView mv = meshView();                // and its poses
  Buffer<std::uint32_t> count, at;
  Buffer<MeshContact> hits;
  Buffer<unsigned char> temp;
  // After the buffers: on an exception the queue is dropped before they free (and drain) it.
  const exec::AbandonOnUnwind<Stream> unwind(s);
  std::uint32_t* c = count.grow(std::size_t(n) + 1);
  std::uint32_t* a = at.grow(std::size_t(n) + 1);
  const MeshHitsVisit hitsOf{mv, m_meshOffsets.data(), m_meshTri.data(), pos, m_orig.data()};
  Exec::forEach(s, std::uint64_t(n) + 1, VisitCountFn<MeshHitsVisit>{hitsOf, n, c}, "meshHitsCount");
  Exec::exclusiveSum(s, temp, c, a, n + 1);
  std::uint32_t total = 0;
  Exec::copyToHost(s, &total, a + n, 1);
  s.synchronize();
  std::vector<MeshContact> out(total);
  if (total > 0) {
    Exec::forEach(s, n, MeshHitsFillFn{hitsOf, a, hits.grow(total)}, "meshHitsFill");
    hits.download(out.data(), total, s);
    s.synchronize();
  }
  return out;
}

// The hooks of a domain decomposition (HaloPipeline; tumble::mpi), as CpuPipeline's.
template <class Exec>
void CudaPipeline<Exec>::readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  const auto m = static_cast<std::uint32_t>(bodies.size());
  out.resize(m);
  if (m == 0) return;
  const Stream& s = m_ctx;
  const std::uint32_t* at = bodyIndex();
  m_halo.list.upload(bodies, s);
  Exec::forEach(s, m, ReadMotionFn{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.grow(m)}, "readMotion");
  m_halo.motion.download(out.data(), m, s);
  s.synchronize();
}

template <class Exec>
void CudaPipeline<Exec>::writeMotion(const std::vector<std::uint32_t>& bodies,
                                     const std::vector<BodyMotion>& motion) {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  const auto m = static_cast<std::uint32_t>(bodies.size());
  const Stream& s = m_ctx;
  if (m > 0) {
    const std::uint32_t* at = bodyIndex();
    m_halo.list.upload(bodies, s);
    m_halo.motion.upload(motion.data(), m, s);
    PosRow* pos = m_pos[m_cur].data();
    if (m_clumps)
      Exec::forEach(s, m,
                    WriteMotionFn<true>{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.data(), m_own.data(),
                                        m_radius.data(), pos},
                    "writeMotion");
    else
      Exec::forEach(s, m,
                    WriteMotionFn<false>{m_bodies.data(), at, m_halo.list.data(), m_halo.motion.data(), m_own.data(),
                                         m_radius.data(), pos},
                    "writeMotion");
  }
  if (m_steps == 0) {  // the first step rebuilds anyway
    s.synchronize();
    return;
  }
  // The skin test of the step just taken, again, on the positions as they are now.
  StepReadback* rb = clearReadbacks(1);
  Exec::forEach(s, m_world.numParticles(), ParticleDriftFn{m_pos[m_cur].data(), m_buildPos.data(), m_periodic, rb},
                "particleDrift");
  StepReadback h{};
  Exec::copyToHost(s, &h, rb, 1);
  s.synchronize();
  // The step just taken has advanced m_time: the next step's start.
  m_needRebuild = rebuildDue(driftOf(h), hasMesh(), meshClosureUntil(m_time), m_skinLimit);
}

template <class Exec>
std::uint64_t CudaPipeline<Exec>::contactsOf(const std::vector<std::uint32_t>& bodies) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  const auto m = static_cast<std::uint32_t>(bodies.size());
  if (m_steps == 0 || m == 0) return 0;
  const Stream& s = m_ctx;
  const std::uint32_t* at = bodyIndex();
  m_halo.list.upload(bodies, s);
  unsigned long long* total = m_halo.total.grow(1);
  Exec::fillZero(s, total, 1);
  Exec::forEach(s, m,
                BodyContactCountFn{m_bodies.data(), at, m_halo.list.data(), m_touching.data(), m_pos[1 - m_cur].data(),
                                   readoutList(), m_periodic, total},
                "contactsOf");
  unsigned long long h = 0;
  Exec::copyToHost(s, &h, total, 1);
  s.synchronize();
  return h;
}

// As CpuPipeline::energyOf: the last step's flows and the body index read back.
template <class Exec>
EnergyLimbs CudaPipeline<Exec>::energyOf(const std::vector<std::uint32_t>& bodies) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  EnergyLimbs l = noLimbs();
  if (!m_hasFlows) return l;
  const Stream& s = m_ctx;
  const std::uint32_t nb = m_world.numBodies();
  m_flowsHost.resize(nb);
  m_atHost.resize(nb);
  Exec::copyToHost(s, m_flowsHost.data(), m_bodyFlows.data(), nb);
  Exec::copyToHost(s, m_atHost.data(), bodyIndex(), nb);
  s.synchronize();
  for (const std::uint32_t body : bodies) addEnergy(l, m_flowsHost[m_atHost[body]], m_world.params.dt);
  return l;
}

// As CpuPipeline::contactSumsPerBody: the guard's sums per body where the contacts lie, one
// writer per body; the law's tables (host memory) copied for the kernel.
template <class Exec>
bool CudaPipeline<Exec>::contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const {
  const std::uint32_t nb = m_world.numBodies();
  if (m_steps == 0) {  // no contacts yet, as pairs()
    out.assign(nb, ContactSums{});
    return true;
  }
  const Stream& s = m_ctx;
  Buffer<HertzPair> hertz;
  Buffer<std::uint16_t> material;
  Buffer<ContactSums> sums;
  // After the buffers: on an exception the queue is dropped before they free (and drain) it.
  const exec::AbandonOnUnwind<Stream> unwind(s);
  SpringLaw onDevice = law;
  if (law.hertz != nullptr) {
    hertz.upload(law.hertz, std::size_t(law.numMaterials + 1) * (law.numMaterials + 1), s);
    onDevice.hertz = hertz.data();
  }
  if (law.material != nullptr) {
    material.upload(law.material, m_world.numParticles(), s);
    onDevice.material = material.data();
  }
  Exec::forEach(s, nb,
                BodyContactSumsFn{m_bodies.data(), m_bodyOf.data(), m_touching.data(), m_pos[1 - m_cur].data(),
                                  m_pos[m_cur].data(), m_orig.data(), readoutList(), onDevice, m_periodic,
                                  sums.grow(nb)},
                "contactSums");
  out.resize(nb);
  sums.download(out.data(), nb, s);
  s.synchronize();
  return true;
}

// As CpuPipeline::findPairs (same checks, same messages, a fresh broadphase).
template <class Exec>
std::vector<Pair> CudaPipeline<Exec>::findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) {
  const float maxR = checkCloud(cloud);
  const std::size_t n = cloud.size();
  if (n == 0) return {};
  const Stream& s = m_ctx;
  Buffer<float> x, y, z, r;
  Buffer<std::uint32_t> body;
  Broadphase<Exec> b;
  // After the buffers: on an exception the queue is dropped before they free (and drain) it.
  const exec::AbandonOnUnwind<Stream> unwind(s);
  x.upload(cloud.x, s);
  y.upload(cloud.y, s);
  z.upload(cloud.z, s);
  r.upload(cloud.r, s);
  body.upload(cloud.body, s);
  const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), static_cast<std::uint32_t>(n), maxR,
                           tumble::detail::sizingRadius(cloud.r.data(), n)};
  if (cloud.periodic.axes != 0) return findPeriodicPairs(cloud, in, bp, b);
  b.run(in, bp, s, nullptr);
  return b.sortedPairs(static_cast<std::uint32_t>(n), s);
}

// As CpuPipeline::readDebug.
template <class Exec>
void CudaPipeline<Exec>::readDebug(ParticleDebug& out) const {
  const exec::AbandonOnUnwind<Stream> unwind(m_ctx);
  if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
  const std::uint32_t n = m_world.numParticles();
  const Stream& s = m_ctx;
  std::vector<float> v(3 * std::size_t(n)), f[5];
  std::vector<std::uint32_t> orig(n);
  m_dbgVel.download(v.data(), v.size(), s);
  for (int k = 0; k < 5; ++k) {
    f[k].resize(3 * std::size_t(n));
    m_dbg[k].download(f[k].data(), f[k].size(), s);
  }
  m_orig.download(orig.data(), n, s);
  s.synchronize();
  out.v.resize(3 * std::size_t(n));
  for (auto& c : out.force) c.resize(3 * std::size_t(n));
  for (std::uint32_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const std::size_t o = 3 * std::size_t(orig[i]) + c, a = 3 * std::size_t(i) + c;
      out.v[o] = v[a];
      for (int k = 0; k < 5; ++k) out.force[k][o] = f[k][a];
    }
  out.contacts = pairs();
  std::vector<ContactForce> capture(m_numCand);
  m_dbgContact.download(capture.data(), capture.size(), s);
  s.synchronize();
  out.contactForces = capturedContacts(capture.data(), capture.size());
}

// The contacts of the rows `list` at the positions pos (touching: the particles to walk, nullptr
// for all) as sorted scene-index pairs: per particle its contacts with a higher scene index,
// counted, scanned by scene index and written there (count → scan → fill).
template <class Exec>
std::vector<Pair> CudaPipeline<Exec>::contactsOf(const PosRow* pos, const std::uint32_t* orig,
                                                const CandidateListView& list, const std::uint8_t* touching,
                                                const PeriodicBox& box, std::uint32_t n) const {
  const Stream& s = m_ctx;
  Buffer<std::uint32_t> count, at, outI, outJ;
  Buffer<unsigned char> temp;
  // After the buffers: on an exception the queue is dropped before they free (and drain) it.
  const exec::AbandonOnUnwind<Stream> unwind(s);
  std::uint32_t* c = count.grow(std::size_t(n) + 1);
  std::uint32_t* a = at.grow(std::size_t(n) + 1);
  Exec::forEach(s, std::uint64_t(n) + 1, ContactsAboveFn{pos, orig, list, touching, box, n, c}, "contactsAbove");
  Exec::exclusiveSum(s, temp, c, a, n + 1);
  std::uint32_t total = 0;
  Exec::copyToHost(s, &total, a + n, 1);
  s.synchronize();
  std::vector<std::uint32_t> hi(total), hj(total);
  if (total > 0) {
    Exec::forEach(s, n, EmitContactsFn{pos, orig, list, touching, box, a, outI.grow(total), outJ.grow(total)},
                  "emitContacts");
    outI.download(hi.data(), total, s);
    outJ.download(hj.data(), total, s);
    s.synchronize();
  }
  std::vector<Pair> out(total);
  for (std::uint32_t k = 0; k < total; ++k) out[k] = Pair{hi[k], hj[k]};
  return out;
}

// As CpuPipeline::findPeriodicPairs: the sweep over the images on radii grown by the rounding
// margin of a difference across the boundary, then the exact predicate (the minimum image, as
// the oracle) on each particle's merged row.
template <class Exec>
std::vector<Pair> CudaPipeline<Exec>::findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in,
                                                       const BroadphaseParams& bp, Broadphase<Exec>& b) {
  const std::uint32_t n = in.n;
  const Stream& s = m_ctx;
  const PeriodicBox& box = cloud.periodic;
  const float g = periodicGrowth(in.maxRadius, box);
  std::vector<float> grown(n);
  std::vector<PosRow> rows(n);
  std::vector<std::uint32_t> orig(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    grown[i] = cloud.r[i] + g;
    rows[i] = PosRow{cloud.x[i], cloud.y[i], cloud.z[i], cloud.r[i]};
    orig[i] = i;
  }
  Buffer<float> r;
  Buffer<PosRow> pos;
  Buffer<std::uint32_t> ids, offsets, cand, key;
  PeriodicImages<Exec> images;
  // After the buffers: on an exception the queue is dropped before they free (and drain) it.
  const exec::AbandonOnUnwind<Stream> unwind(s);
  r.upload(grown, s);
  pos.upload(rows, s);
  ids.upload(orig, s);
  const BroadphaseInput gin{in.x, in.y, in.z, r.data(), in.body, n, in.maxRadius + g,
                            in.cellRadius > 0.0f ? in.cellRadius + g : 0.0f};
  images.build(gin, box, ghostReach(gin.maxRadius, box), s);
  b.run(images.input(), bp, s, nullptr);
  images.rows(b.listView(), ids.data(), offsets, cand, key, s);
  return contactsOf(pos.data(), ids.data(), compactList(offsets.data(), cand.data()), nullptr, box, n);
}

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
