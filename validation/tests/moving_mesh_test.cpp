// SPDX-License-Identifier: MIT
// Triangle-mesh walls that move (issue 12): a mesh turning about a pivot and translating, posed
// from the time at each step's start (setWallMotion(), MeshPose). The pose against a
// quaternion in double; the pipeline's mesh contacts equal the brute-force oracle's at every
// step of runs with a turning disk under resting spheres, a plate sweeping through spheres, a
// plate fast enough to rebuild the list every step, a turning drum with lifters and a paddle
// turning about a tilted axis while it translates (each contact's distance also against the
// triangle posed in double). Physics: a mesh piston throws a ball at (1 + e) u, a turning
// mesh drum drags a ball at μ g and stops on time, a turning mesh plate carries a resting ball
// around. A drum of clumps gives the same bits for any thread count, skin and numbering, and
// across a checkpoint taken while it turns; the guard stays quiet on a turning, sinking floor
// and measures its spring once it stops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/mesh.hpp"
#include "tumble/pour.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A drum along y: a band of n flat facets about the axis through c (its vertices at radius R,
// from y = c.y − L/2 to c.y + L/2, turned by half a facet so that a facet lies flat at the
// bottom), closed by two fans, with `lifters` radial plates of height h along it (from just
// inside the facets, 0.5 % short of the ends), evenly spaced from the top.
WallDef drumMesh(Vec3f c, float R, float L, int n, int lifters, float h, const GroundParams& g) {
  std::vector<Vec3f> v;
  std::vector<std::uint32_t> t;
  const float y0 = c.y - 0.5f * L, y1 = c.y + 0.5f * L;
  const auto at = [&](double r, double phi, float y) {
    return Vec3f{float(c.x + r * std::cos(phi)), y, float(c.z + r * std::sin(phi))};
  };
  for (int k = 0; k < n; ++k) {
    const double phi = -0.5 * kPi + 2.0 * kPi * (k + 0.5) / n;
    v.push_back(at(R, phi, y0));
    v.push_back(at(R, phi, y1));
  }
  const std::uint32_t ends = std::uint32_t(v.size());
  v.push_back(Vec3f{c.x, y0, c.z});
  v.push_back(Vec3f{c.x, y1, c.z});
  for (int k = 0; k < n; ++k) {
    const std::uint32_t a = 2 * k, b = 2 * ((k + 1) % n);
    t.insert(t.end(), {a, b, b + 1, a, b + 1, a + 1, ends, b, a, ends + 1, a + 1, b + 1});
  }
  const double inner = R * std::cos(kPi / n) * 0.999, inset = 0.005 * L;
  for (int j = 0; j < lifters; ++j) {
    const double phi = 0.5 * kPi + 2.0 * kPi * j / lifters;
    const std::uint32_t b = std::uint32_t(v.size());
    v.push_back(at(inner, phi, float(y0 + inset)));
    v.push_back(at(inner, phi, float(y1 - inset)));
    v.push_back(at(inner - h, phi, float(y1 - inset)));
    v.push_back(at(inner - h, phi, float(y0 + inset)));
    t.insert(t.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  }
  return meshWall(std::move(v), std::move(t), g);
}

// A vertical plate in the plane x = 0 (then at its position): the grid of nx × ny squares of
// side h from (z0, y0), stood up by its orientation, −90 degrees about y: (x, y, 0) → (0, y, x).
// It spans z0 to z0 + nx h and y0 to y0 + ny h.
WallDef verticalPlate(int nx, int ny, float h, float y0, float z0, const GroundParams& g) {
  WallDef w = flatGrid(nx, ny, h, z0, y0, g);
  w.orientation = Quatf{float(std::sqrt(0.5)), 0.0f, float(-std::sqrt(0.5)), 0.0f};
  return w;
}

MeshOracleRun oracle(const char* name, const World& w, std::uint64_t steps, const PipelineOptions& o = {}) {
  MeshOracleRun run = meshOracleRun(w, steps, o);
  if (!run.difference.empty()) ADD_FAILURE() << name << ": " << run.difference;
  std::printf("%-44s %4llu steps, %5llu contacts, %4llu rebuilds, pose gap %.2e m\n", name,
              (unsigned long long)run.steps, (unsigned long long)run.contacts, (unsigned long long)run.rebuilds,
              run.worstPoseGap);
  return run;
}

}  // namespace

