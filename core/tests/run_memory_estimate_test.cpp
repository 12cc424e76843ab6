// SPDX-License-Identifier: MIT
// The estimate of a run's peak memory (tumble/run_memory.hpp) responds to what the scene uses.
// Its agreement with the memory `tumble run` measures is the test run_memory_estimate
// (examples/tumble/run_memory_test.cpp), which runs the command.
#include <gtest/gtest.h>

#include <cstdint>

#include "tumble/run_memory.hpp"
#include "tumble/scene_io.hpp"

namespace {

tumble::RunSize spheres(std::uint64_t n) {
  tumble::RunSize s;
  s.bodies = n;
  s.particles = n;
  return s;
}

double estimate(const tumble::RunSize& s) { return double(tumble::runMemoryEstimate(s)); }

// Issue 34 measured 1.60 GB for a million single spheres, of which the old estimate (400 bytes
// per body besides its BodyDef, 150 per particle) said 0.55 GB.
TEST(RunMemoryEstimate, AMillionSpheres) {
  EXPECT_NEAR(estimate(spheres(1000000)) / 1.60e9, 1.0, 0.25) << estimate(spheres(1000000));
}

TEST(RunMemoryEstimate, DependsOnWhatTheSceneUses) {
  const tumble::RunSize base = spheres(100000);
  const double b = estimate(base);
  // Clumps: the body rows are shared by 8 particles.
  tumble::RunSize clumps = base;
  clumps.bodies = base.particles / 8;
  EXPECT_LT(estimate(clumps), 0.7 * b);
  // A history per candidate-list entry (12 bytes, both directions of 4 pairs a particle) and per
  // contact, instead of the near list.
  tumble::RunSize history = base;
  history.history = true;
  EXPECT_GT(estimate(history), b + 100.0 * double(base.particles));
  // Five more planes: a spring pair per plane and particle in three states and the pipeline's
  // two columns, and their damping.
  tumble::RunSize walls = base;
  walls.planes = 6;
  EXPECT_GT(estimate(walls), b + 5 * 50.0 * double(base.particles));
  tumble::RunSize periodic = base;
  periodic.periodic = true;
  EXPECT_GT(estimate(periodic), b + 50.0 * double(base.particles));
  tumble::RunSize mesh = base;
  mesh.meshTriangles = 1000000;
  EXPECT_GT(estimate(mesh), b + 400.0 * 1e6);
  // Bodies a pour adds are held as PourBody in four places, and each pour reloads the world.
  tumble::RunSize poured = base;
  poured.bodies = 0;
  poured.pouredBodies = base.bodies;
  EXPECT_GT(estimate(poured), b);
  // Smaller cells: more records per particle.
  tumble::RunSize cells = base;
  cells.recordsPerParticle = 4.0;
  EXPECT_GT(estimate(cells), b + 2.0 * 90.0 * double(base.particles));
  // The lines add up to the total.
  double sum = 0.0;
  for (const tumble::MemoryItem& item : tumble::runMemoryItems(history)) sum += item.count * item.bytes;
  EXPECT_EQ(std::uint64_t(sum), tumble::runMemoryEstimate(history));
}

// runSizeOf() reads the law, the materials, the planes and the cell size off the scene.
TEST(RunMemoryEstimate, SizeOfAScene) {
  const tumble::Scene scene = tumble::parseScene(R"([scene]
dt = 1e-5
steps = 10
[contact]
law = "hertz-mindlin"
[[material]]
name = "a"
density = 2500
youngs_modulus = 1e7
poisson_ratio = 0.3
restitution = 0.5
[[material]]
name = "b"
density = 2500
youngs_modulus = 1e7
poisson_ratio = 0.3
restitution = 0.5
[[wall]]
type = "box"
min = [-1, -1, 0]
max = [1, 1, 2]
open = ["+z"]
[broadphase]
cell_size = 0.5
skin = 0.5
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.25
material = "a"
[[body]]
shape = "ball"
position = [0, 0, 1]
)",
                                                 "size.toml");
  const tumble::RunSize s = tumble::runSizeOf(scene, 10, 5, 15);
  EXPECT_EQ(s.bodies, 10u);
  EXPECT_EQ(s.pouredBodies, 5u);
  EXPECT_EQ(s.particles, 15u);
  EXPECT_EQ(s.planes, 5u);  // the five faces of the box (no [ground] table: no ground)
  EXPECT_TRUE(s.history);
  EXPECT_TRUE(s.materialColumn);
  EXPECT_TRUE(s.pipelineMaterials);
  EXPECT_FALSE(s.periodic);
  EXPECT_DOUBLE_EQ(s.recordsPerParticle, 4.0);  // (1 + 2 × 0.25 / 0.5)²
  // A skin of 2 radii: pairs within 4 radii, (4 / 2.5)³ = 4.096 times those at the automatic
  // skin (a review measured 618 MB at 200k spheres with a skin of 1, the estimate said 417).
  EXPECT_NEAR(s.pairsFactor, 4.096, 1e-6);
  tumble::RunSize thin = s;
  thin.pairsFactor = 1.0;
  EXPECT_GT(double(tumble::runMemoryEstimate(s)), double(tumble::runMemoryEstimate(thin)) + 15.0 * 3.0 * 40.0);
}

}  // namespace
