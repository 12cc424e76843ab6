// SPDX-License-Identifier: MIT
// Recording format (docs/recording.md): bitwise round trips, crash safety, and a reader that
// turns every truncation and corruption into a tumble::InputError instead of a crash.
#include "tumble/recording.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <csignal>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/wall_geometry.hpp"

namespace {

namespace fs = std::filesystem;
using tumble::BodyState;
using tumble::InputError;
using tumble::ParticleDebug;
using tumble::Recording;
using tumble::RecordingWriter;
using tumble::World;

constexpr std::uint32_t kNumBodies = 3;
constexpr std::uint32_t kNumParticles = 5;

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }
std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

std::uint32_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint32_t h = 2166136261u;
  for (std::size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 16777619u;
  return h;
}

void putU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
}
std::uint32_t getU32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

std::vector<std::uint8_t> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void writeAll(const std::string& path, const std::vector<std::uint8_t>& bytes, std::size_t n) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(n));
}
void writeAll(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  writeAll(path, bytes, bytes.size());
}

/// 3 bodies, 5 particles (2 + 1 + 2), built by hand; the values are awkward on purpose.
World makeWorld() {
  World w;
  w.params.name = "three bodies";
  w.params.dt = 2.5e-4f;
  w.params.gravity = {0.25f, -0.0f, -9.81f};
  w.params.ground.enabled = true;
  w.params.ground.height = -1.5f;
  w.radius = {0.5f, 0.25f, 1.0f, 0.125f, std::numeric_limits<float>::denorm_min()};
  w.mass = {1.0f, 2.0f, 3.5f, 1e-30f, 7.0f};
  w.elasticity = {0.5f, 1.0f, 0.1f, 0.75f, 0.3333333f};
  w.groundDamping.assign(kNumParticles, 0.0f);
  w.body = {0, 0, 1, 2, 2};
  w.ux = {-0.1f, 0.2f, 0.0f, -0.0f, 1e20f};
  w.uy = {0.3f, -0.3f, 0.0f, 0.5f, -1e-20f};
  w.uz = {0.0f, 0.0f, 0.0f, -0.5f, 0.5f};
  w.bodyMass = {3.0f, 3.5f, 7.0f};
  w.invMass = {1.0f / 3.0f, 1.0f / 3.5f, 1.0f / 7.0f};
  w.first = {0, 2, 3};
  w.numParticlesOf = {2, 1, 2};
  w.hasClumps = true;
  w.maxRadius = 1.0f;
  return w;
}

float value(std::uint32_t frame, std::uint32_t column, std::uint32_t k) {
  // Distinct per (frame, column, k), with a few special values mixed in.
  const float special[4] = {-0.0f, std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::lowest()};
  if ((frame + column + k) % 7 == 3) return special[(frame + k) % 4];
  return static_cast<float>(frame) * 1.3f - static_cast<float>(column) * 0.77f +
         static_cast<float>(k) / 3.0f;
}

BodyState makeState(std::uint32_t frame) {
  BodyState s;
  std::vector<float>* cols[7] = {&s.px, &s.py, &s.pz, &s.qw, &s.qx, &s.qy, &s.qz};
  for (std::uint32_t c = 0; c < 7; ++c) {
    for (std::uint32_t b = 0; b < kNumBodies; ++b) cols[c]->push_back(value(frame, c, b));
  }
  // Columns the format does not store may be anything, even NaN.
  for (auto* col : {&s.vx, &s.vy, &s.vz, &s.lx, &s.ly, &s.lz}) {
    col->assign(kNumBodies, std::numeric_limits<float>::quiet_NaN());
  }
  return s;
}

ParticleDebug makeDebug(std::uint32_t frame) {
  ParticleDebug d;
  for (std::uint32_t k = 0; k < 3 * kNumParticles; ++k) d.v.push_back(value(frame, 10, k));
  for (std::uint32_t f = 0; f < 5; ++f) {
    for (std::uint32_t k = 0; k < 3 * kNumParticles; ++k) {
      d.force[f].push_back(value(frame, 20 + f, k));
    }
  }
  const std::vector<tumble::Pair> all = {{0, 2}, {1, 4}, {3, 4}};
  d.contacts.assign(all.begin(), all.begin() + frame % 4);  // 0, 1, 2, 3 contacts
  return d;
}

constexpr std::uint32_t kPulls[] = {0, tumble::kPullX, tumble::kPullY | tumble::kPullSwirl,
                                    tumble::kPullX | tumble::kPullY | tumble::kPullSwirl};

/// Writes `numFrames` frames (and closes) into `path`.
void writeRecording(const std::string& path, bool debug, std::uint32_t numFrames, const World& world = makeWorld()) {
  RecordingWriter w(path, world, debug, 10, 60.0f);
  for (std::uint32_t f = 0; f < numFrames; ++f) {
    const ParticleDebug d = makeDebug(f);
    w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f), debug ? &d : nullptr);
  }
  EXPECT_EQ(w.numFrames(), numFrames);
  w.close();
}

void expectSameBits(const std::vector<float>& a, const std::vector<float>& b,
                    const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(bits(a[k]), bits(b[k])) << what << "[" << k << "]";
}

