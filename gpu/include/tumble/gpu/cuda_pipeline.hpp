// SPDX-License-Identifier: MIT
/// @file cuda_pipeline.hpp
/// The CUDA pipeline: the same stage list as the CPU pipeline (state → axis → keys → sort →
/// sweep → forces → integrate), run on one CUDA device. Plain C++: this header includes no CUDA
/// header and exposes no CUDA type, so any host target may include it (STYLE §2.4).
#pragma once
#include <memory>

#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"

namespace tumble {

/// A CUDA runtime or CUB call failed. what() names the expression, file:line and the CUDA error
/// string. The pipeline that threw is left in an unspecified (but destructible) state.
class CudaError : public Error {
 public:
  using Error::Error;
};

namespace gpu {

/// Creates the CUDA pipeline on the current device.
///
/// Determinism: the pair list, every count and offset are bitwise equal to the CPU pipeline's;
/// the float state is bitwise equal to the CPU pipeline's when both are built with
/// TUMBLE_STRICT_FP (no FMA contraction), and bit-identical across runs in any case (fixed-order
/// sums, integer keys, stable sorts, no float atomics).
/// Throws tumble::Error when no CUDA device is available, tumble::CudaError when the device
/// cannot be set up.
std::unique_ptr<HaloPipeline> makeCudaPipeline(const PipelineOptions& options = {});

/// Whether the CUDA runtime can use a device (tumble::cudaStatus() of a build with CUDA): Ready
/// with at least one device; NoDevice when the runtime reports none (cudaErrorNoDevice, or a
/// count of 0) or no driver is installed (driver version 0); Broken for any other error, such as
/// a driver older than the runtime. The message names the driver and runtime versions. Never
/// throws; do not call it from a static initialiser (test discovery runs binaries at build time).
CudaStatus deviceStatus() noexcept;

/// The CUDA module as the pipeline factory (tumble/factory.hpp) finds it: its two entry points.
struct CudaModule {
  std::unique_ptr<HaloPipeline> (*make)(const PipelineOptions&);
  CudaStatus (*status)() noexcept;
};

}  // namespace gpu
}  // namespace tumble

/// Defined by the CUDA module (tumble::cuda) alone. The factory refers to it weakly, so a program
/// links the module, and with it the CUDA runtime, only when it links tumble::cuda (whose link
/// options ask the linker for this symbol): a CPU program built against the package
/// (find_package(tumble) without COMPONENTS cuda) needs no CUDA to start (docs/cpp.md).
extern "C" const tumble::gpu::CudaModule* tumble_cuda_module();
