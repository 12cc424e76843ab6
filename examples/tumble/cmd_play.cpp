// SPDX-License-Identifier: MIT
// `tumble play FILE`: the player (SPEC §6, the report's playback program). The keys are those
// of the report: left/right play continuously while held, up/down step, left shift cycles the
// speed, W A S D Q Z move and E R turn the camera, 0 cycles the colouring and, with a debug
// recording, 1-5 toggle the force lines. The key logic is viewer::PlaybackControls.
#include <memory>
#include <optional>

#include "commands.hpp"
#include "tumble/error.hpp"

#if TUMBLE_HAS_VIEWER
#include <imgui.h>

#include <algorithm>

#include "tumble/recording.hpp"
#include "tumble/viewer/controls.hpp"
#include "tumble/viewer/draw_data.hpp"
#include "tumble/viewer/renderer.hpp"
#include "tumble/viewer/window.hpp"
#endif

namespace tumble::cli {
namespace {

struct PlayOptions {
  std::string file = "record.bin";
  std::string size = "1280x720";
  std::string script;
  std::optional<std::uint64_t> frames;
  std::string screenshot;
  bool noWalls = false;
  FrameRangeOptions range;
  LookOptions look;
};

#if TUMBLE_HAS_VIEWER
using namespace tumble::viewer;

void play(const PlayOptions& o) {
  int w = 0, h = 0;
  parseSize(o.size, "--size", w, h);
  const std::vector<ScriptEvent> script = o.script.empty() ? std::vector<ScriptEvent>{} : readScript(o.script);
  if (!o.screenshot.empty()) checkImageName(o.screenshot, "--screenshot");
  const Look look = parseLook(o.look.background, o.look.ground);
  // RecordingReader names the file, the byte offset and the problem for a corrupt or
  // truncated file; main() prints it and ends with status 2. Frames are read as they are shown.
  RecordingReader reader(o.file);
  const Recording& rec = reader.header();
  const std::size_t numFrames = reader.numFrames();
  if (numFrames == 0) throw InputError(o.file, 0, "the recording holds no frames");
  const std::pair<std::size_t, std::size_t> range = frameRange(o.range, numFrames, o.file);
  const std::size_t first = range.first, last = range.second;

  // One pass over the frames played (each checked) frames the camera before any window opens.
  const ParticleTable table = ParticleTable::from(rec);
  Camera cam = Camera::framing(recordingBounds(reader, table, nullptr, nullptr, {}, first, last));
  cam.setUp(upFromGravity(rec.info.gravity));  // a chute's tilted gravity: down on screen
  Window window("tumble play: " + o.file, w, h);
  Renderer renderer;
  renderer.setWalls(wallMeshes(rec.walls));
  Keyboard kb;
  PlaybackControls controls(last - first + 1, rec.info.debug, first);
  controls.setWallsShown(!o.noWalls);
  window.setKeyHandler([&](Key k, bool pressed) {
    if (kb.event(k, pressed)) controls.keyEvent(k, pressed);
  });
  window.setCamera(&cam);
  DrawData d;
  d.groundEnabled = rec.info.groundEnabled;
  d.groundHeight = rec.info.groundHeight;
  applyLook(look, d);
  ColorMode color = controls.colorMode();
  d.colors = particleColors(table, color);
  const auto massRange = std::minmax_element(rec.mass.begin(), rec.mass.end());
  const auto elasticityRange = std::minmax_element(rec.elasticity.begin(), rec.elasticity.end());

  RecordedFrame f;
  std::size_t shown = numFrames;  // the frame in f (none yet: no frame has this index)
  std::uint64_t frame = 0;
  std::size_t nextEvent = 0;
  bool quit = false;
  double lastTime = window.time();
  while (!quit) {
    if (applyScriptEvents(script, frame, nextEvent, kb, controls)) quit = true;
    window.beginFrame();
    if (window.shouldClose() || controls.quit() || (o.frames && frame >= *o.frames)) quit = true;
    const double dt = frameSeconds(!script.empty(), window.time(), lastTime);
    if (!quit) controls.advance(kb, dt, rec.info.fps);
    const CameraMotion cm = cameraMotionFromKeys(kb);
    if (cm.any()) cam.move(cm.forward, cm.right, cm.up, cm.turn, static_cast<float>(dt));

    if (controls.frame() != shown) {
      shown = controls.frame();
      reader.readFrame(shown, f);
    }
    if (controls.colorMode() != color) {
      color = controls.colorMode();
      d.colors = particleColors(table, color);
    }
    particleSpheres(table, f.px.data(), f.py.data(), f.pz.data(), f.qw.data(), f.qx.data(), f.qy.data(), f.qz.data(),
                    d.spheres, rec.particlesOf(f.numBodies()));
    d.pulls = f.pulls;
    d.time = f.time;
    d.wallsShown = controls.wallsShown();
    bool show[kNumForces];
    for (int k = 0; k < kNumForces; ++k) show[k] = controls.forceShown(k);
    if (rec.info.debug) forceLines(table, d.spheres, f.debug, show, d.lines);
    int fw = 0, fh = 0;
    window.framebufferSize(fw, fh);
    renderer.draw(d, cam, fw, fh);
    if (quit && !o.screenshot.empty()) writeImage(o.screenshot, window.readBack());

    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("tumble play", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::Text("%s (%s): %u particles, %u bodies", o.file.c_str(), rec.info.sceneName.c_str(), rec.info.numParticles,
                rec.info.numBodies);
    ImGui::Text("frame %zu / %zu   step %llu   t = %.4f s", controls.frame(), last,
                static_cast<unsigned long long>(f.step), f.time);
    ImGui::Text("speed %gx   pulls %s", controls.speed(), pullsToString(f.pulls).c_str());
    if (color == ColorMode::Mass)
      ImGui::Text("colouring: mass %.3g (light) to %.3g kg (dark)", *massRange.first, *massRange.second);
    else if (color == ColorMode::Elasticity)
      ImGui::Text("colouring: elasticity %.3g (light) to %.3g (dark)", *elasticityRange.first, *elasticityRange.second);
    else
      ImGui::Text("colouring: plain (one colour per body)");
    if (!rec.walls.empty())
      ImGui::Text("%zu walls %s (V)", rec.walls.size(), controls.wallsShown() ? "shown" : "hidden");
    if (rec.info.debug) {
      for (int k = 0; k < kNumForces; ++k) {
        const Rgb c = forceColor(k);
        ImGui::TextColored(ImVec4(c.r, c.g, c.b, 1.0f), "%d %s %s", k + 1, forceName(k), show[k] ? "on" : "off");
      }
      ImGui::Text("%zu contacts", f.debug.contacts.size());
    } else {
      ImGui::TextUnformatted("no debug data (record with --debug-record for force lines)");
    }
    ImGui::End();
    if (controls.helpShown()) helpOverlay(playKeyHelp(rec.info.debug));
    window.endFrame();
    ++frame;
  }
  std::printf("tumble play: %s\n", controls.describe().c_str());
}
#endif

}  // namespace

void addPlay(CLI::App& app) {
  auto o = std::make_shared<PlayOptions>();
  CLI::App* c = app.add_subcommand("play", "Play a recording in a window (arrows play and step, H shows the keys)");
  c->add_option("file", o->file, "Recording (default record.bin)");
  c->add_option("--size", o->size, "Window size WIDTHxHEIGHT (default 1280x720)");
  c->add_option("--script", o->script,
                "Key script: lines 'FRAME press|release|tap KEY' or 'FRAME quit' (docs/animation.md); each frame "
                "then counts as 1/60 s");
  c->add_option("--frames", o->frames, "Quit after N window frames")->check(countIn(1, kMaxSteps));
  c->add_option("--screenshot", o->screenshot, "When quitting, save the last frame without the overlay (.png or .ppm)");
  c->add_flag("--no-walls", o->noWalls, "Start with the walls hidden (V shows them)");
  addFrameRangeOptions(c, o->range, "; the camera frames the frames played, and play stays within them");
  addLookOptions(c, o->look);
  c->callback([o] {
#if TUMBLE_HAS_VIEWER
    play(*o);
#else
    viewerMissing("play");
#endif
  });
}

}  // namespace tumble::cli
