// SPDX-License-Identifier: MIT
/// @file pipeline.hpp
/// The backend-neutral pipeline interface. Every backend runs the same stage list
/// (SPEC §2–§4). At a rebuild of the candidate list (when the skin test asks for one):
/// reorder → state → axis → cell keys → sort → sweep → list. Every step: forces (contacts from
/// the list, ground, pulls) → integrate (body totals, gravity, integration, the next particle
/// positions and the skin test).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tumble/kernels/contact_sums.hpp"
#include "tumble/soa.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// Which implementation of the pipeline. Cpu: the CPU reference pipeline on oneTBB. Cuda: the
/// CUDA pipeline on a GPU. CudaHost: the CUDA pipeline's own code on the host backend of its
/// execution layer (oneTBB, host memory; every build has it): for testing the CUDA pipeline and
/// checking a GPU result without a GPU, not a fast path (docs/cuda.md).
enum class Backend { Cpu, Cuda, CudaHost };

/// "cpu" / "cuda" / "cuda-host".
const char* toString(Backend b);
/// Parses "cpu" / "cuda" / "cuda-host"; throws tumble::Error otherwise.
Backend backendFromString(const std::string& s);
/// Whether b runs the CUDA pipeline's code (Cuda or CudaHost).
inline bool isCudaPipeline(Backend b) { return b == Backend::Cuda || b == Backend::CudaHost; }

/// Whether the CUDA pipeline can run here. NoDevice: the build has no CUDA module, or the
/// machine has no CUDA device or no driver at all. Broken: a device may be there but CUDA
/// cannot use it (a driver older than the runtime, a failed initialisation): an error, never
/// a reason to skip.
enum class CudaState { Ready, NoDevice, Broken };
struct CudaStatus {
  CudaState state;
  std::string message;  ///< one line; names the driver and runtime versions when the module is built
};
// cudaStatus(), makePipeline() and the rest of what needs every backend of this build:
// tumble/factory.hpp (tumble::pipelines).
/// Throws tumble::Error with s.message unless s.state is Ready.
void requireReady(const CudaStatus& s);
/// TUMBLE_REQUIRE_CUDA=1 in the environment: tests of the CUDA pipeline fail instead of skipping
/// when there is no device.
bool cudaRequired();

/// The most worker threads a pipeline accepts (oneTBB fails beyond 65536).
inline constexpr int kMaxThreads = 4096;

/// Options that do not change results: they change only speed.
struct PipelineOptions {
  int threads = 0;      ///< 0 = all cores (CPU pipeline); at most kMaxThreads
  bool reorder = true;  ///< renumber bodies in spatial order at each rebuild (locality)
};

/// The Verlet skin a world runs with: params.broadphase.skin, or when that is negative
/// (automatic) kAutoSkinPerRadius × world.sizingRadius (the 99th percentile of the radii: the
/// largest radius unless under 1 % of the particles are larger).
float effectiveSkin(const World& world);
/// The same from a given skin (negative: automatic) and the radii's sizing and largest radius.
float effectiveSkin(float skin, float sizingRadius, float maxRadius);
/// How far beyond touching a contact may hold (m): under cohesion = "jkr" the largest neck's
/// length |δ_c| = ¾ c (c R* / 4)^{1/3}, c = √(2 π γ / Y*), over the pairs of materials at the
/// largest R* two spheres of the world can have (half its largest radius), with a margin for the
/// kernel's float δ_c (kernels/cohesion.hpp, jkrContact()); 0 for every other model. The
/// detection finds the pairs within r_i + r_j + skin + this, so that a neck stays in the lists
/// until it breaks; the skin test is unchanged (docs/model.md#cohesion).
float neckReach(const World& world);
/// The automatic skin, in units of the largest radius (docs/performance.md measures it).
inline constexpr float kAutoSkinPerRadius = 0.5f;

