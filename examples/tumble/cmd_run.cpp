// SPDX-License-Identifier: MIT
// `tumble run SCENE.toml`: simulate a scene, optionally record it and write the final state.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "stop_signal.hpp"
#include "tumble/mpi/mpi_pipeline.hpp"
#include "tumble/mpi/session.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/memory.hpp"
#include "tumble/run.hpp"
#include "tumble/run_memory.hpp"
#include "tumble/scene_io.hpp"

namespace tumble::cli {
namespace {

struct RunOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::optional<std::uint64_t> steps;
  int threads = 0;
  std::string pipeline = "cpu";
  std::string decomposition = "rcb";
  std::string record;
  std::optional<std::uint64_t> recordSteps;
  bool debug = false;
  bool contacts = false;
  std::string stateOut;
  std::optional<float> cellSize;
  std::optional<int> pcaEvery;
  std::optional<float> skin;
  bool quiet = false;
  std::string progress;  ///< --progress[=SECONDS]: seconds between progress lines (empty: only the terminal's line)
  bool noGuard = false;
  std::optional<std::uint64_t> guardEvery;
  std::string checkpoint;
  std::optional<std::uint64_t> checkpointEvery;
  std::string resume;
  std::string thermo;
  std::optional<std::uint64_t> thermoEvery;
  bool energyBalance = false;
};

// REC=<n_steps>[,<file>] (SPEC §6).
void applyRecEnv(RunOptions& o) {
  const char* rec = std::getenv("REC");
  if (!rec || !*rec) return;
  const std::string s = rec;
  const auto comma = s.find(',');
  const std::string n = s.substr(0, comma);
  const std::optional<std::uint64_t> v = parseCount(n, 1, kMaxSteps);
  if (!v) throw Error("REC=" + s + ": expected REC=<n_steps>[,<file>] with n_steps a whole number from 1 to " +
                      std::to_string(kMaxSteps));
  if (!o.recordSteps) o.recordSteps = *v;
  if (o.record.empty()) o.record = comma == std::string::npos ? "record.bin" : s.substr(comma + 1);
  if (o.record.empty()) throw Error("REC=" + s + ": the file name after the comma is empty");
}

void printPhases(const StepStats& st, std::FILE* out) {
  const double total = st.totalSeconds();
  const double n = st.steps ? double(st.steps) : 1.0;
  std::fprintf(out, "%-10s %12s %12s %7s\n", "phase", "total ms", "ms/step", "share");
  // Both pipelines integrate in the forces' pass (one pass per body): the integration has no time
  // of its own to show, and a row of zeros would read as a phase that costs nothing.
  const bool fused = st.seconds[static_cast<int>(Phase::Integrate)] == 0.0;
  for (int p = 0; p < kNumPhases; ++p) {
    if (fused && static_cast<Phase>(p) == Phase::Integrate) continue;
    std::fprintf(out, "%-10s %12.2f %12.4f %6.1f%%\n", toString(static_cast<Phase>(p)), 1e3 * st.seconds[p],
                 1e3 * st.seconds[p] / n, total > 0 ? 100.0 * st.seconds[p] / total : 0.0);
  }
  std::fprintf(out, "%-10s %12.2f %12.4f %6.1f%%\n", "step", 1e3 * total, 1e3 * total / n, 100.0);
  if (fused) std::fprintf(out, "(forces includes the integration: the pipeline integrates each body in the same pass)\n");
}

// What a run starts from: the scene with the command line's overrides and the run of it (its
// world, the checkpoint's on --resume).
struct Start {
  Scene scene;
  std::unique_ptr<Run> run;
};

Start prepare(RunOptions& o) {
  const bool prints = mpi::session().writes();
  applyRecEnv(o);
  Scene scene = readSceneFile(o.scene, o.sets);
  if (o.steps) scene.steps = *o.steps;
  if (o.cellSize) {
    if (!(*o.cellSize >= 0.0f) || !std::isfinite(*o.cellSize)) throw Error("--cell-size must be >= 0 (0 = automatic)");
    scene.broadphase.cellSize = *o.cellSize;
  }
  if (o.pcaEvery) {
    if (*o.pcaEvery < 1) throw Error("--pca-every must be >= 1");
    scene.broadphase.pcaEvery = *o.pcaEvery;
  }
  if (o.skin) {
    if (!(*o.skin >= 0.0f) || !std::isfinite(*o.skin)) throw Error("--skin must be a finite number >= 0 (0 = detect every step)");
    scene.broadphase.skin = *o.skin;
  }
  if (o.skin || o.cellSize) {  // the scene reader's memory check saw the file's skin and cells
    std::uint64_t particles = 0;
    for (const BodyDef& b : scene.bodies) particles += scene.shapes[b.shape].spheres.size();
    for (const PourBody& b : scene.pourBodies) particles += scene.shapes[b.body.shape].spheres.size();
    const RunSize size = runSizeOf(scene, scene.bodies.size(), scene.pourBodies.size(), particles);
    if (const std::string why = memoryShortfall(runMemoryEstimate(size)); !why.empty())
      throw Error("with --skin or --cell-size as given, the run needs " + why +
                  " (docs/scenes.md#memory); use a thinner skin or larger cells");
  }
  if (o.checkpointEvery && o.checkpoint.empty()) throw Error("--checkpoint-every N needs --checkpoint FILE");
  if (o.record.empty() && !scene.recordFile.empty()) o.record = scene.recordFile;
  if (!o.recordSteps && scene.recordSteps > 0) o.recordSteps = scene.recordSteps;
  if (o.thermo.empty()) o.thermo = scene.thermoFile;
  if (o.energyBalance && o.thermo.empty())
    throw Error("--energy-balance adds columns to the time series: give --thermo FILE.csv too (docs/thermo.md#energy-balance)");
  // --resume may name the --checkpoint file (a run that goes on checkpointing into it).
  refuseSameFile({{"--record", o.record}, {"--thermo", o.thermo}, {"--checkpoint", o.checkpoint},
                  {"--state-out", o.stateOut}, {"scene", o.scene}});
  refuseSameFile({{"--resume", o.resume}, {"--record", o.record}, {"--thermo", o.thermo}, {"--state-out", o.stateOut}});
  for (const auto& [option, path] : {std::pair<const char*, const std::string&>{"--record", o.record},
                                     {"--thermo", o.thermo}, {"--checkpoint", o.checkpoint}, {"--state-out", o.stateOut}})
    refuseSceneInput(scene, path, option);  // a mesh the scene reads, before anything is written

  auto run = std::make_unique<Run>(scene);
  if (!run->timeStepWarning().empty() && prints)
    std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.scene.c_str(), run->timeStepWarning().c_str());
  if (!o.resume.empty()) {
    run->resume(o.resume, o.scene);
    if (!run->resumeWarning().empty() && prints)
      std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.resume.c_str(), run->resumeWarning().c_str());
    const std::uint64_t at = run->world().step;
    if (at >= scene.steps)
      throw Error(o.resume + ": the checkpoint is at step " + std::to_string(at) + " and the run ends at step " +
                  std::to_string(scene.steps) + ": nothing to do (--steps N sets the step to run to)");
  }
  return Start{std::move(scene), std::move(run)};
}

