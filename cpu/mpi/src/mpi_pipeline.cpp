// SPDX-License-Identifier: MIT
// The MPI pipeline (tumble/mpi/mpi_pipeline.hpp, docs/mpi.md): one run over the ranks of
// MPI_COMM_WORLD, bit-identical to one process.
//
// Design notes
// - Every rank holds the whole static world (the tables of every body and particle) and runs a
//   pipeline (HaloPipeline: the CPU pipeline, or the CUDA pipeline on the rank's device or on the
//   host backend) on a *local world*: the bodies it owns and ghost copies of every
//   body with a particle near its own. Local bodies are in ascending scene index, so the local
//   pipeline's canonical order (ascending scene index of the partner, kernels/contact_list.hpp)
//   is the global one, and the local world integrates in the global run's frame (LocalFrame of
//   the whole world, or the checkpoint's), never one of its own.
// - Why the bits match: an owned particle's force reads only its own row, its body's, and its
//   partners' positions and bodies' rows, summed in ascending scene index; a body's integration
//   reads only its particles' forces. Every partner of an owned particle is local (the halo,
//   below), and every row it reads is the one the single process has: after each step each
//   ghost's whole row (X, V, Q, L and the Ω and R its owner's integration produced) is
//   overwritten by its owner's (HaloPipeline::writeMotion), and its particles' positions
//   recomputed. A ghost's own forces may miss partners beyond the halo: they are computed and
//   thrown away. Nothing is summed across ranks but a max, a min and integers.
// - The halo: at a redistribution, every body with a particle inside the bounding box of a rank's
//   particles grown by 2 r_max + s (plus a margin for rounding) is local to it (ghostsOf()). It
//   holds until two particles may have closed in by s: after each step the drift of every
//   particle since the redistribution (its owner's: a max of |Δx|² and the box of the Δx, as the
//   skin test) is reduced over the ranks (MPI_Allreduce of a max: exact in any order), and the
//   next step first redistributes when the closure reaches the limit (skinClosureLimit(s)). s is
//   twice the run's skin (the automatic skin when the run's is 0), so that redistributions are
//   rarer than the local pipelines' own rebuilds, which change no bit and stay theirs.
// - A redistribution is the migration and the rebalance: the owners' state (bodies, plane
//   springs, contact histories with the lower particle owned, mesh springs) is gathered on every
//   rank in scene order (MPI_Allgatherv), the domain is cut afresh by particle count
//   (decompose()), and each rank loads its new local world: a resume from that state, which the
//   checkpoints prove exact.
//   It costs O(N) memory and traffic per rank (docs/mpi.md says what a distributed migration would
//   change).
// - Collective reads (readState, readLocalPositions, pairs, meshContacts, contactSumsPerBody,
//   readDebug) gather the owners' rows into scene order on every rank, so the guards, the time
//   series, the checkpoints and the recordings run unchanged on top, the same on every rank; only
//   rank 0 writes (tumble run).
// - Failures: a rank whose step throws still joins the step's reduction, which carries a flag and
//   the lowest diverged particle; then every rank throws the same error (agree()).
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "agree.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/mpi/mpi_pipeline.hpp"

