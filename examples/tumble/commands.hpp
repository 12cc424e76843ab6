// SPDX-License-Identifier: MIT
// The subcommands of the `tumble` program.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tumble::cli {

/// Exit status for bad input (missing file, malformed TOML or CSV, bad values).
inline constexpr int kExitBadInput = 2;
/// Exit status when a run stops because the simulation diverged.
inline constexpr int kExitDiverged = 3;

void addRun(CLI::App& app);
void addPairs(CLI::App& app);
void addBench(CLI::App& app);
void addValidate(CLI::App& app);
void addView(CLI::App& app);
void addPlay(CLI::App& app);
void addRender(CLI::App& app);
void addPlot(CLI::App& app);
void addExport(CLI::App& app);
void addRepair(CLI::App& app);
void addClump(CLI::App& app);
void addFields(CLI::App& app);

/// Debian packages the viewer (view, play, render) needs at build time.
inline constexpr const char* kViewerPackages =
    "libglfw3-dev libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libimgui-dev libpng-dev";

/// Writes a file atomically (tumble/output_file.hpp): `write` fills a temporary next to the
/// target, which is then renamed over it (a device or FIFO is written directly). On any failure
/// the temporary is removed and tumble::Error is thrown.
template <class F>
void writeAtomically(const std::string& path, F&& write);

/// Thrown by subcommands to end with a given status after printing `what()`.
struct Exit {
  int status;
};

/// For view, play and render in a build without the viewer: prints how to get it and ends
/// with status 2.
[[noreturn]] void viewerMissing(const char* command);

/// Parses "WxH" (each 16 to 8192); throws tumble::Error naming `option` otherwise.
void parseSize(const std::string& text, const char* option, int& outW, int& outH);

/// --background and --ground of view, play and render (addLookOptions), parsed by
/// viewer::parseLook before any work and applied by viewer::applyLook (draw_data.hpp).
struct LookOptions {
  std::string background = "default";
  std::string ground = "on";
};
/// Adds --background and --ground to a viewer command.
void addLookOptions(CLI::App* command, LookOptions& look);

/// --from and --to of play and render: frames of a recording, both included, negative counting
/// from the end (the default, 0 to -1, is every frame).
struct FrameRangeOptions {
  long from = 0, to = -1;
};
/// Adds --from and --to; `note` ends --from's help (what the range changes besides the frames).
/// Returns the two options (render makes them exclude --still).
std::pair<CLI::Option*, CLI::Option*> addFrameRangeOptions(CLI::App* command, FrameRangeOptions& range,
                                                           const std::string& note);
/// The index of frame `n` of a recording of `numFrames` frames (negative counts from the end);
/// throws tumble::Error naming `option`, the value and the frames `file` has.
std::size_t frameIndex(long n, const char* option, std::size_t numFrames, const std::string& file);
/// The first and last frame --from and --to select; throws tumble::Error as frameIndex does and
/// when the first comes after the last.
std::pair<std::size_t, std::size_t> frameRange(const FrameRangeOptions& range, std::size_t numFrames,
                                               const std::string& file);

/// The most steps a run accepts (10^15: decades at a microsecond per step).
inline constexpr std::uint64_t kMaxSteps = 1000000000000000ull;

/// A whole number written with digits only (no sign: "-1" must not wrap to 2^64 − 1; no leading
/// zero, which CLI11 reads as octal), from lo to hi; nothing when the text is not one.
std::optional<std::uint64_t> parseCount(const std::string& text, std::uint64_t lo, std::uint64_t hi);

/// The CLI11 check of a count option: parseCount(text, lo, hi) must succeed.
CLI::Validator countIn(std::uint64_t lo, std::uint64_t hi);

/// The command as the user can type it again: argv[0] when it names a path ("build/examples/tumble",
/// "./tumble"), else "tumble" (found on PATH). For the tips a command prints.
const std::string& invokedAs();

/// The pipelines this build has (compiledBackends(): "cpu, cuda-host" or "cpu, cuda, cuda-host").
std::string compiledPipelines();

/// The CLI11 check of a --pipeline value: a pipeline name (backendFromString). A pipeline this
/// build or machine cannot run passes the check and is refused when the command asks for it,
/// saying why (requireBackend()). The type name lists the pipelines this build has.
CLI::Validator pipelineName();

/// Adds `--set SECTION.KEY=VALUE` (repeatable, one override per --set) to a command that reads
/// scene files: the overrides are passed to readSceneFile (tumble/scene_io.hpp). `note` ends the
/// help text.
CLI::Option* addSetOption(CLI::App* command, std::vector<std::string>& sets, const std::string& note);

/// One file a command reads or writes: the option that names it ("--record") and the path.
struct NamedFile {
  const char* option;
  std::string path;
};

/// Throws tumble::Error when two of `files` (empty paths skipped) are the same regular file, or
/// would become it (the same path, links followed, that does not exist yet): one output would
/// overwrite the other, or an input. Devices and FIFOs may be shared (--record /dev/null).
void refuseSameFile(const std::vector<NamedFile>& files);

}  // namespace tumble::cli

#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

template <class F>
void tumble::cli::writeAtomically(const std::string& path, F&& write) {
  OutputFile out(path);
  write(out.file());  // an exception abandons the temporary
  out.commit();
}
