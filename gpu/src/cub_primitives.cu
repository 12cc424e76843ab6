// SPDX-License-Identifier: MIT
// The only translation unit that instantiates CUB (see cub_primitives.cuh). CUDA 13 ships
// CCCL 3, which no longer has cub::Sum; ExclusiveSum uses cuda::std::plus internally.
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include "cub_primitives.cuh"

namespace tumble::gpu::detail {

cudaError_t exclusiveSum(void* temp, std::size_t& tempBytes, const std::uint32_t* in, std::uint32_t* out,
                         std::uint32_t n, cudaStream_t stream) {
  return cub::DeviceScan::ExclusiveSum(temp, tempBytes, in, out, n, stream);
}

cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint64_t* keysIn, std::uint64_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream) {
  return cub::DeviceRadixSort::SortPairs(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit, endBit,
                                         stream);
}

cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint32_t* keysIn, std::uint32_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream) {
  return cub::DeviceRadixSort::SortPairs(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit, endBit,
                                         stream);
}

}  // namespace tumble::gpu::detail
