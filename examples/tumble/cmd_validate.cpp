// SPDX-License-Identifier: MIT
// `tumble validate`: cross-validation of the compiled pipelines. Pair sets against the
// brute-force oracle on every hard case of SPEC §3 and on random clouds; then two pipelines
// stepped side by side from the same scene and compared after every step. With one pipeline,
// it is compared with itself at 1 thread against all threads (must be bitwise identical).
// With --out DIR (or --quick, --cases), it also runs the validation study (docs/validation.md):
// analytic physics and stability cases for every pipeline, written as report.md + CSV + PNG.
#include <algorithm>
#include <filesystem>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/validation/study.hpp"

namespace tumble::cli {
namespace {

struct ValidateOptions {
  std::vector<std::string> pipelines{"cpu"};
  std::string scene;
  std::vector<std::string> sets;
  std::uint64_t steps = 300;
  std::uint64_t seed = 20261122;
  int random = 20;
  validation::TrajectoryTolerance tol;
  // The study.
  std::string out;
  bool quick = false;
  bool list = false;
  std::vector<std::string> cases;
  std::string commandLine;
  bool study() const { return !out.empty() || quick || !cases.empty(); }
};

/// Runs the study (physics and stability catalogue) on `backends`; true when every check passes.
bool runStudy(const ValidateOptions& o, const std::vector<Backend>& backends) {
  namespace st = validation::study;
  st::StudyOptions so;
  so.depth = o.quick ? st::Depth::Quick : st::Depth::Full;
  so.outDir = o.out;
  so.caseIds = o.cases;
  so.seed = o.seed;
  so.progress = true;
  so.command = o.commandLine;
  st::StudyReport rep = st::runStudy(st::allCases(), backends, so);
  std::printf("\n## Validation study (%s, %zu cases, %.1f s)\n\n", o.quick ? "quick" : "full",
              rep.runs.size() / std::max<std::size_t>(1, backends.size()), rep.seconds);
  st::printSummary(rep, stdout);
  std::printf("\n- %zu of %zu checks within tolerance\n", rep.totalChecks() - rep.failedChecks(), rep.totalChecks());
  if (rep.notSupported() > 0)
    std::printf("- %zu case runs not run: their pipeline does not support the case's model yet (table above)\n",
                rep.notSupported());
  if (!o.out.empty()) {
    std::printf("- report: %s/report.md (CSV: summary.csv, <pipeline>/<case>_<table>.csv)\n", o.out.c_str());
    std::printf("- plots: %s\n", rep.plotsDrawn ? ("drawn by " + rep.plotNote).c_str() : rep.plotNote.c_str());
  }
  return rep.pass();
}

void validate(const ValidateOptions& o) {
  if (o.list) {
    for (const auto& c : validation::study::allCases()) std::printf("%s\n", c.id.c_str());
    return;
  }
  // Bad study input fails before any work: unknown case ids, an output folder that cannot be made.
  if (o.study()) {
    const auto all = validation::study::allCases();
    for (const auto& id : o.cases)
      if (std::none_of(all.begin(), all.end(), [&](const auto& c) { return c.id == id; }))
        throw Error("--cases: unknown case \"" + id + "\"; `tumble validate --list` lists them");
    if (!o.out.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(o.out, ec);
      if (ec || !std::filesystem::is_directory(o.out))
        throw Error("--out: cannot create folder " + o.out + (ec ? ": " + ec.message() : std::string()));
    }
  }
  std::vector<Backend> backends;
  for (const auto& p : o.pipelines) {
    const Backend b = backendFromString(p);
    requireBackend(b);
    backends.push_back(b);
  }
  // The scene of the side-by-side run, read (with its --set overrides) before any work.
  const Scene scene = readSceneFile(o.scene.empty() ? validation::sourcePath("scenes/molecules.toml") : o.scene, o.sets);
  const World world = World::fromScene(scene);
  bool ok = true;
  std::printf("## Pair sets against the brute-force oracle (seed %llu)\n\n| case | oracle pairs |",
              static_cast<unsigned long long>(o.seed));
  for (Backend b : backends) std::printf(" %s |", toString(b));
  std::printf("\n|---|---|");
  for (std::size_t k = 0; k < backends.size(); ++k) std::printf("---|");
  std::printf("\n");
  for (const auto& c : validation::comparePairSets(backends, o.seed, o.random)) {
    std::printf("| %s | %zu |", c.name.c_str(), c.oraclePairs);
    for (std::size_t k = 0; k < backends.size(); ++k) {
      std::printf(" %s |", c.matches[k] ? "identical" : ("DIFFERS: " + c.detail[k]).c_str());
      ok = ok && c.matches[k];
    }
    std::printf("\n");
  }

  std::unique_ptr<Pipeline> a, b;
  std::string what;
  if (backends.size() >= 2) {
    a = makePipeline(backends[0]);
    b = makePipeline(backends[1]);
    what = std::string(toString(backends[0])) + " vs " + toString(backends[1]);
  } else {
    PipelineOptions one;
    one.threads = 1;
    a = makePipeline(backends[0], one);
    b = makePipeline(backends[0]);
    what = std::string(toString(backends[0])) + " 1 thread vs all threads";
  }
  const auto r = validation::compareTrajectories(*a, *b, world, o.steps, o.tol);
  std::printf("\n## Trajectories side by side: %s, scene %s, %llu steps\n\n", what.c_str(), scene.name.c_str(),
              static_cast<unsigned long long>(r.steps));
  std::printf("- pair lists identical after every step: %s",
              r.pairsIdentical ? "yes\n" : ("no, first at step " + std::to_string(r.firstPairMismatchStep) + "\n").c_str());
  if (r.bitwiseIdentical) {
    std::printf("- body states bitwise identical after every step\n");
  } else {
    std::printf("- states first differ at step %llu, body %u\n", static_cast<unsigned long long>(r.firstDifferentStep),
                r.firstDifferentBody);
    std::printf("- within the first %llu steps: max |dX| = %.3g r_min, max |dq| = %.3g (tolerance %.3g r_min, %.3g)\n",
                static_cast<unsigned long long>(o.tol.horizon), r.maxPositionDev, r.maxOrientationDev,
                o.tol.positionTol, o.tol.orientationTol);
    if (!r.withinTolerance())
      std::printf("- OUT OF TOLERANCE first at step %llu, body %u\n",
                  static_cast<unsigned long long>(r.firstOutOfTolStep), r.firstOutOfTolBody);
  }
  // The same pipeline must be bitwise deterministic, and so must two pipelines built by one
  // compiler (cpu and cuda-host: the same operations in the same order, no FMA contraction);
  // against the GPU (nvcc) the states must stay in tolerance (docs/cuda.md).
  const bool bitwiseDue = backends.size() < 2 || (backends[0] != Backend::Cuda && backends[1] != Backend::Cuda) ||
                          backends[0] == backends[1];
  std::printf(bitwiseDue ? "- required: bitwise identical (one compiler)\n"
                          : "- required: within tolerance (the GPU's code is another compiler's)\n");
  ok = ok && r.pairsIdentical && (bitwiseDue ? r.bitwiseIdentical : r.withinTolerance());
  if (o.study()) ok = runStudy(o, backends) && ok;
  std::printf("\nvalidate: %s\n", ok ? "PASSED" : "FAILED");
  if (!ok) throw Exit{1};
}

}  // namespace

void addValidate(CLI::App& app) {
  auto o = std::make_shared<ValidateOptions>();
  CLI::App* c = app.add_subcommand(
      "validate",
      "Cross-validate the pipelines (pair sets against brute force, trajectories side by side) and, with --out, "
      "run the validation study (analytic physics, stability, speed against error) and write its report. "
      "Exit status: 0 all checks passed, 1 a check failed, 2 bad input.");
  c->add_option("--pipelines", o->pipelines, "Pipelines to compare, e.g. cpu,cuda or cpu,cuda-host")->delimiter(',')
      ->check(pipelineName());
  c->add_option("--scene", o->scene, "Scene for the side-by-side run (default scenes/molecules.toml)");
  addSetOption(c, o->sets, "; applies to the --scene (or the default) of the side-by-side run");
  c->add_option("--steps", o->steps, "Steps of the side-by-side run")->check(countIn(1, kMaxSteps));
  c->add_option("--seed", o->seed, "Seed of the random clouds and hard cases")
      ->check(countIn(0, 9999999999999999999ull));
  c->add_option("--random", o->random, "Number of random clouds")->check(CLI::NonNegativeNumber);
  c->add_option("--position-tol", o->tol.positionTol, "Position tolerance in units of the smallest radius");
  c->add_option("--orientation-tol", o->tol.orientationTol, "Orientation tolerance |dq|");
  c->add_option("--horizon", o->tol.horizon, "Steps over which the tolerance must hold")
      ->check(countIn(1, kMaxSteps));
  c->add_option("--out", o->out,
                 "Run the validation study and write DIR/report.md, DIR/summary.csv, DIR/<pipeline>/*.csv and *.png "
                 "(the folder is created)");
  c->add_flag("--quick", o->quick, "Study at quick depth (the ctest version: few dt values, short horizons)");
  c->add_option("--cases", o->cases, "Run only these study cases, e.g. ground_restitution,slope (see --list)")
      ->delimiter(',');
  c->add_flag("--list", o->list, "List the study's case ids and exit");
  c->callback([o] {
    std::ostringstream cmd;
    cmd << "tumble validate --pipelines ";
    for (std::size_t k = 0; k < o->pipelines.size(); ++k) cmd << (k ? "," : "") << o->pipelines[k];
    if (o->quick) cmd << " --quick";
    if (!o->cases.empty()) {
      cmd << " --cases ";
      for (std::size_t k = 0; k < o->cases.size(); ++k) cmd << (k ? "," : "") << o->cases[k];
    }
    if (!o->out.empty()) cmd << " --out " << o->out;
    o->commandLine = cmd.str();
    validate(*o);
  });
}

}  // namespace tumble::cli
