// SPDX-License-Identifier: MIT
// Recording format: a reader that turns every truncation and corruption into a
// tumble::InputError instead of a crash.
#include "recording_test_util.hpp"

namespace {

using namespace recording_test;

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
  putU32(bytes, 8, 4);
  writeAll(path, bytes);
  const std::string problem = readError(path);
  EXPECT_TRUE(contains(problem, "byte 8: unsupported recording version 4")) << problem;
  EXPECT_TRUE(contains(problem, "reads versions 1 to 3")) << problem;
  // Even with its header checksum fixed up, a future version is refused before anything else.
  putU32(bytes, kHeaderBytes - 4, fnv1a(bytes.data(), kHeaderBytes - 4));
  writeAll(path, bytes);
  EXPECT_TRUE(contains(readError(path), "unsupported recording version 4"));
}

void truncatedEverywhere(const std::string& path, const std::string& cut, bool debug, bool contactForces = false) {
  writeRecording(path, debug, 3, makeWorld(), contactForces);
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

TEST_F(RecordingTest, ContactForcesTruncatedAtEveryByteIsAnError) {
  truncatedEverywhere(file("forces.bin"), file("cut.bin"), false, true);
  truncatedEverywhere(file("both.bin"), file("cut.bin"), true, true);
}

void flippedEverywhere(const std::string& path, const std::string& bad, bool debug, bool contactForces = false) {
  // FNV-1a detects any single changed byte, so two masks per byte are enough to exercise it.
  writeRecording(path, debug, 3, makeWorld(), contactForces);
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

TEST_F(RecordingTest, ContactForcesAnyFlippedByteIsAnError) {
  flippedEverywhere(file("forces.bin"), file("bad.bin"), false, true);
  flippedEverywhere(file("both.bin"), file("bad.bin"), true, true);
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

TEST_F(RecordingTest, BadContactForceWithValidChecksumIsRejected) {
  // Frame 3 holds (0, 2), (1, 4), (3, 4) with their forces, after the bodies (and the count).
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "with the debug block" : "contact forces alone");
    const std::string path = file("forces.bin"), bad = file("bad.bin");
    writeRecording(path, debug, 4, makeWorld(), true);
    const std::vector<std::uint8_t> bytes = readAll(path);
    std::size_t frame3 = kFramesAt;
    for (int k = 0; k < 3; ++k) frame3 += 4 + getU32(bytes, frame3) + 4;
    const std::uint32_t payloadBytes = getU32(bytes, frame3);
    const std::size_t first = payloadBytes - 3 * 40;  // the first contact's i, in the payload
    auto patched = [&](std::size_t offset, std::uint32_t v) {
      std::vector<std::uint8_t> copy = bytes;
      putU32(copy, frame3 + 4 + offset, v);
      putU32(copy, frame3 + 4 + payloadBytes, fnv1a(copy.data() + frame3 + 4, payloadBytes));
      writeAll(bad, copy);
      return readError(bad);
    };
    std::string problem = patched(first + 8 + 4, bits(std::numeric_limits<float>::infinity()));  // n.y
    EXPECT_TRUE(contains(problem, "frame 3 contact force (0, 2) is not finite")) << problem;
    problem = patched(first + 40 + 36, bits(std::numeric_limits<float>::quiet_NaN()));  // the second's overlap
    EXPECT_TRUE(contains(problem, "frame 3 contact force (1, 4) is not finite")) << problem;
    if (debug) {  // (1, 4) becomes (0, 4): after (0, 2), in order, but not the debug block's pair
      problem = patched(first + 40, 0);
      EXPECT_TRUE(contains(problem, "contact force 1 is not for the debug block's contact 1")) << problem;
    }
    problem = patched(first + 2 * 40, 0);  // (3, 4) becomes (0, 4): before (1, 4)
    EXPECT_TRUE(contains(problem, "frame 3 contact force (0, 4) is not a pair i < j < 5 after the one before it"))
        << problem;
    problem = patched(first + 4, 9);  // (0, 9)
    EXPECT_TRUE(contains(problem, "contact force (0, 9) is not a pair")) << problem;
    problem = patched(first + 40 + 8, bits(2.0f));  // the second's n.x: not a unit vector any more
    EXPECT_TRUE(contains(problem, "frame 3 contact force (1, 4): its normal is not a unit vector")) << problem;
    problem = patched(payloadBytes - 3 * 40 - 4, 2);  // the count
    EXPECT_TRUE(contains(problem, "frame 3 contact force count 2 does not match")) << problem;
  }
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

}  // namespace
