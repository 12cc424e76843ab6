// SPDX-License-Identifier: MIT
#include "agree.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

#include "tumble/error.hpp"

namespace tumble::mpi::detail {
namespace {

enum class Kind : std::int32_t { Error, Simulation, Other };

struct Head {
  Kind kind;
  std::int32_t length;
  std::int64_t particle;
};

}  // namespace

void agree(MPI_Comm comm, std::exception_ptr failure) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int mine = failure ? rank : size;
  int first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  Head head{Kind::Other, 0, -1};
  std::string what;
  if (rank == first) {
    try {
      std::rethrow_exception(failure);
    } catch (const SimulationError& e) {
      head = Head{Kind::Simulation, 0, e.particle()};
      what = e.what();
    } catch (const Error& e) {
      head.kind = Kind::Error;
      what = e.what();
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
      what = "an unknown exception";
    }
    head.length = static_cast<std::int32_t>(what.size());
  }
  MPI_Bcast(&head, sizeof head, MPI_BYTE, first, comm);
  what.resize(static_cast<std::size_t>(head.length));
  MPI_Bcast(what.data(), head.length, MPI_CHAR, first, comm);
  if (rank == first) std::rethrow_exception(failure);
  switch (head.kind) {
    case Kind::Simulation: throw SimulationError(what, head.particle);
    case Kind::Error: throw Error(what);
    default: throw std::runtime_error(what);
  }
}

}  // namespace tumble::mpi::detail
