// SPDX-License-Identifier: MIT
// libFuzzer target: the recording reader (recording.hpp). Any input opens or is refused with
// tumble::InputError, and so does every frame; the frames of a recording that opens read the
// same bits in reverse order, through the same reused frame, as in file order (the frame index
// and the reuse of storage).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_util.hpp"
#include "tumble/error.hpp"
#include "tumble/recording.hpp"

namespace {
std::uint64_t hashOf(const tumble::RecordedFrame& f) {
  tumble::fuzz::Hash h;
  h.bytes(&f.step, sizeof f.step);
  h.bytes(&f.time, sizeof f.time);
  h.bytes(&f.pulls, sizeof f.pulls);
  for (const auto* c : {&f.px, &f.py, &f.pz, &f.qw, &f.qx, &f.qy, &f.qz}) h.column(*c);
  h.column(f.debug.v);
  for (const auto& c : f.debug.force) h.column(c);
  h.column(f.debug.contacts);
  return h.h;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  const std::string path = fuzz::writeInput(data, size, "in.bin");
  try {
    RecordingReader reader(path);
    const std::size_t n = reader.numFrames();
    std::vector<std::uint64_t> forward(n, 0);
    std::vector<bool> ok(n, false);
    RecordedFrame frame;
    for (std::size_t k = 0; k < n; ++k) {
      try {
        reader.readFrame(k, frame);
        forward[k] = hashOf(frame);
        ok[k] = true;
      } catch (const InputError&) {
      }
    }
    for (std::size_t k = n; k-- > 0;) {
      bool read = false;
      try {
        reader.readFrame(k, frame);
        read = true;
      } catch (const InputError&) {
      }
      if (read != ok[k]) fuzz::fail("frame " + std::to_string(k) + " read once and was refused once");
      if (read && hashOf(frame) != forward[k])
        fuzz::fail("frame " + std::to_string(k) + " read other bits in reverse order");
    }
  } catch (const InputError&) {
  }
  return 0;
}
