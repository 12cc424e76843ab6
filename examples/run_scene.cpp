// SPDX-License-Identifier: MIT
// run_scene: a scene file run from C++ with the run driver tumble::Run (docs/cpp.md): the scene's
// pours enter, the guard checks the state, and the outputs named on the command line are written
// at the steps tumble run writes them (not the scene's own [output] files, not --debug-record).
// Prints the kinetic energy ten times along the way.
//   run_scene SCENE.toml [--steps N] [--pipeline cpu|cuda|cuda-host] [--record FILE] [--thermo FILE.csv]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"

int main(int argc, char** argv) {
  std::string scenePath, pipeline = "cpu", record, thermo;
  long long steps = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--steps" && hasValue) {
      char* end = nullptr;
      steps = std::strtoll(argv[++i], &end, 10);
      if (*end != '\0' || steps < 1) {
        std::fprintf(stderr, "run_scene: --steps %s: expected a whole number of steps >= 1\n", argv[i]);
        return 2;
      }
    }
    else if (a == "--pipeline" && hasValue) pipeline = argv[++i];
    else if (a == "--record" && hasValue) record = argv[++i];
    else if (a == "--thermo" && hasValue) thermo = argv[++i];
    else if (scenePath.empty() && a.rfind("--", 0) != 0) scenePath = a;
    else {
      std::fprintf(stderr, "usage: run_scene SCENE.toml [--steps N] [--pipeline cpu|cuda|cuda-host] [--record FILE] "
                           "[--thermo FILE.csv]\n");
      return 2;
    }
  }
  if (scenePath.empty()) {
    std::fprintf(stderr, "run_scene: name a scene file (e.g. scenes/molecules.toml)\n");
    return 2;
  }
  try {
    const tumble::Scene scene = tumble::readSceneFile(scenePath, {});
    tumble::Run run(scene);  // the world at the start; [[pour]] bodies enter during advance()
    if (!run.timeStepWarning().empty()) std::fprintf(stderr, "run_scene: warning: %s\n", run.timeStepWarning().c_str());
    run.load(tumble::makePipeline(tumble::backendFromString(pipeline)));  // guard on, every 50 steps
    run.setEndStep(steps > 0 ? std::uint64_t(steps) : scene.steps);
    if (!record.empty()) {
      tumble::RecordSettings rs;
      rs.path = record;
      rs.stepsPerFrame = scene.stepsPerFrame;
      run.record(rs);
    }
    if (!thermo.empty()) run.writeThermo(thermo, scene.thermoEvery, scene.energyBalance);
    const std::uint64_t total = steps > 0 ? std::uint64_t(steps) : scene.steps;
    tumble::BodyState state;
    for (int k = 1; k <= 10; ++k) {
      run.advance(total * k / 10 - run.pipeline().stepCount());  // throws SimulationError if a guard trips
      run.pipeline().readState(state);
      std::printf("step %llu  t = %.4f s  %u bodies  kinetic energy %.6g J\n",
                  static_cast<unsigned long long>(run.pipeline().stepCount()), run.pipeline().time(),
                  run.world().numBodies(), tumble::kineticEnergy(run.world(), state));
    }
    run.closeOutputs();
  } catch (const tumble::SimulationError& e) {
    std::fprintf(stderr, "run_scene: stopped: %s\n", e.what());
    return 3;
  } catch (const tumble::Error& e) {
    std::fprintf(stderr, "run_scene: %s\n", e.what());
    return 2;
  }
  return 0;
}
