// SPDX-License-Identifier: MIT
// The pipeline factory: the one place that knows which backends this build has. Every pipeline
// has the hooks of a domain decomposition (HaloPipeline): makePipeline() is makeHaloPipeline().
#include <string>

#include "tumble/config.hpp"
#include "tumble/cpu/cpu_pipeline.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/gpu/cuda_pipeline.hpp"
#include "tumble/gpu/host_pipeline.hpp"

// The CUDA module, when the program links it (tumble::cuda): a weak reference, null otherwise, so
// that linking this factory pulls in neither the module nor the CUDA runtime.
extern "C" const tumble::gpu::CudaModule* tumble_cuda_module() __attribute__((weak));

namespace tumble {
namespace {

const gpu::CudaModule* cudaModule() { return tumble_cuda_module != nullptr ? tumble_cuda_module() : nullptr; }

}  // namespace

std::vector<Backend> compiledBackends() {
  if (cudaModule() != nullptr) return {Backend::Cpu, Backend::Cuda, Backend::CudaHost};
  return {Backend::Cpu, Backend::CudaHost};
}

CudaStatus cudaStatus() {
  if (const gpu::CudaModule* m = cudaModule()) return m->status();
#if TUMBLE_HAS_CUDA
  return {CudaState::NoDevice, "this program was not linked with tumble's CUDA module (link tumble::cuda: "
                               "find_package(tumble COMPONENTS cuda), docs/cpp.md)"};
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
  if (const gpu::CudaModule* m = cudaModule()) return m->make(options);  // requireReady(deviceStatus()) first
  requireBackend(backend);  // throws: no CUDA module
  return nullptr;
}

}  // namespace tumble
