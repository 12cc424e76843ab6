// SPDX-License-Identifier: MIT
// Host wrappers around the CUB primitives the pipeline uses. Every CUB instantiation lives in
// cub_primitives.cu (one translation unit, as DEM-Engine's DEMCubInstantiations.cu), so the
// other .cu files compile quickly and include no CUB header.
//
// Contract (STYLE §2.3): the argument order and two-phase protocol of CUB and of the CPU twins
// tumble::cpu::exclusiveSum / radixSortPairs: with temp == nullptr the call only writes
// tempBytes. Inputs and outputs must not overlap. The radix sorts are stable and look only at
// bits [beginBit, endBit), exactly like the CPU sort, so both give the same permutation.
// Each returns the cudaError_t of the CUB call (wrap it in TUMBLE_CUDA_CHECK).
#pragma once
#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

namespace tumble::gpu::detail {

/// out[i] = in[0] + ... + in[i−1] (integers: exact and reproducible, STYLE §6).
cudaError_t exclusiveSum(void* temp, std::size_t& tempBytes, const std::uint32_t* in, std::uint32_t* out,
                         std::uint32_t n, cudaStream_t stream);

/// Stable sort of (key, value) pairs by key bits [beginBit, endBit) (an empty range copies).
cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint64_t* keysIn, std::uint64_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream);
cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint32_t* keysIn, std::uint32_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream);

}  // namespace tumble::gpu::detail
