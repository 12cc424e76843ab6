// SPDX-License-Identifier: MIT
// The CUDA pipeline (SPEC §2–§4): the CPU pipeline's stages (cpu/src/cpu_pipeline.cpp), one
// kernel per stage.
//
// Design notes
// - Same functions, same bits. Every per-element decision or force is a shared TUMBLE_HD
//   function of core/ (kernels/step.hpp, kernels/contact_list.hpp), called with the same
//   arguments as on the CPU; with --fmad=false (TUMBLE_STRICT_FP) the state is bit-identical to
//   the CPU pipeline's after every step. The CPU fuses the force and integration stages into one
//   pass over the bodies; here they are two kernels (particleForce per particle, then
//   finishBody per body, which adds its particles' forces in their order): the same sums in the
//   same order.
// - Contacts as state. The candidate list is rebuilt only when the skin test asks (the drift since
//   the last rebuild: a max and a box of displacements, by integer atomics on order-preserving
//   images of the floats, exact in any order); the rows are sorted by scene index, so the contacts and their order do not
//   depend on the sweep's output order, the skin or the internal numbering.
// - Determinism of the GPU run itself: every output element has one writer, scans are integer
//   scans, sorts are stable, and the only atomics are an integer max and an integer count.
// - Host synchronisation: per step one small read-back (the skin test and the contact count);
//   at a rebuild also the broadphase's (bounds, record and entry counts) and the list's total.
#include <cuda_runtime_api.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "broadphase.cuh"
#include "cub_primitives.cuh"
#include "cuda_context.cuh"
#include "device_buffer.cuh"
#include "tumble/error.hpp"
#include "tumble/gpu/cuda_pipeline.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::gpu {
namespace detail {
namespace {

// --- Kernels: two-line wrappers around the shared stage bodies -----------------------------

// Stage 1 at a rebuild: particle positions from the bodies.
template <bool kClumps>
__global__ void stateKernel(const BodyRow* bodies, std::uint32_t numBodies, const OwnRow* own, const float* radius,
                            PosRow* pos) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < numBodies) bodyParticles<kClumps>(bodies[k], own, radius, nullptr, pos, nullptr);
}

// The detection's input columns (radii grown by skin/2) and the build positions.
__global__ void detectionInputKernel(const PosRow* pos, std::uint32_t n, float halfSkin, float* x, float* y, float* z,
                                     float* r, PosRow* buildPos) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  detectionInput(pos, i, halfSkin, x, y, z, r);
  buildPos[i] = pos[i];
}

__global__ void candidateCountKernel(SweepListView s, std::uint32_t n, std::uint32_t* counts) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) counts[i] = candidateCount(s, i);
  if (i == n) counts[i] = 0;
}

__global__ void candidateFillKernel(SweepListView s, std::uint32_t n, const std::uint32_t* orig,
                                    const std::uint32_t* offsets, std::uint32_t* cand, std::uint32_t* key) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) fillCandidates(s, orig, offsets, cand, key, i);
}

// The reordering: Morton keys of the body centres, then gathers in the sorted order.
__global__ void mortonKeyKernel(const BodyRow* bodies, std::uint32_t numBodies, MortonGrid g, std::uint32_t* keys,
                                std::uint32_t* vals) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= numBodies) return;
  keys[k] = mortonKey(g, bodies[k].x);
  vals[k] = k;
}

__global__ void bodyBoundsKernel(const BodyRow* bodies, std::uint32_t numBodies, tumble::detail::BoundsPartial* out) {
  __shared__ tumble::detail::BoundsPartial sh[kBlock];
  const std::uint32_t t = threadIdx.x, k = blockIdx.x * blockDim.x + t;
  tumble::detail::BoundsPartial b = tumble::detail::emptyBounds();
  if (k < numBodies) tumble::detail::addParticle(b, k, bodies[k].x.x, bodies[k].x.y, bodies[k].x.z, 1.0f);
  sh[t] = b;
  __syncthreads();
  for (std::uint32_t d = 1; d < kBlock; d <<= 1) {  // min and max: exact in any order
    tumble::detail::boundsTreeStep(sh, t, d);
    __syncthreads();
  }
  if (t == 0) out[blockIdx.x] = sh[0];
}

