// SPDX-License-Identifier: MIT
// Key handling shared by `tumble view` and `tumble play` (SPEC §6). Everything here is plain
// C++; the window code only maps GLFW key codes to Key and calls Keyboard::event and keyEvent.
#include "tumble/viewer/controls.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"

namespace tumble::viewer {
namespace {

constexpr const char* kKeyNames[kNumKeys] = {
    "left", "right", "up", "down", "space", "lshift", "w", "a", "s", "d", "q", "z", "e", "r",
    "0",    "1",     "2",  "3",    "4",     "5",      "p", "n", "c", "h", "l", "v", "escape"};

// GCC 12 at -O3 reports a false -Wrestrict in InputError's inlined `":" + std::to_string(line)`
// here (GCC bug 105329, std::string operator+ on an rvalue); CMakeLists.txt turns that one
// warning off for this file.
[[noreturn]] void scriptError(const std::string& file, long line, const std::string& what) {
  throw InputError(file, line, what);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

const char* toString(Key k) {
  const int i = static_cast<int>(k);
  return i >= 0 && i < kNumKeys ? kKeyNames[i] : "?";
}

std::optional<Key> keyFromString(const std::string& name) {
  const std::string n = lower(name);
  for (int i = 0; i < kNumKeys; ++i)
    if (n == kKeyNames[i]) return static_cast<Key>(i);
  return std::nullopt;
}

bool Keyboard::event(Key k, bool pressed) {
  bool& d = m_down[static_cast<int>(k)];
  if (d == pressed) return false;
  d = pressed;
  return true;
}

std::uint32_t pullMaskFromKeys(const Keyboard& kb) {
  std::uint32_t m = 0;
  if (kb.down(Key::Left)) m |= kPullX;
  if (kb.down(Key::Up)) m |= kPullY;
  if (kb.down(Key::Space)) m |= kPullSwirl;
  return m;
}

std::string pullsToString(std::uint32_t mask) {
  std::string s;
  const auto add = [&](const char* n) { s += s.empty() ? n : std::string("+") + n; };
  if (mask & kPullX) add("x");
  if (mask & kPullY) add("y");
  if (mask & kPullSwirl) add("swirl");
  return s.empty() ? "none" : s;
}

Rgb groundColor(std::uint32_t pullMask) {
  Rgb c{0.45f, 0.46f, 0.48f};  // neutral grey-blue: no pull
  if (pullMask & kPullX) c = {c.r + 0.40f, c.g - 0.12f, c.b - 0.14f};
  if (pullMask & kPullY) c = {c.r - 0.14f, c.g + 0.38f, c.b - 0.14f};
  if (pullMask & kPullSwirl) c = {c.r - 0.12f, c.g - 0.02f, c.b + 0.42f};
  const auto clamp = [](float v) { return std::min(1.0f, std::max(0.05f, v)); };
  return {clamp(c.r), clamp(c.g), clamp(c.b)};
}

const char* toString(ColorMode m) {
  switch (m) {
    case ColorMode::Plain: return "plain";
    case ColorMode::Mass: return "mass";
    case ColorMode::Elasticity: return "elasticity";
    case ColorMode::Shape: return "shape";
    case ColorMode::Speed: return "speed";
    case ColorMode::Height: return "height";
    case ColorMode::User: return "user";
  }
  return "?";
}

std::optional<ColorMode> colorModeFromString(const std::string& s) {
  const std::string n = lower(s);
  if (n == "body") return ColorMode::Plain;
  for (const ColorMode m : {ColorMode::Plain, ColorMode::Mass, ColorMode::Elasticity, ColorMode::Shape,
                            ColorMode::Speed, ColorMode::Height})
    if (n == toString(m)) return m;
  return std::nullopt;
}

const char* colorModeNames() { return "plain, body, mass, elasticity, shape, speed, height"; }

bool hasRamp(ColorMode m) { return m != ColorMode::Plain && m != ColorMode::Shape; }

ColorMode nextColorMode(ColorMode m) {
  switch (m) {
    case ColorMode::Plain: return ColorMode::Mass;
    case ColorMode::Mass: return ColorMode::Elasticity;
    default: return ColorMode::Plain;
  }
}

const char* forceName(int kind) {
  static_assert(std::size(kDebugForceNames) == kNumForces);
  return kind >= 0 && kind < kNumForces ? kDebugForceNames[kind] : "?";
}

Rgb forceColor(int kind) {
  static constexpr Rgb kColors[kNumForces] = {
      {1.0f, 0.25f, 0.2f}, {1.0f, 0.85f, 0.1f}, {0.2f, 0.9f, 1.0f}, {0.3f, 1.0f, 0.3f}, {1.0f, 0.3f, 1.0f}};
  return kind >= 0 && kind < kNumForces ? kColors[kind] : Rgb{1, 1, 1};
}

CameraMotion cameraMotionFromKeys(const Keyboard& kb) {
  const auto axis = [&](Key plus, Key minus) {
    return static_cast<float>(int(kb.down(plus)) - int(kb.down(minus)));
  };
  CameraMotion m;
  m.forward = axis(Key::W, Key::S);
  m.right = axis(Key::D, Key::A);
  m.up = axis(Key::Q, Key::Z);
  m.turn = axis(Key::R, Key::E);
  return m;
}

const std::vector<KeyHelp>& liveKeyHelp() {
  static const std::vector<KeyHelp> kHelp = {
      {"arrow-left (hold)", "pull along x toward the origin"},
      {"arrow-up (hold)", "pull along y toward the origin"},
      {"space (hold)", "swirl about the origin"},
      {"P", "pause / run"},
      {"N", "one frame (10 steps) while paused"},
      {"C", "recording on / off"},
      {"0", "colouring: plain, mass, elasticity"},
      {"V", "walls shown / hidden"},
      {"mouse drag / wheel", "orbit / zoom the camera"},
      {"W S A D Q Z", "move the camera"},
      {"E R", "turn the camera"},
      {"H", "this help on / off"},
      {"Esc", "quit"},
  };
  return kHelp;
}

std::vector<KeyHelp> playKeyHelp(bool debug) {
  std::vector<KeyHelp> h = {
      {"space", "play / pause"},
      {"L", "loop on / off"},
      {"arrow-right (hold)", "play forwards"},
      {"arrow-left (hold)", "play backwards"},
      {"arrow-up / arrow-down", "one frame forwards / backwards"},
      {"left shift", "speed: 1x 2x 4x 8x 0.25x 0.5x"},
      {"W S A D Q Z", "move the camera"},
      {"E R", "turn the camera"},
      {"mouse drag / wheel", "orbit / zoom the camera"},
      {"0", "colouring: plain, mass, elasticity"},
      {"V", "walls shown / hidden"},
  };
  if (debug) h.push_back({"1 2 3 4 5", "force lines: repulsion, damping, shear, ground, friction"});
  h.push_back({"H", "this help on / off"});
  h.push_back({"Esc", "quit"});
  return h;
}

PlaybackControls::PlaybackControls(std::size_t numFrames, bool debug, std::size_t first)
    : m_numFrames(numFrames), m_debug(debug), m_first(first) {}

std::size_t PlaybackControls::local() const {
  if (m_numFrames == 0) return 0;
  const double p = std::floor(m_position + 1e-9);
  return std::min(m_numFrames - 1, static_cast<std::size_t>(std::max(0.0, p)));
}

void PlaybackControls::keyEvent(Key k, bool pressed) {
  if (!pressed) return;
  const double last = m_numFrames ? double(m_numFrames - 1) : 0.0;
  switch (k) {
    case Key::Up: m_position = std::min(last, double(local()) + 1.0); break;
    case Key::Down: m_position = std::max(0.0, double(local()) - 1.0); break;
    case Key::LeftShift: m_speedIndex = (m_speedIndex + 1) % kSpeeds.size(); break;
    case Key::Space:
      m_playing = !m_playing;
      if (m_playing && !m_loop && local() + 1 >= m_numFrames) m_position = 0.0;  // play again from the start
      break;
    case Key::L: m_loop = !m_loop; break;
    case Key::V: m_walls = !m_walls; break;
    case Key::Num0: m_color = nextColorMode(m_color); break;
    case Key::Num1: case Key::Num2: case Key::Num3: case Key::Num4: case Key::Num5:
      if (m_debug) {
        const auto i = static_cast<std::size_t>(static_cast<int>(k) - static_cast<int>(Key::Num1));
        m_forces[i] = !m_forces[i];
      }
      break;
    case Key::H: m_help = !m_help; break;
    case Key::Escape: m_quit = true; break;
    default: break;
  }
}

void PlaybackControls::advance(const Keyboard& kb, double seconds, double fps) {
  const int held = int(kb.down(Key::Right)) - int(kb.down(Key::Left));
  const int dir = held != 0 ? held : int(m_playing);
  if (dir == 0 || m_numFrames == 0) return;
  const double last = double(m_numFrames - 1);
  const double next = m_position + dir * seconds * fps * speed();
  if (dir > 0 && next > last && m_loop && m_numFrames > 1) {
    m_position = std::fmod(next, double(m_numFrames));  // after the last frame, the first
  } else {
    m_position = std::clamp(next, 0.0, last);
    if (m_playing && held == 0 && m_position >= last) m_playing = false;  // the end, without the loop
  }
}

std::string PlaybackControls::describe() const {
  std::ostringstream s;
  s << "frame " << frame() << "/" << m_first + (m_numFrames ? m_numFrames - 1 : 0) << " speed " << speed()
    << "x colour " << toString(m_color) << " forces ";
  std::string f;
  for (int i = 0; i < kNumForces; ++i)
    if (m_forces[static_cast<std::size_t>(i)]) {
      if (!f.empty()) f += ',';
      f += std::to_string(i + 1);
    }
  s << (f.empty() ? "none" : f) << (m_playing ? " playing" : "") << (m_loop ? " loop" : "") << (m_walls ? "" : " no-walls");
  return s.str();
}

void LiveControls::keyEvent(Key k, bool pressed) {
  if (!pressed) return;
  switch (k) {
    case Key::P: m_paused = !m_paused; break;
    case Key::N:
      if (m_paused) ++m_pendingSteps;
      break;
    case Key::C: m_recording = !m_recording; break;
    case Key::V: m_walls = !m_walls; break;
    case Key::Num0: m_color = nextColorMode(m_color); break;
    case Key::H: m_help = !m_help; break;
    case Key::Escape: m_quit = true; break;
    default: break;
  }
}

bool LiveControls::takeStep() {
  if (m_pendingSteps == 0) return false;
  --m_pendingSteps;
  return true;
}

std::vector<ScriptEvent> parseScript(const std::string& text, const std::string& fileName) {
  std::vector<ScriptEvent> out;
  std::istringstream in(text);
  std::string line;
  long lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::string frameText, verb, keyName, extra;
    if (!(ls >> frameText)) continue;  // blank or comment
    const auto fail = [&](const std::string& what) { scriptError(fileName, lineNo, what); };
    char* end = nullptr;
    const unsigned long long frame = std::strtoull(frameText.c_str(), &end, 10);
    if (frameText.empty() || *end != '\0' || frameText[0] == '-')
      fail("expected a frame number, got '" + frameText + "'");
    if (!(ls >> verb)) fail("expected press, release, tap or quit after the frame number");
    verb = lower(verb);
    ScriptEvent e;
    e.frame = frame;
    if (verb == "quit") {
      e.kind = ScriptEvent::Kind::Quit;
    } else if (verb == "press" || verb == "release" || verb == "tap") {
      if (!(ls >> keyName)) fail("expected a key name after '" + verb + "'");
      const auto key = keyFromString(keyName);
      if (!key) fail("unknown key '" + keyName + "' (keys: left right up down space lshift w a s d q z e r 0-5 p n c h l v escape)");
      e.key = *key;
      e.kind = verb == "release" ? ScriptEvent::Kind::Release : ScriptEvent::Kind::Press;
    } else {
      fail("unknown action '" + verb + "' (expected press, release, tap or quit)");
    }
    if (ls >> extra) fail("unexpected '" + extra + "' at the end of the line");
    out.push_back(e);
    if (verb == "tap") {
      e.kind = ScriptEvent::Kind::Release;
      e.frame = frame + 1;
      out.push_back(e);
    }
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const ScriptEvent& a, const ScriptEvent& b) { return a.frame < b.frame; });
  return out;
}

std::vector<ScriptEvent> readScript(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, "cannot open key script");
  std::ostringstream s;
  s << f.rdbuf();
  return parseScript(s.str(), path);
}

}  // namespace tumble::viewer
