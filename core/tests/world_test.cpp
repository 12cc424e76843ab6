// SPDX-License-Identifier: MIT
// Mass properties (SPEC §1) against analytic values, the restitution–damping relation, and the
// time-step check.
#include <gtest/gtest.h>

#include <cmath>

#include "tumble/error.hpp"
#include "tumble/world.hpp"

using namespace tumble;

namespace {

Scene oneBody(const ShapeDef& shape) {
  Scene s;
  s.shapes = {shape};
  s.bodies = {BodyDef{}};
  return s;
}

}  // namespace

TEST(World, SingleSphereIsASolidSphere) {
  const World w = World::fromScene(oneBody(ShapeDef{"s", {SphereDef{{1, 2, 3}, 0.5f, 2.0f, 0.5f}}}));
  const float i = 0.4f * 2.0f * 0.25f;  // 2/5 m r²
  EXPECT_FLOAT_EQ(w.inertia[0].xx, i);
  EXPECT_FLOAT_EQ(w.inertia[0].yy, i);
  EXPECT_FLOAT_EQ(w.inertia[0].zz, i);
  EXPECT_FLOAT_EQ(w.inertia[0].xy, 0.0f);
  EXPECT_FLOAT_EQ(w.invInertia[0].xx, 1.0f / i);
  EXPECT_FLOAT_EQ(w.ux[0], 0.0f);  // the offset is measured from the centre of mass
  EXPECT_FALSE(w.hasClumps);
}

TEST(World, DumbbellCentreOfMassAndInertia) {
  // Masses 1 and 3 at x = 0 and x = 4: centre of mass at x = 3, offsets −3 and +1.
  const World w = World::fromScene(
      oneBody(ShapeDef{"d", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}, SphereDef{{4, 0, 0}, 0.5f, 3.0f, 0.5f}}}));
  EXPECT_FLOAT_EQ(w.ux[0], -3.0f);
  EXPECT_FLOAT_EQ(w.ux[1], 1.0f);
  EXPECT_FLOAT_EQ(w.bodyMass[0], 4.0f);
  const double spheres = 0.4 * 1.0 * 0.25 + 0.4 * 3.0 * 0.25;
  EXPECT_NEAR(w.inertia[0].xx, spheres, 1e-6);                          // along the axis
  EXPECT_NEAR(w.inertia[0].yy, spheres + 1.0 * 9.0 + 3.0 * 1.0, 1e-5);  // parallel axis terms
  EXPECT_NEAR(w.inertia[0].zz, w.inertia[0].yy, 1e-6);
  EXPECT_TRUE(w.hasClumps);
}

TEST(World, InitialAngularMomentumIsInertiaTimesOmega) {
  Scene s = oneBody(ShapeDef{"d", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}, SphereDef{{4, 0, 0}, 0.5f, 3.0f, 0.5f}}});
  s.bodies[0].angularVelocity = {0.0f, 0.0f, 2.0f};
  const World w = World::fromScene(s);
  EXPECT_NEAR(w.state.lz[0], 2.0 * w.inertia[0].zz, 1e-4);
}

TEST(World, RejectsBadScenes) {
  Scene empty;
  EXPECT_THROW(World::fromScene(empty), Error);
  EXPECT_THROW(World::fromScene(oneBody(ShapeDef{"s", {SphereDef{{0, 0, 0}, -1.0f, 1.0f, 0.5f}}})), Error);
  EXPECT_THROW(World::fromScene(oneBody(ShapeDef{"s", {SphereDef{{0, 0, 0}, 1.0f, 0.0f, 0.5f}}})), Error);
  EXPECT_THROW(World::fromScene(oneBody(ShapeDef{"s", {SphereDef{{0, 0, 0}, 1.0f, 1.0f, 1.5f}}})), Error);
}

TEST(World, DampingGivesTheRequestedRestitution) {
  for (double e : {0.05, 0.2, 0.5, 0.9, 1.0}) {
    const double c = dampingForRestitution(e, 1e5, 0.3);
    EXPECT_NEAR(restitutionForDamping(c, 1e5, 0.3), e, 1e-12) << "e = " << e;
  }
  EXPECT_EQ(dampingForRestitution(1.0, 1e5, 0.3), 0.0);
}