void expectRecording(const Recording& r, bool debug, std::uint32_t numFrames) {
  const World w = makeWorld();
  EXPECT_EQ(r.info.version, tumble::kRecordingVersion);
  EXPECT_EQ(r.info.numParticles, kNumParticles);
  EXPECT_EQ(r.info.numBodies, kNumBodies);
  EXPECT_EQ(r.info.stepsPerFrame, 10u);
  EXPECT_EQ(bits(r.info.dt), bits(w.params.dt));
  EXPECT_EQ(bits(r.info.fps), bits(60.0f));
  EXPECT_EQ(r.info.debug, debug);
  EXPECT_TRUE(r.info.groundEnabled);
  EXPECT_EQ(bits(r.info.groundHeight), bits(w.params.ground.height));
  EXPECT_EQ(bits(r.info.gravity.x), bits(w.params.gravity.x));
  EXPECT_EQ(bits(r.info.gravity.y), bits(w.params.gravity.y));
  EXPECT_EQ(bits(r.info.gravity.z), bits(w.params.gravity.z));
  EXPECT_EQ(r.info.sceneName, w.params.name);

  expectSameBits(r.radius, w.radius, "radius");
  expectSameBits(r.mass, w.mass, "mass");
  expectSameBits(r.elasticity, w.elasticity, "elasticity");
  EXPECT_EQ(r.body, w.body);
  expectSameBits(r.ux, w.ux, "ux");
  expectSameBits(r.uy, w.uy, "uy");
  expectSameBits(r.uz, w.uz, "uz");

  ASSERT_EQ(r.frames.size(), numFrames);
  for (std::uint32_t f = 0; f < numFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const tumble::RecordedFrame& fr = r.frames[f];
    const BodyState s = makeState(f);
    EXPECT_EQ(fr.step, 10u * f);
    EXPECT_EQ(bits(fr.time), bits(10.0 * f * 2.5e-4));
    EXPECT_EQ(fr.pulls, kPulls[f % 4]);
    expectSameBits(fr.px, s.px, "px");
    expectSameBits(fr.py, s.py, "py");
    expectSameBits(fr.pz, s.pz, "pz");
    expectSameBits(fr.qw, s.qw, "qw");
    expectSameBits(fr.qx, s.qx, "qx");
    expectSameBits(fr.qy, s.qy, "qy");
    expectSameBits(fr.qz, s.qz, "qz");
    if (debug) {
      const ParticleDebug d = makeDebug(f);
      expectSameBits(fr.debug.v, d.v, "v");
      for (int c = 0; c < 5; ++c) expectSameBits(fr.debug.force[c], d.force[c], "force");
      EXPECT_EQ(fr.debug.contacts, d.contacts);
    } else {
      EXPECT_TRUE(fr.debug.v.empty());
      EXPECT_TRUE(fr.debug.contacts.empty());
    }
  }
}

/// Reads `path` expecting an InputError; returns its problem() ("" and a failure otherwise).
std::string readError(const std::string& path) {
  try {
    Recording::read(path);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 0);
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    return e.problem();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected tumble::InputError, got: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected tumble::InputError reading " << path;
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

class RecordingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() /
            ("tumble_recording_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(m_dir, ec);
  }
  std::string file(const std::string& name) const { return (m_dir / name).string(); }

  fs::path m_dir;
};

// Layout facts used to aim corruptions (docs/recording.md).
constexpr std::size_t kHeaderBytes = 72 + 12;  // "three bodies"
constexpr std::size_t kTableBytes = 28 * kNumParticles + 4;
constexpr std::size_t kWallBlockBytes = 12;  // no walls: W = 0, S = 0, the checksum
constexpr std::size_t kFramesAt = kHeaderBytes + kTableBytes + kWallBlockBytes;
constexpr std::size_t kFrameBytes = 4 + 20 + 28 * kNumBodies + 4;

TEST_F(RecordingTest, RoundTripIsBitwise) {
  const std::string path = file("plain.bin");
  writeRecording(path, false, 6);
  EXPECT_EQ(fs::file_size(path), kFramesAt + 6 * kFrameBytes);
  expectRecording(Recording::read(path), false, 6);
}

TEST_F(RecordingTest, DebugRoundTripIsBitwise) {
  const std::string path = file("debug.bin");
  writeRecording(path, true, 6);
  expectRecording(Recording::read(path), true, 6);
}

TEST_F(RecordingTest, ZeroFrames) {
  const std::string path = file("empty.bin");
  writeRecording(path, true, 0);
  expectRecording(Recording::read(path), true, 0);
}

TEST_F(RecordingTest, PartFileUntilClose) {
  const std::string path = file("rec.bin");
  RecordingWriter w(path, makeWorld(), false, 10);
  EXPECT_EQ(w.path(), path);
  w.writeFrame(0, 0.0, 0, makeState(0));
  const std::string part = w.writingTo();
  EXPECT_EQ(part.rfind(path + ".part-", 0), 0u) << part;  // next to it, with an unpredictable suffix
  EXPECT_TRUE(fs::exists(part));
  EXPECT_FALSE(fs::exists(path));
  w.close();
  EXPECT_FALSE(fs::exists(part));
  EXPECT_TRUE(fs::exists(path));
  w.close();  // idempotent
  EXPECT_THROW(w.writeFrame(10, 0.0, 0, makeState(1)), tumble::Error);
  EXPECT_EQ(Recording::read(path).frames.size(), 1u);
}

TEST_F(RecordingTest, ReplacesAnOldFileOnlyAtClose) {
  const std::string path = file("rec.bin");
  writeRecording(path, false, 2);
  {
    RecordingWriter w(path, makeWorld(), false, 10);
    for (std::uint32_t f = 0; f < 5; ++f)
      w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f));
    EXPECT_EQ(Recording::read(path).frames.size(), 2u);  // still the old one
  }
  expectRecording(Recording::read(path), false, 5);
}

TEST_F(RecordingTest, DestroyedWithoutCloseKeepsCompleteFrames) {
  const std::string path = file("rec.bin");
  {
    RecordingWriter w(path, makeWorld(), true, 10);
    for (std::uint32_t f = 0; f < 3; ++f) {
      const ParticleDebug d = makeDebug(f);
      w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f), &d);
    }
  }
  for (const auto& e : fs::directory_iterator(m_dir))
    EXPECT_EQ(e.path().filename().string().find(".part"), std::string::npos) << e.path();
  expectRecording(Recording::read(path), true, 3);
}

TEST_F(RecordingTest, CrashedWriterPartFileIsReadable) {
  const std::string path = file("rec.bin");
  const std::string crashed = file("crashed.bin");
  RecordingWriter w(path, makeWorld(), false, 10);
  // Right after the header: the sentinel frame count and no frames.
  fs::copy_file(w.writingTo(), crashed);
  expectRecording(Recording::read(crashed), false, 0);
  for (std::uint32_t f = 0; f < 3; ++f)
    w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f));
  // Every frame is flushed, so a copy taken now is what a crash would leave behind.
  const std::vector<std::uint8_t> bytes = readAll(w.writingTo());
  ASSERT_EQ(bytes.size(), kFramesAt + 3 * kFrameBytes);
  writeAll(crashed, bytes);
  expectRecording(Recording::read(crashed), false, 3);
  // A torn last frame is still an error, naming the frame.
  writeAll(crashed, bytes, bytes.size() - 5);
  const std::string problem = readError(crashed);
  EXPECT_TRUE(contains(problem, "frame 2 truncated")) << problem;
  EXPECT_TRUE(
      contains(problem, "byte " + std::to_string(kFramesAt + 2 * kFrameBytes)))
      << problem;
  w.close();
  expectRecording(Recording::read(path), false, 3);
}

