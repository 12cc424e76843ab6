// SPDX-License-Identifier: MIT
// tumble: simulate rigid bodies made of spheres, find contact pairs, benchmark the pipelines,
// and show, play back or render the animation.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "tumble/config.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/mpi/session.hpp"
#include "tumble/output_file.hpp"
#include "tumble/pipeline.hpp"

std::optional<std::uint64_t> tumble::cli::parseCount(const std::string& text, std::uint64_t lo, std::uint64_t hi) {
  if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos) return {};
  if (text.size() > 1 && text[0] == '0') return {};  // CLI11 would read a leading 0 as octal
  const std::uint64_t v = std::stoull(text);  // at most 19 digits: no overflow
  if (v < lo || v > hi) return {};
  return v;
}

CLI::Validator tumble::cli::countIn(std::uint64_t lo, std::uint64_t hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        return parseCount(s, lo, hi) ? std::string() : "expected a whole number from " + range + ", got '" + s + "'";
      },
      "INT " + range);
}

namespace {
std::string g_invokedAs = "tumble";
}

const std::string& tumble::cli::invokedAs() { return g_invokedAs; }

std::string tumble::cli::compiledPipelines() {
  std::string out;
  for (tumble::Backend b : tumble::compiledBackends()) out += std::string(out.empty() ? "" : ", ") + tumble::toString(b);
  return out;
}

CLI::Validator tumble::cli::pipelineName() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          tumble::backendFromString(s);
          return {};
        } catch (const tumble::Error& e) {
          return std::string(e.what()) + "; this build: " + compiledPipelines();
        }
      },
      "PIPELINE (this build: " + compiledPipelines() + ")");
}

CLI::Option* tumble::cli::addSetOption(CLI::App* command, std::vector<std::string>& sets, const std::string& note) {
  return command
      ->add_option("--set", sets,
                   "Override a scene key, SECTION.KEY=VALUE with VALUE in TOML (strings in quotes), e.g. --set "
                   "ground.friction=0.3 --set output.record='\"r.bin\"'; a key of an entry of [[wall]], "
                   "[[material]], [[group]] ... by its index from 0 or its name: --set 'wall[1].friction=0.1' "
                   "--set material.glass.friction=0.3; repeatable, the last of a key wins; checked as the file is "
                   "(docs/scenes.md)" + note)
      ->type_name("SECTION.KEY=VALUE")
      ->allow_extra_args(false);
}

void tumble::cli::refuseSameFile(const std::vector<NamedFile>& files) {
  for (std::size_t a = 0; a < files.size(); ++a)
    for (std::size_t b = a + 1; b < files.size(); ++b)
      if (!files[a].path.empty() && !files[b].path.empty() && sameFile(files[a].path, files[b].path))
        throw Error(std::string(files[a].option) + " " + files[a].path + " and " + files[b].option + " " + files[b].path +
                    " are the same file: one would overwrite the other; name two different files");
}

namespace {

// The subcommand named on the command line (the first argument that is not an option), or "".
std::string subcommandOf(int argc, char** argv) {
  for (int a = 1; a < argc; ++a)
    if (argv[a][0] != '-') return argv[a];
  return "";
}

// Levenshtein distance of two short strings.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// After "The following arguments were not expected": for each argument that looks like an option
// the subcommand does not have (--stesp), the nearest it has (--steps), when one is close.
void suggestOptions(const CLI::App& app, int argc, char** argv) {
  const std::vector<CLI::App*> subs = app.get_subcommands();
  const CLI::App& sub = subs.empty() ? app : *subs.front();
  std::vector<std::string> names;
  for (const CLI::Option* opt : sub.get_options())
    for (const std::string& n : opt->get_lnames()) names.push_back("--" + n);
  for (int a = 1; a < argc; ++a) {
    const std::string arg = std::string(argv[a]).substr(0, std::string(argv[a]).find('='));
    if (arg.rfind("--", 0) != 0 || std::find(names.begin(), names.end(), arg) != names.end()) continue;
    std::string best;
    std::size_t bestDistance = 3;  // at most two edits away, and less than half the name
    for (const std::string& n : names)
      if (const std::size_t d = editDistance(arg, n); d < bestDistance && 2 * d < n.size()) {
        best = n;
        bestDistance = d;
      }
    if (!best.empty()) std::fprintf(stderr, "tumble %s: unknown option %s; did you mean %s?\n", sub.get_name().c_str(),
                                    arg.c_str(), best.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 0 && std::string(argv[0]).find('/') != std::string::npos) g_invokedAs = argv[0];
  // Under mpirun MPI starts here (docs/mpi.md); only `run` runs on several ranks, every rank exits
  // with the same status, and only rank 0 prints.
  std::unique_ptr<tumble::mpi::Session> session;
  try {
    session = std::make_unique<tumble::mpi::Session>(&argc, &argv);
  } catch (const tumble::Error& e) {
    if (tumble::mpi::launchedRank() == 0) std::fprintf(stderr, "tumble: %s\n", e.what());
    return tumble::cli::kExitBadInput;
  }
  const bool prints = session->writes();
  if (session->size() > 1 && subcommandOf(argc, argv) != "run") {
    if (prints)
      std::fprintf(stderr, "tumble: under mpirun only `tumble run` runs (on %d ranks here); run `tumble %s` without "
                           "mpirun\n", session->size(), subcommandOf(argc, argv).c_str());
    return tumble::cli::kExitBadInput;
  }
  CLI::App app{"tumble " TUMBLE_VERSION_STRING
               ": rigid bodies made of spheres, with sweep-and-prune collision detection along the PCA axis"};
  app.require_subcommand(1);
  // The version, then the pipelines this build has and whether CUDA can run here (the CLI test
  // reads the last line to know what `--pipelines cpu,cuda` must do).
  app.set_version_flag("--version", [] {
    std::string v = "tumble " TUMBLE_VERSION_STRING "\npipelines:";
    for (tumble::Backend b : tumble::compiledBackends()) v += std::string(" ") + tumble::toString(b);
    v += " (cuda-host: the CUDA pipeline's code on the CPU, for testing; not a fast path)";
    const tumble::CudaStatus s = tumble::cudaStatus();
    const char* state = s.state == tumble::CudaState::Ready ? "ready" : s.state == tumble::CudaState::NoDevice
                                                                          ? "no device"
                                                                          : "broken";
    return v + "\ncuda: " + state + ": " + s.message;
  });
  tumble::cli::addRun(app);
  tumble::cli::addPairs(app);
  tumble::cli::addBench(app);
  tumble::cli::addValidate(app);
  tumble::cli::addView(app);
  tumble::cli::addPlay(app);
  tumble::cli::addRender(app);
  tumble::cli::addPlot(app);
  tumble::cli::addExport(app);
  tumble::cli::addRepair(app);
  tumble::cli::addClump(app);
  tumble::cli::addFields(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = prints ? app.exit(e) : e.get_exit_code();
    if (prints && dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) suggestOptions(app, argc, argv);
    return rc == 0 ? 0 : tumble::cli::kExitBadInput;
  } catch (const tumble::cli::Exit& e) {
    return e.status;
  } catch (const tumble::SimulationError& e) {
    if (prints) std::fprintf(stderr, "tumble: %s\n", e.what());
    return tumble::cli::kExitDiverged;
  } catch (const tumble::Error& e) {
    if (prints) std::fprintf(stderr, "tumble: %s\n", e.what());
    return tumble::cli::kExitBadInput;
  } catch (const std::exception& e) {
    if (prints) std::fprintf(stderr, "tumble: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
