// SPDX-License-Identifier: MIT
// `tumble run SCENE.toml`: simulate a scene, optionally record it and write the final state.
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "stop_signal.hpp"
#include "tumble/checkpoint.hpp"
#include "tumble/thermo.hpp"
#include "tumble/guard.hpp"
#include "tumble/mpi/mpi_pipeline.hpp"
#include "tumble/mpi/session.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/pour.hpp"
#include "tumble/recording.hpp"
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
  std::string stateOut;
  std::optional<float> cellSize;
  std::optional<int> pcaEvery;
  std::optional<float> skin;
  bool quiet = false;
  bool noGuard = false;
  std::optional<std::uint64_t> guardEvery;
  std::string checkpoint;
  std::optional<std::uint64_t> checkpointEvery;
  std::string resume;
  std::string thermo;
  std::optional<std::uint64_t> thermoEvery;
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

void writeState(const std::string& path, const World& world, const BodyState& s) {
  writeAtomically(path, [&](std::FILE* f) {
    // With periodic boundaries, the periods each centre has crossed (BodyState::imageX, imageY).
    std::fprintf(f, "body,x,y,z,vx,vy,vz,qw,qx,qy,qz,lx,ly,lz%s%s\n", s.imageX.empty() ? "" : ",image_x",
                 s.imageY.empty() ? "" : ",image_y");
    for (std::size_t k = 0; k < s.size(); ++k) {
      const Quatf q = shapeOrientation(world, s, k);  // the scene file's shape frame
      // %.9g: nine significant digits read back to the same float bits.
      std::fprintf(f, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", k, s.px[k], s.py[k],
                   s.pz[k], s.vx[k], s.vy[k], s.vz[k], q.w, q.x, q.y, q.z, s.lx[k], s.ly[k], s.lz[k]);
      if (!s.imageX.empty()) std::fprintf(f, ",%d", static_cast<int>(s.imageX[k]));
      if (!s.imageY.empty()) std::fprintf(f, ",%d", static_cast<int>(s.imageY[k]));
      std::fputc('\n', f);
    }
    if (std::ferror(f)) throw Error("cannot write " + path + ": " + std::strerror(errno != 0 ? errno : EIO));
  });
}

void printPhases(const StepStats& st, std::FILE* out) {
  const double total = st.totalSeconds();
  const double n = st.steps ? double(st.steps) : 1.0;
  std::fprintf(out, "%-10s %12s %12s %7s\n", "phase", "total ms", "ms/step", "share");
  for (int p = 0; p < kNumPhases; ++p)
    std::fprintf(out, "%-10s %12.2f %12.4f %6.1f%%\n", toString(static_cast<Phase>(p)), 1e3 * st.seconds[p],
                 1e3 * st.seconds[p] / n, total > 0 ? 100.0 * st.seconds[p] / total : 0.0);
  std::fprintf(out, "%-10s %12.2f %12.4f %6.1f%%\n", "step", 1e3 * total, 1e3 * total / n, 100.0);
}

// The continuity of a recording continued by a resumed run: its frames must reach the last frame
// due at or before the checkpoint's step.
void checkContinues(const RecordingWriter& rec, std::uint64_t start, std::uint64_t recSteps, std::uint64_t perFrame,
                    bool debug) {
  const std::uint64_t due = (std::min(start, recSteps) / perFrame) * perFrame;  // last frame due by now
  const bool any = !(debug && due == 0);  // a debug recording has no step-0 frame
  if (any ? rec.lastStep() != due : rec.numFrames() != 0)
    throw Error("recording '" + rec.path() + "' ends at step " + std::to_string(rec.lastStep()) +
                " but the checkpoint is at step " + std::to_string(start) +
                ": it does not continue there; record the resumed run to another file");
}

