// SPDX-License-Identifier: MIT
// `tumble render FILE -o out.mp4`: draw every frame of a recording off-screen (EGL, no X server
// needed) and pipe the frames to ffmpeg as raw RGB; `--still N` writes one frame as PNG/PPM.
// The output appears only when complete: ffmpeg writes a temporary next to OUT (OutputFile),
// renamed on success and deleted on any failure (ffmpeg error, our error, Ctrl-C).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "stop_signal.hpp"
#include "tumble/output_file.hpp"
#include "tumble/error.hpp"

#if TUMBLE_HAS_VIEWER
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tumble/recording.hpp"
#include "tumble/viewer/camera_path.hpp"
#include "tumble/viewer/color_file.hpp"
#include "tumble/viewer/draw_data.hpp"
#include "tumble/viewer/label.hpp"
#include "tumble/viewer/offscreen.hpp"
#include "tumble/viewer/renderer.hpp"
#endif

namespace tumble::cli {

[[noreturn]] void viewerMissing(const char* command) {
  std::fprintf(stderr,
               "tumble %s: this tumble was built without the viewer; install %s and rebuild "
               "(cmake -DTUMBLE_VIEWER=ON reports anything still missing)\n",
               command, kViewerPackages);
  throw Exit{kExitBadInput};
}

void parseSize(const std::string& text, const char* option, int& outW, int& outH) {
  const auto x = text.find_first_of("xX");
  const auto num = [&](const std::string& s, int& out) {
    char* end = nullptr;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || v < 16 || v > 8192) return false;
    out = static_cast<int>(v);
    return true;
  };
  if (x == std::string::npos || !num(text.substr(0, x), outW) || !num(text.substr(x + 1), outH))
    throw Error(std::string(option) + " " + text + ": expected WIDTHxHEIGHT, each from 16 to 8192 (e.g. 1280x720)");
}

void addLookOptions(CLI::App* c, LookOptions& look) {
  c->add_option("--background", look.background,
                "Background colour: default (dark blue-grey), black, white, grey (gray) or #RRGGBB");
  c->add_option("--ground", look.ground,
                "The scene's ground: on (default: grey, tinted by the pulls), off (no ground, no shadows) or a colour "
                "as for --background");
}

std::pair<CLI::Option*, CLI::Option*> addFrameRangeOptions(CLI::App* c, FrameRangeOptions& range,
                                                           const std::string& note) {
  return {c->add_option("--from", range.from, "First frame (default 0; negative counts from the end)" + note),
          c->add_option("--to", range.to, "Last frame, included (default -1: the last; negative counts from the end)")};
}

std::size_t frameIndex(long n, const char* option, std::size_t numFrames, const std::string& file) {
  const long i = n < 0 ? static_cast<long>(numFrames) + n : n;
  if (i < 0 || i >= static_cast<long>(numFrames))
    throw Error(std::string(option) + " " + std::to_string(n) + ": " + file + " has frames 0 to " +
                std::to_string(numFrames - 1) + " (negative counts from the end)");
  return static_cast<std::size_t>(i);
}

std::pair<std::size_t, std::size_t> frameRange(const FrameRangeOptions& range, std::size_t numFrames,
                                               const std::string& file) {
  const std::size_t first = frameIndex(range.from, "--from", numFrames, file);
  const std::size_t last = frameIndex(range.to, "--to", numFrames, file);
  if (first > last)
    throw Error("--from " + std::to_string(range.from) + " --to " + std::to_string(range.to) + ": frame " +
                std::to_string(first) + " comes after frame " + std::to_string(last) + " of " + file);
  return {first, last};
}

