// SPDX-License-Identifier: MIT
/// @file run_memory.hpp
/// How much memory a run of the CPU pipeline holds at its peak, estimated from the buffers it
/// allocates: the size of each row type times how many rows the run holds per body, per
/// particle, per candidate pair and per contact, and the copies the load makes. The scene
/// reader compares it with the available memory (tumble/memory.hpp) as each [[group]], [[fill]]
/// or [[pour]] is read, and refuses a scene that cannot fit at the table that makes it too big,
/// instead of a run that ends with std::bad_alloc or is killed later.
#pragma once
#include <cstdint>
#include <vector>

#include "tumble/scene.hpp"

namespace tumble {

/// What a run's peak memory depends on: its size, and what the scene uses that changes which
/// buffers exist or how big they are.
struct RunSize {
  std::uint64_t bodies = 0;        ///< placed at the start ([[body]], [[group]], [[fill]])
  std::uint64_t pouredBodies = 0;  ///< added by [[pour]] tables during the run
  std::uint64_t particles = 0;     ///< of all of them
  std::uint64_t planes = 1;        ///< Scene::planes(): the ground (when on) and the walls, a spring each per particle
  std::uint64_t meshTriangles = 0; ///< of the mesh walls
  bool history = false;            ///< the law keeps a tangential history per contact (every law but report)
  bool materialColumn = false;     ///< hertz-mindlin: the world's tables hold each particle's material
  bool pipelineMaterials = false;  ///< hertz-mindlin with several materials: the pipeline's rows too
  bool periodic = false;           ///< periodic boundaries: image counters, the detection's images
  double recordsPerParticle = 16.0 / 9.0;  ///< detection cells a particle covers (runSizeOf())
  /// The candidate pairs against those at the automatic skin (0.5 r): a thicker `[broadphase]
  /// skin` finds the pairs within 2r + s, a shell (2r + s)³ / (2.5 r)³ as large (never below 1).
  double pairsFactor = 1.0;

  std::uint64_t allBodies() const { return bodies + pouredBodies; }
};

/// The RunSize of `scene`'s settings (law, materials, planes, meshes, periodic boundaries, cell
/// size) with these counts; the scene reader calls it before the scene holds its bodies.
RunSize runSizeOf(const Scene& scene, std::uint64_t bodies, std::uint64_t pouredBodies, std::uint64_t particles);

/// The candidate pairs and the touching contacts per particle the estimate assumes: those of a
/// settled packing (measured on a heap of 8000 spheres after 20000 steps: 4.25 candidate pairs
/// and 2.3 contacts per particle; a lattice as a scene first places it has fewer: about 3 pairs
/// and no contact). Clumps have fewer pairs between bodies (3.3 in bench-16k settled), none
/// within one.
inline constexpr double kCandidatePairsPerParticle = 4.0;
inline constexpr double kContactsPerParticle = 2.0;

/// One line of the estimate: `count` buffers' rows of `bytes` each.
struct MemoryItem {
  const char* what;  ///< which buffers
  double count;      ///< rows
  double bytes;      ///< bytes per row, summed over the buffers of the line
};

/// The estimate line by line (run_memory.cpp says which buffer each line counts and why).
std::vector<MemoryItem> runMemoryItems(const RunSize& size);

/// The estimate of the run's peak memory in bytes: the sum of runMemoryItems(). Within 25 % of
/// the peak resident memory `tumble run` measures, less that of a tiny scene (test
/// run_memory_estimate), for spheres, clumps and the laws with history.
std::uint64_t runMemoryEstimate(const RunSize& size);

}  // namespace tumble
