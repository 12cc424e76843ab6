// SPDX-License-Identifier: MIT
// CPU ≡ CUDA step by step: the CPU pipeline and the CUDA pipeline stepped side by side on
// molecules, spheres, bench-16k, a pour and every other scene of scenes/ (the bench-128k and
// bench-960k aside) for 1000 steps (and a dense cluster for 200), under the report's law and the
// laws with history, with walls, meshes and periodic boundaries, comparing after every step the pair
// lists, every bit of the body state and contact-list state (the contacts and their histories),
// and the debug velocities and forces; a failure names the first differing step, quantity and
// body or particle. Each runs on every backend of the CUDA pipeline: cuda-host (its code on the
// host backend, in every build and every CI run) and cuda (on a GPU). The comparison itself is
// checked on the CPU (StepDifferenceTest): it finds nothing between two CPU runs that must agree,
// and names the first difference of two that must not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "tumble/config.hpp"
#include "tumble/factory.hpp"
#include "tumble/pour.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

World sceneWorld(const char* file) { return World::fromScene(readSceneFile(sourcePath(file))); }

// Balls and dimers poured onto the ground under the report's law, a batch every 50 steps
// (interval 0.005 s): the world grows and both pipelines are loaded afresh with it.
const char* kPour = R"(
[scene]
dt = 1e-4
steps = 1000
seed = 7
[ground]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.01
mass = 0.0105
[[shape]]
name = "dimer"
[[shape.sphere]]
radius = 0.01
offset = [-0.006, 0, 0]
mass = 0.0105
[[shape.sphere]]
radius = 0.01
offset = [0.006, 0, 0]
mass = 0.0105
[[fill]]
shape = "dimer"
count = 40
region = "box"
min = [-0.1, -0.1, 0.0]
max = [0.1, 0.1, 0.05]
[[pour]]
shapes = ["ball", "dimer"]
count = 100
rate = 1500
interval = 0.005
region = "box"
min = [-0.08, -0.08, 0.08]
max = [0.08, 0.08, 0.3]
velocity = [0, 0, -1]
scale = [0.8, 1.2]
)";

// A jittered 12 × 12 × 12 lattice of spheres that overlap their neighbours (spacing 1.8 r), no
// gravity: every particle is in contact from the first step on, so that a row, a record or an
// offset lost at any index shows (the last particle of the internal order included, which in
// the scenes above may touch nothing).
// `cohesion`: under hooke-history dmt (γ 10 J/m^2: 3 N of pull-off against some 20 N of spring),
// under hertz-mindlin sjkr (k_c 1e4 and 2e4 J/m^3 for the two materials, 1.4e4 between them).
World denseCluster(ContactLaw law = ContactLaw::Report, Cohesion cohesion = Cohesion::None) {
  Scene s;
  s.gravity = {0.0f, 0.0f, 0.0f};
  s.dt = 1e-3f;
  s.contact = {1e3f, 0.5f, 0.2f};
  s.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
  Rng rng(2026);
  for (int i = 0; i < 12 * 12 * 12; ++i) {
    BodyDef b;
    b.position = {0.18f * float(i % 12) + rng.uniform(-0.01f, 0.01f),
                  0.18f * float(i / 12 % 12) + rng.uniform(-0.01f, 0.01f),
                  0.18f * float(i / 144) + rng.uniform(-0.01f, 0.01f)};
    s.bodies.push_back(b);
  }
  if (law == ContactLaw::HookeHistory) {
    s = withHookeHistory(s);
    s.contact.rollingFriction = 0.05f;  // rolling resistance between the spheres and on the ground
  }
  if (law == ContactLaw::HertzMindlin) {  // every other sphere of the second material
    s.shapes.push_back(s.shapes[0]);
    for (std::size_t k = 1; k < s.bodies.size(); k += 2) s.bodies[k].shape = 1;
    s = withHertzMindlin(s, 1.0e6f, true);
    SphereDef& b = s.shapes[1].spheres[0];
    b.material = 1;
    b.elasticity = s.materials[1].restitution;
  }
  s.contact.cohesion = cohesion;
  s.contact.cohesionValue = 10.0f;
  // (jkr: γ [J/m²], necks of about 1 mm at R* 5 cm, rest overlaps of 3 % of R*; sjkr: k_c [J/m³])
  const bool jkr = cohesion == Cohesion::Jkr;
  for (std::size_t k = 0; k < s.materials.size(); ++k) s.materials[k].cohesion = k == 0 ? (jkr ? 50.0f : 1e4f) : (jkr ? 100.0f : 2e4f);
  return World::fromScene(s);
}