// The pose of a mesh (setWallMotion(), MeshPose): the rotation by |ω| τ about ω through the
// pivot, then the translation v τ, against a quaternion in double; the identity (posed 0)
// before the start, held from the stop; the same bits at a time whatever came before (a
// resumed run poses it identically); the Wall's pivot now and its motion flag.
TEST(MovingMeshTest, APoseTurnsAboutThePivotThenTranslates) {
  WallDef w = flatGrid(2, 2, 0.5f, -0.5f, -0.5f, wallContact(1e5f, 0.5f));
  w.velocity = {0.3f, -0.2f, 0.1f};
  w.meshAngularVelocity = {0.0f, 1.5f, 2.0f};  // 2.5 rad/s about (0, 0.6, 0.8)
  w.pivot = Vec3f{0.1f, 0.2f, 0.3f};
  w.start = 0.5;
  w.stop = 2.0;
  Scene s;
  s.walls = {w};
  std::vector<Wall> walls = kernelWalls(s, LocalFrame{});
  std::vector<MeshPose> pose(1, MeshPose{});
  MeshPose at13{};
  for (const double t : {0.0, 0.5, 0.75, 1.3, 1.9999, 2.0, 7.0}) {
    setWallMotion(walls, s, t, pose.data());
    const double tau = std::clamp(t - 0.5, 0.0, 1.5), half = 0.5 * 2.5 * tau;
    EXPECT_EQ(pose[0].posed, tau > 0.0 ? 1u : 0u) << "t = " << t;
    EXPECT_EQ(walls[0].moving, t >= 0.5 && t < 2.0 ? 1u : 0u) << "t = " << t;
    if (t == 1.3) at13 = pose[0];
    // q = (cos θ/2, sin θ/2 k): its matrix in double.
    const double qw = std::cos(half), qx = 0.0, qy = 0.6 * std::sin(half), qz = 0.8 * std::sin(half);
    const double R[9] = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy),
                         2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx),
                         2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)};
    if (pose[0].posed == 0u) continue;
    const float* got = &pose[0].rot.xx;
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(got[k], R[k], 1.2e-7) << "t = " << t << ", entry " << k;
    const double c[3] = {0.1 + 0.3 * tau, 0.2 - 0.2 * tau, 0.3 + 0.1 * tau};
    EXPECT_NEAR(pose[0].centre.x, c[0], 1e-7);
    EXPECT_NEAR(pose[0].centre.y, c[1], 1e-7);
    EXPECT_NEAR(pose[0].centre.z, c[2], 1e-7);
    EXPECT_EQ(walls[0].centre.x, pose[0].centre.x) << "the material's velocity turns about the pivot now";
    // A corner of the mesh, (0.5, 0.5, 0): where the pose puts it, and back into the mesh's frame.
    const double y[3] = {0.5 - 0.1, 0.5 - 0.2, 0.0 - 0.3};
    const Vec3f x{float(c[0] + R[0] * y[0] + R[1] * y[1] + R[2] * y[2]), float(c[1] + R[3] * y[0] + R[4] * y[1] + R[5] * y[2]),
                  float(c[2] + R[6] * y[0] + R[7] * y[1] + R[8] * y[2])};
    const Vec3f back = toMeshFrame(pose[0], x);
    EXPECT_NEAR(back.x, 0.5, 1e-6);
    EXPECT_NEAR(back.y, 0.5, 1e-6);
    EXPECT_NEAR(back.z, 0.0, 1e-6);
  }
  // Time 1.3 s posed straight from the rest geometry: the bits of the pose reached through others.
  std::vector<Wall> fresh = kernelWalls(s, LocalFrame{});
  std::vector<MeshPose> again(1, MeshPose{});
  setWallMotion(fresh, s, 1.3, again.data());
  EXPECT_EQ(std::memcmp(&again[0], &at13, sizeof(MeshPose)), 0);
  // Held from the stop: 7 s is where 2 s put it.
  setWallMotion(fresh, s, 2.0, again.data());
  EXPECT_EQ(std::memcmp(&again[0], &pose[0], sizeof(MeshPose)), 0);
}

