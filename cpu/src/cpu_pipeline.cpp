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

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cfloat>
#include <string>

#include "broadphase.hpp"
#include "grow.hpp"
#include "periodic_images.hpp"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/error.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/step.hpp"
#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble::cpu {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr std::uint32_t kGrain = 2048;      // particles per task
constexpr std::uint32_t kBodyGrain = 256;   // bodies per task of the step pass
constexpr float kNearSkinFraction = 0.25f;  // near skin / skin: chosen by measurement (docs/performance.md)

template <class F>
void forEach(std::uint32_t n, std::uint32_t grain, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, grain), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) f(i);
  });
}

/// The per-step reduction: the drift since the rebuild (skin test) and the touching contacts.
struct StepTotals {
  Drift drift = noDrift();
  std::uint64_t contacts = 0;
};

class CpuPipeline final : public HaloPipeline {
 public:
  explicit CpuPipeline(const PipelineOptions& o)
      : m_arena(o.threads > 0 ? o.threads : tbb::task_arena::automatic), m_reorder(o.reorder) {}

  Backend backend() const override { return Backend::Cpu; }

  void load(const World& world) override {
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
    m_periodic = kernelPeriodic(w.params, m_frame);
    const double periodicReach = periodicRoundingReach(m_periodic);
    m_periodicGrowth = m_periodic.axes != 0 ? periodicGrowth(w.maxRadius + 0.5f * m_skin, m_periodic) : 0.0f;
    m_fullLimit = skinClosureLimit(m_skin, w.maxRadius, periodicReach);
    m_nearSkin = kNearSkinFraction * m_skin;
    m_nearLimit = skinClosureLimit(m_nearSkin, w.maxRadius, periodicReach);
    // Too thin to help, or a law whose history lives beside the candidate list: the forces read
    // the candidate list.
    if (!(m_nearLimit > 0.0f) || m_history) m_nearSkin = 0.0f;
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
  }

  void step(std::uint64_t n) override {
    if (m_bodies.empty()) throw Error("step() before load()");
    m_arena.execute([&] {
      for (std::uint64_t s = 0; s < n; ++s) stepOnce();
    });
  }

  void readState(BodyState& out) const override {
    readLocalState(out);
    toWorld(out, m_frame);
  }
  LocalFrame frame() const override { return m_frame; }