__global__ void permutedCountKernel(const BodyRow* bodies, const std::uint32_t* perm, std::uint32_t numBodies,
                                    std::uint32_t* counts) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < numBodies) counts[k] = bodies[perm[k]].count;
  if (k == numBodies) counts[k] = 0;
}

// The reordering's gathers (moveBody, kernels/contact_list.hpp), one body per thread.
__global__ void moveBodiesKernel(const BodyRow* bodies, const BodyStatic* bodyStatic, const std::uint32_t* perm,
                                 const std::uint32_t* first, std::uint32_t numBodies, std::uint32_t n,
                                 std::uint32_t numPlanes, ReorderColumns from, BodyRow* outBodies,
                                 BodyStatic* outStatic, ReorderColumns to) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < numBodies) moveBody(bodies, bodyStatic, perm, first, k, n, numPlanes, from, outBodies, outStatic, to);
}

// Stages 3–5 per particle; its force and torque go to f, t (one writer each).
template <bool kDebug, bool kClumps>
__global__ void forcesKernel(StepView v, ForceParams fp, DebugForcesView dbg, Vec3f* f, Vec3f* t,
                             unsigned long long* contacts) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= v.numParticles) return;
  const ParticleForce pf = particleForce<kDebug, kClumps>(v, fp, dbg, v.bodies[kClumps ? v.bodyOf[i] : i], i);
  f[i] = pf.f;
  t[i] = pf.t;
  if (pf.contacts != 0) atomicAdd(contacts, static_cast<unsigned long long>(pf.contacts));  // integer: exact
}

/// What each step reads back: the drift (skin test; as order-preserving integer images of the
/// floats, so that integer atomics give the exact max and min in any order) and the contacts.
struct StepReadback {
  unsigned int max2, lo[3], hi[3];
  unsigned int pad;
  unsigned long long contacts;
};

// Stages 6–7 and the next step's stage 1 per body; the drift's max and mins by integer atomics.
template <bool kClumps>
__global__ void integrateKernel(StepView v, const Vec3f* f, const Vec3f* t, Vec3f gravity, float dt,
                                RotationScheme scheme, StepReadback* rb) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= v.numBodies) return;
  const BodyRow& b = v.bodies[k];
  Vec3f F{0.0f, 0.0f, 0.0f}, T{0.0f, 0.0f, 0.0f};
  for (std::uint32_t i = b.first, e = b.first + b.count; i < e; ++i)
    addToBody<kClumps>(F, T, ParticleForce{f[i], t[i], 0u});
  Drift d = noDrift();
  finishBody<kClumps>(v, F, T, gravity, dt, scheme, k, &d);
  atomicMax(&rb->max2, orderedBits(d.max2));
  for (int a = 0; a < 3; ++a) {
    atomicMin(&rb->lo[a], orderedBits(d.lo[a]));
    atomicMax(&rb->hi[a], orderedBits(d.hi[a]));
  }
}

// pairs(): per particle the contacts with a higher scene index, written at its scene index's
// offset, so that the output comes out sorted by (i, j).
__global__ void contactsAboveKernel(const PosRow* pos, const std::uint32_t* orig, CandidateListView list,
                                    const std::uint8_t* touching, std::uint32_t n, std::uint32_t* countByOrig) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) countByOrig[orig[i]] = touching[i] ? contactsAbove(pos, orig, list, i) : 0u;
  if (i == n) countByOrig[n] = 0;
}

__global__ void emitContactsKernel(const PosRow* pos, const std::uint32_t* orig, CandidateListView list,
                                   const std::uint8_t* touching, std::uint32_t n, const std::uint32_t* at,
                                   std::uint32_t* outI, std::uint32_t* outJ) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n && touching[i]) emitContactsAbove(pos, orig, list, i, at[orig[i]], outI, outJ);
}

constexpr const char* kNoPeriodic =
    "the CUDA pipeline has no periodic boundaries yet: a scene with [periodic] runs on the CPU pipeline "
    "(--pipeline cpu)";

class CudaPipeline final : public Pipeline {
 public:
  explicit CudaPipeline(const PipelineOptions& options) : m_reorder(options.reorder) {}

  Backend backend() const override { return Backend::Cuda; }

