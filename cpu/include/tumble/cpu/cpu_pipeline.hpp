// SPDX-License-Identifier: MIT
/// @file cpu_pipeline.hpp
/// The CPU reference pipeline on oneTBB. Use tumble::makePipeline(Backend::Cpu) or
/// makeCpuPipeline(); everything else about it is behind the tumble::Pipeline interface.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "tumble/pipeline.hpp"
#include "tumble/soa.hpp"

namespace tumble::cpu {

/// Creates the CPU pipeline. options.threads = 0 uses every core; the results do not depend
/// on the thread count (bitwise).
std::unique_ptr<Pipeline> makeCpuPipeline(const PipelineOptions& options = {});

/// The CPU pipeline behind the HaloPipeline interface (the same pipeline as makeCpuPipeline()).
std::unique_ptr<HaloPipeline> makeCpuHaloPipeline(const PipelineOptions& options = {});

}  // namespace tumble::cpu