namespace tumble::mpi {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr int kGhostTag = 15;

/// A body's state as BodyState holds it (a redistribution's gather).
struct BodyRecord {
  float x[3], v[3], q[4], l[3];
};
static_assert(std::is_trivially_copyable_v<BodyRecord>, "sent as bytes");

/// What every step reduces over the ranks: the owned particles' drift since the redistribution
/// (a Drift: max |Δx|² and the box of the Δx, merged by mergeDrift()), whether a rank failed otherwise,
/// the lowest diverged particle (scene index; INT64_MAX for none), and the touching contacts of
/// the owned particles (each contact twice over the ranks). Max, min and integer sum: exact in any
/// order.
struct StepReduce {
  Drift drift;
  std::int32_t failed;
  std::int64_t bad;
  std::uint64_t contacts;
};

void reduceSteps(void* in, void* inout, int* len, MPI_Datatype*) {
  const StepReduce* a = static_cast<const StepReduce*>(in);
  StepReduce* b = static_cast<StepReduce*>(inout);
  for (int k = 0; k < *len; ++k) {
    mergeDrift(b[k].drift, a[k].drift);
    b[k].failed = std::max(b[k].failed, a[k].failed);
    b[k].bad = std::min(b[k].bad, a[k].bad);
    b[k].contacts += a[k].contacts;
  }
}

/// Every rank's `mine` concatenated in rank order (MPI_Allgatherv of bytes); `received` gains the
/// bytes this rank received.
template <class T>
std::vector<T> allGather(MPI_Comm comm, int size, const std::vector<T>& mine, std::uint64_t* received) {
  static_assert(std::is_trivially_copyable_v<T>, "sent as bytes");
  const long long myBytes = static_cast<long long>(mine.size() * sizeof(T));
  std::vector<long long> all(static_cast<std::size_t>(size));
  MPI_Allgather(&myBytes, 1, MPI_LONG_LONG, all.data(), 1, MPI_LONG_LONG, comm);
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
  long long total = 0;
  for (int r = 0; r < size; ++r) {
    displs[static_cast<std::size_t>(r)] = static_cast<int>(total);
    counts[static_cast<std::size_t>(r)] = static_cast<int>(all[static_cast<std::size_t>(r)]);
    total += all[static_cast<std::size_t>(r)];
    if (total > INT_MAX)
      throw Error("a gather of the state over the ranks exceeds 2 GiB (" + std::to_string(total) +
                  " bytes): the MPI pipeline gathers the whole state on every rank (docs/mpi.md#limits)");
  }
  std::vector<T> out(static_cast<std::size_t>(total) / sizeof(T));
  MPI_Allgatherv(mine.data(), static_cast<int>(myBytes), MPI_BYTE, out.data(), counts.data(), displs.data(), MPI_BYTE,
                 comm);
  *received += static_cast<std::uint64_t>(total - myBytes);
  return out;
}

class MpiPipelineImpl final : public MpiPipeline {
 public:
  MpiPipelineImpl(const PipelineOptions& o, Decomposition how, Backend backend)
      : m_options(o), m_how(how), m_backend(backend) {
    int on = 0;
    MPI_Initialized(&on);
    if (!on) throw Error("the MPI pipeline needs MPI started (tumble::mpi::Session, under mpirun)");
    MPI_Comm_dup(MPI_COMM_WORLD, &m_comm);
    MPI_Comm_rank(m_comm, &m_rank);
    MPI_Comm_size(m_comm, &m_size);
    MPI_Type_contiguous(sizeof(StepReduce), MPI_BYTE, &m_reduceType);
    MPI_Type_commit(&m_reduceType);
    MPI_Op_create(&reduceSteps, 1, &m_reduceOp);
    m_mpi.rank = m_rank;
  }

  ~MpiPipelineImpl() override {
    int done = 0;
    MPI_Finalized(&done);
    if (done) return;
    MPI_Op_free(&m_reduceOp);
    MPI_Type_free(&m_reduceType);
    MPI_Comm_free(&m_comm);
  }

  Backend backend() const override { return m_backend; }
  Decomposition decomposition() const override { return m_how; }

  void load(const World& world) override {
    if (world.numParticles() == 0) throw Error("cannot load an empty world");
    if (world.params.periodic.any())
      throw NotSupported("periodic boundaries ([periodic]) under mpirun: not yet (docs/mpi.md#limits); run without mpirun");
    LocalFrame frame;
    World lw = localWorld(world, &frame);  // the state in the run's frame; checks the sizes
    m_global = world;  // its state stays: what a divergence message's advice reads
    m_global.frame.reset();
    m_global.params.pourBodies.clear();  // the drivers' Pouring keeps its own
    m_frame = frame;
    m_skin = effectiveSkin(world);
    m_haloSkin = m_skin > 0.0f ? kHaloSkinPerSkin * m_skin : effectiveSkin(-1.0f, world.sizingRadius, world.maxRadius);
    m_haloLimit = skinClosureLimit(m_haloSkin, world.maxRadius);
    m_clumps = world.hasClumps || world.params.contact.rotatesSpheres();
    m_time = world.time;
    m_step0 = world.step;
    m_steps = 0;
    m_pulls = world.params.pulls.active & 7u & ~world.params.periodic.conflictingPulls();
    m_hasDebug = false;
    m_numPairs = 0;
    m_tally.clear();
    m_before = StepStats{};
    m_mpi = MpiStats{};
    m_mpi.rank = m_rank;
    m_local.reset();
    redistribute(lw.state);
  }

  void step(std::uint64_t n) override {
    if (m_global.numBodies() == 0) throw Error("step() before load()");
    for (std::uint64_t s = 0; s < n; ++s) stepOnce();
  }

  void readState(BodyState& out) const override {
    readLocalState(out);
    toWorld(out, m_frame);
  }
  LocalFrame frame() const override { return m_frame; }
  void readLocalState(BodyState& out) const override { out = gatherState(m_mpi.counts.readBytes); }

  void readLocalPositions(std::vector<float>& out) const override {
    std::vector<float> mine;
    if (m_local) {
      m_local->readLocalPositions(m_buf);
      mine.reserve(3 * m_ownedParticles.size());
      for (const std::uint32_t p : m_ownedParticles) mine.insert(mine.end(), &m_buf[3 * std::size_t(p)], &m_buf[3 * std::size_t(p)] + 3);
    }
    const std::vector<float> all = allGather(m_comm, m_size, mine, &m_mpi.counts.readBytes);
    out.resize(3 * std::size_t(m_global.numParticles()));
    std::size_t at = 0;
    forOwnedParticles([&](std::uint32_t i) {
      std::memcpy(&out[3 * std::size_t(i)], &all[at], 3 * sizeof(float));
      at += 3;
    });
  }