  // As CpuPipeline::load.
  void load(const World& world) override {
    if (world.numParticles() == 0) throw Error("cannot load an empty world");
    if (world.params.contact.law != ContactLaw::Report)
      throw NotSupported(std::string("the CUDA pipeline runs the report's contact law only so far; [contact] law = \"") +
                  toString(world.params.contact.law) + "\" runs on the CPU pipeline (--pipeline cpu)");
    if (!world.params.walls.empty())
      throw NotSupported(std::string("the CUDA pipeline has no walls yet") +
                  (meshTriangleCount(world.params) > 0 ? " (triangle meshes included)" : "") +
                  ": a scene with [[wall]] runs on the CPU pipeline (--pipeline cpu)");
    if (world.params.periodic.any()) throw NotSupported(kNoPeriodic);
    m_loaded = false;
    m_world = localWorld(world, &m_frame);  // far from the origin: integrate in a local frame
    const World& w = m_world;
    const std::uint32_t n = w.numParticles(), nb = w.numBodies();
    const cudaStream_t s = m_ctx.stream();
    m_clumps = w.hasClumps;
    m_ground = w.params.ground.enabled;
    m_planes.upload(kernelWalls(world.params, m_frame), s);  // the ground only (no walls: above)
    std::vector<BodyRow> bodies;
    std::vector<BodyStatic> bodyStatic;
    std::vector<OwnRow> own;
    initialRows(w, &bodies, &bodyStatic, &own);
    std::vector<std::uint32_t> orig(n);
    for (std::uint32_t i = 0; i < n; ++i) orig[i] = i;
    const BodyState& st = w.state;
    m_bodies.upload(bodies, s);
    m_bodiesNext.grow(nb);
    m_bodyStatic.upload(bodyStatic, s);
    m_own.upload(own, s);
    m_radius.upload(w.radius, s);
    m_mass.upload(w.mass, s);
    m_orig.upload(orig, s);
    m_bodyOf.upload(w.body, s);
    m_tx.upload(m_ground ? st.groundSpringX : std::vector<float>{}, s);
    m_ty.upload(m_ground ? st.groundSpringY : std::vector<float>{}, s);
    for (auto& p : m_pos) p.grow(n);
    m_buildPos.grow(n);
    m_touching.grow(n);
    m_f.grow(n);
    m_t.grow(n);
    m_candOffsets.grow(std::size_t(n) + 1);
    m_readback.grow(1);
    m_clumps ? launchState<true>() : launchState<false>();  // readLocalPositions() before the first step
    m_ctx.synchronize();
    m_cur = 0;
    m_numCand = 0;
    m_skin = effectiveSkin(w);
    m_skinLimit = skinClosureLimit(m_skin, w.maxRadius);
    m_needRebuild = true;
    m_pulls = w.params.pulls.active;
    m_time = w.time;
    m_steps = 0;
    m_bp.reset();
    resetStats();
    m_hasDebug = false;
    m_loaded = true;
  }

  void step(std::uint64_t n) override {
    if (!m_loaded) throw Error("step() before load()");
    for (std::uint64_t s = 0; s < n; ++s) stepOnce();
  }

  void readState(BodyState& out) const override {
    readLocalState(out);
    toWorld(out, m_frame);
  }
  LocalFrame frame() const override { return m_frame; }

  void readLocalState(BodyState& out) const override {
    if (!m_loaded) {
      out = BodyState{};  // as the CPU pipeline's empty state before load()
      return;
    }
    const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
    const cudaStream_t s = m_ctx.stream();
    std::vector<BodyRow> bodies(nb);
    std::vector<std::uint32_t> orig(n);
    std::vector<float> tx(m_ground ? n : 0), ty(m_ground ? n : 0);
    m_bodies.download(bodies.data(), nb, s);
    m_orig.download(orig.data(), n, s);
    m_tx.download(tx.data(), tx.size(), s);
    m_ty.download(ty.data(), ty.size(), s);
    m_ctx.synchronize();
    out.resize(nb);
    for (const BodyRow& b : bodies) {
      const std::uint32_t o = b.orig;
      out.px[o] = b.x.x; out.py[o] = b.x.y; out.pz[o] = b.x.z;
      out.vx[o] = b.v.x; out.vy[o] = b.v.y; out.vz[o] = b.v.z;
      out.qw[o] = b.q.w; out.qx[o] = b.q.x; out.qy[o] = b.q.y; out.qz[o] = b.q.z;
      out.lx[o] = b.l.x; out.ly[o] = b.l.y; out.lz[o] = b.l.z;
    }
    out.contacts.clear();  // no contact history: the report's law only (load())
    out.groundSpringX.resize(tx.size());
    out.groundSpringY.resize(ty.size());
    for (std::size_t i = 0; i < tx.size(); ++i) {
      out.groundSpringX[orig[i]] = tx[i];
      out.groundSpringY[orig[i]] = ty[i];
    }
  }

