// SPDX-License-Identifier: MIT
/// @file controls.hpp
/// Keyboard state and what the keys do in the live window (`tumble view`) and the player
/// (`tumble play`), as plain C++ without a window, so that it can be unit-tested. The GLFW key
/// callback and the scripted input (`--script`) both feed the same Keyboard.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tumble::viewer {

/// The keys the programs react to (independent of GLFW's key codes).
enum class Key {
  Left, Right, Up, Down, Space, LeftShift,
  W, A, S, D, Q, Z, E, R,
  Num0, Num1, Num2, Num3, Num4, Num5,
  P, N, C, H, L, V, Escape,
  Count
};
inline constexpr int kNumKeys = static_cast<int>(Key::Count);

/// Name used in scripts and messages: "left", "right", "up", "down", "space", "lshift", "w", …,
/// "0" … "5", "p", "n", "c", "h", "l", "v", "escape".
const char* toString(Key k);
/// Inverse of toString() (case-insensitive); empty when the name is unknown.
std::optional<Key> keyFromString(const std::string& name);

/// Which keys are held. Not thread-safe.
class Keyboard {
 public:
  /// Records a press or release. Returns true when it changed the state (a repeated press of a
  /// held key returns false).
  bool event(Key k, bool pressed);
  bool down(Key k) const { return m_down[static_cast<int>(k)]; }
  /// Releases every key (window lost focus).
  void clear() { m_down.fill(false); }

 private:
  std::array<bool, kNumKeys> m_down{};
};

/// The user pulls from the held keys (SPEC §6): arrow-left → kPullX, arrow-up → kPullY,
/// space → kPullSwirl; several keys add.
std::uint32_t pullMaskFromKeys(const Keyboard& kb);

/// "none", or the pulls joined by '+': "x", "x+y", "x+y+swirl", …
std::string pullsToString(std::uint32_t mask);

/// RGB in [0, 1].
struct Rgb {
  float r, g, b;
};

/// Ground colour for a pull mask: grey with none, then x adds red, y green and swirl blue, so
/// every combination has its own colour.
Rgb groundColor(std::uint32_t pullMask);

/// How particles are coloured: plain (one colour per body), by mass or by elasticity
/// (light = small, dark = large); by shape (one colour per shape); by speed or by height, which
/// change from frame to frame (tumble render only: draw_data.hpp, frameValues); by the user's
/// values of a colour file (tumble render --color-file: color_file.hpp; no name of its own).
enum class ColorMode { Plain, Mass, Elasticity, Shape, Speed, Height, User };
const char* toString(ColorMode m);
/// "plain" (or "body", the same), "mass", "elasticity", "shape", "speed", "height"; empty otherwise
/// (User, "user", needs a file: --color-file).
std::optional<ColorMode> colorModeFromString(const std::string& s);
/// The names colorModeFromString takes, for messages and --help: "plain, body, mass, ...".
const char* colorModeNames();
/// Whether the mode maps a value to a ramp and has a legend (mass, elasticity, speed, height, user).
bool hasRamp(ColorMode m);
/// The windows' 0 key: plain → mass → elasticity → plain (any other mode → plain).
ColorMode nextColorMode(ColorMode m);

/// The five per-particle force kinds of a debug recording (keys 1–5).
inline constexpr int kNumForces = 5;
/// "repulsion", "damping", "shear", "ground", "friction".
const char* forceName(int kind);
/// Line colour of each force kind.
Rgb forceColor(int kind);

/// Camera motion asked for by the held keys, each in {−1, 0, 1}: W/S forward/back, D/A
/// right/left, Q/Z up/down, R/E turn right/left.
struct CameraMotion {
  float forward = 0, right = 0, up = 0, turn = 0;
  bool any() const { return forward != 0 || right != 0 || up != 0 || turn != 0; }
};
CameraMotion cameraMotionFromKeys(const Keyboard& kb);

/// One line of the key help overlay.
struct KeyHelp {
  const char* keys;
  const char* action;
};
/// Key help of `tumble view`.
const std::vector<KeyHelp>& liveKeyHelp();
/// Key help of `tumble play` (the force lines only with a debug recording).
std::vector<KeyHelp> playKeyHelp(bool debug);

/// Playback state of `tumble play`: a position in [0, numFrames − 1], continuous play while
/// arrow-left (backwards) or arrow-right (forwards) is held, one frame per arrow-up (forwards)
/// or arrow-down (backwards), speed cycled by left shift, colouring by 0, force lines by 1–5,
/// the walls shown or hidden by V.
class PlaybackControls {
 public:
  /// Speeds cycled by left shift, starting at 1×.
  static constexpr std::array<double, 6> kSpeeds{1.0, 2.0, 4.0, 8.0, 0.25, 0.5};

