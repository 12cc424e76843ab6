// SPDX-License-Identifier: MIT
// The energy tally (kernels/energy.hpp, docs/thermo.md#energy-balance): a sliding sphere turns
// 2/7 of its kinetic energy into heat by friction before it rolls (analytic), the balance
// E + dissipated − work in stays constant on scenes with every kind of contact (a heap under
// hooke-history and under hertz-mindlin, the drum's turning walls, the silo, the report's law),
// and the tally is the same bits for any thread count, numbering and pipeline, changing no bit
// of the state.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/thermo.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using tumble::validation::sourcePath;
using tumble::validation::thrownAtWalls;

namespace {

// The guard's sample of the pipeline now, with the pipeline's tally.
ThermoSample sampleWithTally(RunGuard& guard, const Pipeline& p) {
  (void)guard.check(p);
  return withEnergy(guard.sample(), p.stats().energy);
}

}  // namespace

// A sphere launched sliding at v0 on the ground (μ 0.3, no rolling resistance) slides until
// it rolls at 5/7 v0: friction takes 2/7 of ½ m v0², whatever the friction coefficient. The
// tally's tangential and friction columns together hold that heat, and the balance closes.
TEST(EnergyBalance, SlidingSphereTurnsTwoSeventhsIntoHeat) {
  Scene s = validation::modelProbe(ContactLaw::HookeHistory);
  s.ground.friction = 0.3f;
  const float k = s.ground.stiffness, g = 9.81f, m = 1.0f;
  s.bodies[0].position.z = 0.1f - m * g / k;  // at rest on its spring
  const float v0 = 1.0f;
  s.bodies[0].velocity = {v0, 0.0f, 0.0f};
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  p->setEnergyTally(true);
  RunGuard guard(w, *p);
  const ThermoSample s0 = sampleWithTally(guard, *p);
  p->step(4000);  // 0.4 s; rolling from 2 v0 / (7 μ g) = 0.097 s on
  const ThermoSample s1 = sampleWithTally(guard, *p);
  const double ke0 = 0.5 * m * v0 * v0;
  const double heat = s1.dissipatedTangential + s1.dissipatedFriction;
  std::printf("KE %.6f -> %.6f J, friction %.6f + tangential dashpot %.6f J (2/7 KE0 = %.6f), normal %.3g J, "
              "balance %.9f -> %.9f J\n",
              s0.kineticTranslation + s0.kineticRotation, s1.kineticTranslation + s1.kineticRotation,
              s1.dissipatedFriction, s1.dissipatedTangential, 2.0 / 7.0 * ke0, s1.dissipatedNormal, s0.balance(),
              s1.balance());
  EXPECT_NEAR(heat, 2.0 / 7.0 * ke0, 0.01 * 2.0 / 7.0 * ke0);
  EXPECT_GT(s1.dissipatedFriction, 0.9 * heat);  // mostly slip: the dashpot only while it sticks
  EXPECT_NEAR(s1.kineticTranslation + s1.kineticRotation, 5.0 / 7.0 * ke0, 0.01 * ke0);
  EXPECT_NEAR(s1.balance(), s0.balance(), 1e-3 * ke0);
  EXPECT_EQ(s1.wallWork, 0.0);
}

