// SPDX-License-Identifier: MIT
// The only translation unit that instantiates CUB (see cub_primitives.cuh). CUDA 13 ships
// CCCL 3, which no longer has cub::Sum; ExclusiveSum uses cuda::std::plus internally.
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include "cub_primitives.cuh"

namespace tumble::gpu::detail {
namespace {

// An empty bit range sorts nothing: the stable result is the input, as the CPU's sort gives it
// (CUB is not asked what it makes of a range with no bits).
template <class K>
cudaError_t copyUnsorted(void* temp, std::size_t& tempBytes, const K* keysIn, K* keysOut,
                         const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n,
                         cudaStream_t stream) {
  if (temp == nullptr) {
    tempBytes = 1;
    return cudaSuccess;
  }
  if (n == 0) return cudaSuccess;
  const cudaError_t e = cudaMemcpyAsync(keysOut, keysIn, n * sizeof(K), cudaMemcpyDeviceToDevice, stream);
  if (e != cudaSuccess) return e;
  return cudaMemcpyAsync(valuesOut, valuesIn, n * sizeof(std::uint32_t), cudaMemcpyDeviceToDevice, stream);
}

}  // namespace

cudaError_t exclusiveSum(void* temp, std::size_t& tempBytes, const std::uint32_t* in, std::uint32_t* out,
                         std::uint32_t n, cudaStream_t stream) {
  return cub::DeviceScan::ExclusiveSum(temp, tempBytes, in, out, n, stream);
}

cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint64_t* keysIn, std::uint64_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream) {
  if (beginBit >= endBit) return copyUnsorted(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, stream);
  return cub::DeviceRadixSort::SortPairs(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit, endBit,
                                         stream);
}

cudaError_t radixSortPairs(void* temp, std::size_t& tempBytes, const std::uint32_t* keysIn, std::uint32_t* keysOut,
                           const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::uint32_t n, int beginBit,
                           int endBit, cudaStream_t stream) {
  if (beginBit >= endBit) return copyUnsorted(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, stream);
  return cub::DeviceRadixSort::SortPairs(temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, beginBit, endBit,
                                         stream);
}

}  // namespace tumble::gpu::detail
