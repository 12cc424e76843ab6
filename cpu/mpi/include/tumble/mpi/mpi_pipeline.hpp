// SPDX-License-Identifier: MIT
/// @file mpi_pipeline.hpp
/// The MPI pipeline (docs/mpi.md): one simulation over every rank of MPI_COMM_WORLD, each rank
/// running a pipeline (the CPU's or the CUDA pipeline) on the bodies it owns plus ghost copies of those near them, with
/// trajectories bit-identical to one process. It is a tumble::Pipeline whose every method is
/// collective: all ranks call the same methods in the same order with the same arguments (the
/// drivers do, running the same code on the same scene), and every read returns the whole
/// state, in scene order, on every rank.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tumble/mpi/decomposition.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::mpi {

/// One rank's share of the work and of the communication.
struct MpiStats {
  int rank = 0;
  /// At the last redistribution: the bodies and particles this rank owns, and its ghosts.
  std::uint64_t ownedBodies = 0, ownedParticles = 0, ghostBodies = 0, ghostParticles = 0;
  /// Neighbour ranks it sends ghost rows to at the last redistribution.
  std::uint64_t neighbours = 0;
  /// Since load() or resetStats().
  struct Counts {
    /// Redistributions of the bodies (the load included): the state gathered on every rank, the
    /// domain cut afresh and each rank's world loaded (docs/mpi.md#rebuilds-migration-and-rebalancing).
    std::uint64_t redistributions = 0;
    std::uint64_t steps = 0;
    std::uint64_t haloBytes = 0;          ///< ghost rows sent after the steps (108 bytes a body)
    std::uint64_t haloMessages = 0;       ///< point-to-point messages of those
    std::uint64_t reduceBytes = 0;        ///< this rank's part of the per-step reductions
    std::uint64_t redistributeBytes = 0;  ///< state this rank received in the redistributions' gathers
    std::uint64_t readBytes = 0;          ///< state received by the collective reads (guards, outputs)
    double stepSeconds = 0.0;             ///< in its CPU pipeline
    double exchangeSeconds = 0.0;         ///< in the per-step reduction and ghost exchange (waits included)
    double redistributeSeconds = 0.0;
  } counts;
};

/// The MPI pipeline. backend(): the pipeline each rank runs.
class MpiPipeline : public Pipeline {
 public:
  /// Every rank's MpiStats, in rank order (collective).
  virtual std::vector<MpiStats> gatherStats() const = 0;
  virtual Decomposition decomposition() const = 0;
};

/// Creates the MPI pipeline over MPI_COMM_WORLD (started by Session), each rank running the
/// pipeline of `backend` (makeHaloPipeline(); Backend::Cuda on the rank's current CUDA device:
/// one GPU per rank where CUDA_VISIBLE_DEVICES gives each rank its own, docs/mpi.md).
/// options.threads are each rank's. Throws tumble::Error when this build has no MPI, MPI is not
/// started or the backend cannot run here (requireBackend()).
/// load() refuses, for now, periodic boundaries (tumble::Error naming them).
std::unique_ptr<MpiPipeline> makeMpiPipeline(const PipelineOptions& options, Decomposition how = Decomposition::Rcb,
                                             Backend backend = Backend::Cpu);

/// The table of gatherStats() that `tumble run` prints: per rank the bodies, particles, ghosts
/// (and their share of the rank's particles), neighbours, the ghost rows' bytes and messages per
/// step, the redistributions and the bytes each received, and the bytes of the collective reads
/// (guards, outputs) per step.
std::string describe(const std::vector<MpiStats>& stats);

}  // namespace tumble::mpi