// E + dissipated − wall work stays at its initial value within 0.5 % of the energy that flowed
// (dissipated + wall work) on scenes with each kind of contact; each scene must have
// dissipated (and the drum's walls worked) for the check to mean something. The error left is
// the integration's (the springs' energy sampled at whole steps).
TEST(EnergyBalance, ClosesOnScenes) {
  struct Case {
    const char* what;
    Scene scene;
    std::uint64_t steps;
    bool wallWork;
  };
  Scene molecules = readSceneFile(sourcePath("scenes/molecules.toml"));
  molecules.bodies.resize(400);
  // heap-hertz under JKR, γ 12 J/m² (the pull-off force of two grains about 2.4 times a grain's
  // weight, heap-cohesive's Bond number): necks stretch and break as the column slumps.
  Scene jkr = readSceneFile(sourcePath("scenes/heap-hertz.toml"));
  jkr.contact.cohesion = Cohesion::Jkr;
  for (MaterialDef& m : jkr.materials) m.cohesion = 12.0f;
  const Case cases[] = {{"heap (hooke-history, rolling resistance)", readSceneFile(sourcePath("scenes/heap.toml")), 4000, false},
                        {"heap-hertz (hertz-mindlin)", readSceneFile(sourcePath("scenes/heap-hertz.toml")), 3000, false},
                        {"drum, thrown, turning from the start", thrownAtWalls("scenes/drum.toml"), 3000, true},
                        {"silo, thrown", thrownAtWalls("scenes/silo.toml"), 3000, false},
                        {"molecules (the report's law)", molecules, 3000, false},
                        {"heap-hertz under jkr", jkr, 3000, false}};
  for (const Case& c : cases) {
    const World w = World::fromScene(c.scene);
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    p->setEnergyTally(true);
    RunGuard guard(w, *p);
    const ThermoSample s0 = sampleWithTally(guard, *p);
    double worst = 0.0;
    ThermoSample s;
    for (std::uint64_t done = 0; done < c.steps; done += 500) {
      p->step(500);
      s = sampleWithTally(guard, *p);
      worst = std::max(worst, std::abs(s.balance() - s0.balance()));
    }
    const double flowed = s.dissipatedNormal + s.dissipatedTangential + s.dissipatedFriction +
                          std::abs(s.dissipatedCohesion) + std::abs(s.wallWork);
    std::printf("%s, %llu steps: dissipated normal %.5g, tangential %.5g, friction %.5g, cohesion %.5g J, wall work "
                "%.5g J; balance %.8g J, largest change %.3g J (%.3g of what flowed)\n",
                c.what, static_cast<unsigned long long>(c.steps), s.dissipatedNormal, s.dissipatedTangential,
                s.dissipatedFriction, s.dissipatedCohesion, s.wallWork, s0.balance(), worst, worst / flowed);
    if (c.scene.contact.cohesion == Cohesion::Jkr) {
      EXPECT_GT(s.dissipatedCohesion, 0.0) << c.what << ": necks broke";
    } else {
      EXPECT_EQ(s.dissipatedCohesion, 0.0) << c.what;
    }
    EXPECT_GT(s.dissipatedNormal, 0.0) << c.what;
    EXPECT_GT(s.dissipatedTangential + s.dissipatedFriction, 0.0) << c.what;
    if (c.wallWork) {
      EXPECT_GT(s.wallWork, 0.0) << c.what;
    }
    EXPECT_LT(worst, 5e-3 * flowed) << c.what;
  }
}

// The tally's sums are integers: the same bits for 1 and 2 threads, without the reordering,
// and on every compiled pipeline (the CUDA pipeline's code on its host backend here); the
// state with the tally is the state without it, bit for bit.
TEST(EnergyBalance, SameBitsEverywhere) {
  const World w = World::fromScene(thrownAtWalls("scenes/drum.toml"));
  const std::uint64_t steps = 600;
  BodyState plain;
  {
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    p->step(steps);
    p->readState(plain);
  }
  struct Run {
    std::string what;
    Backend backend;
    int threads;
    bool reorder;
  };
  std::vector<Run> runs = {{"cpu, 1 thread", Backend::Cpu, 1, true},
                           {"cpu, 2 threads", Backend::Cpu, 2, true},
                           {"cpu, no reordering", Backend::Cpu, 2, false}};
  for (const Backend b : compiledBackends()) {
    if (b == Backend::Cpu) continue;
    if (b == Backend::Cuda && cudaStatus().state != CudaState::Ready) {
      if (cudaRequired()) ADD_FAILURE() << cudaStatus().message << " (TUMBLE_REQUIRE_CUDA=1)";
      std::printf("cuda: not run (%s)\n", cudaStatus().message.c_str());
      continue;
    }
    runs.push_back({toString(b), b, 0, true});
  }
  EnergyTotals first{};
  for (std::size_t r = 0; r < runs.size(); ++r) {
    PipelineOptions po;
    po.threads = runs[r].threads;
    po.reorder = runs[r].reorder;
    auto p = makePipeline(runs[r].backend, po);
    p->load(w);
    p->setEnergyTally(true);
    p->step(steps / 2);
    p->step(steps / 2);
    const EnergyTotals e = p->stats().energy;
    BodyState st;
    p->readState(st);
    std::printf("%s: %.17g %.17g %.17g %.17g J\n", runs[r].what.c_str(), e.normal, e.tangential, e.friction, e.wall);
    EXPECT_TRUE(st.px == plain.px && st.vx == plain.vx && st.lz == plain.lz) << runs[r].what << ": the state changed";
    EXPECT_GT(e.wall, 0.0);
    if (r == 0) {
      first = e;
      continue;
    }
    EXPECT_EQ(std::memcmp(&e, &first, sizeof e), 0) << runs[r].what;
  }
}
