// SPDX-License-Identifier: MIT
// Recording format: the walls (version 2), version 1 recordings, and recordings that grow.
#include "recording_test_util.hpp"

namespace {

using namespace recording_test;

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
    EXPECT_EQ(r.info.version, tumble::kRecordingVersion);
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

// Version 2 is version 3 without flag bit 3: a file of the new writer relabelled 2 reads the
// same, and a version 2 file with that bit is refused.
TEST_F(RecordingTest, Version2RecordingsStillRead) {
  for (const bool debug : {false, true}) {
    SCOPED_TRACE(debug ? "debug" : "plain");
    const std::string path = file("v3.bin"), old = file("v2.bin");
    writeRecording(path, debug, 4, wallWorld(true));
    std::vector<std::uint8_t> v2 = readAll(path);
    ASSERT_EQ(getU32(v2, 8), 3u);
    putU32(v2, 8, 2);
    putU32(v2, kHeaderBytes - 4, fnv1a(v2.data(), kHeaderBytes - 4));
    writeAll(old, v2);
    const Recording a = Recording::read(path), b = Recording::read(old);
    EXPECT_EQ(b.info.version, 2u);
    EXPECT_FALSE(b.info.contactForces);
    EXPECT_EQ(b.walls.size(), a.walls.size());
    ASSERT_EQ(b.frames.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) {
      expectSameBits(b.frames[k].px, a.frames[k].px, "px");
      expectSameBits(b.frames[k].debug.v, a.frames[k].debug.v, "v");
    }
  }
  const std::string path = file("v3.bin");
  writeRecording(path, false, 2, wallWorld(true), true);
  std::vector<std::uint8_t> bytes = readAll(path);
  putU32(bytes, 8, 2);
  putU32(bytes, kHeaderBytes - 4, fnv1a(bytes.data(), kHeaderBytes - 4));
  writeAll(path, bytes);
  const std::string problem = readError(path);
  EXPECT_TRUE(contains(problem, "byte 36: unknown flag bits 0x00000008 for version 2")) << problem;
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
