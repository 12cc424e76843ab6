// SPDX-License-Identifier: MIT
// The gate of every test of the CUDA pipeline (gpu/tests, the */cuda and Cuda* tests of
// validation/tests): it runs where a device is ready; it skips where the build or the machine has
// none, unless TUMBLE_REQUIRE_CUDA=1 asks that it run; it fails where CUDA is there but broken
// (a driver older than the runtime, …), with the driver and runtime versions in the message.
#pragma once
#include <gtest/gtest.h>

#include "tumble/pipeline.hpp"

/// In a test body or SetUp(): returns from it after GTEST_SKIP() or FAIL() unless CUDA is ready.
/// `status`: tumble::cudaStatus() (the factory's), or tumble::gpu::deviceStatus() where the test
/// links the CUDA module alone.
#define TUMBLE_NEED_CUDA(status)                                                                  \
  do {                                                                                            \
    const ::tumble::CudaStatus tumbleCuda_ = (status);                                            \
    if (tumbleCuda_.state == ::tumble::CudaState::Ready) break;                                    \
    if (tumbleCuda_.state == ::tumble::CudaState::NoDevice && !::tumble::cudaRequired())          \
      GTEST_SKIP() << tumbleCuda_.message;                                                        \
    FAIL() << tumbleCuda_.message                                                                 \
           << (::tumble::cudaRequired() ? " (TUMBLE_REQUIRE_CUDA=1: a CUDA test may not skip)" : ""); \
  } while (0)