namespace {

struct RenderOptions {
  std::string file;
  std::string out;
  std::string size = "1280x720";
  std::optional<double> fps;
  std::string color = "plain";
  std::string colorFile;
  std::optional<long> still;
  FrameRangeOptions range;
  LookOptions look;
  std::string forces;
  std::optional<double> yaw, pitch;
  std::vector<double> lookAt;
  double zoom = 1.0;
  std::string camera = "fixed";
  double cameraSmooth = 0.5;
  std::string cameraPath;
  bool realtime = false;
  bool noLabel = false;
  bool noWalls = false;
  bool quiet = false;
};

#if TUMBLE_HAS_VIEWER
using namespace tumble::viewer;

bool endsWith(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

// A number in at most three significant digits: 5.56, 0.18, 12.
std::string compact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// A time with `decimals` decimals, the label's.
std::string fixed(double t, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, t);
  return buf;
}

void printProgress(std::size_t done, std::size_t total, double elapsed) {
  std::fprintf(stderr, "\r  frame %zu/%zu (%5.1f%%)  %.1f frames/s  eta %.1f s   ", done, total,
               100.0 * double(done) / double(total), double(done) / elapsed,
               elapsed / double(done) * double(total - done));
}

// -o DIR/: one PNG per video frame, DIR/frame_000000.png …, each written atomically; Ctrl-C stops
// after the frame under way (the frames written stay).
template <class Draw>
void writePngSequence(const RenderOptions& o, const std::vector<std::size_t>& sequence, double fps, Draw&& drawFrame) {
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (!std::filesystem::is_directory(o.out))
    throw Error(o.out + ": cannot create the folder for the PNG sequence" + (ec ? ": " + ec.message() : ""));
  const StopOnSignal stopOnSignal(/*restart=*/true);
  const bool tty = isatty(fileno(stderr)) && !o.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto lastPrint = t0;
  std::size_t k = 0;
  for (; k < sequence.size() && g_stopSignal == 0; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06zu.png", k);
    writeImage((std::filesystem::path(o.out) / name).string(), drawFrame(k));
    const auto now = std::chrono::steady_clock::now();
    if (tty && (now - lastPrint > std::chrono::milliseconds(200) || k + 1 == sequence.size())) {
      lastPrint = now;
      printProgress(k + 1, sequence.size(), std::chrono::duration<double>(now - t0).count());
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  if (g_stopSignal != 0) {
    std::fprintf(stderr, "tumble render: interrupted after %zu frames in %s\n", k, o.out.c_str());
    dieOfSignal(g_stopSignal);
  }
  // Frames of an earlier, longer render into this folder would follow these in a video: they go.
  std::size_t stale = 0;
  for (std::size_t j = k;; ++j) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06zu.png", j);
    if (!std::filesystem::remove(std::filesystem::path(o.out) / name, ec)) break;
    ++stale;
  }
  if (!o.quiet)
    std::fprintf(stderr, "tumble render: %zu frames to %sframe_000000.png …%s (ffmpeg -framerate %g -i %sframe_%%06d.png "
                 "makes a video of them)\n", k, o.out.c_str(),
                 stale ? (" (" + std::to_string(stale) + " later frames of an earlier render removed)").c_str() : "", fps,
                 o.out.c_str());
}

// The summary's second line: how fast the video plays.
void printSpeed(const std::string& speedText, double speed, bool realtime) {
  std::fprintf(stderr, "  %s: a second of video shows %s s of simulated time%s\n", speedText.c_str(),
               compact(speed).c_str(), realtime ? "" : " (--realtime plays it at the simulation's speed)");
}

// The ffmpeg on PATH (or $TUMBLE_FFMPEG), empty when there is none.
std::string findFfmpeg() {
  if (const char* e = std::getenv("TUMBLE_FFMPEG"); e && *e) return access(e, X_OK) == 0 ? e : "";
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string p = (dir.empty() ? "." : dir) + "/ffmpeg";
    struct stat st {};
    if (stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(p.c_str(), X_OK) == 0) return p;
  }
  return "";
}

// ffmpeg reading raw RGB frames from a pipe; the child's stdout and stderr stay ours, so its
// own errors reach the user.
class FfmpegPipe {
 public:
  FfmpegPipe(const std::string& exe, const std::vector<std::string>& args) {
    // Everything the child needs is built before fork: the process has other threads (oneTBB,
    // llvmpipe), so between fork and exec only async-signal-safe calls are allowed (no malloc,
    // no stdio).
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const std::string execFailed = "tumble render: cannot run " + exe + "\n";
    int fds[2];
    if (pipe(fds) != 0) throw Error(std::string("cannot create a pipe to ffmpeg: ") + std::strerror(errno));
    m_pid = fork();
    if (m_pid < 0) {
      const int err = errno;
      close(fds[0]);
      close(fds[1]);
      throw Error(std::string("cannot start ffmpeg: ") + std::strerror(err));
    }
    if (m_pid == 0) {
      // We ignore SIGPIPE; an ignored signal stays ignored across exec, so give ffmpeg the default.
      signal(SIGPIPE, SIG_DFL);
      dup2(fds[0], 0);
      close(fds[0]);
      close(fds[1]);
      execv(exe.c_str(), argv.data());
      const ssize_t ignored = ::write(2, execFailed.data(), execFailed.size());
      (void)ignored;
      _exit(127);
    }
    close(fds[0]);
    m_fd = fds[1];
  }
  ~FfmpegPipe() {
    if (m_pid > 0) {
      kill(m_pid, SIGTERM);
      finish();
    }
  }
  bool write(const std::uint8_t* data, std::size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(m_fd, data, n);
      if (w < 0 && errno == EINTR && !g_stopSignal) continue;
      if (w <= 0) return false;
      data += w;
      n -= static_cast<std::size_t>(w);
    }
    return true;
  }
  /// Closes the pipe and waits; returns ffmpeg's exit status (−signal when killed).
  int finish() {
    if (m_fd >= 0) close(m_fd);
    m_fd = -1;
    int status = 0;
    while (waitpid(m_pid, &status, 0) < 0 && errno == EINTR) {
    }
    m_pid = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }

 private:
  pid_t m_pid = -1;
  int m_fd = -1;
};

void render(const RenderOptions& o) {
  int w = 0, h = 0;
  parseSize(o.size, "--size", w, h);
  const auto mode = o.colorFile.empty() ? colorModeFromString(o.color) : ColorMode::User;
  if (!mode) throw Error("--color " + o.color + ": expected one of " + colorModeNames());
  // A user's values: read and checked now, their count once the recording's header is read.
  const std::optional<ColorFile> colorFile =
      o.colorFile.empty() ? std::nullopt : std::optional<ColorFile>(readColorFile(o.colorFile));
  const Look look = parseLook(o.look.background, o.look.ground);
  if (o.fps && !(*o.fps > 0.0 && *o.fps <= 1000.0)) throw Error("--fps must be in (0, 1000]");
  if (!(o.zoom > 0.0)) throw Error("--zoom must be positive");
  for (const double v : o.lookAt)
    if (!std::isfinite(v) || std::abs(v) > 1e30) throw Error("--look-at: expected three finite coordinates X,Y,Z in m");
  if (!(o.cameraSmooth >= 0.0 && o.cameraSmooth <= 3600.0))
    throw Error("--camera-smooth must be from 0 to 3600 seconds of video");
  const bool follow = o.camera == "follow";
  const std::vector<CameraKey> path = o.cameraPath.empty() ? std::vector<CameraKey>() : readCameraPath(o.cameraPath);
  bool show[kNumForces] = {};
  for (char c : o.forces) {
    if (c == ',' || c == ' ') continue;
    if (c < '1' || c > '5') throw Error("--forces " + o.forces + ": expected digits 1-5 (1 repulsion, 2 damping, 3 shear, 4 ground, 5 friction)");
    show[c - '1'] = true;
  }

  // Decide everything about the output before any expensive work.
  std::string muxer, codec;
  const bool pngs = !o.still && !o.out.empty() && o.out.back() == '/';  // a PNG sequence into a folder
  if (o.still) checkImageName(o.out, "-o");
  if (!o.still && !pngs) {
    if (endsWith(o.out, ".mp4")) muxer = "mp4", codec = "libx264";
    else if (endsWith(o.out, ".mkv")) muxer = "matroska", codec = "libx264";
    else if (endsWith(o.out, ".mov")) muxer = "mov", codec = "libx264";
    else if (endsWith(o.out, ".webm")) muxer = "webm", codec = "libvpx-vp9";
    else throw Error("-o " + o.out + ": expected a video name ending in .mp4, .mkv, .mov or .webm, a folder ending in / "
                     "for a PNG sequence, or --still N for one image");
    if (w % 2 || h % 2) throw Error("--size " + o.size + ": a video needs an even width and height");
  }
  const std::string ffmpeg = o.still || pngs ? std::string() : findFfmpeg();
  if (!o.still && !pngs && ffmpeg.empty()) {
    std::fprintf(stderr, "tumble render: ffmpeg was not found on PATH; install it (Debian: apt-get install ffmpeg) "
                         "or write single frames with --still N -o FRAME.png\n");
    throw Exit{kExitBadInput};
  }

  // Frame by frame: memory is one frame whatever the recording's length.
  if (!pngs) refuseSameFile({{"recording", o.file}, {"-o", o.out}, {"--color-file", o.colorFile}});
  RecordingReader reader(o.file);
  const Recording& rec = reader.header();
  if (reader.numFrames() == 0) throw InputError(o.file, 0, "the recording holds no frames");
  if (!o.forces.empty() && !rec.info.debug)
    throw Error("--forces needs a debug recording (tumble run --debug-record); " + o.file + " is not one");
  // The frames rendered, first to last: --from and --to, or the one of --still (framed as the
  // whole recording is, as in a video of it).
  const std::size_t numFrames = reader.numFrames();
  const std::pair<std::size_t, std::size_t> range = frameRange(o.range, numFrames, o.file);
  const std::size_t first = range.first, last = range.second;
  const std::size_t stillIndex = o.still ? frameIndex(*o.still, "--still", numFrames, o.file) : first;
  const std::size_t count = last - first + 1;  // frames in the range

  // One pass over the range's frames (each checked) frames the camera before anything is drawn,
  // and finds the range of a colouring by speed or height.
  const ParticleTable table = ParticleTable::from(rec);
  const std::vector<float> userValues = colorFile ? colorFile->particleValues(table, o.file) : std::vector<float>();
  const bool perFrame = *mode == ColorMode::Speed || *mode == ColorMode::Height;
  float valueLo = std::numeric_limits<float>::infinity(), valueHi = -valueLo;
  RecordedFrame before;  // the frame before the one visited (positions and time)
  bool haveBefore = false;
  std::vector<float> values;
  const auto visit = [&](const RecordedFrame& f, const std::vector<float>& spheres) {
    if (*mode == ColorMode::Height) {
      frameValues(*mode, table, spheres, {}, values);
      // The bulk, as the camera frames it: from the 1st to the 99th percentile (all below 100).
      const bool all = values.size() < 100;
      valueLo = std::min(valueLo, quantile(values, all ? 0.0 : 0.01));
      valueHi = std::max(valueHi, quantile(values, all ? 1.0 : 0.99));
    } else if (*mode == ColorMode::Speed) {
      if (haveBefore) {
        values = bodySpeeds(f, before);
        valueLo = 0.0f;
        valueHi = std::max(valueHi, quantile(values, values.size() < 100 ? 1.0 : 0.99));
      }
      before.time = f.time, before.px = f.px, before.py = f.py, before.pz = f.pz;
      haveBefore = true;
    }
  };
  std::vector<double> times;
  std::vector<Bounds> boxes;
  const Camera fixedCamera =
      Camera::framing(recordingBounds(reader, table, &times, follow ? &boxes : nullptr, visit, first, last));
  if (perFrame && !(valueHi >= valueLo)) valueLo = valueHi = 0.0f;  // one frame: no speed
  OffscreenContext ctx;
  Renderer renderer;
  renderer.setWalls(wallMeshes(rec.walls));
  Framebuffer fb(w, h);
  DrawData d;
  d.wallsShown = !o.noWalls;
  d.groundEnabled = rec.info.groundEnabled;
  d.groundHeight = rec.info.groundHeight;
  applyLook(look, d);
  d.colors = particleColors(table, *mode);
  float legendLo = valueLo, legendHi = valueHi;
  if (*mode == ColorMode::Mass || *mode == ColorMode::Elasticity || *mode == ColorMode::User) {
    const std::vector<float>& v = *mode == ColorMode::Mass         ? table.mass
                                  : *mode == ColorMode::Elasticity ? table.elasticity
                                                                   : colorFile->values;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    legendLo = *lo, legendHi = *hi;
  }
  if (*mode == ColorMode::User) rampColors(*mode, userValues, legendLo, legendHi, d.colors);
  const std::string legendName = *mode == ColorMode::Mass         ? "mass kg"
                                 : *mode == ColorMode::Elasticity ? "elasticity"
                                 : *mode == ColorMode::Speed      ? "speed m/s"
                                 : *mode == ColorMode::Height     ? "height m"
                                 : colorFile                      ? colorFile->name
                                                                  : "";
  const std::string colouring = colorFile ? "--color-file " + o.colorFile : std::string(toString(*mode));

  // How fast the video plays: simulated seconds per second of video. Without --realtime one
  // recorded frame is one video frame; with it, video frame k shows the last recorded frame at or
  // before t0 + k / fps, so the video runs at the simulation's speed. times[k] is frame first + k's.
  const double fps = o.fps ? *o.fps : rec.info.fps;
  const double span = times.back() - times.front();
  const double speed = o.realtime || count < 2 ? 1.0 : span / double(count - 1) * fps;
  std::vector<std::size_t> sequence;  // the recorded frame of each video frame
  if (o.still) {
    sequence = {stillIndex};
  } else if (!o.realtime) {
    for (std::size_t i = first; i <= last; ++i) sequence.push_back(i);
  } else {
    // A thousandth of a video frame of slack: frame times carry the rounding of the time steps.
    const double tol = 1e-3 / fps;
    const auto videoFrames = static_cast<std::size_t>(std::floor((span + tol) * fps)) + 1;
    std::size_t i = 0;
    for (std::size_t k = 0; k < videoFrames; ++k) {
      const double t = times.front() + double(k) / fps;
      while (i + 1 < count && times[i + 1] <= t + tol) ++i;
      sequence.push_back(first + i);
    }
  }
  // The camera of each video frame: the fixed framing or the following one, then the options, then
  // the path. A still is framed as it is in a video of one recorded frame per video frame.
  std::vector<Camera> cams;
  if (follow) {
    std::vector<Bounds> seqBoxes;
    if (o.still) seqBoxes = boxes;
    else
      for (const std::size_t i : sequence) seqBoxes.push_back(boxes[i - first]);
    cams = followCameras(seqBoxes, o.cameraSmooth * fps);
    if (o.still) cams = {cams[stillIndex]};
  } else {
    cams.assign(sequence.size(), fixedCamera);
  }
  const Vec3f up = upFromGravity(rec.info.gravity);  // a chute's tilted gravity: down on screen
  for (std::size_t k = 0; k < cams.size(); ++k) {
    Camera& c = cams[k];
    c.setUp(up);
    if (o.yaw) c.yaw = static_cast<float>(*o.yaw * 3.14159265358979 / 180.0);
    if (o.pitch) c.pitch = static_cast<float>(std::max(-85.0, std::min(85.0, *o.pitch)) * 3.14159265358979 / 180.0);
    c.distance /= static_cast<float>(o.zoom);
    if (o.lookAt.size() == 3)
      c.target = {static_cast<float>(o.lookAt[0]), static_cast<float>(o.lookAt[1]), static_cast<float>(o.lookAt[2])};
    if (!path.empty()) c = cameraOnPath(path, times[sequence[k] - first], c);
  }

  const std::string speedText = count < 2 ? std::string("one frame")
                                : o.realtime || std::abs(speed - 1.0) < 0.01 ? std::string("real time")
                                : speed < 1.0 ? "slow motion x" + compact(1.0 / speed)
                                              : "fast motion x" + compact(speed);
  // Enough decimals in the time label to tell the frames apart (at least 4).
  const int decimals = count < 2 || !(span > 0.0)
                           ? 4
                           : std::clamp(static_cast<int>(std::ceil(-std::log10(span / double(count - 1)))) + 1, 4, 12);

  RecordedFrame f, neighbour;
  std::vector<float> speeds;
  const auto drawFrame = [&](std::size_t k) {
    const std::size_t i = sequence[k];
    reader.readFrame(i, f);
    particleSpheres(table, f.px.data(), f.py.data(), f.pz.data(), f.qw.data(), f.qx.data(), f.qy.data(), f.qz.data(),
                    d.spheres, rec.particlesOf(f.numBodies()));
    if (perFrame) {
      speeds.clear();
      if (*mode == ColorMode::Speed && numFrames > 1) {
        reader.readFrame(i > 0 ? i - 1 : 1, neighbour);  // the frame before (after the first)
        speeds = bodySpeeds(f, neighbour);
      }
      frameValues(*mode, table, d.spheres, speeds, values);
      rampColors(*mode, values, valueLo, valueHi, d.colors);
    }
    d.pulls = f.pulls;
    d.time = f.time;
    if (rec.info.debug) forceLines(table, d.spheres, f.debug, show, d.lines);
    fb.bind();
    renderer.draw(d, cams[k], w, h);
    Image img = fb.read();
    if (!o.noLabel) {
      const int scale = labelScale(h), margin = 4 * scale;
      drawLabel(img, margin, margin, "t = " + fixed(f.time, decimals) + " s", scale);
      if (!o.still) drawLabel(img, margin, margin + 10 * scale, speedText, scale);
      if (hasRamp(*mode)) drawLegend(img, *mode, legendLo, legendHi, legendName, scale);
    }
    return img;
  };

  if (o.still) {
    writeImage(o.out, drawFrame(0));
    if (!o.quiet)
      std::fprintf(stderr, "tumble render: frame %zu (step %llu, t = %.4f s) of %s, %dx%d, %s, to %s\n", stillIndex,
                   static_cast<unsigned long long>(f.step), f.time, o.file.c_str(), w,
                   h, colouring.c_str(), o.out.c_str());
    return;
  }

  if (pngs) {
    writePngSequence(o, sequence, fps, drawFrame);
    if (!o.quiet && count > 1) printSpeed(speedText, speed, o.realtime);
    return;
  }
  // ffmpeg writes the temporary by name (output_file.hpp: created exclusively next to the target,
  // or the target itself when it is a device or a FIFO); it is renamed into place at the end.
  OutputFile out(o.out);
  const std::string part = out.writingTo();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", fps);
  std::vector<std::string> args = {"-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24",
                                   "-s", std::to_string(w) + "x" + std::to_string(h), "-r", rate, "-i", "pipe:0",
                                   "-an", "-c:v", codec, "-pix_fmt", "yuv420p"};
  if (codec == "libx264") args.insert(args.end(), {"-crf", "20", "-preset", "medium"});
  if (muxer == "mp4" || muxer == "mov") args.insert(args.end(), {"-movflags", "+faststart"});
  args.insert(args.end(), {"-f", muxer, part});

  // A dead ffmpeg must give a write error, not kill us; Ctrl-C must clean up the temporary.
  // The previous dispositions come back however this function ends.
  std::optional<StopOnSignal> stopOnSignal(std::in_place, /*restart=*/false);  // stop_signal.hpp; also ignores SIGPIPE
  const auto restore = [&] { stopOnSignal.reset(); };
  const bool tty = isatty(fileno(stderr)) && !o.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto lastPrint = t0;
  std::string failure;
  int status = 0;
  try {
    FfmpegPipe pipe(ffmpeg, args);
    for (std::size_t k = 0; k < sequence.size() && failure.empty(); ++k) {
      if (g_stopSignal) {
        failure = "interrupted";
        break;
      }
      const Image img = drawFrame(k);
      if (!pipe.write(img.rgb.data(), img.rgb.size())) failure = "ffmpeg stopped reading frames";
      const auto now = std::chrono::steady_clock::now();
      if (tty && (now - lastPrint > std::chrono::milliseconds(200) || k + 1 == sequence.size())) {
        lastPrint = now;
        printProgress(k + 1, sequence.size(), std::chrono::duration<double>(now - t0).count());
      }
    }
    if (tty) std::fprintf(stderr, "\n");
    status = pipe.finish();
  } catch (...) {
    // Our own failure (a read-back error, bad_alloc, ...): ~FfmpegPipe has already stopped and
    // reaped ffmpeg, so its half-written output can go.
    if (tty) std::fprintf(stderr, "\n");
    restore();
    throw;  // ~OutputFile removes the temporary
  }
  restore();
  if (g_stopSignal) failure = "interrupted";
  if (failure.empty() && status != 0) failure = "ffmpeg failed (exit status " + std::to_string(status) + ")";
  if (failure.empty()) {
    try {
      out.commit();
    } catch (const Error& e) {
      failure = e.what();
    }
  }
  if (!failure.empty()) {
    out.abandon();
    if (failure == "interrupted") {
      std::fprintf(stderr, "tumble render: interrupted; %s not written\n", o.out.c_str());
      dieOfSignal(g_stopSignal != 0 ? g_stopSignal : SIGINT);
    }
    throw Error(o.out + ": " + failure + "; nothing written");
  }
  if (!o.quiet) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "tumble render: %zu frames of %s (%dx%d, %g frames/s, %s) to %s in %.1f s (%s, EGL %s)\n",
                 sequence.size(), o.file.c_str(), w, h, fps, colouring.c_str(), o.out.c_str(), el,
                 Renderer::glRenderer().c_str(), ctx.platform().c_str());
    if (count > 1) printSpeed(speedText, speed, o.realtime);
  }
}
#endif

}  // namespace

