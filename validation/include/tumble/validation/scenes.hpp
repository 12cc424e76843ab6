// SPDX-License-Identifier: MIT
/// @file scenes.hpp
/// Scene and particle-cloud generators shared by tests, benchmarks and examples.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"

namespace tumble {
struct Checkpoint;
}

namespace tumble::validation {

/// The `bench` scene (SPEC §5; the peers' "clumps"): bodies of 8 spheres (radius 0.5, mass 1,
/// offsets ±0.25) on a jittered lattice of spacing 1.65 above a ground, random velocities in
/// ±0.5, k = 2e4, dt = 5e-4. numParticles is 16000, 128000 or 960000 (the peers' lattices) or
/// any multiple of 8 (a near-cubic 4:4:1 lattice). Identical to scenes/bench-*.toml.
Scene benchScene(std::uint32_t numParticles, std::uint64_t seed = 12345);

/// A named particle cloud for the broadphase tests.
struct NamedCloud {
  std::string name;
  ParticleCloud cloud;
};

/// Uniform random spheres in a box (radii in [rMin, rMax]), `bodySize` particles per body.
ParticleCloud randomCloud(std::uint32_t n, std::uint64_t seed, float boxSize, float rMin, float rMax,
                          std::uint32_t bodySize = 1);

/// The hard cases of SPEC §3: every particle at one z, isotropic cloud (degenerate PCA), offset
/// 1e6 with radii 1e-3, radii 1:100, exactly touching lattice, particles spanning many cells,
/// negative coordinates, coincident particles, N = 0 and N = 1, all in one cell, one body.
std::vector<NamedCloud> hardCases(std::uint64_t seed);

/// The scene with hooke-history contacts (k_n its stiffness, k_t = 2/7 k_n, γ_t = γ_n / 2):
/// the friction and rotating spheres of the granular laws, for the tests that also hold for them.
Scene withHookeHistory(Scene s, float gammaN = 100.0f, float friction = 0.5f);

/// The scene under hertz-mindlin with one material (E, ν = 0.3, e = 0.5, μ = 0.5) or two (the
/// second: 2E, ν = 0.25, e = 0.7, μ = 0.3, μ_r = 0.05, on every other sphere of each shape). The
/// masses stay the scene's. E = 1 MPa gives the unit spheres of the test scenes contact times
/// near those of their linear springs.
Scene withHertzMindlin(Scene s, float youngsModulus = 1.0e6f, bool twoMaterials = false);

/// One sphere resting on the ground under `law` (hertz-mindlin: withHertzMindlin's material), and
/// a plane wall beside it when `wall`: a probe that asks a pipeline at load whether it has the
/// model (tumble::NotSupported; TUMBLE_SKIP_IF_NOT_SUPPORTED).
Scene modelProbe(ContactLaw law, bool wall = false);

/// A wall scene of scenes/ (`file` relative to the source tree) with its walls moving from the
/// first step (as they would after their start) and every body thrown down at 3 m/s onto the
/// walls below it: wall contacts within the first few hundred steps.
Scene thrownAtWalls(const char* file);

/// A shape of one sphere (radius r, mass m, elasticity e) at its centre, named "sphere".
ShapeDef sphereShape(float r, float m, float e);

/// A wall's contact (WallDef::contact): on, stiffness k, friction μ, the ground's other defaults.
GroundParams wallContact(float k, float mu);

/// A mesh wall built in code of the given (welded) vertices and triangles (three indices each),
/// named "test mesh", each triangle's source its number.
WallDef meshWall(std::vector<Vec3f> vertices, std::vector<std::uint32_t> triangles, const GroundParams& contact);

/// A grid of nx × ny squares of side h from (x0, y0), at the height height(x, y) (z), each
/// square split in two along alternating diagonals (so that vertices have four and eight
/// triangles around them).
WallDef gridMesh(int nx, int ny, float h, float x0, float y0, const std::function<float(float, float)>& height,
                 const GroundParams& contact);
/// gridMesh() in the plane z = 0.
WallDef flatGrid(int nx, int ny, float h, float x0, float y0, const GroundParams& contact);

/// Spheres of radius r (0.1 kg, elasticity 0.5) at the given places on the wall `wall`,
/// hooke-history (k 1e5, γ_n 100), dt 1e-4, the ground (k 1e5) only when asked.
Scene spheresOn(const WallDef& wall, float r, const std::vector<Vec3f>& at, bool ground = false);

/// A ball slipping in a turning drum (scene s: its wall 0 turns from t = 0), as the drum tests
/// run it: its x velocity after 0.02 s (200 steps of 1e-4 s: dragged at μ g while it slips), and
/// the scene with wall 0 stopping at 0.05 s against the one turning on: the same bits after 450
/// steps, others after 1500, and both x velocities then.
struct DrumStop {
  double earlyVx = 0.0;
  bool sameBeforeTheStop = false, differentAfter = false;
  std::string before;  ///< the first difference before the stop (empty: none)
  double turningVx = 0.0, stoppedVx = 0.0;
};
DrumStop drumDragAndStop(const Scene& s);

/// The state of a world after `steps` steps on a fresh CPU pipeline with the given options.
BodyState runCpu(const World& world, std::uint64_t steps, const PipelineOptions& options = {});

/// A run of a scene's [[pour]]s: the world it ends with (the bodies that entered) and its state.
struct PourRun {
  World world;
  BodyState state;
};
/// Checks a batch that added bodies: the world, the pipeline one step after it, the bodies before
/// it and the time it fell at.
using PourBatchCheck = std::function<void(const World&, const Pipeline&, std::size_t before, double t)>;
/// Runs a scene's pours to step `steps` on a CPU pipeline step by step as the drivers do
/// (Pouring::step), from the start or from a checkpoint; `atBatch` sees each batch.
PourRun pourRun(const Scene& s, std::uint64_t steps, const PipelineOptions& options = {},
                const PourBatchCheck& atBatch = {}, const Checkpoint* from = nullptr);

/// Path of a file in the source tree (scenes/…, validation/golden/…); when the source tree is
/// gone (an installed tumble), of the installed data (share/tumble: the scenes).
std::string sourcePath(const std::string& relative);

}  // namespace tumble::validation
