// SPDX-License-Identifier: MIT
/// @file session.hpp
/// The ranks of a run started by mpirun (docs/mpi.md). One Session per process, made by main()
/// before anything else: it starts MPI when this build has it and the process was started by an
/// MPI launcher; otherwise it is a session of one rank without MPI, and every call below is what
/// a single process would do. Plain C++: no MPI type appears here.
#pragma once
#include <exception>
#include <memory>
#include <utility>

#include "tumble/mpi/decomposition.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::mpi {

/// Whether an MPI launcher (mpirun, mpiexec, srun) started this process: its environment
/// variables are set (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK).
bool launched();

/// The rank an MPI launcher gave this process (OMPI_COMM_WORLD_RANK, PMI_RANK or PMIX_RANK), 0
/// when none did: who prints when MPI cannot start.
int launchedRank();

class Session {
 public:
  /// Starts MPI (MPI_Init_thread, MPI_THREAD_FUNNELED: only the calling thread talks to MPI)
  /// when this build has MPI (TUMBLE_ENABLE_MPI: tumble/config.hpp's TUMBLE_HAS_MPI) and launched(). Throws tumble::Error when launched() in a build without MPI:
  /// every process would then run the whole job and write the same files.
  Session(int* argc, char*** argv);
  /// Ends MPI (MPI_Finalize) when it was started.
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// MPI was started (under mpirun, even with one rank).
  bool active() const { return m_active; }
  int rank() const { return m_rank; }
  int size() const { return m_size; }
  /// The rank that writes the outputs and prints: rank 0.
  bool writes() const { return m_rank == 0; }

  /// Collective: every rank learns whether any rank failed (`failure` not null) and, if so,
  /// every rank throws the failure of the lowest failing rank: the same kind (tumble::Error,
  /// tumble::SimulationError with its particle, or std::runtime_error for anything else) and the
  /// same message. That rank rethrows its own exception. Without MPI: rethrows `failure`.
  void agree(std::exception_ptr failure) const;

  /// Runs f on this rank, then agree()s on its failure: what fails on one rank (an output it
  /// alone writes) ends every rank with that message.
  template <class F>
  void together(F&& f) const {
    std::exception_ptr failure;
    try {
      std::forward<F>(f)();
    } catch (...) {
      failure = std::current_exception();
    }
    agree(failure);
  }

  /// Collective: the largest of the ranks' values (a stop signal seen by any rank).
  int maxOf(int value) const;

  /// The pipeline of a run: under MPI the MPI pipeline (makeMpiPipeline(): the pipeline of
  /// `backend` on each rank's share of the bodies, cut as `how` says); otherwise
  /// makePipeline(backend, options).
  std::unique_ptr<Pipeline> makePipeline(Backend backend, const PipelineOptions& options,
                                         Decomposition how = Decomposition::Rcb) const;

 private:
  bool m_active = false;
  int m_rank = 0, m_size = 1;
};

/// The session main() made (a session of one rank without MPI before that, or in programs that
/// make none: the tests, the Python module).
const Session& session();

}  // namespace tumble::mpi