TEST(World, TimeStepWarning) {
  Scene s = oneBody(ShapeDef{"s", {SphereDef{{0, 0, 0}, 0.1f, 0.5f, 0.5f}}});
  s.ground.enabled = true;
  s.ground.stiffness = 1.0e4f;
  const double tc = 3.14159265358979 * std::sqrt(0.5 / 1.0e4);  // ≈ 22 ms
  s.dt = static_cast<float>(tc / 50.0);
  EXPECT_NEAR(shortestContactTime(World::fromScene(s)), tc, 1e-9);
  EXPECT_TRUE(timeStepWarning(World::fromScene(s)).empty());
  s.dt = static_cast<float>(tc / 4.0);
  const std::string w = timeStepWarning(World::fromScene(s));
  EXPECT_NE(w.find("use dt <="), std::string::npos) << w;
}

// The local frame (docs/model.md#precision): a scene near the origin keeps its coordinates; a
// compact scene far away is moved, per axis, to its bounding-box centre, with the ground and
// the pull centre; toWorld undoes it.
TEST(World, LocalFrameMovesOnlyFarAxes) {
  Scene s;
  s.ground.enabled = true;
  s.ground.height = 1.0e5f;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}}};
  BodyDef a, b;
  a.position = {1.0f, 2.0f, 3.0f};
  b.position = {4.0f, -2.0f, 1.0f};
  s.bodies = {a, b};
  const World near = World::fromScene(s);
  EXPECT_FALSE(LocalFrame::of(near).active()) << "within 4 × the extent of the origin";
  const World same = toLocal(near, LocalFrame::of(near));
  EXPECT_EQ(same.state.px, near.state.px);
  EXPECT_EQ(same.params.ground.height, near.params.ground.height);

  s.bodies[0].position = {100000.0f, 2.0f, 100000.5f};
  s.bodies[1].position = {100004.0f, -2.0f, 100001.5f};
  const World far = World::fromScene(s);
  const LocalFrame f = LocalFrame::of(far);
  EXPECT_EQ(f.x, 100002.0);
  EXPECT_EQ(f.y, 0.0) << "y is near the origin: that axis stays";
  EXPECT_EQ(f.z, 100000.75) << "the ground (1e5) is part of the z range";
  const World local = toLocal(far, f);
  EXPECT_EQ(local.state.px[0], -2.0f);
  EXPECT_EQ(local.state.py[0], 2.0f);
  EXPECT_EQ(local.state.pz[1], 0.75f);
  EXPECT_EQ(local.params.ground.height, -0.75f);
  EXPECT_EQ(local.params.pulls.centre.x, -100002.0f);
  EXPECT_EQ(local.params.pulls.centre.y, 0.0f);
  BodyState back = local.state;
  toWorld(back, f);
  EXPECT_EQ(back.px, far.state.px);
  EXPECT_EQ(back.pz, far.state.pz);
}

// What the bodies move towards is part of the frame's box: a ball dropped from 20 m onto the
// ground lands near the origin, where float resolves best, so no frame; likewise an axis on
// which a pull (towards the origin) is on at load.
TEST(World, LocalFrameKeepsTheGroundAndThePullCentreInTheBox) {
  Scene s;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.01f, 0.001f, 0.5f}}}};
  BodyDef b;
  b.position = {0, 0, 20.0f};
  s.bodies = {b};
  EXPECT_EQ(LocalFrame::of(World::fromScene(s)).z, 20.0) << "no ground: the ball is far from everything";
  s.ground.enabled = true;
  EXPECT_FALSE(LocalFrame::of(World::fromScene(s)).active()) << "it will land on the ground at z = 0";

  s.ground.enabled = false;
  s.bodies[0].position = {100.0f, 100.0f, 0.0f};
  const LocalFrame free = LocalFrame::of(World::fromScene(s));
  EXPECT_EQ(free.x, 100.0);
  EXPECT_EQ(free.y, 100.0);
  s.pulls.active = kPullX;
  const LocalFrame pulled = LocalFrame::of(World::fromScene(s));
  EXPECT_EQ(pulled.x, 0.0) << "the x pull draws it to x = 0";
  EXPECT_EQ(pulled.y, 0.0) << "the box now spans 100 m, so y = 100 m is no longer far either";
}