// Steps of each wall scene (WallsStepByStep).
constexpr std::uint64_t kWallSteps = 1000;

class CudaEqualsCpu : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
    if (GetParam() == Backend::Cuda && !TUMBLE_STRICT_FP)
      GTEST_SKIP() << "TUMBLE_STRICT_FP=OFF: nvcc may contract multiply-adds, so CPU and CUDA "
                      "agree within tolerance only (tumble validate checks that)";
  }

  // Returns the number of bodies at the end (the pours add some).
  // debug: the debug capture compared too.
  std::size_t expectEqual(const World& w, std::uint64_t steps, const char* what, const Pouring* pouring = nullptr,
                          bool debug = true) {
    auto cpu = makePipeline(Backend::Cpu);
    auto cuda = makePipeline(GetParam());
    const auto d = firstStepDifference(*cpu, w, *cuda, w, steps, debug, pouring);
    EXPECT_FALSE(d) << what << ", CPU against " << toString(GetParam()) << ": " << d->what;
    BodyState s;
    cpu->readState(s);
    return s.size();
  }

  // A resume: the CPU's state after `before` steps (with its histories) loaded into a CPU and a
  // CUDA pipeline; their states before any step, then `after` steps side by side.
  // meshSprings: the state must hold mesh springs too.
  void expectResumeEqual(const World& w, std::uint64_t before, std::uint64_t after, const char* what,
                         bool meshSprings = false) {
    auto first = makePipeline(Backend::Cpu);
    first->load(w);
    first->step(before);
    World resumed = w;
    first->readState(resumed.state);
    resumed.time = first->time();
    resumed.step = first->stepCount();
    std::printf("%s: resumed after %llu steps with %zu contact histories and %zu mesh springs\n", what,
                static_cast<unsigned long long>(before), resumed.state.contacts.size(),
                resumed.state.meshContacts.size());
    ASSERT_FALSE(resumed.state.contacts.empty()) << what << ": no history to resume";
    if (meshSprings) {
      ASSERT_FALSE(resumed.state.meshContacts.empty()) << what << ": no mesh spring to resume";
    }
    auto cpu = makePipeline(Backend::Cpu);
    auto cuda = makePipeline(GetParam());
    cpu->load(resumed);
    cuda->load(resumed);
    BodyState a, b;
    cpu->readState(a);
    cuda->readState(b);
    const auto loaded = firstDifference(a, b);
    EXPECT_FALSE(loaded) << what << ", resumed, before its first step: " << loaded->describe();
    EXPECT_EQ(b.contacts.size(), resumed.state.contacts.size()) << what;
    EXPECT_EQ(b.meshContacts.size(), resumed.state.meshContacts.size()) << what;
    const auto d = firstStepDifference(*cpu, resumed, *cuda, resumed, after, /*debug=*/true);
    EXPECT_FALSE(d) << what << ", resumed, CPU against " << toString(GetParam()) << ": " << d->what;
  }
};

}  // namespace

TEST(StepDifferenceTest, NoneBetweenRunsThatMustAgree) {
  PipelineOptions one, two;
  one.threads = 1;
  two.threads = 2;
  two.reorder = false;
  auto a = makePipeline(Backend::Cpu, one);
  auto b = makePipeline(Backend::Cpu, two);
  const World w = sceneWorld("scenes/molecules.toml");
  const auto d = firstStepDifference(*a, w, *b, w, 60, /*debug=*/true);
  EXPECT_FALSE(d) << d->what;
}