  // As CpuPipeline::readLocalPositions.
  void readLocalPositions(std::vector<float>& out) const override {
    const std::uint32_t n = m_world.numParticles();
    std::vector<PosRow> pos(n);
    std::vector<std::uint32_t> orig(n);
    m_pos[m_cur].download(pos.data(), n, m_ctx.stream());
    m_orig.download(orig.data(), n, m_ctx.stream());
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
  std::vector<Pair> pairs() const override {
    if (m_steps == 0) return {};
    const std::uint32_t n = m_world.numParticles();
    const cudaStream_t s = m_ctx.stream();
    const CandidateListView list = compactList(m_candOffsets.data(), m_cand.data());
    const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
    DeviceBuffer<std::uint32_t> count, at, outI, outJ;
    DeviceBuffer<unsigned char> temp;
    count.grow(std::size_t(n) + 1);
    at.grow(std::size_t(n) + 1);
    contactsAboveKernel<<<blocksFor(std::uint64_t(n) + 1), kBlock, 0, s>>>(pos, m_orig.data(), list, m_touching.data(),
                                                                        n, count.data());
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "contactsAboveKernel");
    std::size_t bytes = 0;
    TUMBLE_CUDA_CHECK(exclusiveSum(nullptr, bytes, count.data(), at.data(), n + 1, s));
    TUMBLE_CUDA_CHECK(exclusiveSum(temp.grow(bytes), bytes, count.data(), at.data(), n + 1, s));
    std::uint32_t total = 0;
    TUMBLE_CUDA_CHECK(cudaMemcpyAsync(&total, at.data() + n, sizeof total, cudaMemcpyDeviceToHost, s));
    m_ctx.synchronize();
    std::vector<std::uint32_t> hi(total), hj(total);
    if (total > 0) {
      emitContactsKernel<<<blocksFor(n), kBlock, 0, s>>>(pos, m_orig.data(), list, m_touching.data(), n, at.data(),
                                                          outI.grow(total), outJ.grow(total));
      TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "emitContactsKernel");
      outI.download(hi.data(), total, s);
      outJ.download(hj.data(), total, s);
      m_ctx.synchronize();
    }
    std::vector<Pair> out(total);
    for (std::uint32_t k = 0; k < total; ++k) out[k] = Pair{hi[k], hj[k]};
    return out;
  }

  // As CpuPipeline::findPairs (same checks, same messages, a fresh broadphase).
  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    const float maxR = checkCloud(cloud);
    if (cloud.periodic.axes != 0) throw NotSupported(kNoPeriodic);
    const std::size_t n = cloud.size();
    if (n == 0) return {};
    const cudaStream_t s = m_ctx.stream();
    DeviceBuffer<float> x, y, z, r;
    DeviceBuffer<std::uint32_t> body;
    x.upload(cloud.x, s);
    y.upload(cloud.y, s);
    z.upload(cloud.z, s);
    r.upload(cloud.r, s);
    body.upload(cloud.body, s);
    Broadphase b;
    const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), static_cast<std::uint32_t>(n), maxR,
                             detail::sizingRadius(cloud.r.data(), n)};
    b.run(in, bp, m_ctx, nullptr);
    return b.sortedPairs(static_cast<std::uint32_t>(n), s);
  }

  void setDebugCapture(bool on) override { m_debug = on; }

  // As CpuPipeline::readDebug.
  void readDebug(ParticleDebug& out) const override {
    if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
    const std::uint32_t n = m_world.numParticles();
    const cudaStream_t s = m_ctx.stream();
    std::vector<float> v(3 * std::size_t(n)), f[5];
    std::vector<std::uint32_t> orig(n);
    m_dbgVel.download(v.data(), v.size(), s);
    for (int k = 0; k < 5; ++k) {
      f[k].resize(3 * std::size_t(n));
      m_dbg[k].download(f[k].data(), f[k].size(), s);
    }
    m_orig.download(orig.data(), n, s);
    m_ctx.synchronize();
    out.v.resize(3 * std::size_t(n));
    for (auto& c : out.force) c.resize(3 * std::size_t(n));
    for (std::uint32_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::size_t o = 3 * std::size_t(orig[i]) + c, a = 3 * std::size_t(i) + c;
        out.v[o] = v[a];
        for (int k = 0; k < 5; ++k) out.force[k][o] = f[k][a];
      }
    out.contacts = pairs();
  }

  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u; }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override {
    m_stats = StepStats{};
    m_stats.skin = m_skin;
  }
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_world.step + m_steps; }

 private:
  StepView stepView() {
    const int c = m_cur;
    return StepView{m_bodies.data(),
                    m_bodiesNext.data(),
                    m_bodyStatic.data(),
                    m_world.numBodies(),
                    m_pos[c].data(),
                    m_pos[1 - c].data(),
                    m_own.data(),
                    m_radius.data(),
                    m_mass.data(),
                    m_bodyOf.data(),
                    m_orig.data(),
                    GroundSpringView{m_tx.data(), m_ty.data()},
                    m_buildPos.data(),
                    compactList(m_candOffsets.data(), m_cand.data()),
                    m_touching.data(),
                    m_world.numParticles(),
                    nullptr,   // no contact history: the report's law only (load())
                    false,
                    nullptr,   // the report's law: no materials
                    nullptr,
                    0,
                    m_planes.data(),
                    m_ground ? 1u : 0u,
                    nullptr,   // one plane at most: its damping is in the own rows
                    nullptr,
                    PeriodicBox{},  // no periodic boundaries (load())
                    MeshView{},     // no mesh walls (load())
                    MeshListView{},
                    nullptr};       // the skin test per particle (buildPos)
  }

  // As CpuPipeline::stepOnce.
  void stepOnce() {
    const std::uint32_t n = m_world.numParticles(), nb = m_world.numBodies();
    const cudaStream_t s = m_ctx.stream();
    const Scene& p = m_world.params;
    if (m_needRebuild) {
      rebuild();
    } else {
      for (Phase ph : {Phase::Reorder, Phase::State, Phase::Axis, Phase::Keys, Phase::Sort, Phase::Sweep, Phase::List})
        m_timer.mark(ph, s);  // no rebuild this step: the phases take no time
    }

    m_timer.mark(Phase::Forces, s);
    const StepView v = stepView();
    const ForceParams fp = makeForceParams(p, m_pulls);
    DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}, nullptr};
    if (m_debug) {
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].grow(3 * std::size_t(n));
      dbg.v = m_dbgVel.grow(3 * std::size_t(n));
    }
    StepReadback* rb = m_readback.data();
    const Drift none = noDrift();
    StepReadback init{orderedBits(none.max2), {}, {}, 0u, 0ull};
    for (int a = 0; a < 3; ++a) {
      init.lo[a] = orderedBits(none.lo[a]);
      init.hi[a] = orderedBits(none.hi[a]);
    }
    m_readbackInit = init;  // a member: the copy may still read it after this function returns
    TUMBLE_CUDA_CHECK(cudaMemcpyAsync(rb, &m_readbackInit, sizeof init, cudaMemcpyHostToDevice, s));
    unsigned long long* contacts = &rb->contacts;
    if (m_debug) {
      if (m_clumps) forcesKernel<true, true><<<blocksFor(n), kBlock, 0, s>>>(v, fp, dbg, m_f.data(), m_t.data(), contacts);
      else forcesKernel<true, false><<<blocksFor(n), kBlock, 0, s>>>(v, fp, dbg, m_f.data(), m_t.data(), contacts);
    } else {
      if (m_clumps) forcesKernel<false, true><<<blocksFor(n), kBlock, 0, s>>>(v, fp, dbg, m_f.data(), m_t.data(), contacts);
      else forcesKernel<false, false><<<blocksFor(n), kBlock, 0, s>>>(v, fp, dbg, m_f.data(), m_t.data(), contacts);
    }
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "forcesKernel");
    if (m_debug) m_hasDebug = true;

    m_timer.mark(Phase::Integrate, s);
    if (m_clumps)
      integrateKernel<true><<<blocksFor(nb), kBlock, 0, s>>>(v, m_f.data(), m_t.data(), p.gravity, p.dt,
                                                              p.integrator.rotation, rb);
    else
      integrateKernel<false><<<blocksFor(nb), kBlock, 0, s>>>(v, m_f.data(), m_t.data(), p.gravity, p.dt,
                                                               p.integrator.rotation, rb);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "integrateKernel");
    StepReadback h{};
    TUMBLE_CUDA_CHECK(cudaMemcpyAsync(&h, rb, sizeof h, cudaMemcpyDeviceToHost, s));
    m_timer.finish(s);
    m_timer.accumulate(m_stats.seconds);  // waits for the step (and the read-back)
    Drift drift{fromOrderedBits(h.max2), {}, {}};
    for (int a = 0; a < 3; ++a) {
      drift.lo[a] = fromOrderedBits(h.lo[a]);
      drift.hi[a] = fromOrderedBits(h.hi[a]);
    }
    m_cur = 1 - m_cur;
    std::swap(m_bodies, m_bodiesNext);
    m_needRebuild = !listStillValid(drift, m_skinLimit);

    ++m_steps;
    m_time += p.dt;
    ++m_stats.steps;
    m_stats.numPairs = h.contacts / 2;  // each contact is seen from both sides
  }

  // Stage 1: the particle positions of the current body state (after a reordering, and at load).
  template <bool kClumps>
  void launchState() {
    const std::uint32_t nb = m_world.numBodies();
    stateKernel<kClumps><<<blocksFor(nb), kBlock, 0, m_ctx.stream()>>>(m_bodies.data(), nb, m_own.data(),
                                                                        m_radius.data(), m_pos[m_cur].data());
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "stateKernel");
  }

  // As CpuPipeline::rebuild.
  void rebuild() {
    const std::uint32_t n = m_world.numParticles(), nb = m_world.numBodies();
    const cudaStream_t s = m_ctx.stream();
    m_timer.mark(Phase::Reorder, s);
    if (m_reorder) reorder();

    m_timer.mark(Phase::State, s);
    m_clumps ? launchState<true>() : launchState<false>();
    PosRow* pos = m_pos[m_cur].data();
    const float h = 0.5f * m_skin;
    detectionInputKernel<<<blocksFor(n), kBlock, 0, s>>>(pos, n, h, m_bx.grow(n), m_by.grow(n), m_bz.grow(n),
                                                         m_br.grow(n), m_buildPos.data());
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "detectionInputKernel");

    const BroadphaseInput in{m_bx.data(), m_by.data(), m_bz.data(), m_br.data(), m_bodyOf.data(), n,
                             m_world.maxRadius + h,
                             m_world.sizingRadius > 0.0f ? m_world.sizingRadius + h : 0.0f};
    try {
      m_bp.run(in, m_world.params.broadphase, m_ctx, &m_timer);
    } catch (const SimulationError& e) {
      if (e.particle() < 0) throw;
      std::uint32_t o = 0;
      TUMBLE_CUDA_CHECK(cudaMemcpy(&o, m_orig.data() + e.particle(), sizeof o, cudaMemcpyDeviceToHost));
      throw SimulationError(divergenceMessage(m_world, m_world.step + m_steps, o), o);
    }

    m_timer.mark(Phase::List, s);
    const SweepListView sl{m_bp.recFirst.data(), m_bp.inv.data(),         m_bp.nbrOffsets.data(),
                           m_bp.nbr.data(),      m_bp.backOffsets.data(), m_bp.back.data()};
    std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
    candidateCountKernel<<<blocksFor(std::uint64_t(n) + 1), kBlock, 0, s>>>(sl, n, count);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "candidateCountKernel");
    std::size_t bytes = 0;
    TUMBLE_CUDA_CHECK(exclusiveSum(nullptr, bytes, count, m_candOffsets.data(), n + 1, s));
    TUMBLE_CUDA_CHECK(exclusiveSum(m_temp.grow(bytes), bytes, count, m_candOffsets.data(), n + 1, s));
    TUMBLE_CUDA_CHECK(
        cudaMemcpyAsync(&m_numCand, m_candOffsets.data() + n, sizeof m_numCand, cudaMemcpyDeviceToHost, s));
    m_ctx.synchronize();
    candidateFillKernel<<<blocksFor(n), kBlock, 0, s>>>(sl, n, m_orig.data(), m_candOffsets.data(),
                                                        m_cand.grow(m_numCand), m_candKey.grow(m_numCand));
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "candidateFillKernel");
    m_needRebuild = false;
    ++m_stats.numRebuilds;
    m_stats.numCandidates = m_numCand / 2;
    m_stats.numRecords = m_bp.numRecords();
    m_stats.numCells = m_bp.numCells();
    m_stats.cellSize = m_bp.frame().cellSize;
  }

  // As CpuPipeline::reorder.
  void reorder() {
    const std::uint32_t nb = m_world.numBodies(), n = m_world.numParticles();
    if (nb < 2) return;
    const cudaStream_t s = m_ctx.stream();
    const std::uint32_t blocks = blocksFor(nb);
    bodyBoundsKernel<<<blocks, kBlock, 0, s>>>(m_bodies.data(), nb, m_boundsPart.grow(blocks));
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "bodyBoundsKernel");
    m_hostBounds.resize(blocks);
    m_boundsPart.download(m_hostBounds.data(), blocks, s);
    m_ctx.synchronize();
    const MortonGrid g = mortonGridOf(combineBounds(m_hostBounds.data(), blocks));
    std::uint32_t* keys = m_mKeys.grow(nb);
    std::uint32_t* vals = m_mVals.grow(nb);
    std::uint32_t* skeys = m_mSortedKeys.grow(nb);
    std::uint32_t* perm = m_perm.grow(nb);
    mortonKeyKernel<<<blocks, kBlock, 0, s>>>(m_bodies.data(), nb, g, keys, vals);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "mortonKeyKernel");
    std::size_t bytes = 0;
    TUMBLE_CUDA_CHECK(radixSortPairs(nullptr, bytes, keys, skeys, vals, perm, nb, 0, 30, s));
    TUMBLE_CUDA_CHECK(radixSortPairs(m_temp.grow(bytes), bytes, keys, skeys, vals, perm, nb, 0, 30, s));
    std::uint32_t* count = m_count.grow(std::size_t(nb) + 1);
    std::uint32_t* first = m_first.grow(std::size_t(nb) + 1);
    permutedCountKernel<<<blocksFor(std::uint64_t(nb) + 1), kBlock, 0, s>>>(m_bodies.data(), perm, nb, count);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "permutedCountKernel");
    TUMBLE_CUDA_CHECK(exclusiveSum(nullptr, bytes, count, first, nb + 1, s));
    TUMBLE_CUDA_CHECK(exclusiveSum(m_temp.grow(bytes), bytes, count, first, nb + 1, s));
    const ReorderColumns from{m_own.data(),  m_radius.data(), m_mass.data(),
                              nullptr,  // the report's law only (load()): no materials
                              m_orig.data(), m_bodyOf.data(), m_ground ? m_tx.data() : nullptr,
                              m_ground ? m_ty.data() : nullptr,
                              nullptr};  // one plane at most: no damping of further planes
    const ReorderColumns to{m_ownTmp.grow(n),  m_radiusTmp.grow(n), m_massTmp.grow(n), nullptr, m_origTmp.grow(n),
                            m_bodyOfTmp.grow(n), m_ground ? m_txTmp.grow(n) : nullptr,
                            m_ground ? m_tyTmp.grow(n) : nullptr, nullptr};
    moveBodiesKernel<<<blocks, kBlock, 0, s>>>(m_bodies.data(), m_bodyStatic.data(), perm, first, nb, n,
                                               m_ground ? 1u : 0u, from, m_bodiesNext.data(),
                                               m_bodyStaticTmp.grow(nb), to);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "moveBodiesKernel");
    std::swap(m_bodies, m_bodiesNext);
    std::swap(m_bodyStatic, m_bodyStaticTmp);
    std::swap(m_own, m_ownTmp);
    std::swap(m_radius, m_radiusTmp);
    std::swap(m_mass, m_massTmp);
    std::swap(m_orig, m_origTmp);
    std::swap(m_bodyOf, m_bodyOfTmp);
    if (m_ground) {
      std::swap(m_tx, m_txTmp);
      std::swap(m_ty, m_tyTmp);
    }
  }

  StreamContext m_ctx;
  PhaseTimer m_timer;
  bool m_reorder = true;
  World m_world;
  LocalFrame m_frame;
  bool m_loaded = false;
  bool m_clumps = false;
  bool m_ground = false;
  // Internal numbering (see cpu/src/cpu_pipeline.cpp).
  DeviceBuffer<BodyRow> m_bodies, m_bodiesNext;
  DeviceBuffer<BodyStatic> m_bodyStatic;
  DeviceBuffer<OwnRow> m_own;
  DeviceBuffer<Wall> m_planes;  // the ground, when there is one
  DeviceBuffer<float> m_radius, m_mass, m_tx, m_ty;
  DeviceBuffer<std::uint32_t> m_orig, m_bodyOf;
  DeviceBuffer<PosRow> m_pos[2], m_buildPos;
  int m_cur = 0;
  DeviceBuffer<std::uint32_t> m_candOffsets, m_cand, m_candKey;
  DeviceBuffer<std::uint8_t> m_touching;  // the last step's contacts per particle (capped at 255)
  std::uint32_t m_numCand = 0;
  float m_skin = 0.0f, m_skinLimit = 0.0f;
  bool m_needRebuild = true;
  DeviceBuffer<Vec3f> m_f, m_t;  // per-particle force and torque of the step
  DeviceBuffer<StepReadback> m_readback;
  StepReadback m_readbackInit{};
  Broadphase m_bp;
  // Scratch (grow-only).
  DeviceBuffer<float> m_bx, m_by, m_bz, m_br;
  DeviceBuffer<std::uint32_t> m_count, m_first, m_mKeys, m_mVals, m_mSortedKeys, m_perm;
  DeviceBuffer<tumble::detail::BoundsPartial> m_boundsPart;
  std::vector<tumble::detail::BoundsPartial> m_hostBounds;
  DeviceBuffer<unsigned char> m_temp;
  DeviceBuffer<BodyStatic> m_bodyStaticTmp;
  DeviceBuffer<OwnRow> m_ownTmp;
  DeviceBuffer<float> m_radiusTmp, m_massTmp, m_txTmp, m_tyTmp;
  DeviceBuffer<std::uint32_t> m_origTmp, m_bodyOfTmp;
  DeviceBuffer<float> m_dbg[5], m_dbgVel;
  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
};

}  // namespace
}  // namespace detail

