// SPDX-License-Identifier: MIT
// The gates of the tests of the CUDA pipeline (gpu/tests, the */cuda and */cuda_host instances of
// validation/tests). On the GPU (Backend::Cuda) a test runs where a device is ready; it skips
// where the build or the machine has none, unless TUMBLE_REQUIRE_CUDA=1 asks that it run; it
// fails where CUDA is there but broken (a driver older than the runtime, …), with the driver and
// runtime versions in the message. On the host backend (cuda-host) it always runs. On either, a
// test of a model the CUDA pipeline does not have yet skips with the pipeline's NotSupported.
#pragma once
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
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

/// In a test body or SetUp() of a test over backends: TUMBLE_NEED_CUDA for Backend::Cuda; the
/// other backends (cpu, cuda-host) run everywhere.
#define TUMBLE_NEED_BACKEND(backend)                                                              \
  do {                                                                                            \
    if ((backend) == ::tumble::Backend::Cuda) TUMBLE_NEED_CUDA(::tumble::cudaStatus());           \
  } while (0)

/// In a test body: skips the test where `backend` refuses scene `probe` at load with
/// tumble::NotSupported (the CUDA pipeline, for a model it does not have yet), with
/// "NotSupported: " and the pipeline's own message as the reason. The probe names the model the
/// test needs (validation::modelProbe); once the pipeline has it, the test runs.
#define TUMBLE_SKIP_IF_NOT_SUPPORTED(backend, probe)                                              \
  do {                                                                                            \
    if (const auto why_ = ::tumble_test::notSupported((backend), (probe)))                        \
      GTEST_SKIP() << "NotSupported: " << *why_;                                                  \
  } while (0)

namespace tumble_test {

/// The message of the tumble::NotSupported that `backend` throws when it loads scene `probe`, or
/// nothing when it loads it (a test that needs several models skips each one it lacks).
inline std::optional<std::string> notSupported(::tumble::Backend backend, const ::tumble::Scene& probe) {
  try {
    ::tumble::makePipeline(backend)->load(::tumble::World::fromScene(probe));
  } catch (const ::tumble::NotSupported& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

/// The backends that run the CUDA pipeline's code in this build: cuda-host always, cuda where
/// the CUDA module is built (its tests skip without a device).
inline std::vector<::tumble::Backend> cudaPipelineBackends() {
  std::vector<::tumble::Backend> out;
  for (::tumble::Backend b : ::tumble::compiledBackends())
    if (::tumble::isCudaPipeline(b)) out.push_back(b);
  return out;
}

/// A test-name suffix for a backend: cpu, cuda, cuda_host (gtest names take no '-').
inline std::string backendName(const ::testing::TestParamInfo<::tumble::Backend>& info) {
  std::string s = ::tumble::toString(info.param);
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

}  // namespace tumble_test
