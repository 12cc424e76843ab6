// SPDX-License-Identifier: MIT
// tumble repair (issue 34, item 13): a recording cut short anywhere in its frames (or a frame
// whose bytes fail their checksum) becomes the recording of the whole frames before it, the same
// bits; a whole file is left alone; what cannot be a recording stays an error.
#include "recording_test_util.hpp"

namespace {

using namespace recording_test;
using tumble::RecordedFrame;
using tumble::RecordingReader;
using tumble::RepairResult;
using tumble::repairRecording;

std::vector<RecordedFrame> framesOf(const std::string& path) {
  RecordingReader r(path);
  std::vector<RecordedFrame> out(r.numFrames());
  for (std::size_t k = 0; k < out.size(); ++k) r.readFrame(k, out[k]);
  return out;
}

void expectSameFrame(const RecordedFrame& a, const RecordedFrame& b, const std::string& what) {
  EXPECT_EQ(a.step, b.step) << what;
  EXPECT_EQ(bits(a.time), bits(b.time)) << what;
  EXPECT_EQ(a.pulls, b.pulls) << what;
  for (auto column : {&RecordedFrame::px, &RecordedFrame::py, &RecordedFrame::pz, &RecordedFrame::qw,
                      &RecordedFrame::qx, &RecordedFrame::qy, &RecordedFrame::qz})
    expectSameBits(a.*column, b.*column, what);
  expectSameBits(a.debug.v, b.debug.v, what + " debug v");
  for (int f = 0; f < 5; ++f) expectSameBits(a.debug.force[f], b.debug.force[f], what + " debug force");
}

// Cut after every byte of the frames: the repaired file holds the frames wholly before the cut.
void repairedAtEveryCut(const std::string& path, const std::string& cut, const std::string& out, bool debug) {
  writeRecording(path, debug, 3);
  const std::vector<std::uint8_t> bytes = readAll(path);
  const std::vector<RecordedFrame> whole = framesOf(path);
  std::size_t last = 0;
  for (std::size_t n = kFramesAt + 1; n < bytes.size(); ++n) {
    SCOPED_TRACE("cut at " + std::to_string(n) + " of " + std::to_string(bytes.size()));
    writeAll(cut, bytes, n);
    EXPECT_TRUE(contains(readError(cut), "tumble repair")) << "the refusal names the way out";
    fs::remove(out);
    RepairResult r;
    try {
      r = repairRecording(cut, out);
    } catch (const InputError& e) {  // a cut inside the first frame leaves none to keep
      EXPECT_TRUE(contains(e.problem(), "no whole frame to keep")) << e.problem();
      EXPECT_EQ(last, 0u);
      EXPECT_FALSE(fs::exists(out));
      continue;
    }
    EXPECT_FALSE(r.why.empty());
    EXPECT_GE(r.kept, last) << "a longer prefix keeps at least as many frames";
    last = r.kept;
    const std::vector<RecordedFrame> kept = framesOf(out);
    ASSERT_EQ(kept.size(), r.kept);
    for (std::size_t k = 0; k < kept.size(); ++k) expectSameFrame(kept[k], whole[k], "frame " + std::to_string(k));
    EXPECT_EQ(fs::file_size(out) + r.droppedBytes, n);
  }
  EXPECT_EQ(last, 2u) << "the last cut leaves two whole frames";
}

}  // namespace

TEST_F(RecordingTest, RepairKeepsTheWholeFramesOfAFileCutAnywhere) {
  repairedAtEveryCut(file("plain.bin"), file("cut.bin"), file("out.bin"), false);
}

TEST_F(RecordingTest, RepairKeepsTheWholeFramesOfADebugFileCutAnywhere) {
  repairedAtEveryCut(file("debug.bin"), file("cut.bin"), file("out.bin"), true);
}

TEST_F(RecordingTest, RepairStopsAtAFrameWhoseBytesAreDamaged) {
  const std::string path = file("rec.bin"), out = file("out.bin");
  writeRecording(path, false, 4);
  std::vector<std::uint8_t> bytes = readAll(path);
  bytes[kFramesAt + 2 * kFrameBytes + 30] ^= 0x10;  // inside frame 2's bodies: its checksum fails
  writeAll(path, bytes);
  const RepairResult r = repairRecording(path, out);
  EXPECT_EQ(r.kept, 2u);
  EXPECT_TRUE(contains(r.why, "frame 2")) << r.why;
  EXPECT_EQ(framesOf(out).size(), 2u);
}

TEST_F(RecordingTest, RepairLeavesAWholeFileAlone) {
  const std::string path = file("rec.bin"), out = file("out.bin");
  writeRecording(path, true, 3);
  const RepairResult r = repairRecording(path, out);
  EXPECT_TRUE(r.why.empty()) << r.why;
  EXPECT_EQ(r.kept, 3u);
  EXPECT_FALSE(fs::exists(out)) << "nothing written for a whole file";
  writeAll(path, readAll(path), kHeaderBytes - 3);  // not even a header: still an error
  EXPECT_THROW((void)repairRecording(path, out), InputError);
  EXPECT_FALSE(fs::exists(out));
}