TEST_F(RecordingTest, NonFiniteStateThrowsAndFileStaysValid) {
  const std::string path = file("rec.bin");
  RecordingWriter w(path, makeWorld(), true, 10);
  for (std::uint32_t f = 0; f < 2; ++f) {
    const ParticleDebug d = makeDebug(f);
    w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f), &d);
  }
  const ParticleDebug good = makeDebug(2);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();

  BodyState s = makeState(2);
  s.qx[1] = nan;
  EXPECT_THROW(w.writeFrame(20, 0.005, 0, s, &good), tumble::Error);
  s = makeState(2);
  s.pz[2] = -inf;
  EXPECT_THROW(w.writeFrame(20, 0.005, 0, s, &good), tumble::Error);
  ParticleDebug d = makeDebug(2);
  d.force[4][7] = nan;
  EXPECT_THROW(w.writeFrame(20, 0.005, 0, makeState(2), &d), tumble::Error);
  d = makeDebug(2);
  d.v[0] = inf;
  EXPECT_THROW(w.writeFrame(20, 0.005, 0, makeState(2), &d), tumble::Error);
  EXPECT_THROW(w.writeFrame(20, std::numeric_limits<double>::quiet_NaN(), 0, makeState(2), &good),
               tumble::Error);
  try {
    s = makeState(2);
    s.qx[1] = nan;
    w.writeFrame(20, 0.005, 0, s, &good);
  } catch (const tumble::Error& e) {
    EXPECT_TRUE(contains(e.what(), "body 1 qx")) << e.what();
  }
  EXPECT_EQ(w.numFrames(), 2u);
  // The writer is still usable after a rejected frame.
  w.writeFrame(20, 20 * 2.5e-4, kPulls[2], makeState(2), &good);
  w.close();
  expectRecording(Recording::read(path), true, 3);
}

TEST_F(RecordingTest, WriterRejectsMisuse) {
  const std::string path = file("rec.bin");
  const World world = makeWorld();
  EXPECT_THROW(RecordingWriter(path, world, false, 0), tumble::Error);
  EXPECT_THROW(RecordingWriter(path, world, false, 10, 0.0f), tumble::Error);
  World bad = world;
  bad.body[4] = 3;
  EXPECT_THROW(RecordingWriter(path, bad, false, 10), tumble::Error);
  bad = world;
  bad.mass[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(RecordingWriter(path, bad, false, 10), tumble::Error);
  bad = world;
  bad.uz.pop_back();
  EXPECT_THROW(RecordingWriter(path, bad, false, 10), tumble::Error);

  RecordingWriter plain(path, world, false, 10);
  const ParticleDebug d = makeDebug(1);
  EXPECT_THROW(plain.writeFrame(0, 0.0, 0, makeState(0), &d), tumble::Error);
  BodyState s = makeState(0);
  s.qz.pop_back();
  EXPECT_THROW(plain.writeFrame(0, 0.0, 0, s), tumble::Error);
  plain.close();

  const std::string debugPath = file("debug.bin");
  RecordingWriter debug(debugPath, world, true, 10);
  EXPECT_THROW(debug.writeFrame(0, 0.0, 0, makeState(0)), tumble::Error);
  ParticleDebug pairs = makeDebug(1);
  pairs.contacts = {{2, 1}};
  EXPECT_THROW(debug.writeFrame(0, 0.0, 0, makeState(0), &pairs), tumble::Error);
  pairs.contacts = {{1, 5}};
  EXPECT_THROW(debug.writeFrame(0, 0.0, 0, makeState(0), &pairs), tumble::Error);
  ParticleDebug shortV = makeDebug(1);
  shortV.v.pop_back();
  EXPECT_THROW(debug.writeFrame(0, 0.0, 0, makeState(0), &shortV), tumble::Error);
  debug.close();
  EXPECT_EQ(Recording::read(path).frames.size(), 0u);
  EXPECT_EQ(Recording::read(debugPath).frames.size(), 0u);
}

// A full disk (here a file size limit, which fails writes the same way) in the middle of a frame:
// the torn frame is cut off again, and the finished recording holds every complete frame.
TEST_F(RecordingTest, AFrameThatCannotBeWrittenIsCutOff) {
  const std::string path = file("rec.bin");
  struct rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of the signal
  std::string what;
  {
    RecordingWriter w(path, makeWorld(), false, 10);
    w.writeFrame(0, 0.0, 0, makeState(0));
    w.writeFrame(10, 2.5e-3, 0, makeState(1));
    struct rlimit small = old;
    small.rlim_cur = kFramesAt + 2 * kFrameBytes + kFrameBytes / 2;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    try {
      w.writeFrame(20, 5e-3, 0, makeState(2));
    } catch (const tumble::Error& e) {
      what = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    EXPECT_TRUE(contains(what, "rec.bin': File too large; it keeps the 2 complete frames")) << what;
    EXPECT_EQ(fs::file_size(w.writingTo()), kFramesAt + 2 * kFrameBytes);
  }
  ASSERT_TRUE(fs::exists(path)) << "finished at close despite the failed frame";
  EXPECT_EQ(Recording::read(path).frames.size(), 2u);
}

// Continuing a recording copies its frames first; a copy cut short (a full disk, here a file size
// limit) must leave the recording it copies as it was, with no temporary left.
TEST_F(RecordingTest, AFailedContinuationLeavesTheRecording) {
  const std::string path = file("rec.bin");
  writeRecording(path, false, 5);
  const auto before = readAll(path);
  struct rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
  struct rlimit small = old;
  small.rlim_cur = kFramesAt + 2 * kFrameBytes + kFrameBytes / 2;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    RecordingWriter::continueAt(path, makeWorld(), false, 10, 1000);
  } catch (const tumble::Error&) {
    threw = true;
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, oldHandler);
  EXPECT_TRUE(threw);
  EXPECT_EQ(readAll(path), before) << "the recording was replaced by a shorter copy";
  for (const auto& e : fs::directory_iterator(m_dir))
    EXPECT_EQ(e.path().filename().string().find(".part"), std::string::npos) << e.path();
}

TEST_F(RecordingTest, UnopenablePartFileNamesPathAndReason) {
  const std::string path = file("no/such/dir/rec.bin");
  try {
    RecordingWriter w(path, makeWorld(), false, 10);
    FAIL() << "expected tumble::Error";
  } catch (const tumble::Error& e) {
    const std::string what = e.what();
    EXPECT_TRUE(contains(what, path)) << what;
    EXPECT_TRUE(contains(what, "No such file or directory")) << what;
  }
}

TEST_F(RecordingTest, MissingFileAndDirectory) {
  const std::string missing = file("missing.bin");
  EXPECT_TRUE(contains(readError(missing), "cannot open")) << readError(missing);
  EXPECT_TRUE(contains(readError(m_dir.string()), "not a regular file"));
}

TEST_F(RecordingTest, BadMagic) {
  const std::string path = file("text.bin");
  const std::string text = "[scene]\nname = \"not a recording at all\"\n";
  writeAll(path, std::vector<std::uint8_t>(text.begin(), text.end()));
  const std::string problem = readError(path);
  EXPECT_TRUE(contains(problem, "byte 0: not a tumble recording")) << problem;
  writeAll(path, {'T', 'U', 'M', 'B', 'L', 'x'});
  EXPECT_TRUE(contains(readError(path), "not a tumble recording"));
  writeAll(path, {});
  EXPECT_TRUE(contains(readError(path), "truncated"));
}

TEST_F(RecordingTest, FutureVersionIsRejectedByName) {
  const std::string path = file("rec.bin");
  writeRecording(path, false, 2);
  std::vector<std::uint8_t> bytes = readAll(path);
  putU32(bytes, 8, 3);
  writeAll(path, bytes);
  const std::string problem = readError(path);
  EXPECT_TRUE(contains(problem, "byte 8: unsupported recording version 3")) << problem;
  EXPECT_TRUE(contains(problem, "reads versions 1 and 2")) << problem;
  // Even with its header checksum fixed up, a future version is refused before anything else.
  putU32(bytes, kHeaderBytes - 4, fnv1a(bytes.data(), kHeaderBytes - 4));
  writeAll(path, bytes);
  EXPECT_TRUE(contains(readError(path), "unsupported recording version 3"));
}

void truncatedEverywhere(const std::string& path, const std::string& cut, bool debug) {
  writeRecording(path, debug, 3);
  const std::vector<std::uint8_t> bytes = readAll(path);
  ASSERT_GT(bytes.size(), kFramesAt);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    SCOPED_TRACE("cut at " + std::to_string(n) + " of " + std::to_string(bytes.size()));
    writeAll(cut, bytes, n);
    const std::string problem = readError(cut);
    EXPECT_EQ(problem.rfind("byte ", 0), 0u) << problem;
    if (n >= kFramesAt) {
      EXPECT_TRUE(contains(problem, "frame")) << problem;
    } else if (n >= kHeaderBytes + kTableBytes) {
      EXPECT_TRUE(contains(problem, "wall block truncated")) << problem;
    }
  }
}

