// SPDX-License-Identifier: MIT
// The CUDA pipeline (SPEC §2–§4): the twin of cpu/src/cpu_pipeline.cpp, stage by stage.
//
// Determinism: as on the CPU, every output element has one writer and every floating-point sum
// runs in a fixed order: a particle sums its contacts in CSR order (its records in cell order,
// each record's neighbours in sweep order, then its backward list), then ground, then gravity and
// pulls; a body sums its particles in index order. No float atomics, no float reductions in CUB.
// Each kernel below is a thin wrapper around the shared TUMBLE_HD functions of core/, called
// with the same arguments in the same order as the CPU's loop body, so with --fmad=false
// (TUMBLE_STRICT_FP) the state is bit-identical to the CPU pipeline's after every step.
//
// A scene pays only for what it uses, as on the CPU: single-sphere scenes skip the
// particle-from-body pass (particle columns alias the body columns), torques and rotation;
// scenes without ground skip the ground test.
//
// Host synchronisation per step: after the bounds (the frame is computed on the host, as the
// CPU does), after each of the two scans whose totals size the next buffers (records, entries),
// and at the end of the step for the phase timers.
#include <cuda_runtime_api.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "broadphase.cuh"
#include "cuda_context.cuh"
#include "device_buffer.cuh"
#include "tumble/kernels/step.hpp"
#include "tumble/sweep_frame.hpp"
#include "tumble/error.hpp"
#include "tumble/gpu/cuda_pipeline.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/integrate.hpp"

namespace tumble::gpu {
namespace detail {
namespace {

using ContactList = ContactListView;
using Couples = CouplesView;
using DebugForces = DebugForcesView;

// Two-line wrappers around the shared stage bodies (core/include/tumble/kernels/step.hpp);
// the CPU pipeline calls the same functions from TBB loops.
__global__ void stateKernel(BodiesView bodies, const Vec3f* omega, ParticleStaticView st, ParticleStateView ps) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < st.count) particleStateOf(bodies, omega, st, ps, i);
}

template <bool kDebug, bool kClumps>
__global__ void forcesKernel(ParticleStaticView st, ParticleStateView ps, Couples couples, ContactList cl,
                             ForceParams fp, DebugForces dbg) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < ps.count) particleForces<kDebug, kClumps>(st, ps, couples, cl, fp, dbg, i);
}

__global__ void integrateKernel(BodiesView b, ParticleStateView ps, Couples couples, Vec3f* omega, float dt,
                                bool clumps, RotationScheme scheme) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < b.count) integrateBody(b, ps, couples, omega, dt, clumps, scheme, k);
}

/// The integrated body state on the device, one column per BodyState column.
struct BodyColumns {
  DeviceBuffer<float> px, py, pz, vx, vy, vz, qw, qx, qy, qz, lx, ly, lz;
};

/// Grows b to n elements and zeroes them.
void zeros(DeviceBuffer<float>& b, std::size_t n, cudaStream_t stream) {
  b.grow(n);
  if (n > 0) TUMBLE_CUDA_CHECK(cudaMemsetAsync(b.data(), 0, n * sizeof(float), stream));
}

class CudaPipeline final : public Pipeline {
 public:
  explicit CudaPipeline(const PipelineOptions& /*options: threads do not apply to the device*/) {}

  Backend backend() const override { return Backend::Cuda; }

