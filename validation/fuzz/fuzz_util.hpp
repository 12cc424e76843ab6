// SPDX-License-Identifier: MIT
/// @file fuzz_util.hpp
/// Shared by the libFuzzer targets (docs/fuzzing.md): the readers that take a path get the
/// input through a file of this process, and a property that fails aborts with a message, which
/// libFuzzer reports as a crash and saves the input for.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unistd.h>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::fuzz {

/// A file of this process (in /dev/shm when there is one: no disk traffic), `tag` in its name.
/// The files are removed when the process exits normally (libFuzzer's -max_total_time and
/// -runs end by exit()); a crash leaves them, next to the input libFuzzer saves.
inline std::string scratchPath(const char* tag) {
  static std::set<std::string> made;
  static const bool cleanup = [] {
    std::atexit([] {
      for (const std::string& p : made) std::remove(p.c_str());
    });
    return true;
  }();
  (void)cleanup;
  const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
  const std::string path = std::string(dir) + "/tumble-fuzz-" + std::to_string(::getpid()) + "-" + tag;
  made.insert(path);
  return path;
}

/// Writes the input to scratchPath(tag) and returns that path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, const char* tag) {
  const std::string path = scratchPath(tag);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

/// The CPU pipeline on one thread: `tumble.sh fuzz` runs the targets side by side, one core each,
/// so a target's own threads would only take time from its neighbour.
inline std::unique_ptr<Pipeline> cpuPipeline() {
  PipelineOptions one;
  one.threads = 1;
  return makePipeline(Backend::Cpu, one);
}

/// The checkpoint the input holds, or nothing when the reader refuses it (InputError).
inline std::optional<Checkpoint> readCheckpoint(const std::uint8_t* data, std::size_t size) {
  try {
    return Checkpoint::read(writeInput(data, size, "in.ck"));
  } catch (const InputError&) {
    return std::nullopt;
  }
}

/// A property does not hold: say which, and abort (libFuzzer keeps the input).
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "tumble fuzz: %s\n", what.c_str());
  std::abort();
}

/// 64-bit FNV-1a over raw bytes (floats compared bit for bit).
struct Hash {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 1099511628211ull;
  }
  template <class T>
  void column(const T& v) {
    const std::uint64_t n = v.size();
    bytes(&n, sizeof n);
    if (n) bytes(v.data(), n * sizeof v[0]);
  }
};

}  // namespace tumble::fuzz
