// SPDX-License-Identifier: MIT
// The ranks of a run (tumble/mpi/session.hpp): MPI when this build has it and mpirun started the
// process; otherwise one rank, and every call is what a single process does.
#include "tumble/mpi/session.hpp"

#include <cstdlib>
#include <string>

#include "tumble/config.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/mpi/mpi_pipeline.hpp"
#if TUMBLE_HAS_MPI
#include <mpi.h>

#include "agree.hpp"
#endif

namespace tumble::mpi {
namespace {
const Session* g_session = nullptr;
}

bool launched() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (const char* s = std::getenv(v); s != nullptr && *s != '\0') return true;
  return false;
}

int launchedRank() {
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* s = std::getenv(v); s != nullptr && *s != '\0') return std::atoi(s);
  return 0;
}

Session::Session(int* argc, char*** argv) {
  if (argc == nullptr || !launched()) return;  // one rank, no MPI
#if TUMBLE_HAS_MPI
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &m_size);
  m_active = true;
  g_session = this;
#else
  (void)argv;
  throw Error("this tumble was built without MPI, so it cannot run under mpirun (every process would run the "
              "whole job and write the same files): rebuild it with MPI (apt-get install libopenmpi-dev; "
              "TUMBLE_ENABLE_MPI=ON) or run it without mpirun");
#endif
}

Session::~Session() {
#if TUMBLE_HAS_MPI
  if (m_active) {
    if (g_session == this) g_session = nullptr;
    int done = 0;
    MPI_Finalized(&done);
    if (!done) MPI_Finalize();
  }
#endif
}

void Session::agree(std::exception_ptr failure) const {
#if TUMBLE_HAS_MPI
  if (m_active) {
    detail::agree(MPI_COMM_WORLD, failure);
    return;
  }
#endif
  if (failure) std::rethrow_exception(failure);
}

int Session::maxOf(int value) const {
#if TUMBLE_HAS_MPI
  if (m_active) {
    int out = value;
    MPI_Allreduce(&value, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out;
  }
#endif
  return value;
}

std::unique_ptr<Pipeline> Session::makePipeline(Backend backend, const PipelineOptions& options,
                                                Decomposition how) const {
  if (!m_active) return tumble::makePipeline(backend, options);
  return makeMpiPipeline(options, how, backend);
}

#if !TUMBLE_HAS_MPI
std::unique_ptr<MpiPipeline> makeMpiPipeline(const PipelineOptions&, Decomposition, Backend) {
  throw Error("this tumble was built without MPI: no MPI pipeline (rebuild with libopenmpi-dev, TUMBLE_ENABLE_MPI=ON)");
}
#endif

const Session& session() {
  static const Session single(nullptr, nullptr);
  return g_session != nullptr ? *g_session : single;
}

}  // namespace tumble::mpi