  // Twin: CpuPipeline::load.
  void load(const World& world) override {
    if (world.numParticles() == 0) throw Error("cannot load an empty world");
    m_loaded = false;
    m_frame = LocalFrame::of(world);  // far from the origin: integrate in a local frame
    m_world = toLocal(world, m_frame);
    const std::uint32_t n = world.numParticles();
    const cudaStream_t s = m_ctx.stream();
    m_clumps = world.hasClumps;

    const BodyState& st = m_world.state;
    m_state.px.upload(st.px, s); m_state.py.upload(st.py, s); m_state.pz.upload(st.pz, s);
    m_state.vx.upload(st.vx, s); m_state.vy.upload(st.vy, s); m_state.vz.upload(st.vz, s);
    m_state.qw.upload(st.qw, s); m_state.qx.upload(st.qx, s); m_state.qy.upload(st.qy, s);
    m_state.qz.upload(st.qz, s);
    m_state.lx.upload(st.lx, s); m_state.ly.upload(st.ly, s); m_state.lz.upload(st.lz, s);
    m_invMass.upload(world.invMass, s);
    m_invInertia.upload(world.invInertia, s);
    m_first.upload(world.first, s);
    m_numOf.upload(world.numParticlesOf, s);
    const std::vector<Vec3f> omega = initialOmega(world);
    m_omega.upload(omega, s);

    m_radius.upload(world.radius, s);
    m_mass.upload(world.mass, s);
    m_elasticity.upload(world.elasticity, s);
    m_groundDamping.upload(world.groundDamping, s);
    m_body.upload(world.body, s);
    m_ux.upload(world.ux, s); m_uy.upload(world.uy, s); m_uz.upload(world.uz, s);

    const std::size_t nc = m_clumps ? n : 0;
    for (auto* c : {&m_x, &m_y, &m_z, &m_vx, &m_vy, &m_vz, &m_rx, &m_ry, &m_rz, &m_cx, &m_cy, &m_cz}) zeros(*c, nc, s);
    for (auto* c : {&m_fx, &m_fy, &m_fz, &m_tx, &m_ty}) zeros(*c, n, s);
    m_ctx.synchronize();

    m_pulls = world.params.pulls.active;
    m_time = 0.0;
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
    const std::size_t nb = m_world.numBodies();
    const cudaStream_t s = m_ctx.stream();
    out.resize(nb);
    m_state.px.download(out.px.data(), nb, s); m_state.py.download(out.py.data(), nb, s);
    m_state.pz.download(out.pz.data(), nb, s);
    m_state.vx.download(out.vx.data(), nb, s); m_state.vy.download(out.vy.data(), nb, s);
    m_state.vz.download(out.vz.data(), nb, s);
    m_state.qw.download(out.qw.data(), nb, s); m_state.qx.download(out.qx.data(), nb, s);
    m_state.qy.download(out.qy.data(), nb, s); m_state.qz.download(out.qz.data(), nb, s);
    m_state.lx.download(out.lx.data(), nb, s); m_state.ly.download(out.ly.data(), nb, s);
    m_state.lz.download(out.lz.data(), nb, s);
    m_ctx.synchronize();
  }

  std::vector<Pair> pairs() const override { return m_bp.sortedPairs(m_world.numParticles(), m_ctx.stream()); }