TEST_F(RecordingTest, TruncatedAtEveryByteIsAnError) {
  truncatedEverywhere(file("plain.bin"), file("cut.bin"), false);
}

TEST_F(RecordingTest, DebugTruncatedAtEveryByteIsAnError) {
  truncatedEverywhere(file("debug.bin"), file("cut.bin"), true);
}

void flippedEverywhere(const std::string& path, const std::string& bad, bool debug) {
  // FNV-1a detects any single changed byte, so two masks per byte are enough to exercise it.
  writeRecording(path, debug, 3);
  const std::vector<std::uint8_t> bytes = readAll(path);
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    for (const std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0xFF}}) {
      SCOPED_TRACE("byte " + std::to_string(k) + " ^ " + std::to_string(mask));
      std::vector<std::uint8_t> copy = bytes;
      copy[k] ^= mask;
      writeAll(bad, copy);
      const std::string problem = readError(bad);
      EXPECT_EQ(problem.rfind("byte ", 0), 0u) << problem;
    }
  }
}

TEST_F(RecordingTest, AnyFlippedByteIsAnError) {
  flippedEverywhere(file("plain.bin"), file("bad.bin"), false);
}

TEST_F(RecordingTest, DebugAnyFlippedByteIsAnError) {
  flippedEverywhere(file("debug.bin"), file("bad.bin"), true);
}

TEST_F(RecordingTest, EachRegionReportsItsProblem) {
  const std::string path = file("plain.bin");
  const std::string bad = file("bad.bin");
  writeRecording(path, false, 3);
  const std::vector<std::uint8_t> bytes = readAll(path);
  auto flip = [&](std::size_t at) {
    std::vector<std::uint8_t> copy = bytes;
    copy[at] ^= 0x10;
    writeAll(bad, copy);
    return readError(bad);
  };
  EXPECT_TRUE(contains(flip(3), "not a tumble recording"));
  EXPECT_TRUE(contains(flip(9), "unsupported recording version"));
  EXPECT_TRUE(contains(flip(12), "header"));
  EXPECT_TRUE(contains(flip(20), "header checksum mismatch"));
  EXPECT_TRUE(contains(flip(62), "header checksum mismatch"));                 // scene name
  EXPECT_TRUE(contains(flip(kHeaderBytes - 10), "header checksum mismatch"));  // frame count
  EXPECT_TRUE(contains(flip(kHeaderBytes + 30), "particle table checksum mismatch"));
  const std::size_t frame1 = kFramesAt + kFrameBytes;
  EXPECT_TRUE(
      contains(flip(frame1), "byte " + std::to_string(frame1) + ": frame 1 has payload size"));
  EXPECT_TRUE(contains(flip(frame1 + 30), "frame 1 checksum mismatch"));
  EXPECT_TRUE(contains(flip(frame1 + kFrameBytes - 1), "frame 1 checksum mismatch"));

  // Trailing bytes after the last frame.
  std::vector<std::uint8_t> longer = bytes;
  longer.insert(longer.end(), bytes.end() - kFrameBytes, bytes.end());
  writeAll(bad, longer);
  EXPECT_TRUE(contains(readError(bad), "header says 3 frames but the file holds 4"));
}

