// SPDX-License-Identifier: MIT
// The subcommands of the `tumble` program.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

namespace tumble::cli {

/// Exit status for bad input (missing file, malformed TOML or CSV, bad values).
inline constexpr int kExitBadInput = 2;
/// Exit status when a run stops because the simulation diverged.
inline constexpr int kExitDiverged = 3;

void addRun(CLI::App& app);
void addPairs(CLI::App& app);
void addBench(CLI::App& app);
void addValidate(CLI::App& app);

/// Writes a file atomically: `write` fills `path + ".part"`, which is then renamed to `path`.
/// On any failure the partial file is removed and tumble::Error is thrown.
template <class F>
void writeAtomically(const std::string& path, F&& write);

/// Thrown by subcommands to end with a given status after printing `what()`.
struct Exit {
  int status;
};

}  // namespace tumble::cli

#include <cerrno>
#include <cstring>

#include "tumble/error.hpp"

template <class F>
void tumble::cli::writeAtomically(const std::string& path, F&& write) {
  const std::string part = path + ".part";
  std::FILE* f = std::fopen(part.c_str(), "wb");
  if (!f) throw Error("cannot write " + part + ": " + std::strerror(errno));
  try {
    write(f);
  } catch (...) {
    std::fclose(f);
    std::remove(part.c_str());
    throw;
  }
  if (std::fclose(f) != 0 || std::rename(part.c_str(), path.c_str()) != 0) {
    std::remove(part.c_str());
    throw Error("cannot write " + path + ": " + std::strerror(errno));
  }
}
