// SPDX-License-Identifier: MIT
// DeviceBuffer<T>: a move-only owner of one device array (STYLE §2.1; DEM-Engine's
// DataMigrationHelper explains why GPU arrays must not be copyable: a copy would double-free).
// Scratch buffers are grow-only, like the CPU pipeline's std::vector columns (cpu/src/grow.hpp):
// once capacities have settled, a step never calls cudaMalloc. Internal to tumble::gpu.
#pragma once
#include <cuda_runtime_api.h>

#include <cstddef>
#include <vector>

#include "cuda_check.hpp"

namespace tumble::gpu::detail {

template <class T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  ~DeviceBuffer() { release(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& o) noexcept : m_data(o.m_data), m_capacity(o.m_capacity) {
    o.m_data = nullptr;
    o.m_capacity = 0;
  }
  DeviceBuffer& operator=(DeviceBuffer&& o) noexcept {
    if (this != &o) {
      release();
      m_data = o.m_data;
      m_capacity = o.m_capacity;
      o.m_data = nullptr;
      o.m_capacity = 0;
    }
    return *this;
  }

  T* data() noexcept { return m_data; }
  const T* data() const noexcept { return m_data; }
  std::size_t capacity() const noexcept { return m_capacity; }

  /// Makes room for at least n elements (25 % slack, as cpu/src/grow.hpp) and returns the data.
  /// Growing discards the contents; never shrinks. cudaFree synchronises the device, so work
  /// still in flight on the old array is finished first.
  T* grow(std::size_t n) {
    if (m_capacity < n) {
      release();
      allocate(n + n / 4 + 16);
    }
    return m_data;
  }

  /// Exactly the contents of host[0..n) (load-time copies; capacity grows if needed).
  void upload(const T* host, std::size_t n, cudaStream_t stream) {
    grow(n);
    if (n > 0) TUMBLE_CUDA_CHECK(cudaMemcpyAsync(m_data, host, n * sizeof(T), cudaMemcpyHostToDevice, stream));
  }
  void upload(const std::vector<T>& host, cudaStream_t stream) { upload(host.data(), host.size(), stream); }

  /// Copies the first n elements to host (ordered on `stream`; the caller synchronises).
  void download(T* host, std::size_t n, cudaStream_t stream) const {
    if (n > 0) TUMBLE_CUDA_CHECK(cudaMemcpyAsync(host, m_data, n * sizeof(T), cudaMemcpyDeviceToHost, stream));
  }

 private:
  void allocate(std::size_t n) {
    void* p = nullptr;
    TUMBLE_CUDA_CHECK(cudaMalloc(&p, n * sizeof(T)));
    m_data = static_cast<T*>(p);
    m_capacity = n;
  }
  void release() noexcept {
    if (m_data != nullptr) (void)cudaFree(m_data);  // never throws from a destructor
    m_data = nullptr;
    m_capacity = 0;
  }

  T* m_data = nullptr;
  std::size_t m_capacity = 0;
};

}  // namespace tumble::gpu::detail
