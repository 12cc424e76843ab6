// SPDX-License-Identifier: MIT
/// @file hd.hpp
/// Host/device portability macros. Every per-element kernel in core/ is written once as a
/// TUMBLE_HD function and called from TBB loops on the host and from thin __global__ wrappers
/// in gpu/. This header must stay valid C++17 and compile under nvcc.
#pragma once

#if defined(__CUDACC__)
#define TUMBLE_HD __host__ __device__
#define TUMBLE_HD_INLINE __host__ __device__ __forceinline__
#define TUMBLE_HD_NOINLINE __host__ __device__ __noinline__
#else
#define TUMBLE_HD
#define TUMBLE_HD_INLINE inline __attribute__((always_inline))
#define TUMBLE_HD_NOINLINE __attribute__((noinline))
#endif

#if defined(NDEBUG)
#define TUMBLE_ASSERT(cond, msg) ((void)0)
#elif defined(__CUDA_ARCH__)
#include <cassert>
#define TUMBLE_ASSERT(cond, msg) assert((cond) && (msg))
#else
#include <cstdio>
#include <cstdlib>
/// Contract check for host and device code, compiled out in Release (NDEBUG).
#define TUMBLE_ASSERT(cond, msg)                                                              \
  do {                                                                                        \
    if (!(cond)) {                                                                            \
      std::fprintf(stderr, "%s:%d: assertion '%s' failed: %s\n", __FILE__, __LINE__, #cond,   \
                   msg);                                                                      \
      std::abort();                                                                           \
    }                                                                                         \
  } while (0)
#endif
