// SPDX-License-Identifier: MIT
/// @file factory.hpp
/// The pipelines of this build (tumble::pipelines, core/factory): which backends it has, whether
/// the CUDA pipeline can run here, and the pipeline of a backend. The one target that links every
/// backend (tumble::cpu, tumble::gpu_host, tumble::gpu); the core declares only the interface
/// (tumble/pipeline.hpp), and cpu/ and gpu/ depend on the core alone.
#pragma once
#include <memory>
#include <vector>

#include "tumble/pipeline.hpp"

namespace tumble {

/// Backends compiled into this build: cpu, cuda (with the CUDA module), cuda-host.
std::vector<Backend> compiledBackends();
/// Whether the CUDA pipeline can run here (CudaStatus, tumble/pipeline.hpp).
CudaStatus cudaStatus();
/// cudaStatus().state == CudaState::Ready.
bool cudaAvailable();
/// Throws tumble::Error saying why when backend `b` cannot run here (for CUDA: cudaStatus()).
void requireBackend(Backend b);

/// Creates a pipeline. Throws tumble::Error when the backend is not compiled in or has no device.
std::unique_ptr<Pipeline> makePipeline(Backend backend, const PipelineOptions& options = {});
/// The same pipeline behind the HaloPipeline interface (what each rank of the MPI pipeline runs).
std::unique_ptr<HaloPipeline> makeHaloPipeline(Backend backend, const PipelineOptions& options = {});

}  // namespace tumble
