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

/// The CPU pipeline with the three hooks a domain decomposition needs (tumble::mpi,
/// docs/mpi.md). A rank loads the bodies it owns and ghost copies of the bodies near them; after
/// each step it reads the rows of its own bodies that other ranks hold as ghosts, and overwrites
/// its ghosts' rows with those their owners integrated. Bodies are named by their scene index in
/// the loaded world. Not thread-safe, as Pipeline.
class HaloPipeline : public Pipeline {
 public:
  /// The rows of `bodies` as the last step's integration left them (X, V, Q, L, and the Ω and R
  /// it computed), outRows[k] for bodies[k]. The fields first, count, orig are the pipeline's
  /// internal numbering and mean nothing outside it.
  virtual void readBodyRows(const std::vector<std::uint32_t>& bodies, std::vector<BodyRow>& outRows) const = 0;
  /// Overwrites the motion of `bodies` (V, Ω, R, X, Q, L and the image counters of rows[k]; the
  /// other fields stay the pipeline's), recomputes their particles' positions, then redoes the
  /// skin test on every particle, so that the candidate list and the near list are rebuilt when
  /// the overwritten positions need it. Nothing else of the state changes.
  virtual void writeBodyRows(const std::vector<std::uint32_t>& bodies, const std::vector<BodyRow>& rows) = 0;
  /// How many touching contacts the particles of `bodies` had in the last step, each counted
  /// from its particle's side (a contact between two of them counts twice); 0 before the first step.
  virtual std::uint64_t contactsOf(const std::vector<std::uint32_t>& bodies) const = 0;
};

/// The CPU pipeline behind the HaloPipeline interface (the same pipeline as makeCpuPipeline()).
std::unique_ptr<HaloPipeline> makeCpuHaloPipeline(const PipelineOptions& options = {});

}  // namespace tumble::cpu
