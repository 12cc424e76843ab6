// SPDX-License-Identifier: MIT
// The CUDA pipeline's orchestration (pipeline.hpp) compiled by nvcc over the device backend of
// the execution layer (exec/cuda_exec.cuh): Backend::Cuda. Also the device's status (Ready,
// NoDevice or Broken), which decides whether the CUDA tests run, skip or fail.
#include <cuda_runtime_api.h>

#include <memory>
#include <string>

#include "exec/cuda_exec.cuh"
#include "pipeline.hpp"
#include "tumble/gpu/cuda_pipeline.hpp"

namespace tumble::gpu {

namespace {

// Compiled for the build's architectures like every kernel: whether the device can run it says
// whether it can run this build's code.
__global__ void probeKernel() {}

std::string cudaVersionText(int v) {
  return v == 0 ? std::string("none") : std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10);
}

}  // namespace

CudaStatus deviceStatus() noexcept {
  try {
    int driver = 0, runtime = 0, count = 0;
    if (cudaDriverGetVersion(&driver) != cudaSuccess) driver = 0;
    if (cudaRuntimeGetVersion(&runtime) != cudaSuccess) runtime = 0;
    const cudaError_t e = cudaGetDeviceCount(&count);
    (void)cudaGetLastError();
    const std::string versions =
        " (CUDA driver " + cudaVersionText(driver) + ", runtime " + cudaVersionText(runtime) + ")";
    if (e == cudaSuccess && count > 0) {
      cudaDeviceProp prop{};
      const std::string name = cudaGetDeviceProperties(&prop, 0) == cudaSuccess
                                   ? std::string(prop.name) + " (compute capability " + std::to_string(prop.major) +
                                         "." + std::to_string(prop.minor) + ")"
                                   : "?";
      // A device this build has no code for (below its architectures) fails every launch:
      // Broken, said here rather than at the first kernel.
      cudaFuncAttributes attr{};
      const cudaError_t k = cudaFuncGetAttributes(&attr, probeKernel);
      (void)cudaGetLastError();
      if (k != cudaSuccess)
        return {CudaState::Broken, "CUDA device 0: " + name + " cannot run this build's kernels (" +
                                       cudaGetErrorName(k) + "; built for CUDA architectures " +
                                       TUMBLE_CUDA_ARCHITECTURES + ")" + versions};
      return {CudaState::Ready, "CUDA device 0 of " + std::to_string(count) + ": " + name + versions};
    }
    if (e == cudaSuccess || e == cudaErrorNoDevice) return {CudaState::NoDevice, "no CUDA device" + versions};
    if (driver == 0) return {CudaState::NoDevice, "no CUDA driver is installed" + versions};
    return {CudaState::Broken, std::string("CUDA cannot use the GPU: ") + cudaGetErrorName(e) + " (" +
                                   cudaGetErrorString(e) + ")" + versions};
  } catch (...) {  // std::bad_alloc from the strings
    return {CudaState::Broken, "CUDA status: out of memory"};
  }
}

std::unique_ptr<HaloPipeline> makeCudaPipeline(const PipelineOptions& options) {
  requireReady(deviceStatus());
  return std::make_unique<detail::CudaPipeline<exec::CudaExec>>(Backend::Cuda, options);
}

}  // namespace tumble::gpu

extern "C" const tumble::gpu::CudaModule* tumble_cuda_module() {
  static const tumble::gpu::CudaModule module{&tumble::gpu::makeCudaPipeline, &tumble::gpu::deviceStatus};
  return &module;
}
