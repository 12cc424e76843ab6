// SPDX-License-Identifier: MIT
// The CPU reference pipeline (SPEC §2–§4) on oneTBB.
//
// Determinism: every output element has one writer and every floating-point sum runs in a
// fixed order that does not depend on the thread count: a particle sums its contacts in CSR
// order (its records in cell order, each record's neighbours in sweep order), then ground,
// then gravity and pulls; a body sums its particles in index order. No float atomics, no
// parallel_reduce on floats that feed the state.
//
// A scene pays only for what it uses: single-sphere scenes skip the particle-from-body pass
// (particles alias the body columns), torques and rotation; scenes without ground skip the
// ground test; pulls cost nothing while off.
#include "tumble/cpu/cpu_pipeline.hpp"
#include "tumble/guard.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <string>

#include "broadphase.hpp"
#include "grow.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::cpu {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr std::uint32_t kGrain = 2048;

class CpuPipeline final : public Pipeline {
 public:
  explicit CpuPipeline(const PipelineOptions& o)
      : m_arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic) {}

  Backend backend() const override { return Backend::Cpu; }

  void load(const World& world) override {
    if (world.numParticles() == 0) throw Error("cannot load an empty world");
    m_frame = LocalFrame::of(world);  // far from the origin: integrate in a local frame
    m_world = toLocal(world, m_frame);
    m_state = m_world.state;
    const std::uint32_t n = world.numParticles();
    m_clumps = world.hasClumps;
    for (auto* c : {&m_x, &m_y, &m_z, &m_vx, &m_vy, &m_vz, &m_rx, &m_ry, &m_rz}) c->assign(m_clumps ? n : 0, 0.0f);
    for (auto* c : {&m_fx, &m_fy, &m_fz, &m_tx, &m_ty}) c->assign(n, 0.0f);
    for (auto* c : {&m_cx, &m_cy, &m_cz}) c->assign(m_clumps ? n : 0, 0.0f);
    m_omega = tumble::detail::initialOmega(world);
    m_pulls = world.params.pulls.active;
    m_time = 0.0;
    m_steps = 0;
    m_bp = cpu::detail::Broadphase{};
    resetStats();
    m_hasDebug = false;
  }

  void step(std::uint64_t n) override {
    if (m_world.numParticles() == 0) throw Error("step() before load()");
    m_arena.execute([&] {
      for (std::uint64_t s = 0; s < n; ++s) stepOnce();
    });
  }

  void readState(BodyState& out) const override {
    out = m_state;
    toWorld(out, m_frame);
  }
  LocalFrame frame() const override { return m_frame; }
  void readLocalState(BodyState& out) const override { out = m_state; }

  std::vector<Pair> pairs() const override { return m_bp.sortedPairs(m_world.numParticles()); }

  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    const float maxR = checkCloud(cloud);
    const std::size_t n = cloud.size();
    cpu::detail::Broadphase b;
    double sec[kNumPhases] = {};
    const BroadphaseInput in{cloud.x.data(), cloud.y.data(),    cloud.z.data(),
                                          cloud.r.data(), cloud.body.data(), static_cast<std::uint32_t>(n),
                                          maxR};
    std::vector<Pair> out;
    m_arena.execute([&] {
      b.run(in, bp, sec);
      out = b.sortedPairs(static_cast<std::uint32_t>(n));
    });
    return out;
  }

  void setDebugCapture(bool on) override { m_debug = on; }

  void readDebug(ParticleDebug& out) const override {
    if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
    const std::uint32_t n = m_world.numParticles();
    out.v.resize(3 * std::size_t(n));
    for (std::uint32_t i = 0; i < n; ++i) {
      out.v[3 * i] = vx()[i];
      out.v[3 * i + 1] = vy()[i];
      out.v[3 * i + 2] = vz()[i];
    }
    for (int k = 0; k < 5; ++k) out.force[k].assign(m_dbg[k].begin(), m_dbg[k].begin() + 3 * std::size_t(n));
    out.contacts = pairs();
  }

  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u; }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override { m_stats = StepStats{}; }
  double time() const override { return m_time; }

 private:
  // Particle columns: with single-sphere bodies, particle i is body i.
  const float* x() const { return m_clumps ? m_x.data() : m_state.px.data(); }
  const float* y() const { return m_clumps ? m_y.data() : m_state.py.data(); }
  const float* z() const { return m_clumps ? m_z.data() : m_state.pz.data(); }
  const float* vx() const { return m_clumps ? m_vx.data() : m_state.vx.data(); }
  const float* vy() const { return m_clumps ? m_vy.data() : m_state.vy.data(); }
  const float* vz() const { return m_clumps ? m_vz.data() : m_state.vz.data(); }

  void stepOnce() {
    const std::uint32_t n = m_world.numParticles();
    double* sec = m_stats.seconds;

    // 1. Particle state from body state.
    auto t0 = Clock::now();
    if (m_clumps) {
      const BodiesView bv = bodiesView();
      const ParticleStaticView st = staticView();
      const ParticleStateView ps = stateView();
      tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& rg) {
        for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) particleStateOf(bv, m_omega.data(), st, ps, i);
      });
    }
    sec[int(Phase::State)] += since(t0);

    // 2. Collision detection → CSR contact list.
    const BroadphaseInput in{x(), y(), z(), m_world.radius.data(), m_world.body.data(), n,
                                          m_world.maxRadius};
    try {
      m_bp.run(in, m_world.params.broadphase, sec);
    } catch (const SimulationError& e) {
      if (e.particle() < 0) throw;
      throw SimulationError(divergenceMessage(m_world, m_steps, static_cast<std::uint32_t>(e.particle())),
                            e.particle());
    }

    // 3–5. Per-particle forces: contacts (CSR order), ground, gravity and pulls.
    t0 = Clock::now();
    if (m_debug) {
      for (auto& d : m_dbg) tumble::detail::grow(d, 3 * std::size_t(n));
      if (m_clumps) forces<true, true>(); else forces<true, false>();
      m_hasDebug = true;
    } else {
      if (m_clumps) forces<false, true>(); else forces<false, false>();
    }
    sec[int(Phase::Forces)] += since(t0);

    // 6–7. Body totals and integration.
    t0 = Clock::now();
    integrate();
    sec[int(Phase::Integrate)] += since(t0);

    ++m_steps;
    m_time += m_world.params.dt;
    ++m_stats.steps;
    m_stats.numPairs = m_bp.numPairs();
    m_stats.numRecords = m_bp.numRecords();
    m_stats.numCells = m_bp.numCells();
    m_stats.cellSize = m_bp.frame().cellSize;
  }

  template <bool kDebug, bool kClumps>
  void forces() {
    const std::uint32_t n = m_world.numParticles();
    const ParticleStaticView st = staticView();
    const ParticleStateView ps = stateView();
    const CouplesView couples{m_cx.data(), m_cy.data(), m_cz.data(), m_omega.data()};
    const ContactListView cl{m_bp.recFirst.data(), m_bp.inv.data(),         m_bp.nbrOffsets.data(),
                             m_bp.nbr.data(),      m_bp.backOffsets.data(), m_bp.back.data()};
    const ForceParams fp = makeForceParams(m_world.params, m_pulls);
    DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}};
    if constexpr (kDebug)
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].data();
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& rg) {
      for (std::uint32_t i = rg.begin(); i != rg.end(); ++i)
        particleForces<kDebug, kClumps>(st, ps, couples, cl, fp, dbg, i);
    });
  }

  void integrate() {
    const BodiesView bv = bodiesView();
    const ParticleStateView ps = stateView();
    const CouplesView couples{m_cx.data(), m_cy.data(), m_cz.data(), m_omega.data()};
    const float dt = m_world.params.dt;
    const RotationScheme scheme = m_world.params.integrator.rotation;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, m_world.numBodies(), kGrain), [&](const auto& rg) {
      for (std::uint32_t k = rg.begin(); k != rg.end(); ++k)
        integrateBody(bv, ps, couples, m_omega.data(), dt, m_clumps, scheme, k);
    });
  }

  // Views of the columns (the layout the shared stage bodies read). With single-sphere bodies
  // the particle position and velocity columns are the body columns.
  ParticleStaticView staticView() const {
    const World& w = m_world;
    return {w.radius.data(), w.mass.data(), w.elasticity.data(), w.groundDamping.data(), w.body.data(),
            w.ux.data(),     w.uy.data(),   w.uz.data(),         w.numParticles()};
  }
  ParticleStateView stateView() {
    auto& s = m_state;
    float* px = m_clumps ? m_x.data() : s.px.data();
    float* py = m_clumps ? m_y.data() : s.py.data();
    float* pz = m_clumps ? m_z.data() : s.pz.data();
    float* pvx = m_clumps ? m_vx.data() : s.vx.data();
    float* pvy = m_clumps ? m_vy.data() : s.vy.data();
    float* pvz = m_clumps ? m_vz.data() : s.vz.data();
    return {px, py, pz, pvx, pvy, pvz, m_rx.data(), m_ry.data(), m_rz.data(), m_fx.data(), m_fy.data(),
            m_fz.data(), m_tx.data(), m_ty.data(), m_world.numParticles()};
  }
  BodiesView bodiesView() {
    auto& s = m_state;
    return {m_world.invMass.data(), m_world.invInertia.data(), m_world.first.data(), m_world.numParticlesOf.data(),
            s.px.data(), s.py.data(), s.pz.data(), s.vx.data(), s.vy.data(), s.vz.data(),
            s.qw.data(), s.qx.data(), s.qy.data(), s.qz.data(), s.lx.data(), s.ly.data(), s.lz.data(),
            m_world.numBodies()};
  }

  tbb::task_arena m_arena;
  World m_world;
  BodyState m_state;
  bool m_clumps = false;
  std::vector<float> m_x, m_y, m_z, m_vx, m_vy, m_vz, m_rx, m_ry, m_rz;
  std::vector<float> m_fx, m_fy, m_fz, m_tx, m_ty;
  std::vector<float> m_cx, m_cy, m_cz;  // per-particle couples (clumps only)
  std::vector<Vec3f> m_omega;
  LocalFrame m_frame;
  std::vector<float> m_dbg[5];
  cpu::detail::Broadphase m_bp;
  StepStats m_stats;
  std::uint32_t m_pulls = 0;
  double m_time = 0.0;
  std::uint64_t m_steps = 0;
  bool m_debug = false;
  bool m_hasDebug = false;
};

}  // namespace

std::unique_ptr<Pipeline> makeCpuPipeline(const PipelineOptions& options) {
  return std::make_unique<CpuPipeline>(options);
}

}  // namespace tumble::cpu