// The [[pour]]s' bodies still to come, for the progress line and the summary: "" without pours.
std::string toCome(const Run& run) {
  if (!run.pouring().any()) return "";
  std::string s = "  " + std::to_string(run.bodiesToCome()) + " bodies to come";
  if (run.bodiesWaiting() > 0) s += " (" + std::to_string(run.bodiesWaiting()) + " due, waiting for room)";
  return s;
}

// The command's part of a run (tumble/run.hpp): the ranks under mpirun, the stop signals and the
// progress: on a terminal one line redrawn in place; with --progress SECONDS a whole line every
// SECONDS, for a log (nohup, a redirect, a cluster job).
class CliHooks : public RunHooks {
 public:
  /// `tty`: redraw the line on stderr; `every` > 0: a line every `every` seconds instead.
  CliHooks(const mpi::Session& ranks, bool tty, double every) : m_ranks(ranks), m_tty(tty), m_every(every) {}
  void begin(const Run& run, std::uint64_t start, std::uint64_t end) {
    m_run = &run;
    m_start = start;
    m_end = end;
    m_t0 = m_lastPrint = std::chrono::steady_clock::now();
  }
  bool stopRequested() override { return m_ranks.maxOf(g_stopSignal) != 0; }  // a signal any rank saw
  void write(const std::function<void()>& write) override {
    m_ranks.together([&] {
      if (m_ranks.writes()) write();
    });
  }
  // A write of the loop given up at a stop: a pipe nobody reads (StopOnSignal gave it
  // kWriteGraceSeconds); the run then stops as interrupted, without it.
  bool mayGiveUpWrite() override { return writeStopRequested() && g_stopSignal != 0; }
  bool any(bool yes) override { return m_ranks.maxOf(yes ? 1 : 0) != 0; }
  void notice(const std::string& message) override {
    if (!m_ranks.writes()) return;
    std::fprintf(stderr, "%stumble run: warning: %s\n", redraws() ? "\n" : "", message.c_str());
  }
  void progress(std::uint64_t done) override {
    const auto now = std::chrono::steady_clock::now();
    const bool lines = m_every > 0.0;
    if (!m_tty && !lines) return;
    const std::chrono::duration<double> gap = lines ? std::chrono::duration<double>(m_every) : std::chrono::milliseconds(200);
    if (!(now - m_lastPrint >= gap || done == m_end)) return;
    m_lastPrint = now;
    const double el = std::chrono::duration<double>(now - m_t0).count();
    const double ran = double(done - m_start);
    const double eta = el / ran * double(m_end - done);
    // The energy is that of the last guard check (at most --guard-every steps old).
    char energy[48] = "";
    if (const RunGuard* g = m_run->guard(); g && g->sample().finite)
      std::snprintf(energy, sizeof energy, "  E %.4g J", g->sample().energy());
    const Pipeline& p = m_run->pipeline();
    std::fprintf(stderr, "%sstep %llu/%llu (%5.1f%%)  t %.4g s%s  %llu contacts%s  %.3f ms/step  elapsed %.1f s  eta %.1f s%s",
                 lines ? "tumble run: " : "\r  ", static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(m_end), 100.0 * double(done) / double(m_end), p.time(), energy,
                 static_cast<unsigned long long>(p.stats().numPairs), toCome(*m_run).c_str(), 1e3 * el / ran, el, eta,
                 lines ? "\n" : "   ");
    if (lines) std::fflush(stderr);
  }
  /// Whether the terminal's line is drawn (and needs its newline at the end).
  bool redraws() const { return m_tty && m_every <= 0.0; }

