// SPDX-License-Identifier: MIT
// libFuzzer target: a run resumed from a checkpoint (issue 34, item 9). The input is a checkpoint
// of validation/fuzz/resume.toml (the seeds: that scene at steps 150 and 400); it is read or
// refused with tumble::InputError, resumed or refused with tumble::Error (another scene), and a
// checkpoint that resumes is loaded into the CPU pipeline and stepped, where a refusal is again
// only tumble::Error (a divergence is a SimulationError). Anything else (a crash, a sanitizer
// report, another exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.hpp"
#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"

#ifndef TUMBLE_FUZZ_RESUME_SCENE
#error "TUMBLE_FUZZ_RESUME_SCENE: the path of validation/fuzz/resume.toml (validation/fuzz/CMakeLists.txt)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  static const World scene = World::fromScene(readSceneFile(TUMBLE_FUZZ_RESUME_SCENE));
  const std::optional<Checkpoint> ck = fuzz::readCheckpoint(data, size);
  if (!ck) return 0;
  try {
    std::string warning;  // (other physics: not this target's concern)
    const World world = ck->resume(scene, &warning);
    const auto pipeline = fuzz::cpuPipeline();
    pipeline->load(world);
    pipeline->step(5);
    BodyState state;
    pipeline->readState(state);
  } catch (const Error&) {
  }
  return 0;
}
