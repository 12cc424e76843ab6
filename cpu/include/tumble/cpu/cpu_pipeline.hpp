// SPDX-License-Identifier: MIT
/// @file cpu_pipeline.hpp
/// The CPU reference pipeline on oneTBB. Use tumble::makePipeline(Backend::Cpu) or
/// makeCpuPipeline(); everything else about it is behind the tumble::Pipeline interface.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "tumble/pipeline.hpp"
#include "tumble/soa.hpp"

namespace tumble::cpu {

/// Creates the CPU pipeline. options.threads = 0 uses every core; the results do not depend
/// on the thread count (bitwise).
std::unique_ptr<Pipeline> makeCpuPipeline(const PipelineOptions& options = {});

/// A body's motion as the integration leaves it: its BodyRow without the pipeline's own fields
/// (numbering, mass). What a domain decomposition copies from a body's owner to its ghosts.
struct BodyMotion {
  Vec3f v, omega;  ///< V, and the Ω of this state
  Mat3f rot;       ///< R = rotationMatrix(q), as the integration computed it
  Vec3f x;
  Quatf q;
  Vec3f l;
  std::int32_t image[2];
};
static_assert(sizeof(BodyMotion) == 108, "27 words a body");

/// The CPU pipeline with the three hooks a domain decomposition needs (tumble::mpi,
/// docs/mpi.md). A rank loads the bodies it owns and ghost copies of the bodies near them; after
/// each step it reads the motion of its own bodies that other ranks hold as ghosts, and
/// overwrites its ghosts' with those their owners integrated. Bodies are named by their scene
/// index in the loaded world. Not thread-safe, as Pipeline.
class HaloPipeline : public Pipeline {
 public:
  /// The motion of `bodies` as the last step's integration left it, out[k] for bodies[k].
  virtual void readMotion(const std::vector<std::uint32_t>& bodies, std::vector<BodyMotion>& out) const = 0;
  /// Overwrites the motion of `bodies` (motion[k] for bodies[k]), recomputes their particles'
  /// positions, then redoes the skin test (per particle, or per body as the step does) with the
  /// moving meshes' motion, so that the candidate list and the near list are rebuilt when the
  /// overwritten positions need it. Nothing else of the state changes.
  virtual void writeMotion(const std::vector<std::uint32_t>& bodies, const std::vector<BodyMotion>& motion) = 0;
  /// How many touching contacts the particles of `bodies` had in the last step, each counted
  /// from its particle's side (a contact between two of them counts twice); 0 before the first step.
  virtual std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const = 0;
};

/// The CPU pipeline behind the HaloPipeline interface (the same pipeline as makeCpuPipeline()).
std::unique_ptr<HaloPipeline> makeCpuHaloPipeline(const PipelineOptions& options = {});

}  // namespace tumble::cpu