// What a run starts from: the scene with the command line's overrides, its pours, and the world
// to load (the checkpoint's on --resume).
struct Start {
  Scene scene;
  std::shared_ptr<const Pouring> pouring;  // (not copied: it caches the meshes of its scene)
  World world;
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
  if (o.checkpointEvery && o.checkpoint.empty()) throw Error("--checkpoint-every N needs --checkpoint FILE");
  if (o.record.empty() && !scene.recordFile.empty()) o.record = scene.recordFile;
  if (!o.recordSteps && scene.recordSteps > 0) o.recordSteps = scene.recordSteps;
  if (o.thermo.empty()) o.thermo = scene.thermoFile;
  // --resume may name the --checkpoint file (a run that goes on checkpointing into it).
  refuseSameFile({{"--record", o.record}, {"--thermo", o.thermo}, {"--checkpoint", o.checkpoint},
                  {"--state-out", o.stateOut}, {"scene", o.scene}});
  refuseSameFile({{"--resume", o.resume}, {"--record", o.record}, {"--thermo", o.thermo}, {"--state-out", o.stateOut}});

  // Bodies that enter during the run (tumble/pour.hpp): the world grows at its batch steps.
  const auto pouringOf = std::make_shared<const Pouring>(scene);
  const Pouring& pouring = *pouringOf;
  World world = pouring.worldWith(pouring.initialBodies());
  // (Of every body the run will have: the pours' too.)
  if (const std::string w = timeStepWarning(pouring.any() ? pouring.worldWith(pouring.finalBodies()) : world);
      !w.empty() && prints)
    std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.scene.c_str(), w.c_str());
  if (!o.resume.empty()) {
    const Checkpoint ck = Checkpoint::read(o.resume);
    std::string warning;
    try {
      // A run that pours resumes the world of the bodies that had entered by then.
      if (pouring.any() && ck.state.size() > world.numBodies() && ck.state.size() <= pouring.finalBodies())
        world = pouring.worldWith(ck.state.size());
      world = ck.resume(world, &warning);
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      throw Error(o.resume + ": cannot resume " + o.scene + ": " + e.what());
    }
    if (!warning.empty() && prints) std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.resume.c_str(), warning.c_str());
    if (ck.step >= scene.steps)
      throw Error(o.resume + ": the checkpoint is at step " + std::to_string(ck.step) + " and the run ends at step " +
                  std::to_string(scene.steps) + ": nothing to do (--steps N sets the step to run to)");
  }
  return Start{std::move(scene), pouringOf, std::move(world)};
}

