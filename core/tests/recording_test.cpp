// SPDX-License-Identifier: MIT
// Recording format (docs/recording.md): bitwise round trips, crash safety and the writer's
// refusals. The reader against damage: recording_damage_test.cpp; walls and growing
// recordings: recording_walls_test.cpp.
#include "recording_test_util.hpp"

namespace {

using namespace recording_test;

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

TEST_F(RecordingTest, ContactForcesRoundTripIsBitwise) {
  for (const bool debug : {false, true}) {
    const std::string path = file(debug ? "both.bin" : "forces.bin");
    writeRecording(path, debug, 6, makeWorld(), true);
    expectRecording(Recording::read(path), debug, 6, true);
    tumble::RecordingReader reader(path);  // frame by frame, out of order: the index of sizes
    tumble::RecordedFrame f;
    for (const std::size_t k : {5u, 0u, 3u}) {
      reader.readFrame(k, f);
      EXPECT_EQ(f.step, 10u * k);
      EXPECT_EQ(f.debug.contactForces.size(), k % 4);
    }
  }
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

  // Contact forces: in order, of particles that exist, finite, the debug block's pairs when there
  // is one; each refusal leaves the file as it was.
  for (const bool withDebug : {false, true}) {
    const std::string forcesPath = file(withDebug ? "both.bin" : "forces.bin");
    RecordingWriter forces(forcesPath, world, withDebug, 10, 60.0f, false, true);
    EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0)), tumble::Error);
    const ParticleDebug good = makeDebug(3);  // (0, 2), (1, 4), (3, 4)
    ParticleDebug c = good;
    std::swap(c.contactForces[0], c.contactForces[1]);
    if (!withDebug) {
      EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "out of order";
    }
    c = good;
    c.contactForces[2].j = 5;
    EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "particle 5";
    c = good;
    c.contactForces[1].tangential.z = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "NaN";
    c = good;
    c.contactForces[0].n = {0.6f, 0.6f, 0.0f};
    EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "a normal that is not a unit vector";
    c = good;
    c.contactForces.pop_back();
    if (withDebug) {
      EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "2 of 3 pairs";
    }
    c = good;
    c.contactForces[1].i = 0;  // (0, 4): in order, not the debug pair
    if (withDebug) {
      EXPECT_THROW(forces.writeFrame(0, 0.0, 0, makeState(0), &c), tumble::Error) << "another pair";
    }
    forces.close();
    EXPECT_EQ(Recording::read(forcesPath).frames.size(), 0u);
  }
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
  std::string what;
  try {
    RecordingWriter::continueAt(path, makeWorld(), false, 10, 1000);
  } catch (const tumble::Error& e) {
    threw = true;
    what = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, oldHandler);
  EXPECT_TRUE(threw);
  // The message names what is kept: the recording as it was, not the copy's 2 frames (issue 34, item 12).
  EXPECT_TRUE(contains(what, "cannot continue recording '" + path + "': copying its frames failed at step 20: "
                             "File too large; it is left as it was, with its 5 frames")) << what;
  EXPECT_FALSE(contains(what, "keeps")) << what;
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

}  // namespace
