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

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <string>

#include "broadphase.hpp"
#include "grow.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/integrate.hpp"
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
    m_world = world;
    m_state = world.state;
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

  void readState(BodyState& out) const override { out = m_state; }

  std::vector<Pair> pairs() const override { return m_bp.sortedPairs(m_world.numParticles()); }

  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    const std::size_t n = cloud.size();
    if (cloud.y.size() != n || cloud.z.size() != n || cloud.r.size() != n || cloud.body.size() != n)
      throw Error("particle cloud columns differ in length");
    if (n >= (std::size_t{1} << 31)) throw Error("too many particles (limit 2^31)");
    float maxR = 0.0f;
    for (std::size_t i = 0; i < n; ++i) {
      if (!(cloud.r[i] > 0.0f) || !std::isfinite(cloud.r[i]))
        throw Error("particle " + std::to_string(i) + ": radius must be a positive finite number");
      maxR = std::max(maxR, cloud.r[i]);
    }
    cpu::detail::Broadphase b;
    double sec[kNumPhases] = {};
    const cpu::detail::BroadphaseInput in{cloud.x.data(), cloud.y.data(),    cloud.z.data(),
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
  Quatf quat(std::uint32_t k) const { return {m_state.qw[k], m_state.qx[k], m_state.qy[k], m_state.qz[k]}; }
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
      tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& rg) {
        for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
          const std::uint32_t k = m_world.body[i];
          Vec3f xo, vo;
          const Vec3f ru = particleFromBody(Vec3f{m_state.px[k], m_state.py[k], m_state.pz[k]},
                                            Vec3f{m_state.vx[k], m_state.vy[k], m_state.vz[k]}, quat(k), m_omega[k],
                                            Vec3f{m_world.ux[i], m_world.uy[i], m_world.uz[i]}, &xo, &vo);
          m_x[i] = xo.x; m_y[i] = xo.y; m_z[i] = xo.z;
          m_vx[i] = vo.x; m_vy[i] = vo.y; m_vz[i] = vo.z;
          m_rx[i] = ru.x; m_ry[i] = ru.y; m_rz[i] = ru.z;
        }
      });
    }
    sec[int(Phase::State)] += since(t0);

    // 2. Collision detection → CSR contact list.
    const cpu::detail::BroadphaseInput in{x(), y(), z(), m_world.radius.data(), m_world.body.data(), n,
                                          m_world.maxRadius};
    try {
      m_bp.run(in, m_world.params.broadphase, sec);
    } catch (const SimulationError& e) {
      throw SimulationError("step " + std::to_string(m_steps) + ": " + e.what() +
                            "; the simulation diverged (try a smaller dt, e.g. half of " +
                            std::to_string(m_world.params.dt) + " s)");
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
    const Scene& p = m_world.params;
    const ContactCoeffs cc{p.contact.stiffness, p.contact.damping, p.contact.shear};
    const GroundCoeffs gc{p.ground.height, p.ground.stiffness,
                          p.ground.tangentialStiffness > 0.0f ? p.ground.tangentialStiffness
                                                              : p.ground.stiffness * (2.0f / 7.0f),
                          p.ground.friction};
    const bool ground = p.ground.enabled;
    const float dt = p.dt;
    const std::uint32_t pulls = m_pulls;
    const float* px = x(); const float* py = y(); const float* pz = z();
    const float* pvx = vx(); const float* pvy = vy(); const float* pvz = vz();
    const float* rad = m_world.radius.data();
    const auto& bp = m_bp;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& rg) {
      for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
        const Vec3f xi{px[i], py[i], pz[i]};
        const Vec3f vi{pvx[i], pvy[i], pvz[i]};
        const float ri = rad[i];
        Vec3f f{0.0f, 0.0f, 0.0f};
        Vec3f tau{0.0f, 0.0f, 0.0f};  // couple of forces acting at contact points (clumps only)
        Vec3f rep{0, 0, 0}, dmp{0, 0, 0}, shr{0, 0, 0};
        auto contact = [&](std::uint32_t j) {
            const ContactForces cf = contactForces(xi, vi, ri, Vec3f{px[j], py[j], pz[j]},
                                                   Vec3f{pvx[j], pvy[j], pvz[j]}, rad[j], i < j, cc);
            const Vec3f fc = total(cf);
            f += fc;
            if constexpr (kClumps) tau += cross(cf.lever, fc);
            if constexpr (kDebug) {
              rep += cf.repulsion;
              dmp += cf.damping;
              shr += cf.shear;
            }
        };
        // Fixed order: forward neighbours by record, then backward neighbours (transpose order).
        for (std::uint32_t r = bp.recFirst[i]; r < bp.recFirst[i + 1]; ++r) {
          const std::uint32_t s = bp.inv[r];
          for (std::uint32_t e = bp.nbrOffsets[s]; e < bp.nbrOffsets[s + 1]; ++e) contact(bp.nbr[e]);
        }
        for (std::uint32_t e = bp.backOffsets[i]; e < bp.backOffsets[i + 1]; ++e) contact(bp.back[e]);
        GroundForces gf{{0, 0, 0}, {0, 0, 0}};
        if (ground) {
          gf = groundForces(xi, vi, ri, m_world.groundDamping[i], gc, dt, &m_tx[i], &m_ty[i]);
          f += gf.normal + gf.friction;
          if constexpr (kClumps) {
            const float dg = ri - (xi.z - gc.height);
            tau += cross(Vec3f{0.0f, 0.0f, -(ri - 0.5f * dg)}, gf.friction);
          }
        }
        f += externalForce(xi, m_world.mass[i], p.gravity, p.pulls.x, p.pulls.y, p.pulls.swirl, pulls);
        m_fx[i] = f.x;
        m_fy[i] = f.y;
        m_fz[i] = f.z;
        if constexpr (kClumps) {
          m_cx[i] = tau.x;
          m_cy[i] = tau.y;
          m_cz[i] = tau.z;
        }
        if constexpr (kDebug) {
          const Vec3f parts[5] = {rep, dmp, shr, gf.normal, gf.friction};
          for (int k = 0; k < 5; ++k) {
            m_dbg[k][3 * i] = parts[k].x;
            m_dbg[k][3 * i + 1] = parts[k].y;
            m_dbg[k][3 * i + 2] = parts[k].z;
          }
        }
      }
    });
  }

  void integrate() {
    const std::uint32_t nb = m_world.numBodies();
    const float dt = m_world.params.dt;
    auto& s = m_state;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nb, kGrain), [&](const auto& rg) {
      for (std::uint32_t k = rg.begin(); k != rg.end(); ++k) {
        Vec3f F, T{0, 0, 0};
        if (m_clumps) {
          F = Vec3f{0, 0, 0};
          const std::uint32_t a = m_world.first[k], e = a + m_world.numParticlesOf[k];
          for (std::uint32_t i = a; i < e; ++i) {
            const Vec3f fi{m_fx[i], m_fy[i], m_fz[i]};
            F += fi;
            T += cross(Vec3f{m_rx[i], m_ry[i], m_rz[i]}, fi) + Vec3f{m_cx[i], m_cy[i], m_cz[i]};
          }
        } else {
          F = Vec3f{m_fx[k], m_fy[k], m_fz[k]};
        }
        Vec3f X{s.px[k], s.py[k], s.pz[k]}, V{s.vx[k], s.vy[k], s.vz[k]};
        integrateTranslation(F, m_world.invMass[k], dt, &X, &V);
        s.px[k] = X.x; s.py[k] = X.y; s.pz[k] = X.z;
        s.vx[k] = V.x; s.vy[k] = V.y; s.vz[k] = V.z;
        if (m_clumps && m_world.numParticlesOf[k] > 1) {
          Vec3f L{s.lx[k], s.ly[k], s.lz[k]};
          Quatf q = quat(k);
          m_omega[k] = integrateRotation(T, m_world.invInertia[k], dt, &L, &q);
          s.lx[k] = L.x; s.ly[k] = L.y; s.lz[k] = L.z;
          s.qw[k] = q.w; s.qx[k] = q.x; s.qy[k] = q.y; s.qz[k] = q.z;
        }
      }
    });
  }

  tbb::task_arena m_arena;
  World m_world;
  BodyState m_state;
  bool m_clumps = false;
  std::vector<float> m_x, m_y, m_z, m_vx, m_vy, m_vz, m_rx, m_ry, m_rz;
  std::vector<float> m_fx, m_fy, m_fz, m_tx, m_ty;
  std::vector<float> m_cx, m_cy, m_cz;  // per-particle couples (clumps only)
  std::vector<Vec3f> m_omega;
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