 private:
  const mpi::Session& m_ranks;
  bool m_tty;
  double m_every;
  const Run* m_run = nullptr;
  std::uint64_t m_start = 0, m_end = 0;
  std::chrono::steady_clock::time_point m_t0, m_lastPrint;
};

// Opens an output of the run (its recording, its time series) before the first step. A stop
// signal that comes while the open waits (a FIFO nobody reads: OutputFile waits for its reader
// until a stop is requested) ends the run as interrupted, with the signal's status. Either way the
// outputs already opened are abandoned: a run that could not start replaces no file (a time
// series refused after the recording began left a one-frame recording over the last good one).
template <class Open>
void openOrStop(Run& run, Open&& open, std::uint64_t step, std::uint64_t steps, bool writes) {
  try {
    open();
  } catch (const Error& e) {
    run.abandonOutputs();  // the run never started: what it began to write replaces nothing
    const int sig = g_stopSignal;
    if (sig == 0) throw;
    if (writes)
      std::fprintf(stderr, "tumble run: interrupted (%s) at step %llu of %llu: %s; no final state written\n",
                   sig == SIGTERM ? "SIGTERM" : "SIGINT", static_cast<unsigned long long>(step),
                   static_cast<unsigned long long>(steps), e.what());
    dieOfSignal(sig);
  }
}

