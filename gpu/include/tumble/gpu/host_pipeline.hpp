// SPDX-License-Identifier: MIT
/// @file host_pipeline.hpp
/// The CUDA pipeline run on the host backend of its execution layer (Backend::CudaHost,
/// `--pipeline cuda-host`): the same orchestration and per-element code as the CUDA pipeline,
/// compiled by the host compiler and run on oneTBB with host memory. It needs no GPU and is
/// built in every build. It exists to test the CUDA pipeline's code, and to check a GPU result
/// without a GPU: it is not a fast path (docs/cuda.md).
#pragma once
#include <memory>

#include "tumble/pipeline.hpp"

namespace tumble::gpu {

/// Creates the CUDA pipeline on the host backend. Determinism: as the CUDA pipeline (the pair
/// list, counts and offsets bitwise equal to the CPU pipeline's; the float state bitwise equal
/// under TUMBLE_STRICT_FP), for any thread count (options.threads).
std::unique_ptr<HaloPipeline> makeCudaHostPipeline(const PipelineOptions& options = {});

}  // namespace tumble::gpu
