// SPDX-License-Identifier: MIT
// tumble: simulate rigid bodies made of spheres, find contact pairs, benchmark the pipelines,
// and show, play back or render the animation.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "commands.hpp"
#include "tumble/config.hpp"
#include "tumble/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"tumble " TUMBLE_VERSION_STRING
               ": rigid bodies made of spheres, with sweep-and-prune collision detection along the PCA axis"};
  app.require_subcommand(1);
  app.set_version_flag("--version", TUMBLE_VERSION_STRING);
  tumble::cli::addRun(app);
  tumble::cli::addPairs(app);
  tumble::cli::addBench(app);
  tumble::cli::addValidate(app);
  tumble::cli::addView(app);
  tumble::cli::addPlay(app);
  tumble::cli::addRender(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : tumble::cli::kExitBadInput;
  } catch (const tumble::cli::Exit& e) {
    return e.status;
  } catch (const tumble::SimulationError& e) {
    std::fprintf(stderr, "tumble: %s\n", e.what());
    return tumble::cli::kExitDiverged;
  } catch (const tumble::Error& e) {
    std::fprintf(stderr, "tumble: %s\n", e.what());
    return tumble::cli::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tumble: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