  /// Plays frames `first` to `first + numFrames − 1` of a recording (tumble play --from, --to);
  /// frame() counts from the recording's first frame, position() from `first`.
  PlaybackControls(std::size_t numFrames, bool debug, std::size_t first = 0);
  /// Reacts to a key press (pressed = true) or release; `kb` already holds the new state.
  void keyEvent(Key k, bool pressed);
  /// Advances continuous play by `seconds` of wall time at `fps` recorded frames per second
  /// times the speed: backwards while left is held, forwards while right is held or while
  /// playing (Space). Stops at the first and last frame; playing forwards with the loop on (L)
  /// goes on from the first frame after the last.
  void advance(const Keyboard& kb, double seconds, double fps);

  /// The recording's frame shown.
  std::size_t frame() const { return m_first + local(); }
  double position() const { return m_position; }
  double speed() const { return kSpeeds[m_speedIndex]; }
  ColorMode colorMode() const { return m_color; }
  bool forceShown(int kind) const { return m_forces[static_cast<std::size_t>(kind)]; }
  bool wallsShown() const { return m_walls; }
  void setWallsShown(bool on) { m_walls = on; }
  bool helpShown() const { return m_help; }
  bool quit() const { return m_quit; }
  bool playing() const { return m_playing; }
  bool looping() const { return m_loop; }
  /// One line: "frame 12/31 speed 2x colour mass forces 1,3" (the frame shown / the last one
  /// played), then " playing", " loop" when on and " no-walls" when the walls are hidden (used by
  /// --script runs).
  std::string describe() const;

 private:
  std::size_t local() const;  ///< the frame shown, counted from m_first
  std::size_t m_numFrames;
  bool m_debug;
  std::size_t m_first;
  double m_position = 0.0;
  std::size_t m_speedIndex = 0;
  ColorMode m_color = ColorMode::Plain;
  std::array<bool, kNumForces> m_forces{};
  bool m_walls = true;
  bool m_help = true;
  bool m_quit = false;
  bool m_playing = false;
  bool m_loop = false;
};

/// State of the live window `tumble view` other than the pulls (those follow the held keys):
/// P pauses, N steps one frame (10 steps) while paused, C switches recording on or off, 0 cycles
/// the colouring, V shows or hides the walls, H the help, Escape quits.
class LiveControls {
 public:
  void keyEvent(Key k, bool pressed);
  bool paused() const { return m_paused; }
  void setPaused(bool p) { m_paused = p; }
  /// Single steps asked for and not yet taken; takeStep() consumes one.
  bool takeStep();
  bool recording() const { return m_recording; }
  void setRecording(bool on) { m_recording = on; }
  ColorMode colorMode() const { return m_color; }
  bool wallsShown() const { return m_walls; }
  void setWallsShown(bool on) { m_walls = on; }
  bool helpShown() const { return m_help; }
  bool quit() const { return m_quit; }

 private:
  bool m_paused = false;
  bool m_walls = true;
  int m_pendingSteps = 0;
  bool m_recording = false;
  ColorMode m_color = ColorMode::Plain;
  bool m_help = true;
  bool m_quit = false;
};

/// A scripted input event (`--script FILE`): at the start of frame `frame` (0-based), press or
/// release `key`, or quit.
struct ScriptEvent {
  std::uint64_t frame = 0;
  enum class Kind { Press, Release, Quit } kind = Kind::Press;
  Key key = Key::Escape;
};

/// Parses a key script: one event per line, `FRAME press KEY`, `FRAME release KEY`,
/// `FRAME tap KEY` (press at FRAME, release at FRAME + 1) or `FRAME quit`; '#' starts a
/// comment. Events come out sorted by frame (stable). Throws tumble::InputError naming the
/// file and line on a bad line.
std::vector<ScriptEvent> parseScript(const std::string& text, const std::string& fileName);
/// Reads and parses a script file; throws tumble::InputError.
std::vector<ScriptEvent> readScript(const std::string& path);

/// Feeds the script events due at the start of window frame `frame`, from `ioNext` on, to `kb`
/// and, where they change it, to `controls` (PlaybackControls or LiveControls), as the key
/// callback does. Returns true when one of them is a quit.
template <class Controls>
bool applyScriptEvents(const std::vector<ScriptEvent>& script, std::uint64_t frame, std::size_t& ioNext, Keyboard& kb,
                       Controls& controls) {
  bool quit = false;
  while (ioNext < script.size() && script[ioNext].frame <= frame) {
    const ScriptEvent& e = script[ioNext++];
    if (e.kind == ScriptEvent::Kind::Quit) quit = true;
    else if (kb.event(e.key, e.kind == ScriptEvent::Kind::Press)) controls.keyEvent(e.key, e.kind == ScriptEvent::Kind::Press);
  }
  return quit;
}

/// Seconds of wall time a window frame stands for: the time since the last frame (at most
/// 0.1 s) or, with a script, exactly 1/60 s, so that scripted runs are reproducible. Sets
/// `ioLast` to `now`.
inline double frameSeconds(bool scripted, double now, double& ioLast) {
  const double dt = scripted ? 1.0 / 60.0 : std::min(0.1, now - ioLast);
  ioLast = now;
  return dt;
}

}  // namespace tumble::viewer
