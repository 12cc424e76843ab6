// SPDX-License-Identifier: MIT
// `tumble view SCENE.toml`: the live window (SPEC §6). The simulation runs 10 steps (the
// scene's steps per frame) per drawn frame; with vsync that is 60 frames/s where the machine
// keeps up, otherwise as fast as it can. Held arrow-left / arrow-up / space switch the x, y and
// swirl pulls on (they add) and tint the ground. `--script` feeds key events at given frames
// through the same handler as the keyboard, so tests can drive the window under Xvfb.
#include <algorithm>
#include <memory>
#include <optional>

#include "commands.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"  // kMaxThreads, with or without the viewer

#if TUMBLE_HAS_VIEWER
#include <imgui.h>

#include <chrono>

#include "tumble/recording.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/viewer/controls.hpp"
#include "tumble/viewer/draw_data.hpp"
#include "tumble/viewer/renderer.hpp"
#include "tumble/viewer/window.hpp"
#endif

namespace tumble::cli {
namespace {

struct ViewOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string pipeline = "cpu";
  int threads = 0;
  std::string record;
  bool recordOn = false;
  bool debug = false;
  bool contacts = false;
  std::string size = "1280x720";
  std::string color = "plain";
  bool paused = false;
  std::string script;
  std::optional<std::uint64_t> frames;
  std::string screenshot;
  bool noWalls = false;
  LookOptions look;
};

#if TUMBLE_HAS_VIEWER
using namespace tumble::viewer;

// FILE, FILE-2.ext, FILE-3.ext, …: a new file each time recording is switched on.
std::string numbered(const std::string& path, int n) {
  if (n <= 1) return path;
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  const bool hasExt = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return hasExt ? path.substr(0, dot) + "-" + std::to_string(n) + path.substr(dot)
                : path + "-" + std::to_string(n);
}

void view(const ViewOptions& o) {
  int w = 0, h = 0;
  parseSize(o.size, "--size", w, h);
  const std::vector<ScriptEvent> script = o.script.empty() ? std::vector<ScriptEvent>{} : readScript(o.script);
  if (!o.screenshot.empty()) checkImageName(o.screenshot, "--screenshot");
  const Look look = parseLook(o.look.background, o.look.ground);
  const Scene scene = readSceneFile(o.scene, o.sets);
  refuseSceneInput(scene, o.record, "--record");
  refuseSceneInput(scene, o.screenshot, "--screenshot");
  Run run(scene);  // bodies that enter during the run ([[pour]]): its world grows
  if (!run.timeStepWarning().empty())
    std::fprintf(stderr, "tumble view: warning: %s: %s\n", o.scene.c_str(), run.timeStepWarning().c_str());
  const std::uint64_t perFrame = static_cast<std::uint64_t>(std::max(1, scene.stepsPerFrame));
  PipelineOptions po;
  po.threads = o.threads;
  // Guards (docs/model.md#guards), checked after every frame's steps, before anything is drawn
  // or recorded from them. A trip stops the simulation; the window stays open with the message.
  RunChecks checks;
  checks.every = perFrame;
  run.load(makePipeline(backendFromString(o.pipeline), po), checks);
  Pipeline& pipeline = run.pipeline();
  const World& world = run.world();
  const bool debug = o.debug || scene.recordDebug;
  const std::uint32_t basePulls = scene.pulls.active;  // the scene's `on` pulls stay on; keys add
  // Not the scene's [output] file: a live session must not overwrite what `tumble run` wrote.
  const std::string recordPath = o.record.empty() ? "view.bin" : o.record;

  Window window("tumble view: " + scene.name, w, h);
  Renderer renderer;
  // The walls as a recording of this run draws them (RecordingWriter).
  const std::vector<WallSurface> walls = sceneWallSurfaces(world.params, world.bodiesExtent);
  renderer.setWalls(wallMeshes(walls));
  ParticleTable table = ParticleTable::from(world);
  Keyboard kb;
  LiveControls controls;
  controls.setPaused(o.paused);
  controls.setWallsShown(!o.noWalls);
  controls.setRecording(o.recordOn || !o.record.empty());
  ColorMode color = *colorModeFromString(o.color);
  for (ColorMode m = ColorMode::Plain; m != color; m = nextColorMode(m)) controls.keyEvent(Key::Num0, true);
  window.setKeyHandler([&](Key k, bool pressed) {
    if (kb.event(k, pressed)) controls.keyEvent(k, pressed);
  });

  BodyState state;
  pipeline.readState(state);
  DrawData d;
  d.groundEnabled = world.params.ground.enabled;
  d.groundHeight = world.params.ground.height;
  applyLook(look, d);
  particleSpheres(table, state.px.data(), state.py.data(), state.pz.data(), state.qw.data(), state.qx.data(),
                  state.qy.data(), state.qz.data(), d.spheres);
  Camera cam = Camera::framing(framedWithWalls(sphereBounds(d.spheres), walls));
  if (world.params.ground.enabled) {  // framed as with the ground, drawn or not (--ground off)
    cam.target.z = std::max(cam.target.z, d.groundHeight);
  }
  cam.setUp(upFromGravity(world.params.gravity));  // a chute's tilted gravity: down on screen
  window.setCamera(&cam);
  d.colors = particleColors(table, controls.colorMode());
  color = controls.colorMode();

  std::string stopped;
  int recordings = 0;
  std::uint64_t frame = 0;
  std::size_t nextEvent = 0;
  bool quit = false;
  // Per-phase times per step, refreshed every half second from Pipeline::stats().
  StepStats lastStats = pipeline.stats();
  double phaseMs[kNumPhases] = {}, stepMs = 0.0, fpsShown = 0.0;
  double lastStatsTime = window.time(), lastFrameTime = window.time();
  std::uint64_t framesSinceStats = 0;

  while (!quit) {
    // Scripted keys for this frame, then the real ones.
    if (applyScriptEvents(script, frame, nextEvent, kb, controls)) quit = true;
    window.beginFrame();
    if (window.shouldClose() || controls.quit() || (o.frames && frame >= *o.frames)) quit = true;
    const double now = window.time();
    const double dt = frameSeconds(!script.empty(), now, lastFrameTime);

    const std::uint32_t pulls = pullMaskFromKeys(kb) | basePulls;
    pipeline.setPulls(pulls);
    const CameraMotion cm = cameraMotionFromKeys(kb);
    if (cm.any()) cam.move(cm.forward, cm.right, cm.up, cm.turn, static_cast<float>(dt));

    if (controls.recording() && !run.recordingOn() && stopped.empty()) {
      RecordSettings rs;
      rs.path = numbered(recordPath, ++recordings);
      rs.stepsPerFrame = static_cast<int>(perFrame);
      rs.debug = debug;
      rs.contactForces = o.contacts || scene.recordContacts;
      run.record(rs);  // the state now as its first frame (a debug recording's follows a step)
    } else if (!controls.recording() && run.recordingOn()) {
      run.closeRecording();
      std::fprintf(stderr, "tumble view: recorded %llu frames to %s\n",
                   static_cast<unsigned long long>(run.recording()->numFrames()), run.recording()->path().c_str());
    }

    if (!quit && stopped.empty() && (!controls.paused() || controls.takeStep())) {
      try {
        if (run.advance(perFrame).entered) {  // bodies entered: draw them
          table = ParticleTable::from(world);
          d.colors = particleColors(table, color);
          lastStats = StepStats{};  // the pipeline's counters started afresh
        }
        pipeline.readState(state);
      } catch (const SimulationError& e) {
        // The last good state stays on screen; nothing from the bad one is recorded.
        stopped = e.what();
        std::fprintf(stderr, "tumble view: stopped: %s\n", stopped.c_str());
        if (run.recordingOn()) {
          run.closeRecording();
          std::fprintf(stderr, "tumble view: kept %llu frames in %s\n",
                       static_cast<unsigned long long>(run.recording()->numFrames()), run.recording()->path().c_str());
          controls.setRecording(false);
        }
      }
    }

    if (controls.colorMode() != color) {
      color = controls.colorMode();
      d.colors = particleColors(table, color);
    }
    particleSpheres(table, state.px.data(), state.py.data(), state.pz.data(), state.qw.data(), state.qx.data(),
                    state.qy.data(), state.qz.data(), d.spheres);
    d.pulls = pulls;
    d.time = pipeline.time();
    d.wallsShown = controls.wallsShown();
    int fw = 0, fh = 0;
    window.framebufferSize(fw, fh);
    renderer.draw(d, cam, fw, fh);
    if (quit && !o.screenshot.empty()) writeImage(o.screenshot, window.readBack());

    ++framesSinceStats;
    if (now - lastStatsTime >= 0.5) {
      const StepStats& st = pipeline.stats();
      const double n = double(st.steps - lastStats.steps);
      stepMs = 0.0;
      for (int p = 0; p < kNumPhases; ++p) {
        phaseMs[p] = n > 0 ? 1e3 * (st.seconds[p] - lastStats.seconds[p]) / n : 0.0;
        stepMs += phaseMs[p];
      }
      fpsShown = double(framesSinceStats) / (now - lastStatsTime);
      lastStats = st;
      lastStatsTime = now;
      framesSinceStats = 0;
    }

    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("tumble view", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::Text("%s: %u particles, %u bodies", scene.name.c_str(), world.numParticles(), world.numBodies());
    ImGui::Text("pipeline %s, %llu steps per frame", toString(pipeline.backend()),
                static_cast<unsigned long long>(perFrame));
    ImGui::Text("t = %.4f s (step %llu)%s", pipeline.time(), static_cast<unsigned long long>(pipeline.stepCount()),
                controls.paused() ? "  PAUSED" : "");
    ImGui::Text("%.1f frames/s, %.3f ms per step", fpsShown, stepMs);
    if (ImGui::BeginTable("phases", 2)) {
      for (int p = 0; p < kNumPhases; ++p) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(toString(static_cast<Phase>(p)));
        ImGui::TableNextColumn();
        ImGui::Text("%8.3f ms", phaseMs[p]);
      }
      ImGui::EndTable();
    }
    if (!stopped.empty()) {
      ImGui::PushTextWrapPos(560.0f);
      ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "STOPPED: %s", stopped.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::Text("pulls: %s", pullsToString(pulls).c_str());
    ImGui::Text("colouring: %s", toString(color));
    if (!walls.empty()) ImGui::Text("%zu walls %s (V)", walls.size(), controls.wallsShown() ? "shown" : "hidden");
    bool recOn = controls.recording();
    if (ImGui::Checkbox("record (C)", &recOn)) controls.setRecording(recOn);
    if (const RecordingWriter* rec = run.recording(); rec && run.recordingOn())
      ImGui::Text("%s: %llu frames", rec->path().c_str(), static_cast<unsigned long long>(rec->numFrames()));
    bool pausedBox = controls.paused();
    if (ImGui::Checkbox("pause (P)", &pausedBox)) controls.setPaused(pausedBox);
    ImGui::End();
    if (controls.helpShown()) helpOverlay(liveKeyHelp());
    window.endFrame();
    ++frame;
  }
  if (run.recordingOn()) {
    run.closeRecording();
    std::fprintf(stderr, "tumble view: recorded %llu frames to %s\n",
                 static_cast<unsigned long long>(run.recording()->numFrames()), run.recording()->path().c_str());
  }
  const double wall = window.time();
  std::printf("tumble view: %llu frames, %llu steps, t = %.4f s, pulls %s, %.1f frames/s\n",
              static_cast<unsigned long long>(frame), static_cast<unsigned long long>(pipeline.stepCount()),
              pipeline.time(), pullsToString(pipeline.pulls()).c_str(), wall > 0 ? double(frame) / wall : 0.0);
  if (!stopped.empty()) throw Exit{kExitDiverged};
}
#endif

}  // namespace

void addView(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* c = app.add_subcommand("view", "Live window: simulate a scene and draw it, with the pulls on the keys");
  c->add_option("scene", o->scene, "Scene file, e.g. scenes/molecules.toml")->required();
  addSetOption(c, o->sets, "");
  c->add_option("--pipeline", o->pipeline, "Pipeline (default cpu)")->check(pipelineName());
  c->add_option("--threads", o->threads, "Worker threads, 0 = all cores")->check(countIn(0, kMaxThreads));
  c->add_option("--record", o->record,
                "Record from the start into FILE (C switches recording on and off; default file view.bin; each "
                "new start writes FILE-2, FILE-3, ...)");
  c->add_flag("--record-on", o->recordOn, "Start with recording on (into view.bin)");
  c->add_flag("--debug-record", o->debug, "Recordings include velocities, the five forces and the contacts");
  c->add_flag("--record-contacts", o->contacts, "Recordings include each frame's contacts with their forces");
  c->add_option("--size", o->size, "Window size WIDTHxHEIGHT (default 1280x720)");
  c->add_option("--color", o->color, "Initial colouring: plain, mass or elasticity (0 cycles)")
      ->check(CLI::IsMember({"plain", "mass", "elasticity"}));
  c->add_flag("--paused", o->paused, "Start paused (P runs, N steps)");
  c->add_option("--script", o->script,
                "Key script: lines 'FRAME press|release|tap KEY' or 'FRAME quit' (docs/animation.md); each frame "
                "then counts as 1/60 s");
  c->add_option("--frames", o->frames, "Quit after N frames")->check(countIn(1, kMaxSteps));
  c->add_option("--screenshot", o->screenshot, "When quitting, save the last frame without the overlay (.png or .ppm)");
  c->add_flag("--no-walls", o->noWalls, "Start with the walls hidden (V shows them)");
  addLookOptions(c, o->look);
  c->callback([o] {
#if TUMBLE_HAS_VIEWER
    view(*o);
#else
    viewerMissing("view");
#endif
  });
}

}  // namespace tumble::cli