void addRender(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* c = app.add_subcommand(
      "render", "Render a recording to a video (through ffmpeg) or one frame to an image, off-screen: no X server needed");
  c->add_option("file", o->file, "Recording (tumble run --record, docs/recording.md)")->required();
  c->add_option("-o,--output", o->out,
                "Output: OUT.mp4 / .mkv / .mov / .webm, DIR/ (ending in /) for a PNG sequence DIR/frame_000000.png …, "
                "or with --still an image .png / .ppm")
      ->required();
  c->add_option("--size", o->size, "Image size WIDTHxHEIGHT (default 1280x720; even for a video)");
  c->add_option("--fps", o->fps, "Video frames per second (default: the recording's, 60)");
  CLI::Option* color =
      c->add_option("--color", o->color,
                    "Colouring: plain or body (one colour per body), shape (one per shape), mass, elasticity, speed "
                    "or height (a colour ramp, light to dark, with a legend)")
          ->check(CLI::IsMember({"plain", "body", "mass", "elasticity", "shape", "speed", "height"}));
  c->add_option("--color-file", o->colorFile,
                "Colour by your own values: a CSV of one column, a header line (the legend's name, e.g. stress kPa) "
                "and one number per body (body 0 first) or per particle, for the whole recording; a ramp from "
                "yellow (smallest) to dark purple (largest) (docs/animation.md)")
      ->excludes(color);
  CLI::Option* still =
      c->add_option("--still", o->still, "Write only frame N as an image (negative counts from the end: -1 = last)");
  const auto [from, to] = addFrameRangeOptions(c, o->range, "; the camera frames the frames rendered");
  from->excludes(still);
  to->excludes(still);
  c->add_option("--forces", o->forces,
                "Debug recordings: draw force lines, digits 1-5 (1 repulsion, 2 damping, 3 shear, 4 ground, 5 friction)");
  c->add_option("--yaw", o->yaw,
                "Camera direction about the up (opposite the gravity: z, tilted for a chute), degrees (default -57)");
  c->add_option("--pitch", o->pitch, "Camera elevation above the plane across the up, degrees (default 26)");
  c->add_option("--zoom", o->zoom, "Zoom factor (default 1: the bulk of the bodies over the recording fits)");
  c->add_option("--look-at", o->lookAt, "Point the camera at X,Y,Z (m; default: the centre of the framed box)")
      ->expected(3)
      ->delimiter(',');
  c->add_option("--camera", o->camera,
                "fixed: one framing for the whole recording (the bulk of the bodies over all frames; default); "
                "follow: the camera follows the bulk of each frame, smoothed over --camera-smooth")
      ->check(CLI::IsMember({"fixed", "follow"}));
  c->add_option("--camera-smooth", o->cameraSmooth,
                "With --camera follow: seconds of video the following camera averages over (Gaussian sigma; "
                "default 0.5, 0 = none)");
  c->add_option("--camera-path", o->cameraPath,
                "Key frames of the camera: lines of time,x,y,z,yaw,pitch,distance (simulated s, m, degrees, m), "
                "interpolated linearly; an empty field is automatic (docs/animation.md)");
  c->add_flag("--realtime", o->realtime,
              "Play at the simulation's speed: frames resampled to the simulated time at --fps (default: one "
              "recorded frame per video frame, and the summary and the label say how much slow motion that is)");
  c->add_flag("--no-label", o->noLabel, "No time and speed label (top left) and no colour legend (bottom right)");
  c->add_flag("--no-walls", o->noWalls,
              "Leave out the walls (drawn by default: shaded, faint where they would hide the bodies, a turning "
              "wall with stripes; a recording of version 1 has none)");
  addLookOptions(c, o->look);
  c->add_flag("-q,--quiet", o->quiet, "No progress and no summary");
  c->callback([o] {
#if TUMBLE_HAS_VIEWER
    render(*o);
#else
    viewerMissing("render");
#endif
  });
}

}  // namespace tumble::cli
