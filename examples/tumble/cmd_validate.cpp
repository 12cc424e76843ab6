// SPDX-License-Identifier: MIT
// `tumble validate`: cross-validation of the compiled pipelines. Pair sets against the
// brute-force oracle on every hard case of SPEC §3 and on random clouds; then two pipelines
// stepped side by side from the same scene and compared after every step. With one pipeline,
// it is compared with itself at 1 thread against all threads (must be bitwise identical).
#include <memory>

#include "commands.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

namespace tumble::cli {
namespace {

struct ValidateOptions {
  std::vector<std::string> pipelines{"cpu"};
  std::string scene;
  std::uint64_t steps = 300;
  std::uint64_t seed = 20261122;
  int random = 20;
  validation::TrajectoryTolerance tol;
};

void validate(const ValidateOptions& o) {
  std::vector<Backend> backends;
  for (const auto& p : o.pipelines) {
    const Backend b = backendFromString(p);
    if (b == Backend::Cuda && !cudaAvailable())
      throw Error("--pipelines cuda: this build of tumble has no CUDA pipeline or no CUDA device");
    backends.push_back(b);
  }
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

  const Scene scene = readSceneFile(o.scene.empty() ? validation::sourcePath("scenes/molecules.toml") : o.scene);
  const World world = World::fromScene(scene);
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
  // The same pipeline must be bitwise deterministic; different pipelines must stay in tolerance.
  const bool sameKind = backends.size() < 2 || backends[0] == backends[1];
  ok = ok && r.pairsIdentical && (sameKind ? r.bitwiseIdentical : r.withinTolerance());
  std::printf("\nvalidate: %s\n", ok ? "PASSED" : "FAILED");
  if (!ok) throw Exit{1};
}

}  // namespace

void addValidate(CLI::App& app) {
  auto o = std::make_shared<ValidateOptions>();
  CLI::App* c = app.add_subcommand("validate", "Cross-validate the pipelines: pair sets against brute force, trajectories side by side");
  c->add_option("--pipelines", o->pipelines, "Pipelines to compare, e.g. cpu,cuda")->delimiter(',')
      ->check(CLI::IsMember({"cpu", "cuda"}));
  c->add_option("--scene", o->scene, "Scene for the side-by-side run (default scenes/molecules.toml)");
  c->add_option("--steps", o->steps, "Steps of the side-by-side run")->check(CLI::PositiveNumber);
  c->add_option("--seed", o->seed, "Seed of the random clouds and hard cases");
  c->add_option("--random", o->random, "Number of random clouds")->check(CLI::NonNegativeNumber);
  c->add_option("--position-tol", o->tol.positionTol, "Position tolerance in units of the smallest radius");
  c->add_option("--orientation-tol", o->tol.orientationTol, "Orientation tolerance |dq|");
  c->add_option("--horizon", o->tol.horizon, "Steps over which the tolerance must hold");
  c->callback([o] { validate(*o); });
}

}  // namespace tumble::cli