// The reader reads frame by frame: the same frames as a whole read, any frame first; a damaged
// frame is reported when it is read, with its byte offset, and the frames around it stay
// readable (render --still and play read only the frames they show).
TEST_F(RecordingTest, ReaderReadsAnyFrameAndReportsADamagedOneWhenItIsRead) {
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "debug" : "plain");
    const std::string path = file("rec.bin");
    writeRecording(path, debug, 5);
    const Recording whole = Recording::read(path);
    tumble::RecordingReader reader(path);
    ASSERT_EQ(reader.numFrames(), 5u);
    EXPECT_TRUE(reader.header().frames.empty());
    EXPECT_EQ(reader.header().body, whole.body);
    tumble::RecordedFrame f;
    for (const std::size_t k : {4u, 0u, 2u, 2u, 1u, 3u}) {
      reader.readFrame(k, f);  // reused storage, any order
      EXPECT_EQ(f.step, whole.frames[k].step);
      expectSameBits(f.px, whole.frames[k].px, "px");
      expectSameBits(f.qz, whole.frames[k].qz, "qz");
      EXPECT_EQ(f.debug.contacts, whole.frames[k].debug.contacts);
    }
    EXPECT_THROW(reader.readFrame(5, f), tumble::Error);
  }
  const std::string path = file("plain.bin");
  writeRecording(path, false, 3);
  std::vector<std::uint8_t> bytes = readAll(path);
  const std::size_t frame1 = kFramesAt + kFrameBytes;
  bytes[frame1 + 30] ^= 0x10;
  writeAll(path, bytes);
  tumble::RecordingReader reader(path);  // the header and the table are fine
  tumble::RecordedFrame f;
  reader.readFrame(0, f);
  reader.readFrame(2, f);
  EXPECT_EQ(f.step, 20u);
  try {
    reader.readFrame(1, f);
    ADD_FAILURE() << "a damaged frame 1 was read";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.problem(), "frame 1 checksum mismatch")) << e.problem();
  }
}

/// Rewrites the header's u32 at `at` and fixes the header checksum, so only the value is wrong.
std::vector<std::uint8_t> withHeaderField(std::vector<std::uint8_t> bytes, std::size_t at,
                                          std::uint32_t v) {
  putU32(bytes, at, v);
  putU32(bytes, kHeaderBytes - 4, fnv1a(bytes.data(), kHeaderBytes - 4));
  return bytes;
}

TEST_F(RecordingTest, HugeCountsAreCheckedBeforeAllocating) {
  const std::string path = file("plain.bin");
  const std::string bad = file("bad.bin");
  writeRecording(path, true, 2);
  const std::vector<std::uint8_t> bytes = readAll(path);

  writeAll(bad, withHeaderField(bytes, 16, 0xFFFFFFFFu));  // numParticles
  std::string problem = readError(bad);
  EXPECT_TRUE(
      contains(problem, "byte " + std::to_string(kHeaderBytes) + ": particle table truncated"))
      << problem;

  writeAll(bad, withHeaderField(bytes, 20, 0xFFFFFFFFu));  // numBodies
  problem = readError(bad);
  EXPECT_TRUE(contains(problem, "frame 0 has payload size")) << problem;

  writeAll(bad, withHeaderField(bytes, 20, 1u));  // fewer bodies than the table uses
  problem = readError(bad);
  EXPECT_TRUE(contains(problem, "belongs to body")) << problem;

  writeAll(bad, withHeaderField(bytes, 56, 0xFFFFFFF0u));  // name length
  problem = readError(bad);
  EXPECT_TRUE(contains(problem, "byte 56: scene name length")) << problem;

  writeAll(bad, withHeaderField(bytes, 24, 0));  // steps per frame
  EXPECT_TRUE(contains(readError(bad), "steps per frame"));
  writeAll(bad, withHeaderField(bytes, 36, 0x100u));  // unknown flag
  EXPECT_TRUE(contains(readError(bad), "unknown flag bits"));
  writeAll(bad, withHeaderField(bytes, 48, bits(std::numeric_limits<float>::quiet_NaN())));
  EXPECT_TRUE(contains(readError(bad), "gravity is not finite"));

  // A frame size that points far past the end of the file (and a matching contact count).
  std::vector<std::uint8_t> big = bytes;
  const std::size_t frame0 = kFramesAt;
  const std::uint32_t minDebug = 20 + 28 * kNumBodies + 72 * kNumParticles + 4;
  putU32(big, frame0, minDebug + 8u * 100000000u);
  writeAll(bad, big);
  problem = readError(bad);
  EXPECT_TRUE(contains(problem, "byte " + std::to_string(frame0) + ": frame 0 truncated"))
      << problem;

  // The header size itself.
  std::vector<std::uint8_t> header = bytes;
  putU32(header, 12, 0xFFFFFFFFu);
  writeAll(bad, header);
  EXPECT_TRUE(contains(readError(bad), "byte 12: invalid header size"));
  putU32(header, 12, 60000);
  writeAll(bad, header);
  EXPECT_TRUE(contains(readError(bad), "exceeds the file size"));
}