void run(RunOptions o) {
  // Under mpirun (docs/mpi.md) every rank runs this with the same input: the collective calls
  // (the pipeline's, the guards', the reads) fall in the same order on every rank; rank 0 alone
  // writes the outputs and prints, and each write is agreed (a failure ends every rank with its
  // message and status).
  const mpi::Session& ranks = mpi::session();
  const bool writes = ranks.writes();
  auto onWriter = [&](auto&& write) {
    ranks.together([&] {
      if (writes) write();
    });
  };
  std::optional<Start> input;
  ranks.together([&] { input.emplace(prepare(o)); });  // the same files on every rank, or one message
  const Scene& scene = input->scene;
  const Pouring& pouring = *input->pouring;
  World& world = input->world;
  const bool debug = o.debug || scene.recordDebug;
  const std::uint64_t thermoEvery = o.thermoEvery.value_or(scene.thermoEvery);
  const std::uint64_t start = world.step;
  PipelineOptions po;
  po.threads = o.threads;
  auto pipeline = ranks.makePipeline(backendFromString(o.pipeline), po, mpi::decompositionFromString(o.decomposition));
  pipeline->load(world);
  pipeline->setDebugCapture(debug && !o.record.empty());

  const bool tty = isatty(fileno(stderr)) && !o.quiet && writes;
  if (!o.quiet && writes) {
    const std::string on = ranks.active() ? " on " + std::to_string(ranks.size()) + " MPI ranks" : "";
    std::fprintf(stderr, "tumble run: %s — %u bodies, %u particles, %llu steps of %g s, pipeline %s%s\n",
                 scene.name.c_str(), world.numBodies(), world.numParticles(),
                 static_cast<unsigned long long>(scene.steps), scene.dt, toString(pipeline->backend()), on.c_str());
    if (start > 0)
      std::fprintf(stderr, "tumble run: resuming at step %llu (t = %.9g s) from %s\n",
                   static_cast<unsigned long long>(start), world.time, o.resume.c_str());
  }

  // Steps are counted from the start of the run (a resumed run continues the count), so frames,
  // guard checks and checkpoints fall on the same steps as in an uninterrupted run.
  // SIGINT / SIGTERM from here on stop the run like a guard trip (stop_signal.hpp): the loop ends
  // after the steps under way, the recording is finished, a --checkpoint written.
  const StopOnSignal stopOnSignal(/*restart=*/true);
  std::unique_ptr<RecordingWriter> rec;  // rank 0's
  const std::uint64_t recSteps = o.recordSteps ? std::min<std::uint64_t>(*o.recordSteps, scene.steps) : scene.steps;
  const std::uint64_t perFrame = static_cast<std::uint64_t>(std::max(1, scene.stepsPerFrame));
  const bool recording = !o.record.empty() && start < recSteps;
  BodyState state;
  ParticleDebug dbg;
  if (recording) {
    onWriter([&] {
      // With pours the recording's table holds every body that may enter, each frame those present.
      const World& table = pouring.any() ? pouring.worldWith(pouring.finalBodies()) : world;
      if (start == 0) {
        rec = std::make_unique<RecordingWriter>(o.record, table, debug, static_cast<int>(perFrame), 60.0f, pouring.any());
      } else {
        rec = RecordingWriter::continueAt(o.record, table, debug, static_cast<int>(perFrame), start, 60.0f, pouring.any());
        if (rec->numFrames() > 0) checkContinues(*rec, start, recSteps, perFrame, debug);
      }
    });
    pipeline->readState(state);
    // The first frame of a new recording: the initial state (debug frames start after a step).
    onWriter([&] {
      if (rec->numFrames() == 0 && !debug) rec->writeFrame(start, pipeline->time(), pipeline->pulls(), state);
    });
  }

  // Guards (docs/model.md#guards): checked every guardEvery steps and before every frame and
  // checkpoint. The time series (docs/thermo.md) is what the guard measures, so with --no-guard
  // and --thermo the guard still measures, every thermoEvery steps, and never stops the run.
  std::optional<RunGuard> guard;
  const bool guarding = !o.noGuard;
  std::unique_ptr<ThermoWriter> thermo;  // rank 0's
  const bool thermoOn = !o.thermo.empty();
  if (guarding || thermoOn) {
    guard.emplace(world, *pipeline);
    if (guarding && start == 0 && !guard->initialWarning().empty() && writes)
      std::fprintf(stderr, "tumble run: warning: %s: %s\n", o.scene.c_str(), guard->initialWarning().c_str());
  }
  if (thermoOn) onWriter([&] {
      thermo = std::make_unique<ThermoWriter>(o.thermo);
      thermo->write(guard->sample());  // the state at the start (of the resumed part: its step)
    });
  // A write of the loop, agreed: true when rank 0 gave it up at a stop (a pipe nobody reads:
  // StopOnSignal gave it kWriteGraceSeconds), and the run then stops as interrupted, without it.
  auto writeOrGiveUp = [&](auto&& write) {
    bool givenUp = false;
    onWriter([&] {
      try {
        write();
      } catch (const Error&) {
        if (!writeStopRequested() || g_stopSignal == 0) throw;
        givenUp = true;
      }
    });
    return ranks.maxOf(givenUp ? 1 : 0) != 0;
  };
  const std::uint64_t guardEvery = o.guardEvery.value_or(kDefaultGuardEvery);
  const std::uint64_t ckEvery = o.checkpointEvery.value_or(0);

  const auto t0 = std::chrono::steady_clock::now();
  auto lastPrint = t0;
  StepStats stats;  // the pipeline's counters before the last pour's load()
  std::uint64_t done = start;
  std::uint64_t checkedAt = start;  // the step of the last guard check
  bool frameCut = false;            // a frame's write was given up at a stop
  bool thermoCut = false;           // a time-series row's write was given up at a stop
  try {
    while (done < scene.steps && ranks.maxOf(g_stopSignal) == 0) {  // a signal any rank saw
      std::uint64_t chunk = scene.steps - done;
      if (recording && done < recSteps) chunk = std::min(chunk, perFrame - done % perFrame);
      if (guarding) chunk = std::min(chunk, guardEvery - done % guardEvery);
      if (thermoOn) chunk = std::min(chunk, thermoEvery - done % thermoEvery);
      if (ckEvery) chunk = std::min(chunk, ckEvery - done % ckEvery);
      chunk = std::min<std::uint64_t>(chunk, 100);  // a signal is seen within 100 steps
      // Bodies of a [[pour]] enter at its batch steps, after the frame, checks and checkpoint
      // of the state before them; the guard then starts its energy budget afresh.
      if (pouring.step(*pipeline, world, chunk, &stats) && guard) guard.emplace(world, *pipeline);
      done += chunk;
      const bool frameDue = recording && done <= recSteps && done % perFrame == 0;
      const bool checkpointDue = ckEvery && done % ckEvery == 0 && done < scene.steps;
      const bool thermoDue = thermoOn && (done % thermoEvery == 0 || done == scene.steps);
      if (thermoDue || (guarding && (frameDue || checkpointDue || done % guardEvery == 0 || done == scene.steps))) {
        const auto trip = guard->check(*pipeline);
        if (thermoDue && writeOrGiveUp([&] { thermo->write(guard->sample()); })) {
          thermoCut = true;
          break;
        }
        if (trip && guarding) throw SimulationError(trip->message);
        checkedAt = done;
      }
      if (frameDue) {
        pipeline->readState(state);
        if (debug) pipeline->readDebug(dbg);
        if (writeOrGiveUp([&] { rec->writeFrame(done, pipeline->time(), pipeline->pulls(), state, debug ? &dbg : nullptr); })) {
          frameCut = true;
          break;
        }
        if (done + perFrame > recSteps) onWriter([&] { rec->close(); });  // last frame: the file is complete now
      }
      if (checkpointDue) {
        const Checkpoint ck = Checkpoint::of(world, *pipeline);
        onWriter([&] { ck.write(o.checkpoint); });
      }
      const auto now = std::chrono::steady_clock::now();
      if (tty && (now - lastPrint > std::chrono::milliseconds(200) || done == scene.steps)) {
        lastPrint = now;
        const double el = std::chrono::duration<double>(now - t0).count();
        const double ran = double(done - start);
        const double eta = el / ran * double(scene.steps - done);
        // The energy is that of the last guard check (at most guardEvery steps old).
        char energy[48] = "";
        if (guard && guard->sample().finite) std::snprintf(energy, sizeof energy, "  E %.4g J", guard->sample().energy());
        std::fprintf(stderr, "\r  step %llu/%llu (%5.1f%%)  t %.4g s%s  %llu contacts  %.3f ms/step  elapsed %.1f s  eta %.1f s   ",
                     static_cast<unsigned long long>(done), static_cast<unsigned long long>(scene.steps),
                     100.0 * double(done) / double(scene.steps), pipeline->time(), energy,
                     static_cast<unsigned long long>(pipeline->stats().numPairs), 1e3 * el / ran, el, eta);
      }
    }
    // Interrupted: the state is checked before anything is written from it.
    if (done < scene.steps && guarding && checkedAt != done)
      if (const auto trip = guard->check(*pipeline)) throw SimulationError(trip->message);
  } catch (const SimulationError&) {  // the same on every rank (the pipeline's or the guard's)
    if (tty) std::fprintf(stderr, "\n");
    onWriter([&] {
      if (rec) {
        rec->close();
        std::fprintf(stderr, "tumble run: kept %llu frames in %s\n", static_cast<unsigned long long>(rec->numFrames()),
                     rec->path().c_str());
      }
      if (thermo) {
        thermo->close();
        std::fprintf(stderr, "tumble run: kept %llu rows of the time series in %s\n",
                     static_cast<unsigned long long>(thermo->rows()), thermo->path().c_str());
      }
    });
    throw;
  }
  if (tty) std::fprintf(stderr, "\n");
  if (done < scene.steps) {  // stopped by a signal (any rank's)
    const int sig = ranks.maxOf(g_stopSignal);
    std::string kept;
    onWriter([&] {
      if (rec) {
        rec->close();
        kept = "; kept " + std::to_string(rec->numFrames()) + " frames in " + rec->path();
        if (frameCut) kept += " (the next frame's write was given up: nothing read it for " +
                              std::to_string(kWriteGraceSeconds) + " s)";
      }
      if (thermo) {
        thermo->close();
        kept += "; kept " + std::to_string(thermo->rows()) + " rows of the time series in " + thermo->path();
        if (thermoCut) kept += " (the next row's write was given up)";
      }
    });
    if (!o.checkpoint.empty()) {
      try {
        if (!(ckEvery && done % ckEvery == 0 && done > start)) {  // else just written by the loop
          const Checkpoint ck = Checkpoint::of(world, *pipeline);
          onWriter([&] { ck.write(o.checkpoint); });
        }
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
  onWriter([&] {
    if (rec) rec->close();
  });
  if (rec) {
    if (!o.quiet) {
      std::fprintf(stderr, "recorded %llu frames (up to step %llu, %llu steps per frame) to %s\n",
                   static_cast<unsigned long long>(rec->numFrames()), static_cast<unsigned long long>(rec->lastStep()),
                   static_cast<unsigned long long>(perFrame), rec->path().c_str());
      std::error_code ec;
      if (!namesDescriptor(rec->path()) && std::filesystem::is_regular_file(rec->path(), ec))  // what next
        std::fprintf(stderr,
                     "  watch it: %s play %s    make a video: %s render %s -o video.mp4    "
                     "for ParaView: %s export %s DIR\n",
                     invokedAs().c_str(), rec->path().c_str(), invokedAs().c_str(), rec->path().c_str(),
                     invokedAs().c_str(), rec->path().c_str());
    }
  }
  onWriter([&] {
    if (thermo) thermo->close();
  });
  if (thermo) {
    if (!o.quiet)
      std::fprintf(stderr, "time series: %llu rows (every %llu steps) written to %s (draw it: tumble plot %s)\n",
                   static_cast<unsigned long long>(thermo->rows()), static_cast<unsigned long long>(thermoEvery),
                   thermo->path().c_str(), thermo->path().c_str());
  }
  if (!o.checkpoint.empty()) {
    try {
      const Checkpoint ck = Checkpoint::of(world, *pipeline);
      onWriter([&] { ck.write(o.checkpoint); });
    } catch (const SimulationError& e) {  // a diverged state (--no-guard): nothing more is written from it
      throw SimulationError(std::string(e.what()) + (o.stateOut.empty() ? "" : "; no --state-out written either"),
                            e.particle());
    }
    if (!o.quiet && writes)
      std::fprintf(stderr, "checkpoint at step %llu written to %s (continue with --resume %s)\n",
                   static_cast<unsigned long long>(done), o.checkpoint.c_str(), o.checkpoint.c_str());
  }
  pipeline->readState(state);
  if (!o.stateOut.empty()) onWriter([&] { writeState(o.stateOut, world, state); });
  // Under mpirun: each rank's share of the bodies and of the traffic (collective).
  const auto* mpiPipeline = dynamic_cast<const mpi::MpiPipeline*>(pipeline.get());
  const std::vector<mpi::MpiStats> rankStats = mpiPipeline && !o.quiet ? mpiPipeline->gatherStats() : std::vector<mpi::MpiStats>{};
  if (!o.quiet && writes) {
    stats.add(pipeline->stats());
    const StepStats& st = stats;
    std::printf("%s: %llu steps, %u particles, %llu contacts in the last step\n", scene.name.c_str(),
                static_cast<unsigned long long>(st.steps), world.numParticles(),
                static_cast<unsigned long long>(st.numPairs));
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
  c->add_flag("-q,--quiet", o->quiet, "No progress line and no timing table");
  c->add_option("--guard-every", o->guardEvery,
                "Check the guards (finite state, energy, overlaps) every N steps, and before every frame and "
                "checkpoint (default: " + std::to_string(kDefaultGuardEvery) + ")")
      ->check(countIn(1, kMaxSteps));
  c->add_flag("--no-guard", o->noGuard, "Do not check the guards (a diverging run then stops only at a non-finite position)");
  c->callback([o] { run(*o); });
}

}  // namespace tumble::cli