TEST(StepDifferenceTest, NamesTheFirstDifference) {
  const World w = sceneWorld("scenes/molecules.toml");
  World nudged = w;
  nudged.state.vx[5] += 1e-3f;
  auto a = makePipeline(Backend::Cpu);
  auto b = makePipeline(Backend::Cpu);
  const auto e = firstStepDifference(*a, w, *b, nudged, 60, /*debug=*/true);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->step, 1u);
  EXPECT_NE(e->what.find("of body 5:"), std::string::npos) << e->what;
}

TEST_P(CudaEqualsCpu, MoleculesStepByStep) { expectEqual(sceneWorld("scenes/molecules.toml"), 1000, "molecules"); }

TEST_P(CudaEqualsCpu, SpheresStepByStep) { expectEqual(sceneWorld("scenes/spheres.toml"), 1000, "spheres"); }

TEST_P(CudaEqualsCpu, Bench16kStepByStep) { expectEqual(sceneWorld("scenes/bench-16k.toml"), 1000, "bench-16k"); }

TEST_P(CudaEqualsCpu, DenseClusterStepByStep) { expectEqual(denseCluster(), 200, "dense cluster"); }

// The laws with a tangential history per contact (the histories compared after every step with
// the state): molecules' clumps falling onto the ground and into each other, and the dense
// cluster's single spheres (which rotate under these laws; hooke-history with rolling
// resistance), where every particle carries histories from the first step and each rebuild must
// carry them all across; hertz-mindlin with two materials (a per-pair table, rolling resistance
// between some pairs: withHertzMindlin). Then a resume: the CPU's state after 150 steps of the
// dense cluster, histories and all, loaded into both, read out before any step (the CUDA
// pipeline's from the rows it keeps for its first rebuild) and stepped 50 more.
TEST_P(CudaEqualsCpu, HookeHistoryStepByStep) {
  expectEqual(World::fromScene(withHookeHistory(readSceneFile(sourcePath("scenes/molecules.toml")))), 1000,
              "molecules, hooke-history");
  expectEqual(denseCluster(ContactLaw::HookeHistory), 200, "dense cluster, hooke-history");
  expectResumeEqual(denseCluster(ContactLaw::HookeHistory), 150, 50, "dense cluster, hooke-history");
}

TEST_P(CudaEqualsCpu, HertzMindlinStepByStep) {
  expectEqual(World::fromScene(withHertzMindlin(readSceneFile(sourcePath("scenes/molecules.toml")), 1.0e6f, true)),
              1000, "molecules, hertz-mindlin");
  expectEqual(denseCluster(ContactLaw::HertzMindlin), 200, "dense cluster, hertz-mindlin");
  expectResumeEqual(denseCluster(ContactLaw::HertzMindlin), 150, 50, "dense cluster, hertz-mindlin");
}

// Cohesion on the dense cluster (every particle in contact from the first step): dmt under
// hooke-history, sjkr and jkr under hertz-mindlin with two materials; and across a resume. Under
// jkr the compressed cluster springs apart through its necks, which stretch and break (their
// marks carried by the springs, across the rebuilds and the resume).
TEST_P(CudaEqualsCpu, CohesionStepByStep) {
  expectEqual(denseCluster(ContactLaw::HookeHistory, Cohesion::Dmt), 200, "dense cluster, hooke-history + dmt");
  expectEqual(denseCluster(ContactLaw::HertzMindlin, Cohesion::Sjkr), 200, "dense cluster, hertz-mindlin + sjkr");
  expectResumeEqual(denseCluster(ContactLaw::HertzMindlin, Cohesion::Sjkr), 150, 50, "dense cluster, hertz-mindlin + sjkr");
  const World jkr = denseCluster(ContactLaw::HertzMindlin, Cohesion::Jkr);
  expectEqual(jkr, 200, "dense cluster, hertz-mindlin + jkr");
  expectResumeEqual(jkr, 150, 50, "dense cluster, hertz-mindlin + jkr");
  auto necks = makePipeline(Backend::Cpu);  // the comparison met necks: their energy moved
  necks->load(jkr);
  necks->setEnergyTally(true);
  necks->step(200);
  std::printf("dense cluster, jkr: %.4g J into necks in 200 steps\n", necks->stats().energy.cohesion);
  EXPECT_GT(necks->stats().energy.cohesion, 0.0);
}