TEST_F(RecordingTest, NonFiniteOrBadPairWithValidChecksumIsRejected) {
  // A writer that did not follow the rules: the reader still refuses NaN and bad pairs.
  const std::string path = file("debug.bin");
  const std::string bad = file("bad.bin");
  writeRecording(path, true, 2);  // frame 0 has no contact, frame 1 has (0, 2)
  const std::vector<std::uint8_t> bytes = readAll(path);
  const std::size_t frame0 = kFramesAt;
  const std::size_t frame1 = frame0 + 4 + getU32(bytes, frame0) + 4;
  // Overwrites the u32 at `offset` of the payload of the frame at `frame`, fixing its checksum.
  auto patched = [&](std::size_t frame, std::size_t offset, std::uint32_t v) {
    std::vector<std::uint8_t> copy = bytes;
    const std::size_t payload = frame + 4;
    const std::uint32_t payloadBytes = getU32(copy, frame);
    putU32(copy, payload + offset, v);
    putU32(copy, payload + payloadBytes, fnv1a(copy.data() + payload, payloadBytes));
    writeAll(bad, copy);
    return readError(bad);
  };
  const std::uint32_t nanBits = bits(std::numeric_limits<float>::quiet_NaN());
  const std::size_t py1 = 20 + 4 * 4;  // after step, time, pulls and px[0..2], py[0]
  std::string problem = patched(frame0, py1, nanBits);
  EXPECT_TRUE(contains(
      problem, "byte " + std::to_string(frame0 + 4 + py1) + ": frame 0 py[1] is not finite"))
      << problem;
  const std::size_t damping0 = 20 + 28 * kNumBodies + 2 * 4 * 3 * kNumParticles;
  problem = patched(frame0, damping0, nanBits);
  EXPECT_TRUE(contains(problem, "frame 0 damping force[0] is not finite")) << problem;
  const std::size_t count0 = getU32(bytes, frame0) - 4;
  problem = patched(frame0, count0, 1);
  EXPECT_TRUE(contains(problem, "frame 0 contact count 1 does not match")) << problem;
  const std::size_t pair1 = getU32(bytes, frame1) - 8;
  problem = patched(frame1, pair1, 2);  // (0, 2) becomes (2, 2)
  EXPECT_TRUE(contains(problem, "frame 1 contact (2, 2) is not a pair")) << problem;
  problem = patched(frame1, pair1 + 4, 5);  // (0, 5): particle 5 does not exist
  EXPECT_TRUE(contains(problem, "frame 1 contact (0, 5) is not a pair")) << problem;
}

TEST_F(RecordingTest, RandomDamageNeverCrashes) {
  const std::string path = file("debug.bin");
  const std::string bad = file("bad.bin");
  writeRecording(path, true, 4);
  const std::vector<std::uint8_t> bytes = readAll(path);
  std::mt19937 rng(12345);
  SCOPED_TRACE("seed 12345");
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::uint8_t> copy = bytes;
    const int kind = static_cast<int>(rng() % 4);
    const int damage = 1 + static_cast<int>(rng() % 8);
    for (int d = 0; d < damage; ++d) {
      const std::size_t at = rng() % copy.size();
      if (kind == 0) copy[at] = static_cast<std::uint8_t>(rng());
      if (kind == 1)
        copy.insert(copy.begin() + static_cast<std::ptrdiff_t>(at),
                    static_cast<std::uint8_t>(rng()));
      if (kind == 2 && copy.size() > 1) copy.erase(copy.begin() + static_cast<std::ptrdiff_t>(at));
      if (kind == 3) copy[at] = 0xFF;
    }
    if (copy == bytes) continue;  // the damage happened to change nothing
    writeAll(bad, copy);
    try {
      Recording::read(bad);
      ADD_FAILURE() << "trial " << trial << ": damaged file was accepted";
    } catch (const InputError&) {
    }
  }
  // Pure noise, with and without a valid magic.
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<std::uint8_t> noise(rng() % 400);
    for (auto& b : noise) b = static_cast<std::uint8_t>(rng());
    if (trial % 2 == 0 && noise.size() >= 16) {
      std::copy(bytes.begin(), bytes.begin() + 16, noise.begin());
    }
    writeAll(bad, noise);
    EXPECT_THROW(Recording::read(bad), InputError) << "trial " << trial;
  }
}

// ---- Walls (version 2) ---------------------------------------------------------------------

/// makeWorld() in a box open at the top (five planes), or with `everyKind`: a tilted belt, a
/// turning cylinder that stops, a cone and a ring too.
World wallWorld(bool everyKind) {
  World w = makeWorld();
  const float lo[3] = {-2, -2, -1.5f}, hi[3] = {2, 2, 3};
  for (int f = 0; f < 5; ++f) {
    float p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    p[f / 2] = f % 2 ? hi[f / 2] : lo[f / 2];
    n[f / 2] = f % 2 ? -1.0f : 1.0f;
    w.params.walls.push_back(tumble::planeWall({p[0], p[1], p[2]}, {n[0], n[1], n[2]}));
  }
  if (everyKind) {
    tumble::WallDef belt = tumble::planeWall({0, 0, -1}, {0.3f, 0, 1});
    belt.velocity = {1, 0, -0.3f};
    w.params.walls.push_back(belt);
    tumble::WallDef drum = tumble::revolvedWall({0, -0.5f, 0}, {0, 1, 0}, 1.0f, 1.25f, 1.25f);
    drum.angularVelocity = -3.0f;
    drum.start = 0.25;
    drum.stop = 2.0;
    w.params.walls.push_back(drum);
    w.params.walls.push_back(tumble::revolvedWall({0, 0, 1}, {0, 0, 0.5f}, 0.5f, 0.4f, 0.9f));
    w.params.walls.push_back(tumble::revolvedWall({0, 0, 1}, {0, 0, 1}, 0.0f, 0.1f, 0.4f));
  }
  return w;
}

void expectSameWalls(const std::vector<tumble::WallSurface>& a, const std::vector<tumble::WallSurface>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    SCOPED_TRACE("wall " + std::to_string(k));
    EXPECT_EQ(a[k].kind, b[k].kind);
    const tumble::WallMotion &m = a[k].motion, &n = b[k].motion;
    expectSameBits({m.velocity.x, m.velocity.y, m.velocity.z, m.angularVelocity.x, m.angularVelocity.y,
                    m.angularVelocity.z, m.pivot.x, m.pivot.y, m.pivot.z},
                   {n.velocity.x, n.velocity.y, n.velocity.z, n.angularVelocity.x, n.angularVelocity.y,
                    n.angularVelocity.z, n.pivot.x, n.pivot.y, n.pivot.z},
                   "motion");
    EXPECT_EQ(bits(m.start), bits(n.start));
    EXPECT_EQ(bits(m.stop), bits(n.stop));
    expectSameBits(a[k].triangles, b[k].triangles, "triangles");
  }
}