  std::vector<Pair> pairs() const override {
    std::vector<Pair> mine;
    if (m_local)
      for (const Pair& p : m_local->pairs())
        if (m_particleOwned[p.i]) mine.push_back(Pair{m_particleGlobal[p.i], m_particleGlobal[p.j]});
    std::vector<Pair> all = allGather(m_comm, m_size, mine, &m_mpi.counts.readBytes);
    std::sort(all.begin(), all.end());  // each rank's are sorted; the keys are unique
    return all;
  }

  std::vector<MeshContact> meshContacts() const override {
    std::vector<MeshContact> mine;
    if (m_local)
      for (const MeshContact& c : m_local->meshContacts())
        if (m_particleOwned[c.particle]) mine.push_back(MeshContact{m_particleGlobal[c.particle], c.triangle});
    std::vector<MeshContact> all = allGather(m_comm, m_size, mine, &m_mpi.counts.readBytes);
    std::sort(all.begin(), all.end());  // each rank's are sorted; the keys are unique
    return all;
  }

  bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const override {
    std::vector<ContactSums> mine;
    if (m_local) {
      SpringLaw local = law;
      std::vector<std::uint16_t> material;
      if (law.material != nullptr) {  // the law's materials are in scene order: the local world's
        material.resize(m_particleGlobal.size());
        for (std::size_t i = 0; i < material.size(); ++i) material[i] = law.material[m_particleGlobal[i]];
        local.material = material.data();
      }
      std::vector<ContactSums> sums;
      if (!m_local->contactSumsPerBody(local, sums)) throw Error("the MPI pipeline's ranks must sum their contacts");
      mine.reserve(m_owned.size());
      for (const std::uint32_t b : m_owned) {
        ContactSums s = sums[b];
        if (s.maxOverlap > 0.0) {
          s.deepestI = m_particleGlobal[s.deepestI];
          s.deepestJ = m_particleGlobal[s.deepestJ];
        }
        mine.push_back(s);
      }
    }
    const std::vector<ContactSums> all = allGather(m_comm, m_size, mine, &m_mpi.counts.readBytes);
    out.assign(m_global.numBodies(), ContactSums{});
    std::size_t at = 0;
    for (int r = 0; r < m_size; ++r)
      for (const std::uint32_t b : m_ownedBy[static_cast<std::size_t>(r)]) out[b] = all[at++];
    return true;
  }

  // Every rank finds the pairs of the whole cloud (the guard's first measurement only): the same
  // answer everywhere, no communication.
  std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) override {
    if (!m_finder) m_finder = tumble::makePipeline(m_backend, m_options);
    return m_finder->findPairs(cloud, bp);
  }

  void readDebug(ParticleDebug& out) const override {
    if (!m_hasDebug) throw Error("readDebug(): enable setDebugCapture(true) and run a step first");
    std::vector<float> mine;
    std::vector<ContactForce> myContacts;  // of the contacts whose particle i this rank owns, as pairs()
    if (m_local) {
      ParticleDebug d;
      m_local->readDebug(d);
      for (ContactForce c : d.contactForces)
        if (m_particleOwned[c.i]) {
          c.i = m_particleGlobal[c.i];
          c.j = m_particleGlobal[c.j];
          myContacts.push_back(c);
        }
      mine.reserve(18 * m_ownedParticles.size());
      for (const std::uint32_t p : m_ownedParticles) {
        const float* v = &d.v[3 * std::size_t(p)];
        mine.insert(mine.end(), v, v + 3);
        for (const auto& f : d.force) mine.insert(mine.end(), &f[3 * std::size_t(p)], &f[3 * std::size_t(p)] + 3);
      }
    }
    const std::vector<float> all = allGather(m_comm, m_size, mine, &m_mpi.counts.readBytes);
    const std::size_t n = m_global.numParticles();
    out.v.resize(3 * n);
    for (auto& f : out.force) f.resize(3 * n);
    std::size_t at = 0;
    forOwnedParticles([&](std::uint32_t i) {
      std::memcpy(&out.v[3 * std::size_t(i)], &all[at], 3 * sizeof(float));
      for (int k = 0; k < 5; ++k) std::memcpy(&out.force[k][3 * std::size_t(i)], &all[at + 3 + 3 * std::size_t(k)], 3 * sizeof(float));
      at += 18;
    });
    out.contacts = pairs();
    out.contactForces = allGather(m_comm, m_size, myContacts, &m_mpi.counts.readBytes);
    std::sort(out.contactForces.begin(), out.contactForces.end());  // each rank's are sorted; the keys are unique
  }

