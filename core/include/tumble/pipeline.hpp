// SPDX-License-Identifier: MIT
/// @file pipeline.hpp
/// The backend-neutral pipeline interface. Every backend runs the same stage list
/// (SPEC §2–§4): state → axis → cell keys → sort → sweep (CSR contact list) → forces → integrate.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tumble/world.hpp"

namespace tumble {

/// Which implementation of the pipeline.
enum class Backend { Cpu, Cuda };

/// "cpu" / "cuda".
const char* toString(Backend b);
/// Parses "cpu" / "cuda"; throws tumble::Error otherwise.
Backend backendFromString(const std::string& s);
/// Backends compiled into this build.
std::vector<Backend> compiledBackends();
/// True when the CUDA module is compiled in and a device is present.
bool cudaAvailable();

/// Options that do not change results (threads) or change only speed (broadphase knobs).
struct PipelineOptions {
  int threads = 0;  ///< 0 = all cores (CPU pipeline)
};

/// A particle pair (i < j) in global particle indices.
struct Pair {
  std::uint32_t i, j;
  friend bool operator==(const Pair& a, const Pair& b) { return a.i == b.i && a.j == b.j; }
  friend bool operator<(const Pair& a, const Pair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
};

/// The named phases of one step, in order.
/// state: particle x, v from the bodies; axis: bounds and PCA; keys: cell ranges and sort keys;
/// sort: radix sort of the records; sweep: gather + sweep + CSR contact list; forces: contact,
/// ground, gravity and pulls per particle; integrate: body totals and integration.
enum class Phase : int { State, Axis, Keys, Sort, Sweep, Forces, Integrate, Count };
const char* toString(Phase p);
constexpr int kNumPhases = static_cast<int>(Phase::Count);

/// Timings and counters, accumulated since load() or resetStats().
struct StepStats {
  std::uint64_t steps = 0;
  double seconds[kNumPhases] = {};  ///< wall time per phase, summed over steps
  std::uint64_t numPairs = 0;       ///< pairs found in the last step
  std::uint64_t numRecords = 0;     ///< sweep records (particle × overlapped cell), last step
  std::uint64_t numCells = 0;       ///< cells in the last step's grid
  float cellSize = 0.0f;            ///< cell side used in the last step
  double totalSeconds() const;
};

/// Per-particle debug data for the debug recording: velocity and the five forces.
struct ParticleDebug {
  std::vector<float> v;          ///< 3 per particle
  std::vector<float> force[5];   ///< repulsion, damping, shear, ground, friction; 3 per particle
  std::vector<Pair> contacts;    ///< sorted pairs
};

/// Input of the stand-alone broadphase (`tumble pairs`).
struct ParticleCloud {
  std::vector<float> x, y, z, r;
  std::vector<std::uint32_t> body;
  std::size_t size() const { return x.size(); }
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
  /// Copies the current body state out, positions in the world frame (rounded to float there).
  virtual void readState(BodyState& out) const = 0;
  /// The frame the pipeline integrates in (LocalFrame::of the loaded world; inactive near the
  /// origin, and before load()).
  virtual LocalFrame frame() const { return {}; }
  /// The body state in that frame: positions X − frame origin, as integrated (no rounding to the
  /// world frame). The same as readState() when the frame is inactive.
  virtual void readLocalState(BodyState& out) const { readState(out); }
  /// The pairs found by the last step's detection, sorted by (i, j).
  virtual std::vector<Pair> pairs() const = 0;
  /// Broadphase alone on a particle cloud: every pair i < j of different bodies with
  /// |x_i − x_j| < r_i + r_j, sorted. Throws tumble::Error on NaN/inf or radius ≤ 0.
  virtual std::vector<Pair> findPairs(const ParticleCloud& cloud, const BroadphaseParams& bp) = 0;
  /// Velocities and the five force kinds of the last step, per particle (debug recording).
  /// Requires setDebugCapture(true) before the step; throws tumble::Error otherwise.
  virtual void readDebug(ParticleDebug& out) const = 0;
  /// Keeps the per-particle force components of each step for readDebug() (costs 15 floats
  /// per particle of memory traffic per step; off by default).
  virtual void setDebugCapture(bool on) = 0;
  /// Switches the user pulls (PullBits) on or off from the next step on.
  virtual void setPulls(std::uint32_t mask) = 0;
  virtual std::uint32_t pulls() const = 0;
  virtual const StepStats& stats() const = 0;
  virtual void resetStats() = 0;
  /// Simulated time since load().
  virtual double time() const = 0;
};

/// Creates a pipeline. Throws tumble::Error when the backend is not compiled in or has no device.
std::unique_ptr<Pipeline> makePipeline(Backend backend, const PipelineOptions& options = {});

}  // namespace tumble
