// SPDX-License-Identifier: MIT
// The pipeline factory: the one place that knows which backends this build has. Every pipeline
// has the hooks of a domain decomposition (HaloPipeline): makePipeline() is makeHaloPipeline().
#include <string>

#include "tumble/config.hpp"
#include "tumble/cpu/cpu_pipeline.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/gpu/host_pipeline.hpp"
#if TUMBLE_HAS_CUDA
#include "tumble/gpu/cuda_pipeline.hpp"
#endif

namespace tumble {

std::vector<Backend> compiledBackends() {
#if TUMBLE_HAS_CUDA
  return {Backend::Cpu, Backend::Cuda, Backend::CudaHost};
#else
  return {Backend::Cpu, Backend::CudaHost};
#endif
}

CudaStatus cudaStatus() {
#if TUMBLE_HAS_CUDA
  return gpu::deviceStatus();
#else
  return {CudaState::NoDevice, "this build of tumble has no CUDA pipeline (rebuild with a CUDA compiler, "
                               "TUMBLE_ENABLE_CUDA=ON)"};
#endif
}

bool cudaAvailable() { return cudaStatus().state == CudaState::Ready; }

void requireBackend(Backend b) {
  if (b == Backend::Cuda) requireReady(cudaStatus());
}

std::unique_ptr<Pipeline> makePipeline(Backend backend, const PipelineOptions& options) {
  return makeHaloPipeline(backend, options);
}

std::unique_ptr<HaloPipeline> makeHaloPipeline(Backend backend, const PipelineOptions& options) {
  if (options.threads < 0 || options.threads > kMaxThreads)
    throw Error("threads = " + std::to_string(options.threads) + ": expected 0 (all cores) to " +
                std::to_string(kMaxThreads));
  if (backend == Backend::Cpu) return cpu::makeCpuHaloPipeline(options);
  if (backend == Backend::CudaHost) return gpu::makeCudaHostPipeline(options);
#if TUMBLE_HAS_CUDA
  return gpu::makeCudaPipeline(options);  // requireReady(deviceStatus()) first
#else
  requireBackend(backend);  // throws: no CUDA module
  return nullptr;
#endif
}

}  // namespace tumble