  void setDebugCapture(bool on) override {
    m_debug = on;
    if (m_local) m_local->setDebugCapture(on);
  }
  // Collective: every rank calls it alike (each step then sums the ranks' tallies).
  void setEnergyTally(bool on) override {
    m_tallyOn = on;
    if (m_local) m_local->setEnergyTally(on);
  }
  void setPulls(std::uint32_t mask) override {
    m_pulls = mask & 7u & ~m_global.params.periodic.conflictingPulls();
    if (m_local) m_local->setPulls(m_pulls);
  }
  std::uint32_t pulls() const override { return m_pulls; }

  // The run's counters: its steps and contacts (global), this rank's pipeline's rebuilds and times.
  const StepStats& stats() const override {
    m_stats = m_before;
    if (m_local) m_stats.add(m_local->stats());
    m_stats.steps = m_steps - m_statsFrom;
    m_stats.numPairs = m_numPairs;
    m_stats.skin = m_skin;
    m_stats.energy = m_tally.joules();  // the ranks' sum (the local pipelines' hold their own bodies and ghosts)
    return m_stats;
  }
  void resetStats() override {
    m_before = StepStats{};
    if (m_local) m_local->resetStats();
    m_statsFrom = m_steps;
    m_tally.clear();
    m_mpi.counts = MpiStats::Counts{};  // the decomposition stays
  }
  double time() const override { return m_time; }
  std::uint64_t stepCount() const override { return m_step0 + m_steps; }

  std::vector<MpiStats> gatherStats() const override {
    MpiStats mine = m_mpi;
    mine.counts.steps = m_steps - m_statsFrom;
    std::vector<MpiStats> all(static_cast<std::size_t>(m_size));
    MPI_Allgather(&mine, sizeof(MpiStats), MPI_BYTE, all.data(), sizeof(MpiStats), MPI_BYTE, m_comm);
    return all;
  }

 private:
  void stepOnce() {
    if (m_needRedistribute) {
      const auto t0 = Clock::now();
      redistribute(gatherState(m_mpi.counts.redistributeBytes));
      m_mpi.counts.redistributeSeconds += since(t0);
    }
    StepReduce mine{noDrift(), 0, std::numeric_limits<std::int64_t>::max(), 0};
    std::exception_ptr failure;
    auto t0 = Clock::now();
    if (m_local) {
      try {
        m_local->step(1);
      } catch (const SimulationError& e) {  // a non-finite position: named by its scene index
        if (e.particle() >= 0 && std::size_t(e.particle()) < m_particleGlobal.size())
          mine.bad = m_particleGlobal[static_cast<std::size_t>(e.particle())];
        else
          failure = std::current_exception();
      } catch (...) {
        failure = std::current_exception();
      }
      if (mine.bad == std::numeric_limits<std::int64_t>::max() && !failure) {
        m_local->readLocalPositions(m_buf);
        for (std::size_t k = 0; k < m_ownedParticles.size(); ++k) {
          const float* x = &m_buf[3 * std::size_t(m_ownedParticles[k])];
          const float* r = &m_ref[3 * k];
          addDisplacement(mine.drift, x[0] - r[0], x[1] - r[1], x[2] - r[2]);
        }
        mine.contacts = m_local->contactsOf(m_owned);
      }
    }
    mine.failed = failure ? 1 : 0;
    m_mpi.counts.stepSeconds += since(t0);
    t0 = Clock::now();
    StepReduce all{};
    MPI_Allreduce(&mine, &all, 1, m_reduceType, m_reduceOp, m_comm);
    m_mpi.counts.reduceBytes += sizeof(StepReduce);
    if (all.failed) detail::agree(m_comm, failure);
    if (all.bad != std::numeric_limits<std::int64_t>::max()) {
      const auto particle = static_cast<std::uint32_t>(all.bad);
      throw SimulationError(divergenceMessage(m_global, stepCount(), particle), all.bad);
    }
    if (m_tallyOn) {  // the owners' bodies: exact integer sums, so any rank count gives the same
      const EnergyLimbs mineE = m_local ? m_local->energyOf(m_owned) : noLimbs();
      EnergyLimbs allE;
      MPI_Allreduce(&mineE, &allE, sizeof(EnergyLimbs) / sizeof(unsigned long long), MPI_UINT64_T, MPI_SUM, m_comm);
      m_mpi.counts.reduceBytes += sizeof(EnergyLimbs);
      m_tally.add(allE);
    }
    exchangeGhosts();
    m_mpi.counts.exchangeSeconds += since(t0);
    ++m_steps;
    m_time += m_global.params.dt;
    m_hasDebug = m_debug;  // readDebug() reads the last step's capture, or refuses
    m_numPairs = all.contacts / 2;
    m_needRedistribute = !listStillValid(all.drift, m_haloLimit);
  }