TEST_F(RecordingTest, WallsOfEveryKindRoundTripBitwise) {
  const World world = wallWorld(true);
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "debug" : "plain");
    const std::string path = file(debug ? "debug.bin" : "plain.bin");
    writeRecording(path, debug, 3, world);
    const Recording r = Recording::read(path);
    EXPECT_EQ(r.info.version, 2u);
    const std::vector<tumble::WallSurface> expected = tumble::sceneWallSurfaces(world.params, world.bodiesExtent);
    expectSameWalls(r.walls, expected);
    ASSERT_EQ(r.walls.size(), 9u);
    using tumble::WallKind;
    const WallKind kinds[9] = {WallKind::Plane, WallKind::Plane, WallKind::Plane, WallKind::Plane, WallKind::Plane,
                               WallKind::Plane, WallKind::Cylinder, WallKind::Cone, WallKind::Disk};
    for (std::size_t k = 0; k < 9; ++k) {
      EXPECT_EQ(r.walls[k].kind, kinds[k]) << k;
      EXPECT_GT(r.walls[k].numTriangles(), 0u) << k;
    }
    // The drum's drawing turns about its axis from 0.25 s to 2 s; the belt's plane stands still.
    EXPECT_EQ(r.walls[6].motion.angularVelocity.y, -3.0f);
    EXPECT_EQ(r.walls[6].motion.pivot.y, -0.5f);
    EXPECT_EQ(r.walls[6].motion.start, 0.25);
    EXPECT_EQ(r.walls[6].motion.stop, 2.0);
    EXPECT_FALSE(r.walls[5].motion.moves());
    // The frames follow the walls as before.
    ASSERT_EQ(r.frames.size(), 3u);
    expectSameBits(r.frames[2].qz, makeState(2).qz, "qz");
  }
}

// Version 1 (no wall block) still reads: the files of the fuzz corpus, written by a tumble that
// wrote version 1, and a version 2 file rewritten as version 1.
TEST_F(RecordingTest, Version1RecordingsStillRead) {
  for (const char* name : {"plain_two.rec", "debug_clumps.rec", "empty_steps.rec"}) {
    SCOPED_TRACE(name);
    const std::string path = std::string(TUMBLE_SOURCE_DIR) + "/validation/fuzz/corpus/recording/" + name;
    ASSERT_EQ(getU32(readAll(path), 8), 1u) << "a version 1 file";
    const Recording r = Recording::read(path);
    EXPECT_EQ(r.info.version, 1u);
    EXPECT_TRUE(r.walls.empty());
    EXPECT_GT(r.frames.size(), 0u);
  }
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "debug" : "plain");
    const std::string path = file("v2.bin"), old = file("v1.bin");
    writeRecording(path, debug, 4, wallWorld(true));
    const std::vector<std::uint8_t> v2 = readAll(path);
    const std::size_t walls = kHeaderBytes + kTableBytes;
    const std::size_t frames = walls + 8 + getU32(v2, walls + 4) + 4;
    std::vector<std::uint8_t> v1(v2.begin(), v2.begin() + static_cast<std::ptrdiff_t>(walls));
    v1.insert(v1.end(), v2.begin() + static_cast<std::ptrdiff_t>(frames), v2.end());
    putU32(v1, 8, 1);
    putU32(v1, kHeaderBytes - 4, fnv1a(v1.data(), kHeaderBytes - 4));
    writeAll(old, v1);
    const Recording a = Recording::read(path), b = Recording::read(old);
    EXPECT_EQ(b.info.version, 1u);
    EXPECT_TRUE(b.walls.empty());
    EXPECT_FALSE(a.walls.empty());
    ASSERT_EQ(b.frames.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) {
      expectSameBits(b.frames[k].px, a.frames[k].px, "px");
      expectSameBits(b.frames[k].debug.v, a.frames[k].debug.v, "v");
    }
    // A version 1 file whose frames start where a wall block would: read as frames, not walls.
    tumble::RecordingReader reader(old);
    EXPECT_EQ(reader.numFrames(), 4u);
  }
}

TEST_F(RecordingTest, WallBlockTruncatedOrFlippedAnywhereIsAnError) {
  const std::string path = file("walls.bin"), bad = file("bad.bin");
  writeRecording(path, false, 2, wallWorld(false));
  const std::vector<std::uint8_t> bytes = readAll(path);
  const std::size_t walls = kHeaderBytes + kTableBytes;
  const std::size_t frames = bytes.size() - 2 * kFrameBytes;
  ASSERT_GT(frames, walls + 12 + 5 * 60) << "five faces with their triangles";
  for (std::size_t n = walls; n < frames; ++n) {
    SCOPED_TRACE("cut at " + std::to_string(n));
    writeAll(bad, bytes, n);
    const std::string problem = readError(bad);
    EXPECT_TRUE(contains(problem, "wall block truncated")) << problem;
  }
  for (std::size_t k = walls; k < frames; ++k) {
    SCOPED_TRACE("byte " + std::to_string(k));
    std::vector<std::uint8_t> copy = bytes;
    copy[k] ^= 0x01;
    writeAll(bad, copy);
    const std::string problem = readError(bad);
    EXPECT_EQ(problem.rfind("byte ", 0), 0u) << problem;
    EXPECT_TRUE(contains(problem, "wall")) << problem;
  }
}

