// SPDX-License-Identifier: MIT
// TUMBLE_CUDA_CHECK: every CUDA runtime and CUB call goes through it (STYLE §5). A failure
// throws tumble::CudaError naming the expression, file:line and the CUDA error string, in the
// manner of DEM-Engine's throwing GPU-call wrapper and CUB's CubDebug. Internal to tumble::gpu.
#pragma once
#include <cuda_runtime_api.h>

#include <string>

#include "tumble/gpu/cuda_pipeline.hpp"

namespace tumble::gpu::detail {

[[noreturn]] inline void throwCudaError(cudaError_t e, const char* expr, const char* file, int line) {
  (void)cudaGetLastError();  // clear a non-sticky error so that the next call starts clean
  throw CudaError(std::string(file) + ":" + std::to_string(line) + ": " + expr + " failed: " + cudaGetErrorName(e) +
                  " (" + cudaGetErrorString(e) + ")");
}

inline void cudaCheck(cudaError_t e, const char* expr, const char* file, int line) {
  if (e != cudaSuccess) throwCudaError(e, expr, file, line);
}

}  // namespace tumble::gpu::detail

/// Evaluates a cudaError_t expression and throws tumble::CudaError unless it is cudaSuccess.
#define TUMBLE_CUDA_CHECK(expr) ::tumble::gpu::detail::cudaCheck((expr), #expr, __FILE__, __LINE__)