  // After a step: each owner sends its bodies' rows to the ranks that hold them as ghosts, and
  // each ghost's row is overwritten by its owner's (the exchange's order does not matter: every
  // ghost has one writer).
  void exchangeGhosts() {
    if (!m_local) return;  // no bodies, so no ghosts and nothing to send
    m_local->readMotion(m_sendAll, m_sendBuf);
    m_recvBuf.resize(m_recvAll.size());
    std::vector<MPI_Request>& requests = m_requests;  // kept: no allocation once sized
    requests.clear();
    for (int r = 0; r < m_size; ++r) {
      const std::size_t a = m_recvOffsets[std::size_t(r)], e = m_recvOffsets[std::size_t(r) + 1];
      if (e > a) {
        requests.emplace_back();
        MPI_Irecv(&m_recvBuf[a], static_cast<int>((e - a) * sizeof(BodyMotion)), MPI_BYTE, r, kGhostTag, m_comm,
                  &requests.back());
      }
    }
    for (int r = 0; r < m_size; ++r) {
      const std::size_t a = m_sendOffsets[std::size_t(r)], e = m_sendOffsets[std::size_t(r) + 1];
      if (e > a) {
        requests.emplace_back();
        MPI_Isend(&m_sendBuf[a], static_cast<int>((e - a) * sizeof(BodyMotion)), MPI_BYTE, r, kGhostTag, m_comm,
                  &requests.back());
        m_mpi.counts.haloBytes += (e - a) * sizeof(BodyMotion);
        ++m_mpi.counts.haloMessages;
      }
    }
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    if (!m_recvAll.empty()) m_local->writeMotion(m_recvAll, m_recvBuf);
  }

  // Calls f(i) for every particle (scene index) in the order the ranks' gathers hold them: rank
  // by rank, its bodies in ascending index, each body's particles in order.
  template <class F>
  void forOwnedParticles(F&& f) const {
    for (int r = 0; r < m_size; ++r)
      for (const std::uint32_t b : m_ownedBy[static_cast<std::size_t>(r)])
        for (std::uint32_t i = m_global.first[b]; i < m_global.first[b] + m_global.numParticlesOf[b]; ++i) f(i);
  }

  // The whole state in the run's frame, scene order, on every rank (collective): each owner's
  // bodies, the plane springs of its particles, the contact histories (i, j) with i its own, and
  // its particles' mesh springs.
  BodyState gatherState(std::uint64_t& received) const {
    const std::size_t planes = m_global.params.planes().size();
    std::vector<BodyRecord> bodies;
    std::vector<float> springs;
    std::vector<ContactHistory> history;
    std::vector<MeshContactHistory> meshHistory;
    if (m_local) {
      BodyState s;
      m_local->readLocalState(s);
      bodies.reserve(m_owned.size());
      for (const std::uint32_t b : m_owned)
        bodies.push_back(BodyRecord{{s.px[b], s.py[b], s.pz[b]},
                                    {s.vx[b], s.vy[b], s.vz[b]},
                                    {s.qw[b], s.qx[b], s.qy[b], s.qz[b]},
                                    {s.lx[b], s.ly[b], s.lz[b]}});
      const std::size_t n = m_particleGlobal.size();
      springs.reserve(2 * planes * m_ownedParticles.size());
      for (std::size_t p = 0; p < planes; ++p)
        for (const std::uint32_t i : m_ownedParticles) {
          springs.push_back(s.groundSpringX[p * n + i]);
          springs.push_back(s.groundSpringY[p * n + i]);
        }
      for (const ContactHistory& c : s.contacts)
        if (m_particleOwned[c.i]) history.push_back(ContactHistory{m_particleGlobal[c.i], m_particleGlobal[c.j], c.x, c.y, c.z});
      for (const MeshContactHistory& c : s.meshContacts)
        if (m_particleOwned[c.particle])
          meshHistory.push_back(MeshContactHistory{m_particleGlobal[c.particle], c.triangle, c.x, c.y, c.z});
    }
    const std::vector<BodyRecord> allBodies = allGather(m_comm, m_size, bodies, &received);
    const std::vector<float> allSprings = allGather(m_comm, m_size, springs, &received);
    std::vector<ContactHistory> allHistory = allGather(m_comm, m_size, history, &received);
    std::vector<MeshContactHistory> allMeshHistory = allGather(m_comm, m_size, meshHistory, &received);

    BodyState out;
    const std::uint32_t nb = m_global.numBodies(), np = m_global.numParticles();
    out.resize(nb);
    std::size_t at = 0;
    for (int r = 0; r < m_size; ++r)
      for (const std::uint32_t b : m_ownedBy[static_cast<std::size_t>(r)]) {
        const BodyRecord& x = allBodies[at++];
        out.px[b] = x.x[0], out.py[b] = x.x[1], out.pz[b] = x.x[2];
        out.vx[b] = x.v[0], out.vy[b] = x.v[1], out.vz[b] = x.v[2];
        out.qw[b] = x.q[0], out.qx[b] = x.q[1], out.qy[b] = x.q[2], out.qz[b] = x.q[3];
        out.lx[b] = x.l[0], out.ly[b] = x.l[1], out.lz[b] = x.l[2];
      }
    out.groundSpringX.resize(planes * np);
    out.groundSpringY.resize(planes * np);
    at = 0;
    for (int r = 0; r < m_size; ++r) {
      // Rank r's springs: plane-major over its particles (as packed above).
      std::size_t rankParticles = 0;
      for (const std::uint32_t b : m_ownedBy[static_cast<std::size_t>(r)]) rankParticles += m_global.numParticlesOf[b];
      for (std::size_t p = 0; p < planes; ++p) {
        std::size_t k = 0;
        for (const std::uint32_t b : m_ownedBy[static_cast<std::size_t>(r)])
          for (std::uint32_t i = m_global.first[b]; i < m_global.first[b] + m_global.numParticlesOf[b]; ++i, ++k) {
            out.groundSpringX[p * np + i] = allSprings[at + 2 * (p * rankParticles + k)];
            out.groundSpringY[p * np + i] = allSprings[at + 2 * (p * rankParticles + k) + 1];
          }
      }
      at += 2 * planes * rankParticles;
    }
    std::sort(allHistory.begin(), allHistory.end(), [](const ContactHistory& a, const ContactHistory& b) {
      return a.i != b.i ? a.i < b.i : a.j < b.j;  // unique keys
    });
    out.contacts = std::move(allHistory);
    std::sort(allMeshHistory.begin(), allMeshHistory.end(), [](const MeshContactHistory& a, const MeshContactHistory& b) {
      return a.particle != b.particle ? a.particle < b.particle : a.triangle < b.triangle;  // unique keys
    });
    out.meshContacts = std::move(allMeshHistory);
    return out;
  }