// The heaps of scenes/ as they are: heap (hooke-history, rolling resistance) and heap-hertz
// (hertz-mindlin, materials), each column collapsing onto the ground.
TEST_P(CudaEqualsCpu, HeapsStepByStep) {
  expectEqual(sceneWorld("scenes/heap.toml"), 1000, "heap");
  expectEqual(sceneWorld("scenes/heap-hertz.toml"), 1000, "heap-hertz");
}

// One CUDA pipeline loaded with one world after another (as a run's pours and resumes do): the
// dense cluster under hertz-mindlin (a material column), then the larger molecules under
// hooke-history with two materials that give density only (no column there): nothing of the
// first world may be read in the second.
TEST_P(CudaEqualsCpu, ReloadAcrossLaws) {
  auto cpu = makePipeline(Backend::Cpu);
  auto cuda = makePipeline(GetParam());
  const World first = denseCluster(ContactLaw::HertzMindlin);
  cuda->load(first);
  cuda->step(20);
  const World w =
      World::fromScene(withHookeHistory(withHertzMindlin(readSceneFile(sourcePath("scenes/molecules.toml")), 1.0e6f, true)));
  ASSERT_EQ(w.params.materials.size(), 2u);
  ASSERT_TRUE(w.material.empty());  // density only under hooke-history
  ASSERT_GT(w.numParticles(), first.numParticles());
  const auto d = firstStepDifference(*cpu, w, *cuda, w, 300, /*debug=*/true);
  EXPECT_FALSE(d) << "molecules after the dense cluster, CPU against " << toString(GetParam()) << ": " << d->what;
}