void run(RunOptions o) {
  // Under mpirun (docs/mpi.md) every rank runs this with the same input: the collective calls
  // (the pipeline's, the guards', the reads) fall in the same order on every rank; rank 0 alone
  // writes the outputs and prints, and each write is agreed (a failure ends every rank with its
  // message and status).
  const mpi::Session& ranks = mpi::session();
  const bool writes = ranks.writes();
  std::optional<Start> input;
  ranks.together([&] { input.emplace(prepare(o)); });  // the same files on every rank, or one message
  const Scene& scene = input->scene;
  Run& run = *input->run;
  const World& world = run.world();
  const bool debug = o.debug || scene.recordDebug;
  const std::uint64_t thermoEvery = o.thermoEvery.value_or(scene.thermoEvery);
  const std::uint64_t start = world.step;
  const bool tty = isatty(fileno(stderr)) && !o.quiet && writes;
  // (CLI11 reads a flag's value as an integer: the seconds come as text, checked by CLI::Range.)
  CliHooks hooks(ranks, tty, writes && !o.progress.empty() ? std::stod(o.progress) : 0.0);
  PipelineOptions po;
  po.threads = o.threads;
  // Guards (docs/model.md#guards): checked every --guard-every steps and before every frame and
  // checkpoint. The time series (docs/thermo.md) is what the guard measures, so with --no-guard
  // and --thermo the guard still measures, every thermoEvery steps, and never stops the run.
  // SIGINT / SIGTERM from here on stop the run like a guard trip (stop_signal.hpp): the loop ends
  // after the steps under way, the recording is finished, a --checkpoint written.
  const StopOnSignal stopOnSignal(/*restart=*/true);
  RunChecks checks;
  checks.stop = !o.noGuard;
  checks.every = o.guardEvery.value_or(kDefaultGuardEvery);
  checks.measure = !o.thermo.empty();
  run.load(ranks.makePipeline(backendFromString(o.pipeline), po, mpi::decompositionFromString(o.decomposition)),
           checks, &hooks);
  run.setEndStep(scene.steps);
  Pipeline& pipeline = run.pipeline();

  if (!o.quiet && writes) {
    const std::string on = ranks.active() ? " on " + std::to_string(ranks.size()) + " MPI ranks" : "";
    const Pouring& pours = run.pouring();
    const std::string bodies = pours.any() ? std::to_string(world.numBodies()) + " bodies (" +
                                                 std::to_string(pours.finalBodies()) + " once the [[pour]]s are in)"
                                           : std::to_string(world.numBodies()) + " bodies";
    std::fprintf(stderr, "tumble run: %s — %s, %u particles, %llu steps of %g s, pipeline %s%s\n",
                 printable(scene.name).c_str(), bodies.c_str(), world.numParticles(),
                 static_cast<unsigned long long>(scene.steps), scene.dt, toString(pipeline.backend()), on.c_str());
    if (start > 0)
      std::fprintf(stderr, "tumble run: resuming at step %llu (t = %.9g s) from %s\n",
                   static_cast<unsigned long long>(start), world.time, o.resume.c_str());
  }

  const std::uint64_t recSteps = o.recordSteps ? std::min<std::uint64_t>(*o.recordSteps, scene.steps) : scene.steps;
  if (o.record.empty() && (o.debug || o.contacts) && writes && !o.quiet)
    std::fprintf(stderr, "tumble run: warning: %s adds to a recording, and there is none: add --record FILE (or REC=, "
                         "[output] record)\n", o.contacts ? "--record-contacts" : "--debug-record");
  if (!o.record.empty() && start < recSteps) {
    RecordSettings rs;
    rs.path = o.record;
    rs.stepsPerFrame = std::max(1, scene.stepsPerFrame);
    rs.debug = debug;
    rs.contactForces = o.contacts || scene.recordContacts;
    rs.lastStep = recSteps;
    rs.continues = true;  // a resumed run continues the recording of the first part
    openOrStop(run, [&] { run.record(rs); }, start, scene.steps, writes);
  }
  if (checks.stop && start == 0 && !run.guard()->initialWarning().empty() && writes)
    std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.scene.c_str(), run.guard()->initialWarning().c_str());
  if (!o.thermo.empty())  // a row of the state at the start
    openOrStop(run, [&] { run.writeThermo(o.thermo, thermoEvery, o.energyBalance || scene.energyBalance); }, start,
               scene.steps, writes);
  if (o.checkpointEvery)
    openOrStop(run, [&] { run.checkpointEvery(o.checkpoint, *o.checkpointEvery); }, start, scene.steps, writes);

  // Steps are counted from the start of the run (a resumed run continues the count), so frames,
  // guard checks and checkpoints fall on the same steps as in an uninterrupted run.
  hooks.begin(run, start, scene.steps);
  Advanced ran;
  try {
    ran = run.advance(scene.steps - start);
  } catch (const SimulationError&) {  // the same on every rank (the pipeline's or the guard's)
    if (hooks.redraws()) std::fprintf(stderr, "\n");
    run.closeOutputs();
    if (writes) {
      if (const RecordingWriter* r = run.recording())
        std::fprintf(stderr, "tumble run: kept %llu frames in %s\n", static_cast<unsigned long long>(r->numFrames()),
                     r->path().c_str());
      if (const ThermoWriter* t = run.thermo())
        std::fprintf(stderr, "tumble run: kept %llu rows of the time series in %s\n",
                     static_cast<unsigned long long>(t->rows()), t->path().c_str());
    }
    throw;
  }
  if (hooks.redraws()) std::fprintf(stderr, "\n");
  const std::uint64_t done = start + ran.steps;
  if (ran.stopped) {  // stopped by a signal (any rank's)
    const int sig = ranks.maxOf(g_stopSignal);
    std::string kept;
    run.closeOutputs();
    if (const RecordingWriter* r = run.recording()) {
      kept = "; kept " + std::to_string(r->numFrames()) + " frames in " + r->path();
      if (ran.frameGivenUp)
        kept += " (the next frame's write was given up: nothing read it for " + std::to_string(kWriteGraceSeconds) + " s)";
    }
    if (const ThermoWriter* t = run.thermo()) {
      kept += "; kept " + std::to_string(t->rows()) + " rows of the time series in " + t->path();
      if (ran.rowGivenUp) kept += " (the next row's write was given up)";
    }
    if (!o.checkpoint.empty()) {
      try {
        const std::uint64_t every = o.checkpointEvery.value_or(0);
        if (!(every && done % every == 0 && done > start)) run.writeCheckpoint(o.checkpoint);  // else just written
        kept += "; checkpoint written to " + o.checkpoint + " (continue with --resume " + o.checkpoint + ")";
      } catch (const Error& e) {  // a diverged state (--no-guard) or a write error: said with the rest
        kept += "; " + std::string(e.what());
      }
    }
    if (writes)
      std::fprintf(stderr, "tumble run: interrupted (%s) at step %llu of %llu%s; no final state written\n",
                   sig == SIGTERM ? "SIGTERM" : "SIGINT", static_cast<unsigned long long>(done),
                   static_cast<unsigned long long>(scene.steps), kept.c_str());
    dieOfSignal(sig);
  }
  run.closeRecording();
  if (const RecordingWriter* r = run.recording(); r && !o.quiet) {
    std::fprintf(stderr, "recorded %llu frames (up to step %llu, %llu steps per frame) to %s\n",
                 static_cast<unsigned long long>(r->numFrames()), static_cast<unsigned long long>(r->lastStep()),
                 static_cast<unsigned long long>(run.stepsPerFrame()), r->path().c_str());
    std::error_code ec;
    if (!namesDescriptor(r->path()) && std::filesystem::is_regular_file(r->path(), ec))  // what next
      std::fprintf(stderr,
                   "  watch it: %s play %s    make a video: %s render %s -o video.mp4    "
                   "for ParaView: %s export %s DIR\n",
                   invokedAs().c_str(), r->path().c_str(), invokedAs().c_str(), r->path().c_str(),
                   invokedAs().c_str(), r->path().c_str());
  }
  run.closeThermo();
  if (const ThermoWriter* t = run.thermo(); t && !o.quiet)
    std::fprintf(stderr, "time series: %llu rows (every %llu steps) written to %s (draw it: %s plot %s)\n",
                 static_cast<unsigned long long>(t->rows()), static_cast<unsigned long long>(thermoEvery),
                 t->path().c_str(), invokedAs().c_str(), t->path().c_str());
  if (!o.checkpoint.empty()) {
    try {
      run.writeCheckpoint(o.checkpoint);
    } catch (const SimulationError& e) {  // a diverged state (--no-guard): nothing more is written from it
      throw SimulationError(std::string(e.what()) + (o.stateOut.empty() ? "" : "; no --state-out written either"),
                            e.particle());
    }
    if (!o.quiet && writes)
      std::fprintf(stderr, "checkpoint at step %llu written to %s (continue with --resume %s)\n",
                   static_cast<unsigned long long>(done), o.checkpoint.c_str(), o.checkpoint.c_str());
  }
  if (!o.stateOut.empty()) run.writeState(o.stateOut);
  // Under mpirun: each rank's share of the bodies and of the traffic (collective).
  const auto* mpiPipeline = dynamic_cast<const mpi::MpiPipeline*>(&pipeline);
  const std::vector<mpi::MpiStats> rankStats = mpiPipeline && !o.quiet ? mpiPipeline->gatherStats() : std::vector<mpi::MpiStats>{};
  if (!o.quiet && writes) {
    const StepStats st = run.stats();
    std::printf("%s: %llu steps, %u particles, %llu contacts in the last step\n", printable(scene.name).c_str(),
                static_cast<unsigned long long>(st.steps), run.world().numParticles(),
                static_cast<unsigned long long>(st.numPairs));
    if (run.pouring().any()) {
      const Pouring& pours = run.pouring();
      std::printf("pours: %zu of their %zu bodies entered%s\n", run.world().numBodies() - pours.initialBodies(),
                  pours.finalBodies() - pours.initialBodies(), run.bodiesToCome() > 0 ? (";" + toCome(run).substr(1)).c_str() : "");
    }
    std::printf("candidate list: skin %g, %llu rebuilds (%.1f per 1000 steps), %llu near-list refreshes, "
                "%llu candidate pairs; detection cell size %g (%llu cells)\n",
                st.skin, static_cast<unsigned long long>(st.numRebuilds), st.rebuildsPer1000(),
                static_cast<unsigned long long>(st.numNearRefreshes), static_cast<unsigned long long>(st.numCandidates),
                st.cellSize,
                static_cast<unsigned long long>(st.numCells));
    printPhases(st, stdout);
    if (mpiPipeline)
      std::printf("MPI: %d ranks, decomposition %s (rank 0's phases above; docs/mpi.md)\n%s", ranks.size(),
                  mpi::toString(mpiPipeline->decomposition()), mpi::describe(rankStats).c_str());
  }
}

}  // namespace