// The pipeline's mesh contacts equal the oracle's (every sphere against every triangle, the
// meshes posed at the step's time) at every step, and each contact's distance equals the
// distance in double to the triangle posed in double. The slow cases keep their lists for
// many steps (the skin bound holds the meshes' motion); the fast plate rebuilds every step.
TEST(MovingMeshTest, ContactsEqualTheOracleAtEveryStep) {
  const GroundParams c = wallContact(1e5f, 0.5f);
  const float r = 0.05f, rest = r - 0.1f * 9.81f / 1e5f;
  {  // spheres resting on a disk of 128 triangles turning about z at 2 rad/s (and one on the
     // pivot), carried round (rolling friction: free to roll, they would roll off)
    WallDef disk = flatGrid(8, 8, 0.1f, -0.4f, -0.4f, c);
    disk.meshAngularVelocity = {0.0f, 0.0f, 2.0f};
    disk.contact.rollingFriction = 0.3f;
    disk.pivot = Vec3f{0.0f, 0.0f, 0.0f};
    std::vector<Vec3f> at{{0.0f, 0.0f, rest}};
    for (int k = 0; k < 6; ++k) {  // three at 0.12 m, three at 0.24 m from the axis
      const double rho = k < 3 ? 0.12 : 0.24, phi = 2.1 * k + (k < 3 ? 0.0 : 1.0);
      at.push_back(Vec3f{float(rho * std::cos(phi)), float(rho * std::sin(phi)), rest});
    }
    const MeshOracleRun o = oracle("resting on a turning disk", World::fromScene(spheresOn(disk, r, at)), 2000);
    EXPECT_EQ(o.steps, 2000u);
    EXPECT_GT(o.contacts, 7u * 1900u) << "every sphere stays on it";
    EXPECT_LT(o.rebuilds, 200u) << "the list is kept while the disk turns";
    EXPECT_LT(o.worstPoseGap, 2e-7);
  }
  {  // the same far from the origin (the run integrates in a local frame: the pivot moves with it)
    const Vec3f o{2.0e4f, -1.0e4f, 0.0f};
    WallDef disk = flatGrid(8, 8, 0.1f, -0.4f, -0.4f, c);
    disk.point = o;
    disk.meshAngularVelocity = {0.0f, 0.0f, 2.0f};
    disk.pivot = o;
    disk.contact.rollingFriction = 0.3f;
    std::vector<Vec3f> at;
    for (int k = 0; k < 3; ++k)
      at.push_back(Vec3f{o.x + float(0.12 * std::cos(2.1 * k)), o.y + float(0.12 * std::sin(2.1 * k)), rest});
    const World w = World::fromScene(spheresOn(disk, r, at));
    ASSERT_TRUE(LocalFrame::of(w).active());
    const MeshOracleRun o2 = oracle("the turning disk 2e4 m from the origin", w, 2000);
    EXPECT_EQ(o2.steps, 2000u);
    EXPECT_GT(o2.contacts, 3u * 1900u);
    EXPECT_LT(o2.worstPoseGap, 1e-6);
    const BodyState st = runCpu(w, 5000);  // 0.5 s: 1 rad
    const double angle = std::atan2(double(st.py[0]) - o.y, double(st.px[0]) - o.x);
    std::printf("  the first sphere at %.4f rad after 0.5 s (the disk turned 1 rad)\n", angle);
    EXPECT_NEAR(angle, 1.0, 0.1) << "carried round the pivot, far from the origin";
  }
  {  // a plate sweeping along +x at 1 m/s through a row of spheres on the ground
    WallDef plate = verticalPlate(4, 4, 0.1f, -0.2f, -0.05f, c);
    plate.point = {-0.1f, 0.0f, 0.0f};
    plate.velocity = {1.0f, 0.0f, 0.0f};
    std::vector<Vec3f> at;
    for (int k = 0; k < 4; ++k) at.push_back(Vec3f{-0.04f + 0.03f * k, -0.15f + 0.1f * k, r});
    const MeshOracleRun o = oracle("a plate sweeping through spheres", World::fromScene(spheresOn(plate, r, at, true)), 1500);
    EXPECT_EQ(o.steps, 1500u);
    EXPECT_GT(o.contacts, 50u);
    EXPECT_LT(o.rebuilds, 300u);
  }
  {  // the plate at 150 m/s for 4 ms (15 mm a step, more than half the skin): a rebuild every step
    WallDef plate = verticalPlate(4, 4, 0.1f, -0.2f, -0.05f, c);
    plate.point = {-0.2f, 0.0f, 0.0f};
    plate.velocity = {150.0f, 0.0f, 0.0f};
    plate.contact.friction = 0.0f;
    plate.stop = 0.004;
    std::vector<Vec3f> at;
    for (int k = 0; k < 4; ++k) at.push_back(Vec3f{0.04f * k, -0.15f + 0.1f * k, 0.1f});
    Scene s = spheresOn(plate, r, at);
    s.gravity = {0, 0, 0};
    const MeshOracleRun o = oracle("a plate fast enough to rebuild every step", World::fromScene(s), 60);
    EXPECT_EQ(o.steps, 60u);
    EXPECT_GT(o.contacts, 4u);
    EXPECT_GE(o.rebuilds, 40u) << "every step while it moves";
  }
  {  // a turning drum of 24 facets with 4 lifters and 12 spheres inside (it turns from 5 ms)
    WallDef drum = drumMesh(Vec3f{0, 0, 0}, 0.3f, 0.2f, 24, 4, 0.06f, c);
    drum.meshAngularVelocity = {0.0f, 3.0f, 0.0f};
    drum.pivot = Vec3f{0, 0, 0};
    drum.start = 0.005;
    std::vector<Vec3f> at;
    // Two staggered rows along the axis on the drum's bottom, two layers, and two above.
    const float bottom = 0.3f * float(std::cos(kPi / 24)) - r - 0.0005f;
    for (const float lift : {0.0f, 0.11f}) {
      for (const float x : {-0.12f, 0.0f, 0.12f}) at.push_back(Vec3f{x, -0.05f, lift - std::sqrt(bottom * bottom - x * x)});
      for (const float x : {-0.06f, 0.06f}) at.push_back(Vec3f{x, 0.05f, lift - std::sqrt(bottom * bottom - x * x)});
    }
    at.push_back(Vec3f{-0.06f, 0.0f, 0.1f});
    at.push_back(Vec3f{0.06f, 0.0f, 0.1f});
    const MeshOracleRun o = oracle("a turning drum with lifters", World::fromScene(spheresOn(drum, r, at)), 1500);
    EXPECT_EQ(o.steps, 1500u);
    EXPECT_GT(o.contacts, 2500u);
    EXPECT_LT(o.worstPoseGap, 5e-7);
  }
  {  // a paddle turning about a tilted axis through its end while it translates, over spheres on the ground
    WallDef paddle = verticalPlate(2, 3, 0.1f, -0.05f, 0.0f, c);  // x = 0, y in [-0.05, 0.25], z in [0, 0.2]
    paddle.meshAngularVelocity = {0.5f, 0.0f, 6.0f};
    paddle.pivot = Vec3f{0.0f, 0.0f, 0.1f};
    paddle.velocity = {0.0f, 0.2f, 0.0f};
    std::vector<Vec3f> at;
    for (int k = 0; k < 6; ++k) at.push_back(Vec3f{float(0.18 * std::cos(1.0 * k)), float(0.18 * std::sin(1.0 * k)), r});
    const MeshOracleRun o = oracle("a paddle turning and translating", World::fromScene(spheresOn(paddle, r, at, true)), 2000);
    EXPECT_EQ(o.steps, 2000u);
    EXPECT_GT(o.contacts, 30u);
    EXPECT_LT(o.worstPoseGap, 5e-7);
  }
}