namespace {

std::string cudaVersionText(int v) {
  return v == 0 ? std::string("none") : std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10);
}

}  // namespace

CudaStatus deviceStatus() noexcept {
  try {
    int driver = 0, runtime = 0, count = 0;
    if (cudaDriverGetVersion(&driver) != cudaSuccess) driver = 0;
    if (cudaRuntimeGetVersion(&runtime) != cudaSuccess) runtime = 0;
    const cudaError_t e = cudaGetDeviceCount(&count);
    (void)cudaGetLastError();
    const std::string versions =
        " (CUDA driver " + cudaVersionText(driver) + ", runtime " + cudaVersionText(runtime) + ")";
    if (e == cudaSuccess && count > 0) {
      cudaDeviceProp prop{};
      const std::string name = cudaGetDeviceProperties(&prop, 0) == cudaSuccess
                                   ? std::string(prop.name) + " (compute capability " + std::to_string(prop.major) +
                                         "." + std::to_string(prop.minor) + ")"
                                   : "?";
      // A device this build has no code for (below its architectures) fails every launch:
      // Broken, said here rather than at the first kernel.
      cudaFuncAttributes attr{};
      const cudaError_t k = cudaFuncGetAttributes(&attr, detail::stateKernel<true>);
      (void)cudaGetLastError();
      if (k != cudaSuccess)
        return {CudaState::Broken, "CUDA device 0: " + name + " cannot run this build's kernels (" +
                                       cudaGetErrorName(k) + "; built for CUDA architectures " +
                                       TUMBLE_CUDA_ARCHITECTURES + ")" + versions};
      return {CudaState::Ready, "CUDA device 0 of " + std::to_string(count) + ": " + name + versions};
    }
    if (e == cudaSuccess || e == cudaErrorNoDevice) return {CudaState::NoDevice, "no CUDA device" + versions};
    if (driver == 0) return {CudaState::NoDevice, "no CUDA driver is installed" + versions};
    return {CudaState::Broken, std::string("CUDA cannot use the GPU: ") + cudaGetErrorName(e) + " (" +
                                   cudaGetErrorString(e) + ")" + versions};
  } catch (...) {  // std::bad_alloc from the strings
    return {CudaState::Broken, "CUDA status: out of memory"};
  }
}

std::unique_ptr<Pipeline> makeCudaPipeline(const PipelineOptions& options) {
  requireReady(deviceStatus());
  return std::make_unique<detail::CudaPipeline>(options);
}

}  // namespace tumble::gpu