  // Cuts the domain afresh for `state` (the whole state, run's frame, scene order) and loads each
  // rank's world: owned bodies and ghosts in ascending scene index.
  void redistribute(const BodyState& state) {
    const World& g = m_global;
    const std::uint32_t nb = g.numBodies(), np = g.numParticles();
    // The particles' positions (the pipelines' expression; they only decide the halo).
    std::vector<float> pos(3 * std::size_t(np));
    std::vector<Vec3f> centres(nb);
    for (std::uint32_t k = 0; k < nb; ++k) {
      const Vec3f X{state.px[k], state.py[k], state.pz[k]};
      const Mat3f R = rotationMatrix(Quatf{state.qw[k], state.qx[k], state.qy[k], state.qz[k]});
      centres[k] = X;
      for (std::uint32_t i = g.first[k]; i < g.first[k] + g.numParticlesOf[k]; ++i) {
        const Vec3f x = m_clumps ? particlePosition(X, R, Vec3f{g.ux[i], g.uy[i], g.uz[i]}) : X;
        pos[3 * std::size_t(i)] = x.x;
        pos[3 * std::size_t(i) + 1] = x.y;
        pos[3 * std::size_t(i) + 2] = x.z;
      }
    }
    // The halo's reach (haloReach()): every particle within 2 r_max + s of one of the rank's
    // (s with a JKR neck's reach, neckReach()), and a margin for the rounding of the positions compared.
    double largest = 0.0;
    for (std::size_t c = 0; c < pos.size(); ++c) {
      if (!std::isfinite(pos[c])) {  // as the pipeline's detection says it (the first such particle)
        const auto i = static_cast<std::uint32_t>(c / 3);
        throw SimulationError(divergenceMessage(m_global, stepCount(), i), i);
      }
      largest = std::max(largest, std::abs(double(pos[c])));
    }
    const double reach = haloReach(g.maxRadius, m_haloSkin + neckReach(g), largest);
    const std::vector<int> owner = decompose(centres, g.numParticlesOf, m_size, m_how);
    const std::vector<std::vector<std::uint32_t>> ghosts = ghostsOf(owner, pos, g.first, g.numParticlesOf, m_size, reach);
    const auto me = static_cast<std::size_t>(m_rank);

    m_ownedBy.assign(static_cast<std::size_t>(m_size), {});
    for (std::uint32_t k = 0; k < nb; ++k) m_ownedBy[static_cast<std::size_t>(owner[k])].push_back(k);
    std::vector<std::uint32_t> local;
    std::merge(m_ownedBy[me].begin(), m_ownedBy[me].end(), ghosts[me].begin(), ghosts[me].end(), std::back_inserter(local));
    auto localOf = [&](std::uint32_t body) {
      return static_cast<std::uint32_t>(std::lower_bound(local.begin(), local.end(), body) - local.begin());
    };
    // What this rank sends after each step (its bodies that are ghosts elsewhere, by rank) and
    // what it receives (its ghosts, by owner), as local indices in ascending scene index.
    m_sendAll.clear();
    m_sendOffsets.assign(1, 0);
    m_recvAll.clear();
    m_recvOffsets.assign(1, 0);
    m_mpi.neighbours = 0;
    for (int r = 0; r < m_size; ++r) {
      if (static_cast<std::size_t>(r) != me)
        for (const std::uint32_t b : ghosts[static_cast<std::size_t>(r)])
          if (owner[b] == m_rank) m_sendAll.push_back(localOf(b));
      for (const std::uint32_t b : ghosts[me])
        if (owner[b] == r) m_recvAll.push_back(localOf(b));
      if (m_sendAll.size() > m_sendOffsets.back()) ++m_mpi.neighbours;
      m_sendOffsets.push_back(m_sendAll.size());
      m_recvOffsets.push_back(m_recvAll.size());
    }
    m_owned.clear();
    for (const std::uint32_t b : m_ownedBy[me]) m_owned.push_back(localOf(b));
    m_particleGlobal.clear();
    m_particleOwned.clear();
    m_ownedParticles.clear();
    for (const std::uint32_t b : local)
      for (std::uint32_t i = g.first[b]; i < g.first[b] + g.numParticlesOf[b]; ++i) {
        if (owner[b] == m_rank) m_ownedParticles.push_back(static_cast<std::uint32_t>(m_particleGlobal.size()));
        m_particleOwned.push_back(owner[b] == m_rank ? 1 : 0);
        m_particleGlobal.push_back(i);
      }
    m_mpi.ownedBodies = m_owned.size();
    m_mpi.ghostBodies = local.size() - m_owned.size();
    m_mpi.ownedParticles = m_ownedParticles.size();
    m_mpi.ghostParticles = m_particleGlobal.size() - m_ownedParticles.size();
    ++m_mpi.counts.redistributions;

    // The local pipeline on the new world (a resume from `state`), its counters kept.
    if (m_local) m_before.add(m_local->stats());
    std::exception_ptr failure;
    try {
      if (local.empty()) {
        m_local.reset();
      } else {
        if (!m_local) m_local = makeHaloPipeline(m_backend, m_options);
        m_local->load(worldOf(local, state));
        m_local->setPulls(m_pulls);
        m_local->setDebugCapture(m_debug);
        m_local->setEnergyTally(m_tallyOn);
        m_local->readLocalPositions(m_buf);
        m_ref.resize(3 * m_ownedParticles.size());
        for (std::size_t k = 0; k < m_ownedParticles.size(); ++k)
          std::memcpy(&m_ref[3 * k], &m_buf[3 * std::size_t(m_ownedParticles[k])], 3 * sizeof(float));
      }
    } catch (...) {
      failure = std::current_exception();
    }
    detail::agree(m_comm, failure);
    m_needRedistribute = false;
  }