// A mesh plate (two triangles, 1 m square) facing +x, moving at u = 1.5 m/s, hits a ball at
// rest and throws it at (1 + e) u (e = 0.8, its elasticity on the wall), as a plane piston does
// (WallTest.APistonThrowsABallAtOnePlusETimesItsSpeed): aligned, and turned 0.6 rad about z
// by its orientation.
TEST(MovingMeshTest, AMeshPistonThrowsABallAtOnePlusETimesItsSpeed) {
  const double e = 0.8, u = 1.5;
  for (const double turn : {0.0, 0.6}) {
    const Vec3f n{float(std::cos(turn)), float(std::sin(turn)), 0.0f};
    const GroundParams c = wallContact(1.0e5f, 0.0f);
    WallDef w = meshWall({{0, -0.5f, -0.5f}, {0, 0.5f, -0.5f}, {0, 0.5f, 0.5f}, {0, -0.5f, 0.5f}}, {0, 1, 2, 0, 2, 3}, c);
    w.orientation = Quatf{float(std::cos(0.5 * turn)), 0.0f, 0.0f, float(std::sin(0.5 * turn))};
    w.point = {-0.2f * n.x, -0.2f * n.y, 0.0f};
    w.velocity = {float(u * n.x), float(u * n.y), 0.0f};
    w.stop = 0.2;
    Scene s;
    s.dt = 1e-5f;
    s.gravity = {0, 0, 0};
    s.ground.enabled = false;
    s.walls = {w};
    s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
    s.bodies = {BodyDef{}};
    const BodyState st = runCpu(World::fromScene(s), 30000);  // 0.3 s
    const double out = st.vx[0] * n.x + st.vy[0] * n.y;
    std::printf("mesh piston turned %.1f rad: ball at %.5f m/s, (1 + e) u = %.5f\n", turn, out, (1.0 + e) * u);
    EXPECT_NEAR(out, (1.0 + e) * u, 0.02 * (1.0 + e) * u);
    EXPECT_NEAR(st.vx[0] * n.y - st.vy[0] * n.x, 0.0, 1e-5) << "along the normal only";
    EXPECT_GT(st.px[0] * n.x + st.py[0] * n.y, 0.1 + 0.2 * u) << "well ahead of the stopped plate";
  }
}