TEST_F(RecordingTest, BadWallValuesWithAValidChecksumAreRefusedWithTheirOffset) {
  const std::string path = file("walls.bin"), bad = file("bad.bin");
  writeRecording(path, false, 1, wallWorld(true));
  const std::vector<std::uint8_t> bytes = readAll(path);
  const std::size_t block = kHeaderBytes + kTableBytes;
  const std::uint32_t recordBytes = getU32(bytes, block + 4);
  const std::size_t sum = block + 8 + recordBytes;  // the block's checksum
  const std::size_t wall0 = block + 8;
  // Rewrites the u32 at `at`, fixes the block's checksum and returns the reader's problem.
  const auto patched = [&](std::size_t at, std::uint32_t v) {
    std::vector<std::uint8_t> copy = bytes;
    putU32(copy, at, v);
    putU32(copy, sum, fnv1a(copy.data() + block, sum - block));
    writeAll(bad, copy);
    return readError(bad);
  };
  const auto at = [](std::size_t offset) { return "byte " + std::to_string(offset) + ": "; };
  std::string problem = patched(wall0, 9);
  EXPECT_TRUE(contains(problem, at(wall0) + "wall 0 has unknown kind 9")) << problem;
  problem = patched(wall0 + 4 + 24 + 4, bits(std::numeric_limits<float>::quiet_NaN()));  // pivot y
  EXPECT_TRUE(contains(problem, at(wall0 + 32) + "wall 0 pivot is not finite")) << problem;
  problem = patched(wall0 + 52, 0xFFF80000u);  // stop's high half: NaN
  EXPECT_TRUE(contains(problem, at(wall0 + 40) + "wall 0 start and stop must be finite and in order")) << problem;
  problem = patched(wall0 + 56, 0x10000000u);  // triangles
  EXPECT_TRUE(contains(problem, at(wall0 + 56) + "wall 0 has 268435456 triangles, the block has room for")) << problem;
  problem = patched(wall0 + 60, bits(-std::numeric_limits<float>::infinity()));  // the first corner's x
  EXPECT_TRUE(contains(problem, at(wall0 + 60) + "wall 0 triangle corner[0] is not finite")) << problem;
  problem = patched(block, 0xFFFFFFFFu);  // W
  EXPECT_TRUE(contains(problem, at(block) + "wall count 4294967295 does not fit")) << problem;
  problem = patched(block, getU32(bytes, block) - 1);  // one wall fewer: bytes left over
  EXPECT_TRUE(contains(problem, "bytes after its last wall")) << problem;
  problem = patched(block, getU32(bytes, block) + 1);  // one wall more: the last runs out
  EXPECT_TRUE(contains(problem, "wall 9 truncated")) << problem;
  problem = patched(block + 4, 0xFFFFFFF0u);  // S: far beyond the file, refused before any allocation
  EXPECT_TRUE(contains(problem, at(block + 4) + "wall block truncated")) << problem;
}

TEST_F(RecordingTest, ARecordingOfOtherWallsIsNotContinued) {
  const std::string path = file("rec.bin");
  writeRecording(path, false, 3, wallWorld(false));
  try {
    RecordingWriter::continueAt(path, wallWorld(true), false, 10, 10);
    ADD_FAILURE() << "continued a recording of other walls";
  } catch (const tumble::Error& e) {
    EXPECT_TRUE(contains(e.what(), "the walls differ")) << e.what();
  }
  auto w = RecordingWriter::continueAt(path, wallWorld(false), false, 10, 10);
  w->writeFrame(20, 20 * 2.5e-4, 0, makeState(2));
  w->close();
  EXPECT_EQ(Recording::read(path).frames.size(), 3u);
}

}  // namespace

// A recording that grows (bodies entering during the run, [[pour]]): its frames hold 1, 2 and 3
// bodies (plain and debug) and read back so, bit for bit; each frame's body count is checked
// against the table (more bodies than it holds is an error at its byte), a flipped or cut byte
// anywhere is an error, and a frame of more bodies than the table is refused by the writer.
TEST_F(RecordingTest, ARecordingThatGrowsHoldsThePresentBodiesPerFrame) {
  const World w = makeWorld();
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "debug" : "plain");
    const std::string path = file(debug ? "grow-debug.bin" : "grow.bin");
    {
      RecordingWriter rec(path, w, debug, 10, 60.0f, /*grows=*/true);
      for (std::uint32_t k = 0; k < 3; ++k) {
        BodyState s = makeState(k);
        s.resize(k + 1);  // bodies 0..k present
        ParticleDebug d = makeDebug(k);
        const std::size_t np = k == 0 ? 2 : (k == 1 ? 3 : 5);  // the particles of those bodies
        d.v.resize(3 * np);
        for (auto& f : d.force) f.resize(3 * np);
        d.contacts.clear();
        if (k == 2) d.contacts = {{0, 2}, {3, 4}};
        rec.writeFrame(10 * k, 0.1 * k, 0, s, debug ? &d : nullptr);
      }
      BodyState tooMany = makeState(3);
      tooMany.resize(4);
      const ParticleDebug d3 = makeDebug(3);
      EXPECT_THROW(rec.writeFrame(30, 0.3, 0, tooMany, debug ? &d3 : nullptr), tumble::Error);
      rec.close();
    }
    const Recording r = Recording::read(path);
    EXPECT_TRUE(r.info.grows);
    ASSERT_EQ(r.frames.size(), 3u);
    for (std::uint32_t k = 0; k < 3; ++k) {
      EXPECT_EQ(r.frames[k].numBodies(), k + 1);
      EXPECT_EQ(r.particlesOf(k + 1), k == 0 ? 2u : (k == 1 ? 3u : 5u));
      const BodyState s = makeState(k);
      for (std::uint32_t b = 0; b <= k; ++b)
        EXPECT_EQ(std::bit_cast<std::uint32_t>(r.frames[k].px[b]), std::bit_cast<std::uint32_t>(s.px[b])) << k << " " << b;
      if (debug) {
        EXPECT_EQ(r.frames[k].debug.v.size(), 3 * r.particlesOf(k + 1));
      }
    }
    // Damage: every flipped byte and every cut is reported with its offset.
    const std::vector<std::uint8_t> bytes = readAll(path);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      std::vector<std::uint8_t> copy = bytes;
      copy[n] ^= 0xFF;
      writeAll(file("bad.bin"), copy);
      EXPECT_EQ(readError(file("bad.bin")).rfind("byte ", 0), 0u) << "byte " << n;
      writeAll(file("cut.bin"), bytes, n);
      EXPECT_EQ(readError(file("cut.bin")).rfind("byte ", 0), 0u) << "cut at " << n;
    }
  }
}
