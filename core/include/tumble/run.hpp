// SPDX-License-Identifier: MIT
/// @file run.hpp
/// A run, written once (docs/architecture.md#the-run-driver): the world that grows with its
/// pours, the pipeline that steps it, the guard that checks it and the outputs it writes (the
/// recording, the time series, checkpoints, the state file). Run::advance() decides which step
/// does what: frames, time-series rows, guard checks, checkpoints and pour batches fall on
/// multiples of their intervals counted from the start of the run (a resumed run continues the
/// count), however the steps are split into calls. `tumble run` (also under mpirun), `tumble
/// view` and the Python `Simulation` drive their runs with it; what is theirs (options, messages,
/// the window, signals, the GIL) comes in through RunHooks.
#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tumble/guard.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/pour.hpp"
#include "tumble/recording.hpp"
#include "tumble/scene.hpp"
#include "tumble/thermo.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// Steps between two calls of RunHooks::stopRequested(): Ctrl-C stops a run within this many.
inline constexpr std::uint64_t kStepsBetweenStops = 100;

/// What a front end adds to a run. The defaults are those of one process that prints nothing
/// and cannot be stopped: the Python module, a test. `tumble run` under mpirun agrees every
/// write and stop among the ranks here (rank 0 alone writes).
class RunHooks {
 public:
  virtual ~RunHooks() = default;
  /// Before every stretch of at most kStepsBetweenStops steps: whether to stop now (a signal).
  /// May throw instead (Python's KeyboardInterrupt). Under MPI the same answer on every rank.
  virtual bool stopRequested() { return false; }
  /// Runs a stretch of steps (Python lets go of the GIL around it).
  virtual void stepping(const std::function<void()>& steps) { steps(); }
  /// After every stretch: the step reached (a progress line).
  virtual void progress(std::uint64_t /*step*/) {}
  /// Runs `write` on the process that writes the outputs (under MPI rank 0 alone; the others
  /// hold no file), so that its failure ends every process with its message.
  virtual void write(const std::function<void()>& write) { write(); }
  /// After a write in the loop failed with tumble::Error: whether to give it up, the run then
  /// stopping as interrupted without it (tumble run: a stop was asked and nobody reads the pipe).
  virtual bool mayGiveUpWrite() { return false; }
  /// Whether any process says yes (under MPI, agreed by every rank).
  virtual bool any(bool yes) { return yes; }
  /// Something the user should know while the run goes on (a [[pour]] that fell behind), said
  /// once; the same on every rank.
  virtual void notice(const std::string& /*message*/) {}
};

/// How the run checks its state (docs/model.md#guards).
struct RunChecks {
  /// A trip stops the run (tumble::SimulationError from advance()).
  bool stop = true;
  /// Steps between two checks when nothing else is due (frames, rows and checkpoints are
  /// checked too).
  std::uint64_t every = kDefaultGuardEvery;
  /// Measure even when not stopping: the guard's quantities feed the time series and
  /// Run::sampleNow(). Without either, no guard is made.
  bool measure = true;
};

/// A recording of the run (docs/recording.md).
struct RecordSettings {
  std::string path;
  int stepsPerFrame = 10;
  bool debug = false;             ///< velocities, the five forces and the contacts in every frame
  /// The contacts of the step before each frame with their forces (force chains; version 3).
  /// Only that step is captured (unless debug): the run's speed is kept.
  bool contactForces = false;
  std::uint64_t lastStep = std::numeric_limits<std::uint64_t>::max();  ///< no frame after it
  /// A resumed run continues the recording at `path` (RecordingWriter::continueAt), which must
  /// end with the last frame due by the checkpoint's step.
  bool continues = false;
  /// Whether frames come only after a step (debug, contact forces: forces exist once a step has
  /// run), with no frame of the state at the start.
  bool afterSteps() const { return debug || contactForces; }
};

/// A change of some bodies' motion between steps (Run::setBodies()): for each of `bodies` (scene
/// indices) the quantities whose column is given, k-th entry for bodies[k]; an empty column leaves
/// that quantity as it is. At most one of `l` and `omega`.
struct BodyChanges {
  std::vector<std::uint32_t> bodies;
  std::vector<Vec3f> x;      ///< centre of mass X, world frame
  std::vector<Vec3f> v;      ///< V
  std::vector<Quatf> q;      ///< orientation Q, as BodyState::q (the body frame's), a unit quaternion
  std::vector<Vec3f> l;      ///< angular momentum L, world frame
  std::vector<Vec3f> omega;  ///< angular velocity Ω, world frame: L = R I0 Rᵀ Ω with the new Q
};