  // Twin: CpuPipeline::findPairs (same checks, same messages, a fresh broadphase).
  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    const float maxR = checkCloud(cloud);
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
    const BroadphaseInput in{x.data(), y.data(), z.data(), r.data(), body.data(), static_cast<std::uint32_t>(n), maxR};
    b.run(in, bp, m_ctx, nullptr);
    return b.sortedPairs(static_cast<std::uint32_t>(n), s);
  }

  void setDebugCapture(bool on) override { m_debug = on; }

  // Twin: CpuPipeline::readDebug (velocities as the CPU's vx(): the particle columns for clumps,
  // the body columns otherwise).
  void readDebug(ParticleDebug& out) const override {
    if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
    const std::uint32_t n = m_world.numParticles();
    const cudaStream_t s = m_ctx.stream();
    std::vector<float> v[3];
    const float* src[3] = {m_clumps ? m_vx.data() : m_state.vx.data(), m_clumps ? m_vy.data() : m_state.vy.data(),
                           m_clumps ? m_vz.data() : m_state.vz.data()};
    for (int c = 0; c < 3; ++c) {
      v[c].resize(n);
      if (n > 0) TUMBLE_CUDA_CHECK(cudaMemcpyAsync(v[c].data(), src[c], n * sizeof(float), cudaMemcpyDeviceToHost, s));
    }
    for (int k = 0; k < 5; ++k) {
      out.force[k].resize(3 * std::size_t(n));
      m_dbg[k].download(out.force[k].data(), out.force[k].size(), s);
    }
    m_ctx.synchronize();
    out.v.resize(3 * std::size_t(n));
    for (std::uint32_t i = 0; i < n; ++i) {
      out.v[3 * std::size_t(i)] = v[0][i];
      out.v[3 * std::size_t(i) + 1] = v[1][i];
      out.v[3 * std::size_t(i) + 2] = v[2][i];
    }
    out.contacts = pairs();
  }

  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u; }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override { m_stats = StepStats{}; }
  double time() const override { return m_time; }

 private:
  // Particle columns: with single-sphere bodies, particle i is body i (as the CPU's x() etc.).
  float* x() { return m_clumps ? m_x.data() : m_state.px.data(); }
  float* y() { return m_clumps ? m_y.data() : m_state.py.data(); }
  float* z() { return m_clumps ? m_z.data() : m_state.pz.data(); }
  float* vx() { return m_clumps ? m_vx.data() : m_state.vx.data(); }
  float* vy() { return m_clumps ? m_vy.data() : m_state.vy.data(); }
  float* vz() { return m_clumps ? m_vz.data() : m_state.vz.data(); }

  BodiesView bodiesView() {
    return BodiesView{m_invMass.data(), m_invInertia.data(), m_first.data(), m_numOf.data(),
                      m_state.px.data(), m_state.py.data(), m_state.pz.data(),
                      m_state.vx.data(), m_state.vy.data(), m_state.vz.data(),
                      m_state.qw.data(), m_state.qx.data(), m_state.qy.data(), m_state.qz.data(),
                      m_state.lx.data(), m_state.ly.data(), m_state.lz.data(), m_world.numBodies()};
  }
  ParticleStaticView staticView() const {
    return ParticleStaticView{m_radius.data(), m_mass.data(), m_elasticity.data(), m_groundDamping.data(),
                              m_body.data(),   m_ux.data(),   m_uy.data(),         m_uz.data(),
                              m_world.numParticles()};
  }
  ParticleStateView stateView() {
    const bool c = m_clumps;
    return ParticleStateView{x(), y(), z(), vx(), vy(), vz(),
                             c ? m_rx.data() : nullptr, c ? m_ry.data() : nullptr, c ? m_rz.data() : nullptr,
                             m_fx.data(), m_fy.data(), m_fz.data(), m_tx.data(), m_ty.data(),
                             m_world.numParticles()};
  }

  // Twin: CpuPipeline::stepOnce.
  void stepOnce() {
    const std::uint32_t n = m_world.numParticles();
    const std::uint32_t nb = m_world.numBodies();
    const cudaStream_t s = m_ctx.stream();
    const Scene& p = m_world.params;

    // 1. Particle state from body state.
    m_timer.mark(Phase::State, s);
    if (m_clumps) {
      stateKernel<<<blocksFor(n), kBlock, 0, s>>>(bodiesView(), m_omega.data(), staticView(), stateView());
      TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "stateKernel");
    }

    // 2. Collision detection → CSR contact list.
    const BroadphaseInput in{x(), y(), z(), m_radius.data(), m_body.data(), n, m_world.maxRadius};
    try {
      m_bp.run(in, p.broadphase, m_ctx, &m_timer);
    } catch (const SimulationError& e) {
      if (e.particle() < 0) throw;
      throw SimulationError(divergenceMessage(m_world, m_steps, static_cast<std::uint32_t>(e.particle())),
                            e.particle());
    }

    // 3–5. Per-particle forces: contacts (CSR order), ground, gravity and pulls.
    m_timer.mark(Phase::Forces, s);
    const ForceParams fp = makeForceParams(p, m_pulls);
    const ContactList cl{m_bp.recFirst.data(), m_bp.inv.data(),  m_bp.nbrOffsets.data(),
                         m_bp.nbr.data(),      m_bp.backOffsets.data(), m_bp.back.data()};
    const Couples couples{m_cx.data(), m_cy.data(), m_cz.data(), m_omega.data()};
    DebugForces dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}};
    if (m_debug) {
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].grow(3 * std::size_t(n));
      if (m_clumps)
        forcesKernel<true, true><<<blocksFor(n), kBlock, 0, s>>>(staticView(), stateView(), couples, cl, fp, dbg);
      else
        forcesKernel<true, false><<<blocksFor(n), kBlock, 0, s>>>(staticView(), stateView(), couples, cl, fp, dbg);
    } else {
      if (m_clumps)
        forcesKernel<false, true><<<blocksFor(n), kBlock, 0, s>>>(staticView(), stateView(), couples, cl, fp, dbg);
      else
        forcesKernel<false, false><<<blocksFor(n), kBlock, 0, s>>>(staticView(), stateView(), couples, cl, fp, dbg);
    }
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "forcesKernel");
    if (m_debug) m_hasDebug = true;

    // 6–7. Body totals and integration.
    m_timer.mark(Phase::Integrate, s);
    integrateKernel<<<blocksFor(nb), kBlock, 0, s>>>(bodiesView(), stateView(), couples, m_omega.data(), p.dt,
                                                     m_clumps, p.integrator.rotation);
    TUMBLE_CUDA_AFTER_LAUNCH(m_ctx, "integrateKernel");
    m_timer.finish(s);
    m_timer.accumulate(m_stats.seconds);  // waits for the step

    ++m_steps;
    m_time += p.dt;
    ++m_stats.steps;
    m_stats.numPairs = m_bp.numPairs();
    m_stats.numRecords = m_bp.numRecords();
    m_stats.numCells = m_bp.numCells();
    m_stats.cellSize = m_bp.frame().cellSize;
  }

  StreamContext m_ctx;
  PhaseTimer m_timer;
  World m_world;
  bool m_loaded = false;
  bool m_clumps = false;
  // Bodies.
  BodyColumns m_state;
  DeviceBuffer<float> m_invMass;
  DeviceBuffer<Sym3f> m_invInertia;
  DeviceBuffer<std::uint32_t> m_first, m_numOf;
  DeviceBuffer<Vec3f> m_omega;
  LocalFrame m_frame;
  // Static particle table.
  DeviceBuffer<float> m_radius, m_mass, m_elasticity, m_groundDamping, m_ux, m_uy, m_uz;
  DeviceBuffer<std::uint32_t> m_body;
  // Per-step particle state; x … rz and the couples exist for clump scenes only.
  DeviceBuffer<float> m_x, m_y, m_z, m_vx, m_vy, m_vz, m_rx, m_ry, m_rz;
  DeviceBuffer<float> m_fx, m_fy, m_fz, m_tx, m_ty;
  DeviceBuffer<float> m_cx, m_cy, m_cz;
  DeviceBuffer<float> m_dbg[5];
  Broadphase m_bp;
  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
};

}  // namespace
}  // namespace detail

bool deviceAvailable() noexcept {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) {
    (void)cudaGetLastError();  // no driver / no device: not an error for the caller
    return false;
  }
  return count > 0;
}

std::unique_ptr<Pipeline> makeCudaPipeline(const PipelineOptions& options) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) {
    (void)cudaGetLastError();
    throw Error(std::string("the CUDA pipeline cannot use a GPU: ") + cudaGetErrorString(e) + " (use --pipeline cpu)");
  }
  if (count == 0) throw Error("the CUDA pipeline needs a CUDA device and none is available (use --pipeline cpu)");
  return std::make_unique<detail::CudaPipeline>(options);
}

}  // namespace tumble::gpu