/// A particle pair (i < j) in global particle indices.
struct Pair {
  std::uint32_t i, j;
  friend bool operator==(const Pair& a, const Pair& b) { return a.i == b.i && a.j == b.j; }
  friend bool operator<(const Pair& a, const Pair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
};

/// The named phases of one step, in order. The first seven run only at a rebuild of the
/// candidate list. reorder: spatial renumbering of the bodies; state: particle rows from the
/// bodies; axis: bounds and PCA; keys: cell ranges and sort keys; sort: radix sort of the
/// records; sweep: gather + sweep (pairs within the skin); list: the candidate list sorted by
/// scene index. Every step: forces: per particle its contacts (the list filtered by the exact
/// predicate), the ground and the pulls; integrate: per body the totals, gravity, the
/// integration, the next step's particle positions and the skin test. The CPU pipeline runs
/// the two as one fused pass over the bodies and books it under forces.
enum class Phase : int { Reorder, State, Axis, Keys, Sort, Sweep, List, Forces, Integrate, Count };
const char* toString(Phase p);
constexpr int kNumPhases = static_cast<int>(Phase::Count);

/// Timings and counters, accumulated since load() or resetStats().
struct StepStats {
  std::uint64_t steps = 0;
  double seconds[kNumPhases] = {};  ///< wall time per phase, summed over steps
  std::uint64_t numPairs = 0;       ///< contacts (touching pairs) in the last step
  std::uint64_t numRebuilds = 0;    ///< rebuilds of the candidate list (detection runs)
  std::uint64_t numNearRefreshes = 0;  ///< refreshes of the near list from the candidate list (CPU)
  std::uint64_t numCandidates = 0;  ///< candidate pairs in the list of the last rebuild
  std::uint64_t numRecords = 0;     ///< sweep records (particle × overlapped cell), last rebuild
  std::uint64_t numCells = 0;       ///< cells in the last rebuild's grid
  float cellSize = 0.0f;            ///< cell side used at the last rebuild
  float skin = 0.0f;                ///< the Verlet skin in use
  /// The energy tally (Pipeline::setEnergyTally) over the steps taken while it was on (J).
  EnergyTotals energy;
  double totalSeconds() const;
  /// Adds the steps, times and events of `later` (a run's next part: a pipeline loaded afresh)
  /// and takes its last-step and last-rebuild values.
  void add(const StepStats& later);
  /// Events per 1000 steps (0 before the first step).
  double per1000(std::uint64_t count) const { return steps ? 1000.0 * double(count) / double(steps) : 0.0; }
  double rebuildsPer1000() const { return per1000(numRebuilds); }
};

/// One array a step reads or writes, for the memory floor (Pipeline::stepTraffic()): what it is
/// and the bytes the step moves for it (its size once per read or write).
struct TrafficLine {
  std::string what;
  double bytes = 0.0;
};

/// Per-particle debug data for the debug recording: velocity and the five forces.
/// The five force kinds of ParticleDebug::force, in its order.
inline constexpr const char* kDebugForceNames[5] = {"repulsion", "damping", "shear", "ground", "friction"};

struct ParticleDebug {
  std::vector<float> v;          ///< 3 per particle
  std::vector<float> force[5];   ///< kDebugForceNames: repulsion, damping, shear, ground, friction; 3 per particle
  std::vector<Pair> contacts;    ///< sorted pairs
  /// The same contacts, in the same order, with their forces (soa.hpp): per particle, the
  /// repulsion, damping and shear of debug are the sums of `normal + tangential` over its
  /// contacts (with the sign of its side), within rounding.
  std::vector<ContactForce> contactForces;
};

/// The contacts of a debug capture (DebugForcesView::contact, `entries` entries of the list the
/// step read, each contact once from either side): those from the side of the lower scene index,
/// sorted by (i, j), as Pipeline::pairs().
std::vector<ContactForce> capturedContacts(const ContactForce* capture, std::size_t entries);

/// The branch l = x_i − x_j of contact c between particles of radii ri and rj at the step's
/// positions, n (r_i + r_j − δ) in double: across a periodic boundary, to j's image beside i.
std::array<double, 3> contactBranch(const ContactForce& c, float ri, float rj);

/// Input of the stand-alone broadphase (`tumble pairs`).
struct ParticleCloud {
  std::vector<float> x, y, z, r;
  std::vector<std::uint32_t> body;
  std::size_t size() const { return x.size(); }
  /// Periodic boundaries (kernels/periodic.hpp; none by default): the pairs meet through their
  /// minimum image, the coordinates being those of the frame whose box is [−h, h).
  PeriodicBox periodic{};
};

/// Checks a cloud for Pipeline::findPairs(): equal column lengths, fewer than 2^31 particles,
/// every radius positive and finite. Returns the largest radius; throws tumble::Error.
float checkCloud(const ParticleCloud& cloud);

/// One simulation pipeline. Not thread-safe: one caller at a time.
///
/// Determinism: for a given backend, the state after step() is bit-identical for any thread
/// count and any repetition (fixed-order sums, integer keys, stable sorts).
class Pipeline {
 public:
  virtual ~Pipeline() = default;
  virtual Backend backend() const = 0;
  /// Copies a world in and resets statistics. Throws tumble::Error on invalid input.
  virtual void load(const World& world) = 0;
  /// Advances n steps of world.params.dt. Throws tumble::SimulationError when a particle
  /// position becomes non-finite (the state then holds the last step's result).
  virtual void step(std::uint64_t n = 1) = 0;
  /// Copies the current state out (bodies, and the per-particle contact history), in scene
  /// order, positions in the world frame (rounded to float there).
  virtual void readState(BodyState& out) const = 0;
  /// The frame the pipeline integrates in (LocalFrame::of the loaded world; inactive near the
  /// origin, and before load()).
  virtual LocalFrame frame() const { return {}; }
  /// The body state in that frame: positions X − frame origin, as integrated (no rounding to the
  /// world frame). The same as readState() when the frame is inactive.
  virtual void readLocalState(BodyState& out) const { readState(out); }
  /// The particle positions of the current state, in the frame of readLocalState(), scene
  /// order, 3 floats per particle: the bits the next step's contacts are decided on.
  virtual void readLocalPositions(std::vector<float>& out) const = 0;
  /// The contacts of the last step (the particles that touched at its start), sorted by (i, j),
  /// scene indices; {} before the first step. Exactly the brute-force pair set of that state,
  /// whatever the detection settings and the skin.
  virtual std::vector<Pair> pairs() const = 0;
  /// The mesh contacts of the last step (the (particle, triangle) that met at its start, as
  /// kernels/mesh.hpp counts them), sorted, scene indices; {} before the first step and without
  /// mesh walls. Exactly the brute-force set of that state, whatever the skin and the hierarchy.
  virtual std::vector<MeshContact> meshContacts() const { return {}; }
  /// The guard's contact sums (kernels/contact_sums.hpp) per body, scene order, over the contacts
  /// of the last step (the pairs() set) at the current positions (readLocalPositions()): body b's
  /// entry sums the pairs (i, j) whose particle i is one of b's, each body's rounding taken from
  /// its position in readLocalState() (bodyRounding); law: the contact springs' (SpringLaw). A pipeline that
  /// keeps its contacts computes them where they are (no pair list, no sort); the default
  /// returns false, and the guard computes the same bits from pairs() (contactSumsOfPairs()).
  virtual bool contactSumsPerBody(const SpringLaw& law, std::vector<ContactSums>& out) const {
    (void)law, (void)out;
    return false;
  }
  /// The bytes a step without a rebuild or refresh must move through memory, array by array:
  /// each array the step's pass reads counted once at its size, and once more if it writes it
  /// (the floor of a step bound by bandwidth: `tumble bench` divides it by a measured streaming
  /// bandwidth). Counted from the pipeline's arrays as they are now (after a step). Empty where
  /// the pipeline does not count them (the default).
  virtual std::vector<TrafficLine> stepTraffic() const { return {}; }
  /// Broadphase alone on a particle cloud: every pair i < j of different bodies with
  /// |x_i − x_j| < r_i + r_j, sorted. Throws tumble::Error on NaN/inf or radius ≤ 0.
  virtual std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) = 0;
  /// Velocities (at the start of the last step) and the five force kinds of the last step, per
  /// particle in scene order, and its contacts with their forces (debug recording, contact
  /// forces).
  /// Requires setDebugCapture(true) before the step; throws tumble::Error otherwise.
  virtual void readDebug(ParticleDebug& out) const = 0;
  /// Keeps the per-particle force components of each step for readDebug() (costs 15 floats
  /// per particle and 7 words per entry of the contact list of memory traffic per step; off by
  /// default). Changes no bit of the state.
  virtual void setDebugCapture(bool on) = 0;
  /// Keeps the energy tally (kernels/energy.hpp, docs/thermo.md#energy-balance) from the next
  /// step on: the energy the contacts dissipate and moving walls put in, summed over each step
  /// in fixed point (the same bits for any thread count, numbering, rank count and pipeline).
  /// Its steps take the debug capture's pass (about the cost of the particle-by-particle force
  /// pass); changes no bit of the state. Off by default; off again stops adding. The sums:
  /// stats().energy.
  virtual void setEnergyTally(bool on) = 0;
  /// Switches the user pulls (PullBits) on or off from the next step on.
  virtual void setPulls(std::uint32_t mask) = 0;
  virtual std::uint32_t pulls() const = 0;
  virtual const StepStats& stats() const = 0;
  virtual void resetStats() = 0;
  /// Simulated time: world.time at load() plus the steps since.
  virtual double time() const = 0;
  /// Steps since the start of the run: world.step at load() plus the steps since (unlike
  /// stats().steps, not reset by resetStats()).
  virtual std::uint64_t stepCount() const = 0;
};