/// What Run::advance() did.
struct Advanced {
  std::uint64_t steps = 0;   ///< steps taken
  bool stopped = false;      ///< ended early: RunHooks::stopRequested(), or a write given up
  bool frameGivenUp = false; ///< the write of a frame was given up (RunHooks::giveUpWrite)
  bool rowGivenUp = false;   ///< the write of a time-series row was given up
  bool entered = false;      ///< bodies of a [[pour]] entered: world() has grown
};

class Run {
 public:
  /// A run of `scene` from its start: the bodies present then (tumble/pour.hpp).
  explicit Run(const Scene& scene);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  /// Before load(): the run goes on from the checkpoint at `path`, with the bodies that had
  /// entered by then, in its state. Throws tumble::InputError for an unreadable checkpoint and
  /// tumble::Error naming both when it does not belong to the scene (`sceneName`: what the
  /// message calls the scene, its file; default its name).
  void resume(const std::string& path, const std::string& sceneName = {});

  /// Loads `pipeline` with the world and starts the guard (when `checks` asks for one). `hooks`
  /// (null: the defaults) must outlive the run. Collective under MPI.
  void load(std::unique_ptr<Pipeline> pipeline, const RunChecks& checks = {}, RunHooks* hooks = nullptr);

  /// The step at which the run ends (tumble run's --steps), if it has one: the state there is
  /// checked and gets a time-series row whatever the intervals, and no checkpoint is written
  /// there by the interval (the caller writes the last one).
  void setEndStep(std::uint64_t step) { m_endStep = step; }

  /// Steps n steps, or fewer when stopped. Throws tumble::SimulationError when a guard trips
  /// (the row of that step written, nothing else from its state) or the pipeline finds a
  /// non-finite state; the outputs then stay open with what they hold (close them, or call
  /// closeOutputs()). The state at the end of the call is checked on a copy of the guard, which
  /// changes none of the run's own checks.
  Advanced advance(std::uint64_t n);

  /// Starts a recording (the one under way is finished once the new file is open): with pours,
  /// its table holds every body that may enter. Writes the state now as its first frame, unless
  /// debug (debug frames follow a step) or a continued recording already has frames.
  void record(const RecordSettings& settings);
  /// Finishes the recording, if any (idempotent).
  void closeRecording();
  /// Writes the time series (docs/thermo.md) to `path`: a row now and every `every` steps;
  /// energyBalance: with the energy tally's columns (the pipeline keeps the tally while the
  /// series is written; docs/thermo.md#energy-balance), NaN in them otherwise.
  void writeThermo(const std::string& path, std::uint64_t every, bool energyBalance = false);
  void closeThermo();
  /// Finishes both; the guard's trip, a signal and the end of a run all call this.
  void closeOutputs();
  /// Abandons both: their files stay as they were before the run (a run whose start failed
  /// after one of them was opened, e.g. a time series refused after the recording began).
  void abandonOutputs() noexcept;
  /// Writes a checkpoint to `path` every `every` steps (0: never) from here on.
  void checkpointEvery(const std::string& path, std::uint64_t every);
  /// Writes a checkpoint of the state now to `path` (collective; the writer writes).
  void writeCheckpoint(const std::string& path);
  /// Writes the body state now as CSV (tumble run --state-out: x, v, q in the shape frame, l,
  /// and the periods crossed when periodic), nine significant digits: an exact float round trip.
  void writeState(const std::string& path);

  /// Between steps: overwrites the motion of some bodies and goes on from there as a run resumed
  /// from a checkpoint of that state would: the pipeline is loaded again with its state as it
  /// integrates it (its frame, the contact history, the step, the time and the pulls kept) and the
  /// changes, and the guard starts afresh from it (its energy budget; the time series' pull_work
  /// counts from here). The outputs, the schedule and the pours carry on. Throws tumble::Error,
  /// changing nothing, for a body index beyond the bodies or named twice, a column of another length, a
  /// non-finite value, both l and omega, a Q that is not a unit quaternion (within 1e-4), a
  /// turn of a body that does not rotate (a single sphere under the report's law) or a centre
  /// outside the periodic box. Overlaps are not refused: guard()->initialWarning() names the
  /// deepest. Positions are rounded to float in the run's frame (exact near the origin).
  void setBodies(const BodyChanges& changes);

  /// Between steps: changes contact parameters, given as the scene file's keys ("ground.friction",
  /// "contact.stiffness", "material.NAME.restitution"; docs/python.md lists those of each law),
  /// and goes on as setBodies() does (the state kept bit for bit, the guard afresh). Each value is
  /// checked as the scene file's is, and the world's tables are rebuilt from the changed scene
  /// (World::fromScene()'s checks); timeStepWarning() is then that of the new parameters. What
  /// cannot change during a run (the law, the ground's place, masses, the walls, dt, …) throws
  /// tumble::Error naming the key and saying why, changing nothing.
  void setParameters(const std::vector<std::pair<std::string, double>>& changes);

