# SPDX-License-Identifier: MIT
# Optional MPI (docs/mpi.md): AUTO builds the MPI pipeline when CMake's FindMPI finds an MPI
# (Debian: libopenmpi-dev), ON requires it, OFF skips it. tumble calls MPI's C API from C++: the
# CXX component without the deprecated C++ bindings (MPI_CXX_SKIP_MPICXX). Without it tumble::mpi is a session
# of one rank, and `tumble run` refuses to run under mpirun.
set(TUMBLE_HAS_MPI OFF)
if(NOT TUMBLE_ENABLE_MPI STREQUAL "OFF")
  set(MPI_CXX_SKIP_MPICXX TRUE)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    set(TUMBLE_HAS_MPI ON)
    message(STATUS "tumble: MPI ${MPI_CXX_VERSION}, mpiexec ${MPIEXEC_EXECUTABLE}")
  elseif(TUMBLE_ENABLE_MPI STREQUAL "ON")
    message(FATAL_ERROR "TUMBLE_ENABLE_MPI=ON but no MPI was found (Debian: apt-get install libopenmpi-dev openmpi-bin)")
  else()
    message(STATUS "tumble: no MPI, building without the MPI pipeline (Debian: libopenmpi-dev)")
  endif()
endif()