// A ball at rest at the bottom of a mesh drum (720 facets, radius 0.5 m at its vertices) turning
// at ω = 4 rad/s about +y (angular_velocity = [0, 4, 0] about its axis): the facets under it move
// at −ω R x̂ and drag it at μ g while it slips, as the revolved drum does
// (RevolvedWallTest.ATurningDrumDragsABallAndStopsOnTime). A polygon adds its own push: each
// crease that passes under the ball lifts it by 2 R ω α (α = π/n, half a facet's angle) on the
// next facet, tilted by α towards the motion, about R ω² α on average: 0.26 m/s² with 96
// facets (the ball was dragged 13 % faster than μ g), 0.035 with 720. A drum that stops at
// 0.05 s gives the bits of one that keeps turning up to then, and others after.
TEST(MovingMeshTest, ATurningMeshDrumDragsABallAndStopsOnTime) {
  const double R = 0.5, r = 0.05, m = 0.1, g = 9.81, mu = 0.4, omega = 4.0, k = 1e5;
  WallDef drum = drumMesh(Vec3f{0, 0, 0}, float(R), 1.0f, 720, 0, 0.0f, wallContact(float(k), float(mu)));
  drum.meshAngularVelocity = {0.0f, float(omega), 0.0f};
  drum.pivot = Vec3f{0, 0, 0};
  const DrumStop d = drumDragAndStop(
      spheresOn(drum, float(r), {Vec3f{0.0f, 0.0f, float(-(R * std::cos(kPi / 720) - r) + m * g / k)}}));
  std::printf("mesh drum: v_x after 0.02 s %.5f m/s (-mu g t = %.5f); at 0.15 s %.4f m/s turning, %.4f m/s stopped at "
              "0.05 s\n", d.earlyVx, -mu * g * 0.02, d.turningVx, d.stoppedVx);
  EXPECT_NEAR(d.earlyVx, -mu * g * 0.02, 0.05 * mu * g * 0.02) << "slipping (ω R = 2 m/s)";
  EXPECT_TRUE(d.sameBeforeTheStop) << "before the stop: " << d.before;
  EXPECT_TRUE(d.differentAfter) << "the drum stopped at 0.05 s";
}

// A ball at rest on a square mesh plate (128 triangles) turning at 2 rad/s about the vertical
// axis through its centre, 0.2 m from the axis (hooke-history, μ = 0.5, rolling friction 0.3:
// a ball free to roll on a turntable runs in circles of its own, at 2/7 of its rate, instead of
// riding on it): the plate drags it up to its own speed and carries it round, at 0.2 m, its
// angle following the plate's.
TEST(MovingMeshTest, AMeshPlateTurningAboutAVerticalAxisCarriesABallAround) {
  const double omega = 2.0, rho = 0.2, r = 0.05;
  WallDef plate = flatGrid(8, 8, 0.1f, -0.4f, -0.4f, wallContact(1e5f, 0.5f));
  plate.meshAngularVelocity = {0.0f, 0.0f, float(omega)};
  plate.contact.rollingFriction = 0.3f;
  Scene s = spheresOn(plate, float(r), {Vec3f{float(rho), 0.0f, float(r - 0.1 * 9.81 / 1e5)}});
  const BodyState st = runCpu(World::fromScene(s), 15000);  // 1.5 s: three radians
  const double angle = std::atan2(st.py[0], st.px[0]), radius = std::hypot(st.px[0], st.py[0]);
  const double speed = std::hypot(st.vx[0], st.vy[0]);
  std::printf("turning plate: after 1.5 s the ball is at %.4f m, angle %.4f rad (the plate's %.4f), speed %.4f m/s "
              "(omega rho %.4f)\n", radius, angle, omega * 1.5, speed, omega * radius);
  EXPECT_NEAR(radius, rho, 0.01);
  EXPECT_NEAR(angle, omega * 1.5, 0.2) << "it lags the plate by its first slip only";
  EXPECT_NEAR(speed, omega * radius, 0.01 * omega * radius) << "at the plate's speed";
}

// Clumps tumbling in a turning mesh drum with lifters, beside a mesh baffle that stands still
// (hooke-history): the same bits for 1 and 2 threads, without the renumbering, with skin 0 and
// with a large skin; 300 steps straight equal 150, a checkpoint, a resume and 150, the drum
// turning across the checkpoint (its pose follows from the time: nothing to store).
TEST(MovingMeshTest, ATurningDrumOfClumpsIsTheSameForAnyThreadsSkinAndResume) {
  Scene s = withHookeHistory(benchScene(480));
  s.ground.enabled = false;
  s.dt = 5e-4f;
  for (ShapeDef& sh : s.shapes)
    for (SphereDef& sp : sh.spheres) sp.offset = 0.1f * sp.offset, sp.radius *= 0.1f;
  for (std::size_t k = 0; k < s.bodies.size(); ++k) {  // 4 x 3 x 5, the top layer thrown up towards the baffle
    s.bodies[k].position = Vec3f{0.15f * (float(k % 4) - 1.5f), 0.15f * (float((k / 4) % 3) - 1.0f), -0.3f + 0.15f * float(k / 12)};
    s.bodies[k].velocity.z = k / 12 == 4 ? 2.0f : -1.0f;
  }
  WallDef drum = drumMesh(Vec3f{0, 0, 0}, 0.5f, 0.5f, 32, 4, 0.1f, wallContact(s.ground.stiffness, 0.5f));
  drum.meshAngularVelocity = {0.0f, 6.0f, 0.0f};
  drum.start = 0.02;
  WallDef baffle = meshWall({{-0.15f, -0.24f, 0.4f}, {0.15f, -0.24f, 0.4f}, {0.15f, 0.24f, 0.43f}, {-0.15f, 0.24f, 0.43f}},
                            {0, 1, 2, 0, 2, 3}, wallContact(s.ground.stiffness, 0.5f));
  s.walls = {drum, baffle};
  const World w = World::fromScene(s);
  const BodyState a = runCpu(w, 300, PipelineOptions{2, true});
  Scene s0 = s, sBig = s;
  s0.broadphase.skin = 0.0f;
  sBig.broadphase.skin = 0.2f;  // four radii
  for (const BodyState& o : {runCpu(w, 300, PipelineOptions{1, false}), runCpu(World::fromScene(s0), 300),
                             runCpu(World::fromScene(sBig), 300)}) {
    const auto d = firstDifference(a, o);
    EXPECT_FALSE(d.has_value()) << d->describe();
  }
  std::printf("turning mesh drum of %u clumps: %zu mesh springs at step 300\n", w.numBodies(), a.meshContacts.size());
  EXPECT_GT(a.meshContacts.size(), 20u);

  const std::string path = "/tmp/tumble_moving_mesh_test_" + std::to_string(::getpid()) + ".ck";
  {
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    p->step(150);  // 0.075 s: turning since 0.02 s
    Checkpoint::of(w, *p).write(path);
  }
  std::string warning;
  const World w2 = Checkpoint::read(path).resume(w, &warning);
  std::remove(path.c_str());
  EXPECT_TRUE(warning.empty()) << warning;
  const auto d = firstDifference(a, runCpu(w2, 150));
  EXPECT_FALSE(d.has_value()) << "resumed: " << d->describe();
}