  /// Keeps the five forces of every step per particle (Pipeline::setDebugCapture) for
  /// Pipeline::readDebug(), with or without a debug recording. Off by default; changes no bit.
  void captureForces(bool on);
  bool capturingForces() const { return m_captureForces; }

  /// The quantities now, measured on a copy of the guard (the run's own checks stay where they
  /// fall). Requires a guard (RunChecks::stop or measure). The energy tally's (dissipated,
  /// wall work) while a time series with it is written (writeThermo(…, energyBalance); NaN
  /// otherwise), summed over the steps since that series began.
  ThermoSample sampleNow() const;

  const Scene& scene() const { return m_pouring->scene(); }
  const Pouring& pouring() const { return *m_pouring; }
  const World& world() const { return m_world; }
  Pipeline& pipeline() { return *m_pipeline; }
  const Pipeline& pipeline() const { return *m_pipeline; }
  /// The guard, when there is one (null otherwise).
  const RunGuard* guard() const { return m_guard ? &*m_guard : nullptr; }
  /// The world that names every body the run may have: with pours, all of them.
  World finalWorld() const;
  /// The recording and the time series under way, on the process that writes (null otherwise).
  const RecordingWriter* recording() const { return m_rec.get(); }
  const ThermoWriter* thermo() const { return m_thermo.get(); }
  /// Whether a recording or a time series is under way (on every process).
  bool recordingOn() const { return m_recOn; }
  bool thermoOn() const { return m_thermoOn; }
  /// Steps per frame of the recording (of the last one started).
  std::uint64_t stepsPerFrame() const { return static_cast<std::uint64_t>(m_recSettings.stepsPerFrame); }
  /// Warnings about the start: a time step beyond the stability limit of a contact (of every body
  /// the run will have) and what resuming found; the guard's initial one (bodies pressed into
  /// each other) once loaded. Empty when there is nothing to say.
  const std::string& timeStepWarning() const { return m_dtWarning; }
  const std::string& resumeWarning() const { return m_resumeWarning; }
  /// The pipeline's counters over the whole run (also those before a pour's load()).
  StepStats stats() const;
  /// Bodies of the [[pour]]s still to enter, and of those the ones due by now that found no
  /// place at the last batch (the pour fell behind: RunHooks::notice said so the first time).
  std::size_t bodiesToCome() const { return m_pouring->finalBodies() - m_world.numBodies(); }
  std::size_t bodiesWaiting() const { return m_pourWaiting; }

 private:
  bool writeOrGiveUp(const std::function<void()>& write);
  void writeFrame();
  /// Loads the pipeline again with `world` (its state, step, time and frame those the run goes on
  /// from), keeping the pulls, and starts the guard afresh.
  void reload(World world);
  /// s with the energy tally's sums (stats().energy) where the run keeps one.
  ThermoSample withTally(ThermoSample s) const;

  std::unique_ptr<const Pouring> m_pouring;
  World m_world;
  std::unique_ptr<Pipeline> m_pipeline;
  RunHooks m_ownHooks;
  RunHooks* m_hooks = &m_ownHooks;
  std::optional<RunGuard> m_guard;
  RunChecks m_checks;
  std::optional<std::uint64_t> m_endStep;
  std::uint64_t m_checkedAt = std::numeric_limits<std::uint64_t>::max();
  StepStats m_statsBefore;  ///< the pipeline's counters before the last pour's load()
  std::size_t m_pourWaiting = 0;  ///< bodiesWaiting()
  bool m_toldBehind = false;      ///< notice() said the pour fell behind
  std::string m_dtWarning, m_resumeWarning;
  // The recording: m_recOn on every process, the writer on the one that writes.
  bool m_recOn = false;
  RecordSettings m_recSettings;
  std::unique_ptr<RecordingWriter> m_rec;
  BodyState m_state;
  ParticleDebug m_debug;
  bool m_captureForces = false;
  // The time series.
  bool m_thermoOn = false;
  bool m_tallying = false;  ///< the pipeline keeps the energy tally (while a time series with it is written)
  EnergyTotals m_tallyBase;  ///< stats().energy when that series began
  std::uint64_t m_thermoEvery = 100;
  std::unique_ptr<ThermoWriter> m_thermo;
  // Checkpoints every m_checkpointEvery steps.
  std::string m_checkpointPath;
  std::uint64_t m_checkpointEvery = 0;
};

}  // namespace tumble