  // The world of the bodies `local` (ascending scene indices) with their part of `state` (the
  // run's frame): every column of World, sliced; the scene's parameters, skin and frame are the
  // run's, so the local pipeline integrates exactly as the single process does. A new column of
  // World (or of BodyState) must be sliced here too.
  World worldOf(const std::vector<std::uint32_t>& local, const BodyState& state) const {
    const World& g = m_global;
    const std::size_t planes = g.params.planes().size();
    const std::uint32_t np = g.numParticles();
    World w;
    w.params = g.params;
    w.params.broadphase.skin = m_skin;  // the run's, not the automatic one of the local radii
    w.materialPairs = g.materialPairs;
    w.planeHertz = g.planeHertz;
    std::vector<std::uint32_t> toLocal(np, UINT32_MAX);
    for (std::uint32_t k = 0; k < local.size(); ++k) {
      const std::uint32_t b = local[k];
      w.bodyMass.push_back(g.bodyMass[b]);
      w.invMass.push_back(g.invMass[b]);
      w.invInertia.push_back(g.invInertia[b]);
      w.inertia.push_back(g.inertia[b]);
      w.first.push_back(w.numParticles());
      w.numParticlesOf.push_back(g.numParticlesOf[b]);
      w.bodyToShape.push_back(g.bodyToShape[b]);
      for (std::uint32_t i = g.first[b]; i < g.first[b] + g.numParticlesOf[b]; ++i) {
        toLocal[i] = w.numParticles();
        w.radius.push_back(g.radius[i]);
        w.mass.push_back(g.mass[i]);
        w.elasticity.push_back(g.elasticity[i]);
        w.groundDamping.push_back(g.groundDamping[i]);
        w.body.push_back(k);
        if (!g.material.empty()) w.material.push_back(g.material[i]);
        w.ux.push_back(g.ux[i]);
        w.uy.push_back(g.uy[i]);
        w.uz.push_back(g.uz[i]);
      }
    }
    const std::uint32_t n = w.numParticles();
    if (!g.planeDamping.empty()) {
      w.planeDamping.resize((planes - 1) * n);
      for (std::size_t p = 0; p + 1 < planes; ++p)
        for (std::uint32_t i = 0; i < n; ++i) w.planeDamping[p * n + i] = g.planeDamping[p * np + m_particleGlobal[i]];
    }
    BodyState& s = w.state;
    s.resize(local.size());
    for (std::size_t k = 0; k < local.size(); ++k) {
      const std::uint32_t b = local[k];
      s.px[k] = state.px[b], s.py[k] = state.py[b], s.pz[k] = state.pz[b];
      s.vx[k] = state.vx[b], s.vy[k] = state.vy[b], s.vz[k] = state.vz[b];
      s.qw[k] = state.qw[b], s.qx[k] = state.qx[b], s.qy[k] = state.qy[b], s.qz[k] = state.qz[b];
      s.lx[k] = state.lx[b], s.ly[k] = state.ly[b], s.lz[k] = state.lz[b];
    }
    if (!state.groundSpringX.empty()) {
      s.groundSpringX.resize(planes * n);
      s.groundSpringY.resize(planes * n);
      for (std::size_t p = 0; p < planes; ++p)
        for (std::uint32_t i = 0; i < n; ++i) {
          s.groundSpringX[p * n + i] = state.groundSpringX[p * np + m_particleGlobal[i]];
          s.groundSpringY[p * n + i] = state.groundSpringY[p * np + m_particleGlobal[i]];
        }
    }
    for (const ContactHistory& c : state.contacts)  // sorted by (i, j); toLocal keeps the order
      if (toLocal[c.i] != UINT32_MAX && toLocal[c.j] != UINT32_MAX)
        s.contacts.push_back(ContactHistory{toLocal[c.i], toLocal[c.j], c.x, c.y, c.z});
    for (const MeshContactHistory& c : state.meshContacts)  // sorted likewise
      if (toLocal[c.particle] != UINT32_MAX)
        s.meshContacts.push_back(MeshContactHistory{toLocal[c.particle], c.triangle, c.x, c.y, c.z});
    w.step = stepCount();
    w.time = m_time;
    w.frame = m_frame;
    w.bodiesExtent = g.bodiesExtent;
    w.hasClumps = g.hasClumps;
    w.maxRadius = g.maxRadius;
    w.maxExtent = g.maxExtent;
    w.sizingRadius = g.sizingRadius;
    return w;
  }

