// SPDX-License-Identifier: MIT
// libFuzzer target: the particle CSV reader (particle_csv.hpp) and the detection behind
// `tumble pairs`. Any input parses or is refused with tumble::Error; a cloud that parses and that
// the detection accepts must give exactly the brute-force pair set, with the automatic cell size
// and with a coarse one. (The detection may refuse a cloud, with tumble::Error, when it would
// need too many cell records; that is not a finding.)
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.hpp"
#include "tumble/error.hpp"
#include "tumble/particle_csv.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/validation/brute_force.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  ParticleCloud cloud;
  try {
    cloud = parseParticleCsv(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  } catch (const Error&) {
    return 0;
  }
  if (cloud.size() > 512) return 0;  // the oracle is O(N²): speed
  float maxRadius = 0.0f;
  try {
    maxRadius = checkCloud(cloud);
  } catch (const Error&) {
    return 0;
  }
  static auto pipeline = fuzz::cpuPipeline();
  const std::vector<Pair> want = validation::bruteForcePairs(cloud);
  BroadphaseParams coarse;
  coarse.cellSize = std::min(4.0f * maxRadius, 3.0e38f);
  for (const BroadphaseParams& bp : {BroadphaseParams{}, coarse}) {
    std::vector<Pair> got;
    try {
      got = pipeline->findPairs(cloud, bp);
    } catch (const Error&) {
      continue;
    }
    if (got != want)
      fuzz::fail("findPairs (cell size " + std::to_string(bp.cellSize) + ") found " + std::to_string(got.size()) +
                 " pairs, the brute-force oracle " + std::to_string(want.size()));
  }
  return 0;
}
