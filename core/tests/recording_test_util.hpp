// SPDX-License-Identifier: MIT
// What the recording format's tests share (recording_test.cpp, recording_damage_test.cpp,
// recording_walls_test.cpp): a small world and its frames, file helpers, the expected
// recording, the RecordingTest fixture (a temporary directory) and the layout's sizes.
#pragma once
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

namespace recording_test {

namespace fs = std::filesystem;
using tumble::BodyState;
using tumble::InputError;
using tumble::ParticleDebug;
using tumble::Recording;
using tumble::RecordingWriter;
using tumble::World;

inline constexpr std::uint32_t kNumBodies = 3;
inline constexpr std::uint32_t kNumParticles = 5;

inline std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }
inline std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

inline std::uint32_t fnv1a(const std::uint8_t* p, std::size_t n) {
  std::uint32_t h = 2166136261u;
  for (std::size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 16777619u;
  return h;
}

inline void putU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
}
inline std::uint32_t getU32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

inline std::vector<std::uint8_t> readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
inline void writeAll(const std::string& path, const std::vector<std::uint8_t>& bytes, std::size_t n) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(n));
}
inline void writeAll(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  writeAll(path, bytes, bytes.size());
}

/// 3 bodies, 5 particles (2 + 1 + 2), built by hand; the values are awkward on purpose.
inline World makeWorld() {
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

inline float value(std::uint32_t frame, std::uint32_t column, std::uint32_t k) {
  // Distinct per (frame, column, k), with a few special values mixed in.
  const float special[4] = {-0.0f, std::numeric_limits<float>::denorm_min(),
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::lowest()};
  if ((frame + column + k) % 7 == 3) return special[(frame + k) % 4];
  return static_cast<float>(frame) * 1.3f - static_cast<float>(column) * 0.77f +
         static_cast<float>(k) / 3.0f;
}

inline BodyState makeState(std::uint32_t frame) {
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

inline ParticleDebug makeDebug(std::uint32_t frame) {
  ParticleDebug d;
  for (std::uint32_t k = 0; k < 3 * kNumParticles; ++k) d.v.push_back(value(frame, 10, k));
  for (std::uint32_t f = 0; f < 5; ++f) {
    for (std::uint32_t k = 0; k < 3 * kNumParticles; ++k) {
      d.force[f].push_back(value(frame, 20 + f, k));
    }
  }
  const std::vector<tumble::Pair> all = {{0, 2}, {1, 4}, {3, 4}};
  d.contacts.assign(all.begin(), all.begin() + frame % 4);  // 0, 1, 2, 3 contacts
  for (std::uint32_t c = 0; c < d.contacts.size(); ++c) {  // the same pairs with their forces
    const auto v = [&](std::uint32_t k) { return value(frame, 30, 8 * c + k); };
    const float t = 0.1f * float(c + frame);  // a unit normal (the reader checks it is one)
    d.contactForces.push_back(tumble::ContactForce{d.contacts[c].i, d.contacts[c].j, {std::cos(t), std::sin(t), 0.0f},
                                                   v(3), {v(4), v(5), v(6)}, v(7)});
  }
  return d;
}

inline constexpr std::uint32_t kPulls[] = {0, tumble::kPullX, tumble::kPullY | tumble::kPullSwirl,
                                    tumble::kPullX | tumble::kPullY | tumble::kPullSwirl};

/// Writes `numFrames` frames (and closes) into `path`.
/// `contactForces`: with makeDebug()'s contact forces in every frame (version 3).
inline void writeRecording(const std::string& path, bool debug, std::uint32_t numFrames, const World& world = makeWorld(),
                           bool contactForces = false) {
  RecordingWriter w(path, world, debug, 10, 60.0f, false, contactForces);
  for (std::uint32_t f = 0; f < numFrames; ++f) {
    const ParticleDebug d = makeDebug(f);
    w.writeFrame(10u * f, 10.0 * f * 2.5e-4, kPulls[f % 4], makeState(f), debug || contactForces ? &d : nullptr);
  }
  EXPECT_EQ(w.numFrames(), numFrames);
  w.close();
}

inline void expectSameBits(const std::vector<float>& a, const std::vector<float>& b,
                    const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(bits(a[k]), bits(b[k])) << what << "[" << k << "]";
}

inline void expectRecording(const Recording& r, bool debug, std::uint32_t numFrames, bool contactForces = false) {
  const World w = makeWorld();
  EXPECT_EQ(r.info.version, tumble::kRecordingVersion);
  EXPECT_EQ(r.info.numParticles, kNumParticles);
  EXPECT_EQ(r.info.numBodies, kNumBodies);
  EXPECT_EQ(r.info.stepsPerFrame, 10u);
  EXPECT_EQ(bits(r.info.dt), bits(w.params.dt));
  EXPECT_EQ(bits(r.info.fps), bits(60.0f));
  EXPECT_EQ(r.info.debug, debug);
  EXPECT_EQ(r.info.contactForces, contactForces);
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
    const std::vector<tumble::ContactForce> want = contactForces ? makeDebug(f).contactForces
                                                                 : std::vector<tumble::ContactForce>{};
    ASSERT_EQ(fr.debug.contactForces.size(), want.size());
    for (std::size_t c = 0; c < want.size(); ++c) {
      const tumble::ContactForce &a = fr.debug.contactForces[c], &b = want[c];
      EXPECT_TRUE(a.i == b.i && a.j == b.j) << "contact force " << c;
      expectSameBits({a.n.x, a.n.y, a.n.z, a.fn, a.tangential.x, a.tangential.y, a.tangential.z, a.overlap},
                     {b.n.x, b.n.y, b.n.z, b.fn, b.tangential.x, b.tangential.y, b.tangential.z, b.overlap},
                     "contact force " + std::to_string(c));
    }
  }
}

/// Reads `path` expecting an InputError; returns its problem() ("" and a failure otherwise).
inline std::string readError(const std::string& path) {
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

inline bool contains(const std::string& s, const std::string& part) {
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
inline constexpr std::size_t kHeaderBytes = 72 + 12;  // "three bodies"
inline constexpr std::size_t kTableBytes = 28 * kNumParticles + 4;
inline constexpr std::size_t kWallBlockBytes = 12;  // no walls: W = 0, S = 0, the checksum
inline constexpr std::size_t kFramesAt = kHeaderBytes + kTableBytes + kWallBlockBytes;
inline constexpr std::size_t kFrameBytes = 4 + 20 + 28 * kNumBodies + 4;

}  // namespace recording_test
