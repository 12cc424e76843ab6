// SPDX-License-Identifier: MIT
/// @file memory.hpp
/// Early, clear refusals of inputs too big for the machine: what a run or a reader needs (a
/// run's: runMemoryEstimate(), tumble/run_memory.hpp), compared with what the system says is
/// available, instead of std::bad_alloc after minutes.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace tumble {

/// What this process can still allocate, in bytes: MemAvailable from /proc/meminfo, lowered to
/// the room left under the address-space and data limits (`ulimit -v`, RLIMIT_AS and
/// RLIMIT_DATA, less VmSize and VmData of /proc/self/status) where those are set; nothing where
/// none of it can be read.
std::optional<std::uint64_t> availableMemory();

/// "the 3.2 GiB this machine has available" (or "… this process may still allocate (ulimit -v
/// or -d)"): availableMemory() for messages.
std::string availableMemoryText();

/// "3.2 GiB", "512 MiB": a size for messages.
std::string bytesText(std::uint64_t bytes);

/// Empty when `bytes` fits in the available memory (or that is unknown, or bytes is below
/// 1 GB); otherwise "about X, more than the Y this machine has available" (or "this process
/// may still allocate", when a limit is the lower).
std::string memoryShortfall(std::uint64_t bytes);

}  // namespace tumble