// A ball on a mesh floor that turns about the vertical through the ball and sinks at 0.5 m/s
// from 0.1 s to 0.5 s: the ball rides down with it; the guard stays quiet while it moves (it
// leaves out the energy test then, and measures the overlaps against the floor posed where the
// pipeline has it) and, once the floor has stopped, measures its spring, 1/2 (m g)² / k (as
// given, 0.2 m higher, the floor would hold none).
TEST(MovingMeshTest, TheGuardSeesTheMeshWhereItIs) {
  const double k = 1e4, m = 1.0, g = 9.81;
  WallDef floor = flatGrid(6, 6, 0.1f, -0.3f, -0.3f, wallContact(float(k), 0.5f));
  floor.velocity = {0.0f, 0.0f, -0.5f};
  floor.meshAngularVelocity = {0.0f, 0.0f, 1.0f};
  floor.pivot = Vec3f{0.05f, 0.05f, 0.0f};
  floor.start = 0.1;
  floor.stop = 0.5;
  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = false;
  s.walls = {floor};
  s.shapes = {sphereShape(0.1f, float(m), 0.5f)};
  BodyDef b;
  b.position = {0.05f, 0.05f, float(0.1 - m * g / k)};
  s.bodies = {b};
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  RunGuard guard(w, *p);
  for (int n = 0; n < 10; ++n) {
    p->step(1000);
    const auto trip = guard.check(*p);
    ASSERT_FALSE(trip.has_value()) << "at " << p->time() << " s: " << trip->message;
  }
  BodyState st;
  p->readState(st);
  const double want = 0.5 * (m * g) * (m * g) / k;
  std::printf("turning lift: at 1 s the ball at z %.5f (floor at -0.2 m), vz %.2e; the guard's spring %.4e J "
              "(1/2 (m g)^2 / k = %.4e)\n", double(st.pz[0]), double(st.vz[0]), guard.sample().springs, want);
  EXPECT_NEAR(st.pz[0], -0.2 + 0.1 - m * g / k, 1e-4);
  EXPECT_NEAR(guard.sample().springs, want, 0.01 * want);
}