  void readLocalState(BodyState& out) const override {
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

  void readLocalPositions(std::vector<float>& out) const override {
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

  std::vector<Pair> pairs() const override {
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

  std::vector<MeshContact> meshContacts() const override {
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
  bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const override {
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

  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
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

  void setDebugCapture(bool on) override { m_debug = on; }

  void readDebug(ParticleDebug& out) const override {
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
  }

  // A pull along a periodic axis is left off (its potential has no period; scene files refuse it).
  void setPulls(std::uint32_t mask) override { m_pulls = mask & 7u & ~m_world.params.periodic.conflictingPulls(); }
  std::uint32_t pulls() const override { return m_pulls; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override {
    m_stats = StepStats{};
    m_stats.skin = m_skin;
  }
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_world.step + m_steps; }

  // The hooks of a domain decomposition (HaloPipeline; tumble::mpi).
  void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const override {
    const std::vector<std::uint32_t>& at = internalBodies();
    out.resize(bodies.size());
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      out[k] = motionOf(m_bodies[at[bodies[k]]]);
    }
  }

  void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) override {
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

  std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const override {
    if (m_steps == 0) return 0;
    const std::vector<std::uint32_t>& at = internalBodies();
    const PosRow* pos = m_pos[1 - m_cur].data();  // the rows the last step used
    const CandidateListView list = contactListView();
    std::uint64_t total = 0;
    for (const std::uint32_t body : bodies)
      total += bodyContactCount(m_bodies[at[body]], m_touching.data(), pos, list, m_periodic);
    return total;
  }

 private:
  // Scene index → internal index of every body (the hooks' names for bodies).
  const std::vector<std::uint32_t>& internalBodies() const {
    m_internal.resize(m_bodies.size());
    for (std::uint32_t k = 0; k < m_bodies.size(); ++k) m_internal[m_bodies[k].orig] = k;
    return m_internal;
  }

  // After a step's skin test (the drift of every particle since the reference of the list the
  // step read): whether the next step rebuilds the candidate list or refreshes the near list.
  // `next` is the time the next step starts at: moving meshes add their motion since the
  // rebuild up to it.
  void decideList(const Drift& drift, double next) {
    const float closure = closureFor(drift);
    const double meshes = m_meshMotion.any() ? m_meshMotion.closure(m_rebuildTime, next) : 0.0;
    m_needRebuild = !(m_closed + double(closure) + meshes < double(m_fullLimit));
    // The near list holds sphere pairs only: their closure is enough for it (closureOf(), which
    // a common motion does not use up, where the walls' bound is 2 max |dx|).
    const float pairClosure = m_hasMesh ? closureOf(drift) : closure;
    m_needRefresh = m_nearSkin > 0.0f && !(pairClosure < m_nearLimit);
    m_lastClosure = closure;
  }

  void stepOnce() {
    double* sec = m_stats.seconds;
    if (m_wallsMove)
      setWallMotion(m_planes, m_world.params, m_time, m_meshPoses.empty() ? nullptr : m_meshPoses.data());
    if (m_needRebuild)
      rebuild();
    else if (m_needRefresh)
      refreshNear();

    const auto t0 = Clock::now();
    StepTotals tot;
    if (m_debug) {
      for (auto& d : m_dbg) tumble::detail::grow(d, 3 * std::size_t(m_world.numParticles()));
      tumble::detail::grow(m_dbgVel, 3 * std::size_t(m_world.numParticles()));
      tot = advanceAs<true>();
    } else {
      tot = advanceAs<false>();
    }
    m_hasDebug = m_debug;  // readDebug() reads the last step's capture, or refuses
    m_cur = 1 - m_cur;
    m_bodies.swap(m_bodiesNext);
    decideList(tot.drift, m_time + m_world.params.dt);
    sec[int(Phase::Forces)] += since(t0);

    ++m_steps;
    m_time += m_world.params.dt;
    ++m_stats.steps;
    m_stats.numPairs = tot.contacts / 2;  // each contact is seen from both sides
  }

  // How far the particles may have closed in under a drift: on each other (closureOf()), and
  // with mesh walls on a static wall too (wallClosureOf(), which is at least that).
  float closureFor(const Drift& d) const { return m_hasMesh ? wallClosureOf(d) : closureOf(d); }

  // advance() instantiated for the scene's law, bodies, periodic boundaries and moving meshes
  // (a periodic scene has no mesh).
  template <bool kDebug>
  StepTotals advanceAs() {
    if (m_periodic.axes != 0) return advanceLaw<kDebug, true, false>();
    return m_meshPoses.empty() ? advanceLaw<kDebug, false, false>() : advanceLaw<kDebug, false, true>();
  }
  template <bool kDebug, bool kPeriodic, bool kPosedMesh>
  StepTotals advanceLaw() {
    switch (m_law) {
      case ContactLaw::HookeHistory: return advance<kDebug, true, ContactLaw::HookeHistory, kPeriodic, kPosedMesh>();
      case ContactLaw::HertzMindlin: return advance<kDebug, true, ContactLaw::HertzMindlin, kPeriodic, kPosedMesh>();
      default:
        return m_clumps ? advance<kDebug, true, ContactLaw::Report, kPeriodic, kPosedMesh>()
                        : advance<kDebug, false, ContactLaw::Report, kPeriodic, kPosedMesh>();
    }
  }

  // Stages 3–7 and the next step's stage 1, one pass over the bodies (see the design notes).
  template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh>
  StepTotals advance() {
    const StepView v = stepView();
    const ForceParams fp = makeForceParams(m_world.params, m_pulls);
    DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}, nullptr};
    if constexpr (kDebug) {
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].data();
      dbg.v = m_dbgVel.data();
    }
    const float dt = m_world.params.dt;
    const Vec3f g = m_world.params.gravity;
    const RotationScheme scheme = m_world.params.integrator.rotation;
    return tbb::parallel_reduce(
        tbb::blocked_range<std::uint32_t>(0, v.numBodies, kBodyGrain), StepTotals{},
        [&](const auto& rg, StepTotals acc) {
          for (std::uint32_t k = rg.begin(); k != rg.end(); ++k)
            acc.contacts +=
                stepBody<kDebug, kClumps, kLaw, kPeriodic, kPosedMesh, true>(v, fp, dbg, g, dt, scheme, k, &acc.drift);
          return acc;
        },
        [](StepTotals x, const StepTotals& y) {
          mergeDrift(x.drift, y.drift);
          x.contacts += y.contacts;
          return x;
        });
  }

  // A new candidate list: reorder, particle positions, detection on grown radii, rows sorted by
  // scene index, build positions.
  void rebuild() {
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
    // Detection input: the positions and the radii grown by skin/2 (and with periodic boundaries
    // by the rounding of a difference across them, periodicGrowth()).
    const float h = 0.5f * m_skin + m_periodicGrowth;
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
    if (m_nearSkin > 0.0f)
      fillNearList();
    else if (m_law == ContactLaw::Report) {
      m_owner.resize(m_cand.size());
      forEach(n, kGrain, [&](std::uint32_t i) { ownRow(m_candOffsets, i); });
    } else {  // the laws with history go particle by particle: no owners
      m_owner.clear();
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
  void refreshNear() {
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
  void setBodyReference() {
    forEach(static_cast<std::uint32_t>(m_bodies.size()), kGrain,
            [&](std::uint32_t k) { m_bodyRef[k] = BodyRef{m_bodies[k].x, m_bodies[k].q}; });
  }

  // The displacements of the particles since the rebuild (minimum images with periodic
  // boundaries), measured one by one; with the skin test per particle, the positions now become
  // its reference.
  template <bool kPeriodic>
  Drift driftSinceRebuild() {
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
  // (StepView::listOwner): first at the candidate rows' offsets, then compacted.
  void fillNearList() {
    const std::uint32_t n = m_world.numParticles();
    std::uint32_t* room = tumble::detail::grow(m_nearRoom, m_cand.size());
    std::uint32_t* count = tumble::detail::grow(m_count, std::size_t(n) + 1);
    const CandidateListView full = compactList(m_candOffsets.data(), m_cand.data());
    const PosRow* pos = m_pos[m_cur].data();
    if (m_periodic.axes != 0)
      forEach(n, kGrain, [&](std::uint32_t i) {
        count[i] = fillNear<true>(pos, full, m_nearSkin, room, i, m_periodic) - m_candOffsets[i];
      });
    else
      forEach(n, kGrain, [&](std::uint32_t i) { count[i] = fillNear(pos, full, m_nearSkin, room, i) - m_candOffsets[i]; });
    count[n] = 0;
    m_nearOffsets.resize(std::size_t(n) + 1);
    scanCounts(count, std::size_t(n) + 1, m_nearOffsets.data());
    m_near.resize(m_nearOffsets[n]);
    m_owner.resize(m_nearOffsets[n]);
    forEach(n, kGrain, [&](std::uint32_t i) {
      std::copy(room + m_candOffsets[i], room + m_candOffsets[i] + count[i], m_near.data() + m_nearOffsets[i]);
      ownRow(m_nearOffsets, i);
    });
  }

  // The particle of each entry of the compact list at `offsets` (StepView::listOwner): row i's.
  void ownRow(const std::vector<std::uint32_t>& offsets, std::uint32_t i) {
    std::fill(m_owner.data() + offsets[i], m_owner.data() + offsets[i + 1], i);
  }

  // The list the forces (and pairs()) iterate: the near list when there is one.
  CandidateListView contactListView() const {
    if (m_nearSkin > 0.0f) return compactList(m_nearOffsets.data(), m_near.data());
    return compactList(m_candOffsets.data(), m_cand.data());
  }

  // Stage 1: the particle positions of the current body state (after a reordering, and at load).
  void computePositions() {
    PosRow* pos = m_pos[m_cur].data();
    forEach(static_cast<std::uint32_t>(m_bodies.size()), kBodyGrain, [&](std::uint32_t k) {
      if (m_clumps)
        bodyParticles<true>(m_bodies[k], m_own.data(), m_radius.data(), nullptr, pos, nullptr);
      else
        bodyParticles<false>(m_bodies[k], m_own.data(), m_radius.data(), nullptr, pos, nullptr);
    });
  }

  // The sweep's forward and backward lists → one row per particle, sorted by scene index.
  void buildList() {
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
  void buildPeriodicList(const SweepListView& s) {
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
  std::vector<Pair> findPeriodicPairs(const ParticleCloud& cloud, const BroadphaseInput& in, const BroadphaseParams& bp,
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

  // Histories across a rebuild (the contact histories of laws with a history, the mesh
  // springs). Before it, the non-zero ξ of a list are kept per particle by scene index, each
  // with its key (the partner's scene index, or the triangle), in the row's order (ascending
  // key); after it, each row of the new list takes the ξ of its keys there, by a merge of the
  // two sorted rows, and zero for the others. So the history depends on the contacts only, not
  // on the list, the skin or the numbering.
  struct KeptHistories : tumble::detail::KeptRows {
    std::vector<std::uint32_t> count;  // scratch
  };

  // keyOf(e): the key of entry e of the rows offsets[i] .. offsets[i+1] (internal numbering);
  // count → scan → fill by scene index (kernels/history.hpp, as the CUDA pipeline).
  template <class KeyOf>
  void keepRows(const std::vector<std::uint32_t>& offsets, const std::vector<Vec3f>& hist, const KeyOf& keyOf,
                KeptHistories& out) {
    const std::uint32_t n = m_world.numParticles();
    std::uint32_t* count = tumble::detail::grow(out.count, std::size_t(n) + 1);
    forEach(n, kGrain, [&](std::uint32_t i) {
      count[m_orig[i]] = takenCount(offsets.data(), hist.data(), keyOf, TakeAll{}, i, m_orig[i]);
    });
    count[n] = 0;
    out.offsets.resize(std::size_t(n) + 1);
    scanCounts(count, std::size_t(n) + 1, out.offsets.data());
    out.key.resize(out.offsets[n]);
    out.hist.resize(out.offsets[n]);
    forEach(n, kGrain, [&](std::uint32_t i) {
      takeRow(offsets.data(), hist.data(), keyOf, TakeAll{}, i, m_orig[i], out.offsets[m_orig[i]], out.key.data(),
              out.hist.data());
    });
  }

  template <class KeyOf>
  void restoreRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets, const KeyOf& keyOf,
                   std::vector<Vec3f>& hist) {
    const std::uint32_t n = m_world.numParticles();
    hist.resize(offsets[n]);
    const KeptView k{kept.offsets.data(), kept.key.data(), kept.hist.data()};
    forEach(n, kGrain, [&](std::uint32_t i) { restoreRow(k, m_orig[i], offsets.data(), keyOf, i, hist.data()); });
  }

  // The entries with a key and a non-zero ξ that `take` accepts, as make(scene index, key, ξ),
  // sorted by (scene index, key): taken out of the rows of a list (count → scan → fill by scene
  // index, kernels/history.hpp, as the CUDA pipeline), or before the first rebuild (loaded, not
  // stepped) from the kept histories.
  template <class Out, class KeyOf, class Take, class Make>
  std::vector<Out> readRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets,
                            const std::vector<Vec3f>& hist, const KeyOf& keyOf, const Take& take, const Make& make) const {
    const std::uint32_t n = m_world.numParticles();
    if (!m_listBuilt)
      return tumble::detail::readRows<Out>(n, kept.offsets.data(), kept.key.data(), kept.hist.data(), take, make);
    std::vector<std::uint32_t> at(std::size_t(n) + 1, 0u);
    m_arena.execute([&] {
      forEach(n, kGrain, [&](std::uint32_t i) {
        at[m_orig[i] + 1] = takenCount(offsets.data(), hist.data(), keyOf, take, i, m_orig[i]);
      });
    });
    for (std::uint32_t o = 0; o < n; ++o) at[o + 1] += at[o];
    std::vector<std::uint32_t> key(at[n]);
    std::vector<Vec3f> taken(at[n]);
    m_arena.execute([&] {
      forEach(n, kGrain, [&](std::uint32_t i) {
        takeRow(offsets.data(), hist.data(), keyOf, take, i, m_orig[i], at[m_orig[i]], key.data(), taken.data());
      });
    });
    return tumble::detail::readRows<Out>(n, at.data(), key.data(), taken.data(), TakeAll{}, make);
  }

  void keepHistory() { keepRows(m_candOffsets, m_hist, PartnerKey{m_orig.data(), m_cand.data()}, m_keep); }
  void restoreHistory() { restoreRows(m_keep, m_candOffsets, PartnerKey{m_orig.data(), m_cand.data()}, m_hist); }

  // The histories of a loaded state (BodyState::contacts, i < j sorted) in the kept form.
  void keepLoadedHistory(const std::vector<ContactHistory>& contacts) {
    static_cast<tumble::detail::KeptRows&>(m_keep) = tumble::detail::keptOfContacts(m_world.numParticles(), contacts);
  }

  // BodyState::contacts: the non-zero ξ of the pairs i < j (scene indices), sorted.
  void readHistory(std::vector<ContactHistory>& out) const {
    out.clear();
    if (!m_history) return;
    out = readRows<ContactHistory>(m_keep, m_candOffsets, m_hist, PartnerKey{m_orig.data(), m_cand.data()}, TakeAbove{},
                                   tumble::detail::MakeContact{});
  }

  // The mesh springs: kept and restored by triangle; a loaded state's (BodyState::meshContacts,
  // sorted by (particle, triangle)) in the kept form.
  void keepMeshHistory() { keepRows(m_meshOffsets, m_meshHist, TriangleKey{m_meshTri.data()}, m_meshKeep); }
  void restoreMeshHistory() { restoreRows(m_meshKeep, m_meshOffsets, TriangleKey{m_meshTri.data()}, m_meshHist); }
  void keepLoadedMeshHistory(const std::vector<MeshContactHistory>& contacts) {
    static_cast<tumble::detail::KeptRows&>(m_meshKeep) =
        tumble::detail::keptOfMeshContacts(m_world.numParticles(), contacts);
  }
  void readMeshHistory(std::vector<MeshContactHistory>& out) const {
    out.clear();
    if (!m_hasMesh) return;
    out = readRows<MeshContactHistory>(m_meshKeep, m_meshOffsets, m_meshHist, TriangleKey{m_meshTri.data()}, TakeAll{},
                                       tumble::detail::MakeMeshContact{});
  }

  // The mesh candidate list at the current positions (those of the rebuild): per particle the
  // triangles whose grown box comes within r + skin/2 + margin (forTrianglesNear(); with moving
  // meshes forPosedTrianglesNear(), each mesh where this step's pose puts it), sorted by
  // triangle (so that the rows do not depend on the hierarchy), count → scan → fill. A particle
  // that has moved less than skin/2 − margin since, relative to the mesh (the skin test with
  // wallClosureOf() and the meshes' motion, MeshMotionBound), cannot touch a triangle outside
  // its row.
  void buildMeshList() { m_meshPoses.empty() ? buildMeshRows<false>() : buildMeshRows<true>(); }
  template <bool kPosed>
  void buildMeshRows() {
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
  void scanCounts(const std::uint32_t* count, std::size_t len, std::uint32_t* out) {
    std::size_t bytes = 0;
    exclusiveSum<std::uint32_t>(nullptr, bytes, count, out, len);
    exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, bytes), bytes, count, out, len);
  }

  // Renumbers the bodies in Morton order of their centres; particles follow their bodies.
  void reorder() {
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

  StepView stepView() {
    const int c = m_cur;
    return StepView{m_bodies.data(),
                    m_bodiesNext.data(),
                    m_bodyStatic.data(),
                    static_cast<std::uint32_t>(m_bodies.size()),
                    m_pos[c].data(),
                    m_pos[1 - c].data(),
                    m_own.data(),
                    m_radius.data(),
                    m_mass.data(),
                    m_bodyOf.data(),
                    m_orig.data(),
                    GroundSpringView{m_gtx.data(), m_gty.data()},
                    m_perBody ? nullptr : m_buildPos.data(),  // the skin test per particle, or per body (bodyRef)
                    contactListView(),
                    m_touching.data(),
                    m_world.numParticles(),
                    m_history ? m_hist.data() : nullptr,
                    m_world.params.contact.rotatesSpheres(),
                    m_world.materialPairs.empty() ? nullptr : m_world.materialPairs.data(),
                    m_material.empty() ? nullptr : m_material.data(),
                    static_cast<std::uint32_t>(m_world.params.materials.size()),
                    m_planes.data(),
                    static_cast<std::uint32_t>(m_planes.size()),
                    m_planeDamping.empty() ? nullptr : m_planeDamping.data(),
                    m_planeHertz.empty() ? nullptr : m_planeHertz.data(),
                    m_periodic,
                    m_mesh.view(m_meshPoses),
                    MeshListView{m_meshOffsets.data(), m_meshTri.data(), m_meshHist.data()},
                    m_perBody ? m_bodyRef.data() : nullptr,
                    m_owner.empty() ? nullptr : m_owner.data()};
  }

  mutable tbb::task_arena m_arena;
  bool m_reorder = true;
  World m_world;  // in the integration frame; static tables in scene order
  LocalFrame m_frame;
  bool m_clumps = false;
  std::vector<Wall> m_planes;     // the ground, then the walls (kernelWalls())
  bool m_wallsMove = false;            // some wall's surface moves (setWallMotion() before each step)
  std::vector<float> m_planeDamping;   // planes 1.. (World::planeDamping), internal numbering
  std::vector<HertzPair> m_planeHertz;
  ContactLaw m_law = ContactLaw::Report;
  PeriodicBox m_periodic;   // periodic boundaries in the integration frame (axes 0: none)
  float m_periodicGrowth = 0.0f;  // what the detection grows the radii by beyond skin/2 (periodicGrowth())
  cpu::detail::PeriodicImages m_images;  // the periodic detection's particles and ghosts
  bool m_history = false;   // the law keeps a tangential history per contact
  bool m_listBuilt = false; // a candidate list (and m_hist) exists since the load

  // Internal numbering (see the design notes).
  std::vector<BodyRow> m_bodies, m_bodiesNext;  // double-buffered: neighbours read this step's
  std::vector<BodyStatic> m_bodyStatic;
  std::vector<OwnRow> m_own;
  std::vector<float> m_radius, m_mass;
  std::vector<std::uint16_t> m_material;  // hertz-mindlin with several materials; else empty
  std::vector<std::uint32_t> m_orig;   // scene index of each particle
  std::vector<std::uint32_t> m_bodyOf; // body of each particle (the sweep skips same-body pairs)
  std::vector<float> m_gtx, m_gty;     // plane springs, plane-major (empty without planes)
  std::vector<PosRow> m_pos[2];        // particle rows, double-buffered: [m_cur] is this step's
  int m_cur = 0;
  bool m_perBody = false;            // the skin test per body (bodyDrift()), else per particle
  std::vector<BodyRef> m_bodyRef;    // the reference of the skin test per body: the bodies at the last refresh
  std::vector<PosRow> m_buildPos;    // that of the test per particle: their positions then
  std::vector<PosRow> m_rebuildPos;  // positions at the last rebuild
  std::vector<std::uint32_t> m_candOffsets, m_cand;
  std::vector<std::uint8_t> m_touching;  // the last step's contacts per particle (capped at 255)
  std::vector<Vec3f> m_hist;             // laws with a history: ξ per candidate-list entry
  // The histories kept across a rebuild (or from the load): CSR by scene index (keepHistory).
  KeptHistories m_keep, m_meshKeep;
  // Mesh walls: their kernels' data (in the integration frame) and the mesh candidate list,
  // rows by internal particle at m_meshOffsets, with the springs ξ per entry (buildMeshList()).
  KernelMesh m_mesh;
  bool m_hasMesh = false;
  // Moving meshes: their poses at the step's start (plane-indexed; empty when no mesh moves), the
  // bound on their motion for the skin test, and the time of the last rebuild.
  std::vector<MeshPose> m_meshPoses;
  MeshMotionBound m_meshMotion;
  double m_rebuildTime = 0.0;
  std::vector<std::uint32_t> m_meshOffsets, m_meshTri;
  std::vector<Vec3f> m_meshHist;
  float m_skin = 0.0f;
  bool m_needRebuild = true;
  // The near list (kernels/contact_list.hpp fillNear), compact.
  std::vector<std::uint32_t> m_nearOffsets, m_near, m_nearRoom;
  std::vector<std::uint32_t> m_owner;  // the particle of each entry of contactListView(); empty
                                       // under the laws with history (StepView::listOwner)
  float m_nearSkin = 0.0f;     // 0: no near list
  float m_fullLimit = 0.0f;    // the candidate list holds while m_closed + closure < this
  float m_nearLimit = 0.0f;    // the near list holds while its interval's closure < this
  double m_closed = 0.0;       // bound on the closure from the rebuild to the last refresh
  float m_lastClosure = 0.0f;  // closure of the current interval after the last step
  bool m_needRefresh = false;

  cpu::detail::Broadphase m_bp;
  // Scratch (grow-only).
  std::vector<float> m_bx, m_by, m_bz, m_br;
  std::vector<std::uint32_t> m_count, m_candKey, m_first;
  std::vector<std::uint32_t> m_roomOffsets, m_roomCand;  // buildPeriodicList(): rows before compaction
  std::vector<std::uint32_t> m_mKeys, m_mVals, m_mSortedKeys, m_perm;
  std::vector<std::byte> m_temp;
  std::vector<BodyStatic> m_bodyStaticTmp;
  std::vector<OwnRow> m_ownTmp;
  std::vector<float> m_radiusTmp, m_massTmp, m_gtxTmp, m_gtyTmp, m_planeDampingTmp;
  std::vector<std::uint16_t> m_materialTmp;
  std::vector<std::uint32_t> m_origTmp, m_bodyOfTmp;
  std::vector<float> m_dbg[5], m_dbgVel;
  struct PairChunk {
    std::vector<std::uint32_t> i, j;
  };
  mutable std::vector<PairChunk> m_pairChunks;  // pairs() scratch
  mutable std::vector<std::uint32_t> m_pairI, m_pairJ, m_pairSortedI, m_pairSortedJ;
  mutable std::vector<std::byte> m_pairTemp;
  mutable std::vector<std::uint32_t> m_internal;  // internalBodies() scratch

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

std::unique_ptr<HaloPipeline> makeCpuHaloPipeline(const PipelineOptions& options) {
  return std::make_unique<CpuPipeline>(options);
}

}  // namespace tumble::cpu
