// SPDX-License-Identifier: MIT
// The CUDA pipeline's orchestration (pipeline.hpp) compiled by g++ over the host backend of the
// execution layer (exec/host_exec.hpp): Backend::CudaHost, "cuda-host". The CUDA pipeline's
// own code run on the CPU, for testing and for checking a GPU result without a GPU; not a fast
// path (docs/cuda.md says what it proves and what only a GPU can).
#include "tumble/gpu/host_pipeline.hpp"

#include "exec/host_exec.hpp"
#include "pipeline.hpp"

namespace tumble::gpu {

std::unique_ptr<HaloPipeline> makeCudaHostPipeline(const PipelineOptions& options) {
  return std::make_unique<detail::CudaPipeline<exec::HostExec>>(Backend::CudaHost, options);
}

}  // namespace tumble::gpu