void addRun(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* c = app.add_subcommand("run", "Simulate a scene file (TOML, see docs/scenes.md)");
  c->add_option("scene", o->scene, "Scene file, e.g. scenes/molecules.toml")->required();
  addSetOption(c, o->sets, "; options such as --steps, --record and --skin (and REC) win over it");
  c->add_option("--steps", o->steps, "Step to run to, counted from the start of the run (default: the scene's steps)")
      ->check(countIn(1, kMaxSteps));
  c->add_option("--threads", o->threads, "Worker threads, 0 = all cores (results do not depend on it)")
      ->check(countIn(0, kMaxThreads));
  c->add_option("--pipeline", o->pipeline, "Pipeline (default cpu)")->check(pipelineName());
  c->add_option("--decomposition", o->decomposition,
                "Under mpirun: how the domain is cut among the ranks, rcb (recursive bisection, default) or slabs "
                "(results do not depend on it; docs/mpi.md)")
      ->check(CLI::IsMember({"rcb", "slabs"}));
  c->add_option("--record", o->record, "Write a recording to FILE (docs/recording.md); REC=<n_steps>[,<file>] does the same");
  c->add_option("--record-steps", o->recordSteps, "Record only the first N steps (default: all)")
      ->check(countIn(1, kMaxSteps));
  c->add_flag("--debug-record", o->debug, "Add velocities, the five forces and the contacts to every frame");
  c->add_flag("--record-contacts", o->contacts,
              "Add the contacts of the step before each frame with their forces (force chains: tumble export "
              "--contacts; docs/recording.md)");
  c->add_option("--state-out", o->stateOut, "Write the final body state as CSV (exact float round trip)");
  c->add_option("--checkpoint", o->checkpoint,
                "Write a checkpoint to FILE at the end of the run (docs/checkpoint.md); --resume continues it");
  c->add_option("--checkpoint-every", o->checkpointEvery, "Also write the checkpoint every N steps")
      ->check(countIn(1, kMaxSteps));
  c->add_option("--resume", o->resume,
                "Continue the run of SCENE from a checkpoint, bit for bit, up to step --steps (default: the "
                "scene's steps); a --record file of the first part is continued");
  c->add_option("--cell-size", o->cellSize, "Cell side M of the 2-D subdivision (0 = automatic: 3 diameters of the 99th-percentile radius, at least 1/32 of the largest diameter and 8 rounding margins; a given size is raised to 8 margins)");
  c->add_option("--pca-every", o->pcaEvery, "Recompute the PCA sweep axis every K detections");
  c->add_option("--skin", o->skin,
                "Verlet skin: detect pairs within r_i + r_j + S and reuse them until two particles may have "
                "closed in by S (0 = detect every step; default 0.5 x the 99th-percentile radius, which is the largest radius "
                "unless only a few spheres are larger)");
  c->add_option("--thermo", o->thermo,
                "Write the time series (energies, contacts, overlaps, momenta: docs/thermo.md) to FILE.csv; "
                "default: the scene's [output] thermo");
  c->add_option("--thermo-every", o->thermoEvery, "Steps between two rows of the time series (default: the scene's "
                "[output] thermo_every, 100)")
      ->check(countIn(1, kMaxSteps));
  c->add_flag("--energy-balance", o->energyBalance,
              "With --thermo: the energy dissipated by the contacts and the walls' work, and the balance "
              "(docs/thermo.md#energy-balance; a step costs about 1.5x as much); default: the scene's [output] "
              "energy_balance");
  CLI::Option* quiet = c->add_flag("-q,--quiet", o->quiet, "No progress line and no timing table");
  c->add_flag("--progress{30}", o->progress,
              "A progress line every SECONDS (default 30) as a whole line on stderr, also when it is not a terminal "
              "(a log under nohup, a redirect or a cluster job); without it the line is drawn on a terminal only")
      ->type_name("[=SECONDS]")
      ->check(CLI::Validator(
          [](std::string& s) {  // (CLI::Range lets nan through)
            char* end = nullptr;
            const double v = std::strtod(s.c_str(), &end);
            if (s.empty() || end != s.c_str() + s.size() || !(v >= 0.001 && v <= 1e6))
              return "expected SECONDS, a number from 0.001 to 1e6 (got '" + s + "')";
            return std::string();
          },
          "SECONDS"))
      ->excludes(quiet);
  c->add_option("--guard-every", o->guardEvery,
                "Check the guards (finite state, energy, overlaps) every N steps, and before every frame and "
                "checkpoint (default: " + std::to_string(kDefaultGuardEvery) + ")")
      ->check(countIn(1, kMaxSteps));
  c->add_flag("--no-guard", o->noGuard, "Do not check the guards (a diverging run then stops only at a non-finite position)");
  c->callback([o] { run(*o); });
}

}  // namespace tumble::cli
