// SPDX-License-Identifier: MIT
// The run driver (tumble/run.hpp): what a run writes depends on the steps it takes, not on how a
// front end splits them into calls (tumble run takes one, the window one per frame, a Python
// script any), and the time series does not depend on which other outputs are on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"

using namespace tumble;

namespace {

// Balls dropped on the ground in a box, more poured from above every 50 steps, the swirl pull
// on: frames, rows, checks, checkpoints and pour batches all fall on different steps, and the
// guard's budget integrates the swirl's work between its checks.
const char* kPouredSwirl = R"(
[scene]
name = "poured swirl"
dt = 1e-4
steps = 400
seed = 11
[contact]
stiffness = 2e4
[ground]
[pulls]
swirl = 40
on = ["swirl"]
[[wall]]
type = "box"
min = [-0.2, -0.2, 0.0]
max = [0.2, 0.2, 0.6]
open = ["+z"]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.02
mass = 0.03
[[fill]]
shape = "ball"
count = 40
region = "box"
min = [-0.15, -0.15, 0.02]
max = [0.15, 0.15, 0.2]
[[pour]]
shapes = ["ball"]
count = 30
rate = 1000
region = "box"
min = [-0.1, -0.1, 0.35]
max = [0.1, 0.1, 0.45]
velocity = [0, 0, -0.5]
)";

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Files {
  std::string dir;
  Files() {
    char tmpl[] = "/tmp/tumble_run_test.XXXXXX";
    dir = mkdtemp(tmpl);
  }
  ~Files() { std::system(("rm -rf '" + dir + "'").c_str()); }
  std::string operator()(const std::string& name) const { return dir + "/" + name; }
};

// Runs kPouredSwirl `steps` steps in calls of the given sizes (cycled), with a recording every 7
// steps (when `record`), the time series every 30 steps and a checkpoint every 70; returns the
// bytes of each output.
struct Outputs {
  std::string recording, thermo, checkpoint;
};
Outputs runIn(const std::vector<std::uint64_t>& calls, std::uint64_t steps, bool record, bool guard, const Files& f,
              const std::string& tag) {
  const Scene scene = parseScene(kPouredSwirl, "poured-swirl.toml");
  Run run(scene);
  RunChecks checks;
  checks.stop = guard;
  checks.every = 25;
  run.load(makePipeline(Backend::Cpu), checks);
  if (record) {
    RecordSettings rs;
    rs.path = f(tag + ".bin");
    rs.stepsPerFrame = 7;
    run.record(rs);
  }
  run.writeThermo(f(tag + ".csv"), 30);
  run.checkpointEvery(f(tag + ".ck"), 70);
  std::uint64_t done = 0;
  for (std::size_t k = 0; done < steps; ++k) {
    const std::uint64_t n = std::min(calls[k % calls.size()], steps - done);
    EXPECT_EQ(run.advance(n).steps, n);
    done += n;
  }
  EXPECT_GT(run.world().numBodies(), 40u) << "the pour brought bodies in";
  run.closeOutputs();
  return Outputs{record ? slurp(f(tag + ".bin")) : "", slurp(f(tag + ".csv")), slurp(f(tag + ".ck"))};
}

}  // namespace

// One call of 400 steps, calls of one step, and calls of random sizes (the seed is printed)
// write the same bytes: frames, rows, checks and checkpoints fall on their steps whatever the
// calls, and the check at the end of a call (on a copy of the guard) changes nothing.
TEST(RunTest, OutputsDoNotDependOnHowTheStepsAreSplitIntoCalls) {
  const Files f;
  const std::uint64_t seed = 20261207;
  std::mt19937_64 rng(seed);
  std::vector<std::uint64_t> random;
  for (int k = 0; k < 64; ++k) random.push_back(1 + rng() % 60);
  const Outputs whole = runIn({400}, 400, true, true, f, "whole");
  ASSERT_GT(whole.recording.size(), 0u);
  ASSERT_GT(whole.thermo.size(), 0u);
  ASSERT_GT(whole.checkpoint.size(), 0u);
  for (const auto& [name, calls] : {std::pair<const char*, std::vector<std::uint64_t>>{"ones", {1}},
                                    {"random", random}, {"frames", {7}}}) {
    const Outputs split = runIn(calls, 400, true, true, f, name);
    EXPECT_TRUE(split.recording == whole.recording) << name << " (seed " << seed << ")";
    EXPECT_TRUE(split.thermo == whole.thermo) << name << " (seed " << seed << ")";
    EXPECT_TRUE(split.checkpoint == whole.checkpoint) << name << " (seed " << seed << ")";
  }
}

// Without the guard's stops, the guard still measures for the time series, at the series' own
// steps only: its rows (the swirl's work integrated between them) are the same with a recording
// on or off. With the guard on, its checks at every frame do change that integral.
TEST(RunTest, TheTimeSeriesDoesNotDependOnTheRecordingWithoutGuard) {
  const Files f;
  const Outputs recorded = runIn({400}, 400, true, false, f, "recorded");
  const Outputs plain = runIn({400}, 400, false, false, f, "plain");
  EXPECT_TRUE(recorded.thermo == plain.thermo);
  const Outputs guarded = runIn({400}, 400, true, true, f, "guarded");
  EXPECT_FALSE(guarded.thermo == plain.thermo) << "the guard's checks at every frame sample the swirl's work more often";
}

// No output of a run is written over a file the scene reads (issue 34, item 2): its own file or
// a mesh's. The run refuses before anything is written, whoever asks (the CLI checks first too).
TEST(RunTest, OutputsAreNeverWrittenOverTheScenesInputs) {
  const Files f;
  const std::string mesh = "v -1 -1 0\nv 2 -1 0\nv 2 2 0\nv -1 2 0\nf 1 2 3 4\n";
  std::ofstream(f("floor.obj")) << mesh;
  std::ofstream(f("meshed.toml")) << "[scene]\ndt = 1e-4\nsteps = 10\n[[wall]]\ntype = \"mesh\"\nfile = \"floor.obj\"\n"
                                     "[[shape]]\nname = \"ball\"\n[[shape.sphere]]\nradius = 0.1\nmass = 1.0\n"
                                     "[[body]]\nshape = \"ball\"\nposition = [0.5, 0.5, 0.3]\n";
  const Scene scene = readSceneFile(f("meshed.toml"));
  tumble::Run run(scene);  // (inside a TEST, plain Run is gtest's Test::Run)
  EXPECT_THROW(run.advance(1), Error) << "before load(): said, not a null pipeline";
  EXPECT_THROW(run.writeState(f("state.csv")), Error);
  run.load(makePipeline(Backend::Cpu));
  run.advance(5);
  RecordSettings rs;
  rs.path = f("floor.obj");
  EXPECT_THROW(run.record(rs), Error);
  EXPECT_THROW(run.writeThermo(f("floor.obj"), 10), Error);
  EXPECT_THROW(run.writeCheckpoint(f("floor.obj")), Error);
  EXPECT_THROW(run.checkpointEvery(f("meshed.toml"), 10), Error);
  try {
    run.writeState(f("./floor.obj"));
    ADD_FAILURE() << "the state file replaced the mesh";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the mesh of [[wall]] #1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(f("floor.obj")), mesh);
  run.writeState(f("state.csv"));  // any other file is written
  EXPECT_GT(slurp(f("state.csv")).size(), 0u);
}
