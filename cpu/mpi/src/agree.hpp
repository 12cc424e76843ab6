// SPDX-License-Identifier: MIT
// Agreement on failures across the ranks (Session::agree, the MPI pipeline's steps and loads).
#pragma once
#include <mpi.h>

#include <exception>

namespace tumble::mpi::detail {

/// Collective over comm: when some rank's `failure` is set, every rank throws the failure of the
/// lowest such rank (that rank its own exception, the others one of the same kind with the same
/// message: tumble::SimulationError with its particle, tumble::Error, or std::runtime_error);
/// otherwise returns.
void agree(MPI_Comm comm, std::exception_ptr failure);

}  // namespace tumble::mpi::detail