// Walls: the drum's turning cylinder and end disks, the hopper's cone and cylinder, the box,
// the silo's cylinder and ring, and the triangle meshes of hopper-mesh (standing) and drum-mesh
// (turning), under their scenes' hooke-history, the turning walls turning from the first step
// and every body thrown down at 3 m/s onto the walls below it; then the silo with its ring
// rising at 0.3 m/s from step 200 to step 700 (a wall that moves along, starts and stops), and
// the box under hertz-mindlin (two materials) and under the report's law. Each run prints the
// tangential springs loaded per wall at its end (a plane's or a mesh's) and must have loaded
// some, so that the comparison covered wall contacts.
TEST_P(CudaEqualsCpu, WallsStepByStep) {
  const auto thrown = thrownAtWalls;
  // debug: the debug capture compared too (then the CPU goes particle by particle); without it,
  // under the report's law, the CPU's body batch (bodyForces) is what the CUDA pipeline meets.
  const auto run = [&](const Scene& s, const std::string& what, bool debug = true) {
    const World w = World::fromScene(s);
    auto cpu = makePipeline(Backend::Cpu);
    auto cuda = makePipeline(GetParam());
    const auto d = firstStepDifference(*cpu, w, *cuda, w, kWallSteps, debug);
    EXPECT_FALSE(d) << what << ", CPU against " << toString(GetParam()) << ": " << d->what;
    BodyState st;
    cpu->readLocalState(st);
    const std::size_t n = w.numParticles();
    std::string perWall;
    std::size_t loaded = st.meshContacts.size();  // the non-zero mesh springs
    for (std::size_t k = w.params.ground.enabled ? 1 : 0; n > 0 && k < st.groundSpringX.size() / n; ++k) {
      std::size_t c = 0;  // plane k's springs (plane-major, the ground first)
      for (std::size_t i = k * n; i < (k + 1) * n; ++i)
        c += st.groundSpringX[i] != 0.0f || st.groundSpringY[i] != 0.0f ? 1u : 0u;
      perWall += ' ';  // (not " " + …: GCC 12 warns falsely, -Wrestrict)
      perWall += std::to_string(c);
      loaded += c;
    }
    std::printf("%s: springs loaded after %llu steps: planes%s, mesh %zu\n", what.c_str(),
                static_cast<unsigned long long>(kWallSteps), perWall.c_str(), st.meshContacts.size());
    EXPECT_GT(loaded, 0u) << what << ": no wall contact in " << kWallSteps << " steps";
  };
  for (const char* file : {"scenes/drum.toml", "scenes/hopper.toml", "scenes/box.toml", "scenes/silo.toml",
                           "scenes/hopper-mesh.toml", "scenes/drum-mesh.toml"})
    run(thrown(file), file);
  // Wall `wall` of `file` rising at 0.3 m/s from step 200 to step 700.
  const auto rising = [&](const char* file, std::size_t wall) {
    Scene s = thrown(file);
    WallDef& w = s.walls.at(wall);
    w.velocity = {0.0f, 0.0f, 0.3f};
    w.start = 200.0 * double(s.dt);
    w.stop = 700.0 * double(s.dt);
    return s;
  };
  run(rising("scenes/silo.toml", 1), "silo, the ring rising from step 200 to 700");
  run(rising("scenes/hopper-mesh.toml", 0), "hopper-mesh, the mesh rising from step 200 to 700");
  for (const char* file : {"scenes/box.toml", "scenes/drum-mesh.toml"}) {
    run(withHertzMindlin(thrown(file), 1.0e6f, true), std::string(file) + ", hertz-mindlin");
    Scene report = thrown(file);
    report.contact.law = ContactLaw::Report;
    run(report, std::string(file) + ", the report's law, no debug capture", /*debug=*/false);
  }
}

// A resume with mesh springs: drum-mesh's state after 600 steps (its bodies against the turning
// mesh), loaded into both, read out before the first step, then 100 steps. And one CUDA pipeline
// loaded with one wall scene after another (a turning mesh, a standing one, planes only), each
// against a fresh CPU pipeline: nothing of a scene's walls may remain in the next.
TEST_P(CudaEqualsCpu, WallsAcrossLoads) {
  expectResumeEqual(World::fromScene(thrownAtWalls("scenes/drum-mesh.toml")), 600, 100, "drum-mesh", /*meshSprings=*/true);
  auto cuda = makePipeline(GetParam());
  for (const char* file : {"scenes/drum-mesh.toml", "scenes/hopper-mesh.toml", "scenes/box.toml"}) {
    const World w = World::fromScene(thrownAtWalls(file));
    auto cpu = makePipeline(Backend::Cpu);
    const auto d = firstStepDifference(*cpu, w, *cuda, w, 300, /*debug=*/true);
    EXPECT_FALSE(d) << file << " after the one before in the same pipeline, CPU against " << toString(GetParam())
                    << ": " << d->what;
  }
}

TEST_P(CudaEqualsCpu, PourStepByStep) {
  const Scene s = parseScene(kPour, "pour (cuda_equals_cpu_test.cpp)");
  const Pouring pouring(s);
  const World w = pouring.worldWith(pouring.initialBodies());
  // Every poured body must have entered within the 1000 steps (else the test saw less of it).
  EXPECT_EQ(expectEqual(w, 1000, "pour", &pouring), pouring.finalBodies());
}