  PipelineOptions m_options;
  Decomposition m_how;
  Backend m_backend;  // the pipeline each rank runs
  MPI_Comm m_comm = MPI_COMM_NULL;
  MPI_Datatype m_reduceType = MPI_DATATYPE_NULL;
  MPI_Op m_reduceOp = MPI_OP_NULL;
  int m_rank = 0, m_size = 1;

  World m_global;  // the whole static world (state dropped), params in the world frame
  LocalFrame m_frame;
  float m_skin = 0.0f, m_haloSkin = 0.0f, m_haloLimit = 0.0f;
  bool m_clumps = false;
  std::unique_ptr<HaloPipeline> m_local;  // null on a rank without bodies
  std::unique_ptr<Pipeline> m_finder;          // findPairs()

  // The decomposition of the last redistribution.
  std::vector<std::vector<std::uint32_t>> m_ownedBy;  // per rank its bodies, ascending
  std::vector<std::uint32_t> m_owned;           // this rank's bodies, local indices
  std::vector<std::uint32_t> m_ownedParticles;  // their particles, local indices
  std::vector<std::uint32_t> m_particleGlobal;  // scene index of each local particle
  std::vector<std::uint8_t> m_particleOwned;    // per local particle
  std::vector<std::uint32_t> m_sendAll, m_recvAll;  // local bodies, by rank (offsets below)
  std::vector<std::size_t> m_sendOffsets, m_recvOffsets;
  std::vector<float> m_ref;  // the owned particles' positions at the redistribution
  bool m_needRedistribute = false;

  double m_time = 0.0;
  std::uint64_t m_step0 = 0, m_steps = 0, m_statsFrom = 0;
  std::uint32_t m_pulls = 0;
  bool m_debug = false, m_hasDebug = false;
  std::uint64_t m_numPairs = 0;
  bool m_tallyOn = false;
  EnergyTally m_tally;
  StepStats m_before;         // the local pipelines' counters before the last load
  mutable StepStats m_stats;  // stats()
  mutable MpiStats m_mpi;

  mutable std::vector<float> m_buf;
  std::vector<BodyMotion> m_sendBuf, m_recvBuf;
  std::vector<MPI_Request> m_requests;
};

}  // namespace

std::unique_ptr<MpiPipeline> makeMpiPipeline(const PipelineOptions& options, Decomposition how, Backend backend) {
  if (options.threads < 0 || options.threads > kMaxThreads)
    throw Error("threads = " + std::to_string(options.threads) + ": expected 0 (all cores) to " +
                std::to_string(kMaxThreads));
  requireBackend(backend);
  return std::make_unique<MpiPipelineImpl>(options, how, backend);
}

}  // namespace tumble::mpi
