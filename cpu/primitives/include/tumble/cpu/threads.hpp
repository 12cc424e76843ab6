// SPDX-License-Identifier: MIT
/// @file threads.hpp
/// The threads a pipeline was asked for, honoured also above the number of cores.
#pragma once
#include <memory>

#include <tbb/global_control.h>
#include <tbb/info.h>

namespace tumble::cpu {

/// oneTBB lets an arena have at most as many threads as the machine has cores unless a
/// global_control raises the limit (it would print "TBB Warning: The number of workers is
/// currently limited" and run fewer): for `threads` above the cores, the control that allows
/// them, to be held as long as the arena is used (declare it before the arena). Null otherwise.
/// Two pipelines that ask for different numbers above the cores both get the smaller.
inline std::unique_ptr<tbb::global_control> allowThreads(int threads) {
  if (threads <= tbb::info::default_concurrency()) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<std::size_t>(threads));
}

}  // namespace tumble::cpu