/// A pipeline with the three hooks a domain decomposition needs (tumble::mpi, docs/mpi.md). A
/// rank loads the bodies it owns and ghost copies of the bodies near them; after each step it
/// reads the motion of its own bodies that other ranks hold as ghosts, and overwrites its
/// ghosts' with those their owners integrated. Bodies are named by their scene index in the
/// loaded world. Not thread-safe, as Pipeline.
class HaloPipeline : public Pipeline {
 public:
  /// The motion of `bodies` as the last step's integration left it, out[k] for bodies[k].
  virtual void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const = 0;
  /// Overwrites the motion of `bodies` (motion[k] for bodies[k]), recomputes their particles'
  /// positions, then redoes the skin test (per particle, or per body as the step does) with the
  /// moving meshes' motion, so that the candidate list (and a near list) is rebuilt when the
  /// overwritten positions need it. Nothing else of the state changes.
  virtual void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) = 0;
  /// How many touching contacts the particles of `bodies` had in the last step, each counted
  /// from its particle's side (a contact between two of them counts twice); 0 before the first step.
  virtual std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const = 0;
  /// The energy tally's sums of the last step over `bodies` (setEnergyTally(true) before it;
  /// nothing otherwise and before the first step).
  virtual EnergyLimbs energyOf(const std::vector<std::uint32_t>& bodies) const = 0;
};

}  // namespace tumble