// The scenes of scenes/ as they are (their walls starting when the scenes say, the hopper-mesh's
// [[fill]], the periodic chute), 1000 steps each; the molecules, spheres, bench-16k and the heaps
// are compared above, the larger bench scenes below.
TEST_P(CudaEqualsCpu, ScenesAsTheyAreStepByStep) {
  for (const char* file : {"scenes/box.toml", "scenes/drum.toml", "scenes/silo.toml", "scenes/hopper.toml",
                           "scenes/hopper-mesh.toml", "scenes/drum-mesh.toml", "scenes/chute.toml"})
    expectEqual(sceneWorld(file), 1000, file);
}

// The bench scenes (clumps of the peers' benchmark, as bench-16k above): bench-128k step by
// step for 1000 steps (the debug capture aside: 128 000 particles' forces per step), and
// bench-960k's state after 1000 steps, taken in one call each (the CUDA pipeline's batches),
// with its pair list (its clumps touch from about step 400). Under the sanitizers (10 to 50
// times slower) 200 and 20 steps: the code paths, not the collisions.
TEST_P(CudaEqualsCpu, BenchScenes) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  constexpr std::uint64_t kSteps128k = 200, kSteps = 20;
#else
  constexpr std::uint64_t kSteps128k = 1000, kSteps = 1000;
#endif
  expectEqual(sceneWorld("scenes/bench-128k.toml"), kSteps128k, "bench-128k", nullptr, /*debug=*/false);
  const World w = sceneWorld("scenes/bench-960k.toml");
  auto cpu = makePipeline(Backend::Cpu);
  auto cuda = makePipeline(GetParam());
  cpu->load(w);
  cuda->load(w);
  cpu->step(kSteps);
  cuda->step(kSteps);
  BodyState a, b;
  cpu->readState(a);
  cuda->readState(b);
  const auto d = firstDifference(a, b);
  EXPECT_FALSE(d) << "bench-960k after " << kSteps << " steps, CPU against " << toString(GetParam()) << ": "
                  << d->describe();
  const std::vector<Pair> pairs = cpu->pairs();
  EXPECT_EQ(cuda->pairs(), pairs) << "bench-960k";
  if (kSteps == 1000) {
    EXPECT_GT(pairs.size(), 100000u) << "bench-960k: its clumps must touch";
  }
  std::printf("bench-960k: %llu steps, %zu contacts at the end\n", static_cast<unsigned long long>(kSteps),
              pairs.size());
}

// Periodic boundaries (the ghost images of the detection, minimum images in the forces, bodies
// wrapped into the box): the chute under the report's law (its plates are clumps) and
// hertz-mindlin, and the molecules' clumps in a box periodic on x and y, thrown sideways so that
// they cross it and meet across its boundaries; then a resume of the chute with its histories.
TEST_P(CudaEqualsCpu, PeriodicStepByStep) {
  Scene chute = readSceneFile(sourcePath("scenes/chute.toml"));
  Scene report = chute;
  report.contact.law = ContactLaw::Report;
  expectEqual(World::fromScene(report), 500, "chute, the report's law");
  expectEqual(World::fromScene(withHertzMindlin(chute, 1.0e6f, true)), 500, "chute, hertz-mindlin");
  Scene m = readSceneFile(sourcePath("scenes/molecules.toml"));
  m.pulls.active = 0;
  Vec3f lo{1e30f, 1e30f, 0.0f}, hi{-1e30f, -1e30f, 0.0f};
  for (const BodyDef& b : m.bodies) {
    lo = {std::min(lo.x, b.position.x), std::min(lo.y, b.position.y), 0.0f};
    hi = {std::max(hi.x, b.position.x), std::max(hi.y, b.position.y), 0.0f};
  }
  ASSERT_FALSE(m.bodies.empty());
  for (int a = 0; a < 2; ++a) {
    m.periodic.on[a] = true;
    m.periodic.lo[a] = (a == 0 ? lo.x : lo.y) - 0.3f;
    m.periodic.hi[a] = (a == 0 ? hi.x : hi.y) + 0.3f;
  }
  Rng rng(20261206);
  for (BodyDef& b : m.bodies) b.velocity = {rng.uniform(-4.0f, 4.0f), rng.uniform(-4.0f, 4.0f), b.velocity.z};
  const World w = World::fromScene(m);
  expectEqual(w, 1000, "molecules, periodic on x and y");
  auto cpu = makePipeline(Backend::Cpu);
  cpu->load(w);
  cpu->step(1000);
  BodyState st;
  cpu->readState(st);
  int crossings = 0;
  for (const auto* c : {&st.imageX, &st.imageY})
    for (std::int32_t k : *c) crossings += std::abs(k);
  std::printf("molecules, periodic on x and y: %d crossings in 1000 steps\n", crossings);
  EXPECT_GT(crossings, 20) << "the bodies must cross the boundaries";
  expectResumeEqual(World::fromScene(chute), 600, 200, "chute");
}

