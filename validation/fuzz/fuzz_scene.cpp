// SPDX-License-Identifier: MIT
// libFuzzer target: the scene reader (scene_io.hpp). Any input either parses or is refused with
// tumble::Error (InputError: file and line); a small scene that parses is also built into a
// World and stepped a few times on the CPU pipeline, where a refusal is again only tumble::Error
// (a divergence is a SimulationError). Anything else (a crash, a sanitizer report, another
// exception, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_util.hpp"
#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  Scene scene;
  try {
    scene = parseScene(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const Error&) {
    return 0;
  }
  std::uint64_t particles = 0;
  for (const BodyDef& b : scene.bodies)
    particles += b.shape < scene.shapes.size() ? scene.shapes[b.shape].spheres.size() : 0;
  // Speed: the detection on large scenes has its own tests. At 256 particles the candidate tests
  // of inputs that put them all in one place took 70 % of the campaign of 2026-12-07 (3rd) under
  // the coverage instrumentation (perf), at 500 executions a second.
  if (particles > 64) return 0;
  // Speed too: a given cell size far below the radii (grown by half the skin) makes each sphere
  // cover (1 + 2 (r + s/2) / cell)² cells: 1.2 million for r = 551 m in cells of 1 m (28 s of an
  // instrumented step, a timeout of the campaign of 2026-12-07; 1 s in a release build), 3700
  // for r = 5.2 m and a skin of 50 m (3.7 s); the detection's records are bounded by its memory
  // check and tested in PairsTest.
  if (scene.broadphase.cellSize > 0.0f) {
    float r = 0.0f;
    for (const ShapeDef& shape : scene.shapes)
      for (const SphereDef& sphere : shape.spheres) r = sphere.radius > r ? sphere.radius : r;
    const double grown = double(r) + (scene.broadphase.skin > 0.0f ? 0.5 * double(scene.broadphase.skin) : 0.0);
    const double across = 1.0 + 2.0 * grown / double(scene.broadphase.cellSize);
    if (across * across > 1e3) return 0;
  }
  try {
    const World world = World::fromScene(scene);
    auto pipeline = fuzz::cpuPipeline();
    pipeline->load(world);
    pipeline->step(scene.steps < 3 ? scene.steps : 3);
    BodyState state;
    pipeline->readState(state);
  } catch (const Error&) {
  }
  return 0;
}