// A wall built in code is checked when the world is built: a mesh turns about a vector (not a
// number) and a finite pivot, a pivot needs a rotation, only a mesh turns about a vector.
TEST(MovingMeshTest, MotionsBuiltInCodeAreChecked) {
  const auto refused = [](const WallDef& w, const char* why) {
    Scene s = spheresOn(w, 0.05f, {Vec3f{0.0f, 0.0f, 0.5f}});
    s.walls[0].where = "wall 1";
    try {
      (void)World::fromScene(s);
      ADD_FAILURE() << "accepted; expected: " << why;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  const WallDef plate = flatGrid(2, 2, 0.5f, -0.5f, -0.5f, wallContact(1e5f, 0.5f));
  WallDef w = plate;
  w.angularVelocity = 2.0f;
  refused(w, "a mesh turns about a vector");
  w = plate;
  w.pivot = Vec3f{0, 0, 0};
  refused(w, "pivot is the point a mesh turns about, and this mesh does not turn");
  w.meshAngularVelocity = {0.0f, 0.0f, 1.0f};
  w.pivot = Vec3f{0, NAN, 0};
  refused(w, "pivot must be finite");
  w = plate;
  w.meshAngularVelocity = {0.0f, INFINITY, 1.0f};
  refused(w, "angular_velocity must be finite");
  w = plate;
  w.velocity = {1.0f, 0.0f, 0.0f};
  w.start = 2.0;
  w.stop = 1.0;
  refused(w, "the motion must start at t >= 0 and stop after it starts");
  WallDef drum = revolvedWall(Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, 1.0f, 1.0f, 1.0f);
  drum.meshAngularVelocity = {0.0f, 1.0f, 0.0f};
  refused(drum, "only a mesh turns about a vector angular_velocity");
}

// A [[pour]] batch keeps clear of a moving mesh where it is at the batch's time: a shutter (a
// flat mesh at z = 0.35 across the pour's box, over x from −0.1 to 0.2 where it was given, the
// box's x from −0.1 to 0.1) slides towards +x at 1 m/s; at the batch of t = 0.05 s its edge is at
// x = −0.05: no ball comes within its radius of it there, and some lie in its plane beyond the
// edge, where a shutter left where it was given would have refused them.
TEST(MovingMeshTest, APourKeepsClearOfTheMeshWhereItIsAtTheBatch) {
  Scene s = parseScene(R"(
[scene]
dt = 1e-4
steps = 600
seed = 5
[contact]
law = "hooke-history"
stiffness = 2e4
gamma_n = 1500
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.01
mass = 0.0105
[[pour]]
shape = "ball"
count = 400
rate = 4000
interval = 0.05
region = "box"
min = [-0.1, -0.1, 0.3]
max = [0.1, 0.1, 0.4]
)", "pour.toml");
  const float r = 0.01f;
  WallDef shutter = flatGrid(6, 4, 0.05f, -0.1f, -0.1f, wallContact(2e4f, 0.5f));
  shutter.point = {0.0f, 0.0f, 0.35f};
  shutter.velocity = {1.0f, 0.0f, 0.0f};
  s.walls = {shutter};
  std::size_t inPlane = 0, placed = 0;
  pourRun(s, 600, {}, [&](const World& world, const Pipeline&, std::size_t before, double t) {
    if (t < 0.04) return;
    const double edge = -0.1 + t;  // the shutter's edge then; it covers x >= edge
    const LocalFrame f = world.frame ? *world.frame : LocalFrame{};  // the pour's positions are in the run's frame
    for (std::size_t k = before; k < world.numBodies(); ++k) {
      const double x = world.state.px[k] + f.x, dz = std::abs(world.state.pz[k] + f.z - 0.35);
      const double gap = x >= edge ? dz : std::hypot(edge - x, dz);
      EXPECT_GE(gap, r * (1.0 - 1e-6)) << "ball " << k << " at t = " << t << " s touches the shutter";
      inPlane += dz < r ? 1u : 0u;
      ++placed;
    }
  });
  std::printf("pour past a sliding shutter: %zu balls placed at t >= 0.05 s, %zu of them in its plane beyond its "
              "edge (within a radius of z = 0.35)\n", placed, inPlane);
  EXPECT_GT(placed, 100u);
  EXPECT_GT(inPlane, 5u);
}

// The time-step warning counts a moving wall's speed in the fastest impact a Hertz contact may
// have (wallApproachSpeed()): a blade turning at 20 rad/s, its tip 0.3 m from its pivot, runs
// into a ball at 6 m/s, and shortens the shortest contact time by the fifth root of the speeds.
TEST(MovingMeshTest, TheTimeStepWarningCountsAMovingMeshsSpeed) {
  WallDef blade = verticalPlate(1, 3, 0.1f, 0.0f, 0.0f, wallContact(1e5f, 0.5f));  // y from 0 to 0.3
  Scene s = spheresOn(blade, 0.05f, {Vec3f{0.2f, 0.1f, 0.05f}});
  s.contact.law = ContactLaw::HertzMindlin;
  s.walls[0].contact.stiffness = 0.0f;  // not read under hertz-mindlin: the wall is rigid
  s.materials = {MaterialDef{"soft", 0.0f, 1.0e7f, 0.3f, 0.5f, 0.5f, 0.0f}};
  s.gravity = {0, 0, 0};
  const double still = shortestContactTime(World::fromScene(s));
  s.walls[0].meshAngularVelocity = {0.0f, 0.0f, 20.0f};
  s.walls[0].pivot = Vec3f{0, 0, 0};
  EXPECT_NEAR(wallApproachSpeed(s.walls[0]), 20.0 * std::sqrt(0.3 * 0.3 + 0.1 * 0.1), 1e-5) << "its farthest corner";
  const double turning = shortestContactTime(World::fromScene(s));
  std::printf("Hertz contact time: %.4e s by a still blade (1 m/s), %.4e s by one turning at 20 rad/s\n", still, turning);
  EXPECT_NEAR(turning / still, std::pow(1.0 / (20.0 * std::sqrt(0.1)), 0.2), 1e-6);
}

// A [[pour]] into the inside of a closed mesh (region = "mesh") that moves: a cube of side 0.4 m
// sliding along +x at 1 m/s; the batch of t = 0.1 s fills the cube where it is then (x from
// -0.1 to 0.3): every ball inside it and clear of its faces, some beyond where it was given.
// The scene of the pours into a closed cube of side 0.4 m (cube.obj) that moves as `motion` says:
// one ball above it from the start, balls of radius 0.02 poured into it (region = "mesh") as
// `pour` says, no gravity.
static Scene cubePourScene(const std::string& motion, const std::string& pour) {
  const std::string dir = "/tmp/tumble_moving_mesh_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir + "/cube.obj");
    obj << "v -0.2 -0.2 -0.2\nv 0.2 -0.2 -0.2\nv 0.2 0.2 -0.2\nv -0.2 0.2 -0.2\n"
           "v -0.2 -0.2 0.2\nv 0.2 -0.2 0.2\nv 0.2 0.2 0.2\nv -0.2 0.2 0.2\n"
           "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
  }
  {
    std::ofstream toml(dir + "/scene.toml");
    toml << "[scene]\ndt = 1e-4\nsteps = 1100\nseed = 2\ngravity = [0, 0, 0]\n"
            "[[shape]]\nname = \"ball\"\n[[shape.sphere]]\nradius = 0.02\nmass = 0.03\n"
            "[[body]]\nshape = \"ball\"\nposition = [0, 0, 1]\n"  // one body from the start, above the cube
            "[[wall]]\ntype = \"mesh\"\nfile = \"cube.obj\"\n" << motion << "\n"
         << "[[pour]]\nshape = \"ball\"\nregion = \"mesh\"\nwall = 1\n" << pour << "\n";
  }
  const Scene s = readSceneFile(dir + "/scene.toml");
  std::filesystem::remove_all(dir);
  return s;
}

TEST(MovingMeshTest, APourFillsAMovingClosedMeshWhereItIs) {
  const Scene s = cubePourScene("velocity = [1, 0, 0]", "count = 60\nrate = 600\ninterval = 0.1");
  std::size_t placed = 0, beyond = 0;
  pourRun(s, 1100, {}, [&](const World& world, const Pipeline&, std::size_t before, double t) {
    if (t < 0.05) return;
    const LocalFrame f = world.frame ? *world.frame : LocalFrame{};
    for (std::size_t k = before; k < world.numBodies(); ++k) {
      const double x = world.state.px[k] + f.x - t, y = world.state.py[k] + f.y, z = world.state.pz[k] + f.z;
      EXPECT_LE(std::max({std::abs(x), std::abs(y), std::abs(z)}), 0.2 - 0.02 * (1.0 - 1e-5))
          << "ball " << k << " at t = " << t << " s is not inside the cube where it is";
      beyond += x + t > 0.2 ? 1u : 0u;
      ++placed;
    }
  });
  std::printf("pour into a sliding cube: %zu balls inside it where it is, %zu beyond where it was given\n", placed, beyond);
  EXPECT_GE(placed, 20u);
  EXPECT_GT(beyond, 0u);
}

// Later batches into a moved mesh keep clear of the balls the earlier ones put there: the cube
// slides 0.5 m in 0.1 s and stops (wholly beyond where it was given); batches at t = 0.1, 0.2 and
// 0.3 s put 1, 40 and 40 balls into it. Every ball of a batch is apart from every ball before it
// (the placement had hashed only the particles near the cube as given).
TEST(MovingMeshTest, LaterPourBatchesIntoAMovedMeshKeepClearOfTheEarlier) {
  const Scene s =
      cubePourScene("velocity = [5, 0, 0]\nstop = 0.1", "count = 81\nrate = 400\nstart = 0.1\ninterval = 0.1");
  std::size_t closest = 0, batches = 0;
  double gap = 1.0;
  const World world = pourRun(s, 3100, {}, [&](const World& world, const Pipeline&, std::size_t before, double) {
    ++batches;
    for (std::size_t k = before; k < world.numBodies(); ++k)
      for (std::size_t j = 0; j < k; ++j) {
        const double d = std::hypot(double(world.state.px[k]) - world.state.px[j],
                                    double(world.state.py[k]) - world.state.py[j],
                                    double(world.state.pz[k]) - world.state.pz[j]);
        if (d - 0.04 < gap) gap = d - 0.04, closest = k;
      }
  }).world;
  std::printf("batches into a moved cube: %zu bodies, %zu batches, closest pair %.3g m apart (ball %zu)\n",
              std::size_t(world.numBodies()), batches, gap, closest);
  EXPECT_EQ(world.numBodies(), 82u);
  EXPECT_EQ(batches, 3u);
  EXPECT_GE(gap, 0.0) << "ball " << closest << " overlaps one placed before it";
}