// step(n) runs its steps in batches with no host round trip between them (CudaPipeline::
// stepBatch: each step's skin test on the device, the batch's later steps skipped where it asks
// for a rebuild). One call of step(1000) must take every step the CPU takes, rebuild before the
// same steps as 1000 calls of step(1), and move the walls and meshes at every step: a turning
// mesh drum and a silo whose ring rises, both thrown at their walls, and the chute.
TEST_P(CudaEqualsCpu, BatchesOfStepsEqualSingleSteps) {
  Scene silo = thrownAtWalls("scenes/silo.toml");
  silo.walls.at(1).velocity = {0.0f, 0.0f, 0.3f};
  for (const auto& [scene, what] : {std::pair{thrownAtWalls("scenes/drum-mesh.toml"), "drum-mesh, turning"},
                                    std::pair{silo, "silo, the ring rising"},
                                    std::pair{readSceneFile(sourcePath("scenes/chute.toml")), "chute"}}) {
    const World w = World::fromScene(scene);
    auto cpu = makePipeline(Backend::Cpu);
    auto batched = makePipeline(GetParam());
    auto single = makePipeline(GetParam());
    cpu->load(w);
    batched->load(w);
    single->load(w);
    cpu->step(1000);
    batched->step(1000);
    for (int k = 0; k < 1000; ++k) single->step(1);
    BodyState a, b, c;
    cpu->readState(a);
    batched->readState(b);
    single->readState(c);
    const auto d = firstDifference(a, b);
    EXPECT_FALSE(d) << what << ", step(1000) on " << toString(GetParam()) << " against the CPU: " << d->describe();
    EXPECT_EQ(batched->stats().numRebuilds, single->stats().numRebuilds) << what;
    EXPECT_EQ(batched->stats().steps, 1000u) << what;
    EXPECT_EQ(batched->stepCount(), cpu->stepCount()) << what;
    EXPECT_EQ(batched->time(), cpu->time()) << what;
    EXPECT_EQ(batched->pairs(), cpu->pairs()) << what;
    EXPECT_EQ(batched->meshContacts(), cpu->meshContacts()) << what << ": at the last step's poses";
    EXPECT_EQ(batched->stats().numPairs, cpu->stats().numPairs) << what;
    EXPECT_GT(batched->stats().numRebuilds, 2u) << what << ": rebuilds inside the batches";
    // Spheres: both pipelines test the skin particle by particle (the CPU per body for clumps),
    // so the CPU's rebuilds are the device's skin test's too (one that misjudges the walls'
    // motion since the rebuild rebuilds at other steps, its state still the CPU's).
    if (!w.hasClumps) {
      EXPECT_EQ(batched->stats().numRebuilds, cpu->stats().numRebuilds) << what;
    }
    std::printf("%s: %llu rebuilds in 1000 steps\n", what, static_cast<unsigned long long>(batched->stats().numRebuilds));
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, CudaEqualsCpu, ::testing::ValuesIn(tumble_test::cudaPipelineBackends()),
                         tumble_test::backendName);
