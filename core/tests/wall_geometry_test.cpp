// SPDX-License-Identifier: MIT
// Walls as triangles for drawing (wall_geometry.hpp): a box gives its six faces, an open box its
// container, revolved walls lie on their surface and face the bodies, a plane is clipped by the
// others (the ground included), degenerate walls give nothing; the motion poses a turning drum.
#include "tumble/wall_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "tumble/mesh.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"

using namespace tumble;

namespace {

// The six inward planes of the box [lo, hi], less the faces in `open` ("-x", "+x", … order).
std::vector<WallDef> box(Vec3f lo, Vec3f hi, const std::string& open = "") {
  std::vector<WallDef> out;
  const float l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  const char* const names[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
  for (int f = 0; f < 6; ++f) {
    if (open.find(names[f]) != std::string::npos) continue;
    const int a = f / 2;
    float p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    p[a] = f % 2 ? h[a] : l[a];
    n[a] = f % 2 ? -1.0f : 1.0f;
    out.push_back(planeWall({p[0], p[1], p[2]}, {n[0], n[1], n[2]}));
  }
  return out;
}

Vec3f corner(const WallSurface& s, std::size_t t, int c) {
  const float* v = &s.triangles[9 * t + 3 * static_cast<std::size_t>(c)];
  return {v[0], v[1], v[2]};
}
Vec3f normalOf(const WallSurface& s, std::size_t t) {
  return cross(corner(s, t, 1) - corner(s, t, 0), corner(s, t, 2) - corner(s, t, 0));
}
double area(const WallSurface& s) {
  double a = 0.0;
  for (std::size_t t = 0; t < s.numTriangles(); ++t) a += 0.5 * norm(normalOf(s, t));
  return a;
}
Extent extentOf(const WallSurface& s) {
  Extent e;
  for (std::size_t t = 0; t < s.numTriangles(); ++t)
    for (int c = 0; c < 3; ++c) e.add(corner(s, t, c));
  return e;
}
Extent focusBox(Vec3f lo, Vec3f hi) {
  Extent e;
  e.add(lo);
  e.add(hi);
  return e;
}

}  // namespace

TEST(WallGeometry, ABoxGivesItsSixFacesExactly) {
  const Vec3f lo{-0.4f, -0.1f, 0.0f}, hi{0.4f, 0.1f, 0.6f};
  const std::vector<WallDef> walls = box(lo, hi);
  const std::vector<WallSurface> s = wallSurfaces(walls, focusBox({-0.3f, -0.05f, 0.1f}, {0.0f, 0.05f, 0.3f}));
  ASSERT_EQ(s.size(), 6u);
  const double side[3] = {0.8, 0.2, 0.6};
  for (int f = 0; f < 6; ++f) {
    SCOPED_TRACE("face " + std::to_string(f));
    const int a = f / 2;
    EXPECT_EQ(s[f].kind, WallKind::Plane);
    EXPECT_EQ(s[f].numTriangles(), 2u) << "a rectangle";
    EXPECT_NEAR(area(s[f]), side[(a + 1) % 3] * side[(a + 2) % 3], 1e-6);
    const Extent e = extentOf(s[f]);
    EXPECT_NEAR(e.lo.x, a == 0 && f % 2 ? hi.x : lo.x, 1e-6);
    EXPECT_NEAR(e.hi.x, a == 0 && f % 2 == 0 ? lo.x : hi.x, 1e-6);
    EXPECT_NEAR(e.lo.z, a == 2 && f % 2 ? hi.z : lo.z, 1e-6);
    EXPECT_NEAR(e.hi.z, a == 2 && f % 2 == 0 ? lo.z : hi.z, 1e-6);
    for (std::size_t t = 0; t < 2; ++t) {  // wound towards the inside: along the plane's normal
      const Vec3f n = normalOf(s[f], t);
      EXPECT_GT(dot(n, walls[f].normal), 0.99f * norm(n));
    }
    EXPECT_FALSE(s[f].motion.moves());
  }
}

TEST(WallGeometry, AnOpenBoxIsAContainerWithoutALid) {
  const Vec3f lo{-0.4f, -0.1f, 0.0f}, hi{0.4f, 0.1f, 0.6f};
  const std::vector<WallSurface> s = wallSurfaces(box(lo, hi, "+z"), focusBox({-0.39f, -0.08f, 0.0f}, {-0.23f, 0.08f, 0.45f}));
  ASSERT_EQ(s.size(), 5u);
  // The floor (the -z face) is exact: the four sides cut it.
  EXPECT_NEAR(area(s[4]), 0.8 * 0.2, 1e-6);
  // The sides have no face above them: they end at the drawing region, above the bodies, and
  // nothing is drawn at the open top (no surface lies in z = 0.6 only).
  for (int f = 0; f < 4; ++f) {
    SCOPED_TRACE("side " + std::to_string(f));
    const Extent e = extentOf(s[f]);
    EXPECT_NEAR(e.lo.z, 0.0, 1e-6);
    EXPECT_GT(e.hi.z, 0.45f);
    EXPECT_LT(e.hi.z, 1.0f) << "the region grows by a quarter of its largest side (0.8 m)";
  }
  for (const WallSurface& w : s) EXPECT_FALSE(extentOf(w).lo.z > 0.59f && extentOf(w).hi.z < 0.61f);
}

TEST(WallGeometry, ACylinderLiesOnItsSurfaceAndFacesTheBodies) {
  const Vec3f p{0.5f, -0.03f, 0.2f};
  const WallDef drum = revolvedWall(p, {0.0f, 0.06f, 0.0f}, 0.06f, 0.15f, 0.15f);
  for (const bool inside : {true, false}) {
    SCOPED_TRACE(inside ? "bodies inside" : "bodies outside (a post)");
    const Extent focus = inside ? focusBox({0.45f, -0.02f, 0.1f}, {0.55f, 0.02f, 0.2f})
                                : focusBox({0.9f, -0.02f, 0.1f}, {1.0f, 0.02f, 0.2f});
    const std::vector<WallSurface> s = wallSurfaces({drum}, focus);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0].kind, WallKind::Cylinder);
    ASSERT_EQ(s[0].numTriangles(), 2u * 96u);
    for (std::size_t t = 0; t < s[0].numTriangles(); ++t) {
      for (int c = 0; c < 3; ++c) {
        const Vec3f v = corner(s[0], t, c);
        EXPECT_NEAR(std::hypot(v.x - p.x, v.z - p.z), 0.15, 1e-6);
        EXPECT_GE(v.y, -0.03f - 1e-6f);
        EXPECT_LE(v.y, 0.03f + 1e-6f);
      }
      // The normal points towards the axis when the bodies are inside, away from it otherwise.
      const Vec3f n = normalOf(s[0], t), at = corner(s[0], t, 0);
      const float towardsAxis = dot(n, Vec3f{p.x - at.x, 0.0f, p.z - at.z});
      EXPECT_EQ(towardsAxis > 0.0f, inside) << "triangle " << t;
    }
    // Round: the area is the cylinder's within the tessellation's 0.07 %.
    EXPECT_NEAR(area(s[0]), 2 * M_PI * 0.15 * 0.06, 2 * M_PI * 0.15 * 0.06 * 1e-3);
  }
}

TEST(WallGeometry, ConesDisksAndRings) {
  const Extent above = focusBox({-0.05f, -0.05f, 0.1f}, {0.05f, 0.05f, 0.4f});
  const std::vector<WallSurface> s =
      wallSurfaces({revolvedWall({0, 0, 0}, {0, 0, 0.05f}, 0.05f, 0.065f, 0.1f),  // a hopper's cone
                    revolvedWall({0, 0, 0}, {0, 0, 1}, 0.0f, 0.055f, 0.1f),       // a ring (a silo's floor)
                    revolvedWall({0, 0, 0}, {0, 0, -2}, 0.0f, 0.0f, 0.1f),        // a disk, normal given downwards
                    revolvedWall({0, 0, 0}, {0, 0, 1}, 1.0f, 0.0f, 0.2f)},        // a cone from a point
                   above, WallTessellation{32, 0.25f});
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].kind, WallKind::Cone);
  EXPECT_EQ(s[1].kind, WallKind::Disk);
  EXPECT_EQ(s[2].kind, WallKind::Disk);
  EXPECT_EQ(s[3].kind, WallKind::Cone);
  EXPECT_EQ(s[0].numTriangles(), 64u);
  EXPECT_EQ(s[1].numTriangles(), 64u);
  EXPECT_EQ(s[2].numTriangles(), 32u) << "a full disk: one triangle per segment";
  EXPECT_EQ(s[3].numTriangles(), 32u) << "a cone from a point: one triangle per segment";
  for (std::size_t t = 0; t < s[1].numTriangles(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Vec3f v = corner(s[1], t, c);
      const float r = std::hypot(v.x, v.y);
      EXPECT_EQ(v.z, 0.0f);
      EXPECT_TRUE(std::abs(r - 0.055f) < 1e-6f || std::abs(r - 0.1f) < 1e-6f) << r;
    }
  // The ring and the disk face the bodies above them, whichever way their normal was given.
  for (const std::size_t k : {1u, 2u})
    for (std::size_t t = 0; t < s[k].numTriangles(); ++t) EXPECT_GT(normalOf(s[k], t).z, 0.0f);
  // A cone's triangles lie on it: ρ = 0.065 + 0.7 z.
  for (std::size_t t = 0; t < s[0].numTriangles(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Vec3f v = corner(s[0], t, c);
      EXPECT_NEAR(std::hypot(v.x, v.y), 0.065 + 0.7 * v.z, 1e-6);
    }
}

TEST(WallGeometry, ATiltedPlaneIsClippedByTheGround) {
  // The ground z >= 0 and a plane through the origin tilted by 45 degrees (the bodies above it).
  const std::vector<WallDef> walls = {planeWall({0, 0, 0}, {0, 0, 1}), planeWall({0, 0, 0}, {-1, 0, 1})};
  const std::vector<WallSurface> s = wallSurfaces(walls, focusBox({-1, -0.5f, 0.5f}, {0, 0.5f, 1.5f}));
  ASSERT_EQ(s.size(), 2u);
  ASSERT_GT(s[1].numTriangles(), 0u);
  const Extent e = extentOf(s[1]);
  EXPECT_NEAR(e.lo.z, 0.0, 1e-6) << "cut at the ground";
  EXPECT_GT(e.hi.z, 0.5f) << "up beside the bodies";
  for (std::size_t t = 0; t < s[1].numTriangles(); ++t)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(corner(s[1], t, c).x, corner(s[1], t, c).z, 1e-5) << "on the plane x = z";
  // The ground is cut by the tilted plane in turn: only x <= z, i.e. x <= 0, is left.
  EXPECT_LE(extentOf(s[0]).hi.x, 1e-6f);
  EXPECT_LT(extentOf(s[0]).lo.x, -1.0f);
}

TEST(WallGeometry, ALonePlaneIsAFinitePatchAboutTheBodies) {
  const std::vector<WallSurface> s = wallSurfaces({planeWall({0, 0, -2}, {0, 0, 1})}, focusBox({-1, -1, 0}, {1, 1, 2}));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].numTriangles(), 2u);
  const Extent e = extentOf(s[0]);
  // The region: the focus (2 × 2 × 2) grown by a quarter of its largest side, 0.5 m.
  EXPECT_NEAR(e.lo.x, -1.5, 1e-6);
  EXPECT_NEAR(e.hi.y, 1.5, 1e-6);
  EXPECT_EQ(e.lo.z, -2.0f);
  EXPECT_EQ(e.hi.z, -2.0f);
}

TEST(WallGeometry, EmptyAndDegenerateInputsGiveNoTriangles) {
  EXPECT_TRUE(wallSurfaces({}, Extent{}).empty());
  EXPECT_TRUE(wallSurfaces({}, focusBox({0, 0, 0}, {1, 1, 1})).empty());
  const float nan = std::nanf("");
  const std::vector<WallSurface> s = wallSurfaces(
      {planeWall({0, 0, 0}, {0, 0, 0}),                                  // zero normal
       planeWall({nan, 0, 0}, {0, 0, 1}),                                // non-finite point
       revolvedWall({0, 0, 0}, {0, 0, 1}, 1.0f, 0.0f, 0.0f),        // zero radii: a line
       revolvedWall({0, 0, 0}, {0, 0, 0}, 1.0f, 1.0f, 1.0f),        // zero axis
       revolvedWall({0, 0, 0}, {0, 0, 1}, 0.0f, 0.5f, 0.5f),        // a ring of no width
       planeWall({0, 0, 1}, {0, 0, 1}), planeWall({0, 0, 2}, {0, 0, 1})},  // z >= 2 leaves nothing of z = 1
      Extent{});
  ASSERT_EQ(s.size(), 7u);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(s[k].numTriangles(), 0u) << "wall " << k;
  EXPECT_EQ(s[6].numTriangles(), 2u);
  // Without a focus a lone plane is a patch about its own point, 1 m on every side.
  const std::vector<WallSurface> lone = wallSurfaces({planeWall({0, 0, 2}, {0, 0, 1})}, Extent{});
  ASSERT_EQ(lone[0].numTriangles(), 2u);
  EXPECT_NEAR(area(lone[0]), 4.0, 1e-6);
}

TEST(WallGeometry, ATurningDrumIsPosedAndTheGroundIsLeftOut) {
  Scene scene = readSceneFile(std::string(TUMBLE_SOURCE_DIR) + "/scenes/drum.toml");
  scene.ground.enabled = true;  // the ground clips, and is not drawn as a wall
  scene.ground.height = -1.0f;
  const std::vector<WallSurface> s = sceneWallSurfaces(scene, sceneBodiesExtent(scene));
  ASSERT_EQ(s.size(), scene.walls.size());
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].kind, WallKind::Cylinder);
  EXPECT_EQ(s[1].kind, WallKind::Disk);
  const WallMotion& m = s[0].motion;
  EXPECT_TRUE(m.moves());
  EXPECT_EQ(m.angularVelocity.y, 2.0f);
  EXPECT_EQ(m.angularVelocity.x, 0.0f);
  EXPECT_EQ(m.start, 0.5);
  EXPECT_TRUE(std::isinf(m.stop));
  // Before start: at rest. A quarter turn about +y (pi/4 s after start) takes +x to -z.
  const Vec3f rim{0.15f, 0.0f, 0.0f};
  EXPECT_TRUE(wallPose(m, 0.3).identity());
  const Vec3f q = wallPose(m, 0.5 + M_PI / 4).apply(rim);
  EXPECT_NEAR(q.x, 0.0, 1e-6);
  EXPECT_NEAR(q.z, -0.15, 1e-6);
  // A stop holds the pose from then on.
  WallMotion held = m;
  held.stop = 1.0;
  const Vec3f a = wallPose(held, 1.0).apply(rim), b = wallPose(held, 7.0).apply(rim);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.z, b.z);
  // And a box scene gives five faces, the sides cut by the drawing region.
  const Scene boxScene = readSceneFile(std::string(TUMBLE_SOURCE_DIR) + "/scenes/box.toml");
  const std::vector<WallSurface> box = sceneWallSurfaces(boxScene, World::fromScene(boxScene).bodiesExtent);
  ASSERT_EQ(box.size(), 5u);
  for (const WallSurface& w : box) EXPECT_EQ(w.numTriangles(), 2u);
  EXPECT_NEAR(area(box[4]), 0.8 * 0.2, 1e-6);
}

// Walls that move as a whole are drawn moving: a piston with its velocity, every face of a box
// moving as a whole with the box's (those along the motion too), a cylinder swept sideways with
// its; a belt (a plane whose surface only moves) stands still. A mesh wall is drawn as its
// triangles in world coordinates (hopper-mesh.toml's hopper, 480 facets), kind Mesh.
TEST(WallGeometry, MovingWallsAndMeshesAreDrawnAsTheyAre) {
  const Scene s = parseScene(
      "[scene]\ndt = 1e-4\nsteps = 10\n[[shape]]\nname = \"b\"\n[[shape.sphere]]\nradius = 0.1\nmass = 1\n"
      "[[body]]\nshape = \"b\"\nposition = [0, 0, 0.5]\n"
      "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nvelocity = [0, 0, 0.5]\nstop = 1\n"
      "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 2]\nnormal = [0, 0, -1]\nvelocity = [1, 0, 0]\n"
      "[[wall]]\ntype = \"box\"\nmin = [-1, -1, -1]\nmax = [1, 1, 3]\nopen = [\"+z\", \"-z\"]\nvelocity = [0, 0.5, 0]\n"
      "[[wall]]\ntype = \"cylinder\"\npoint = [0, 0, -1]\naxis = [0, 0, 4]\nradius = 3\nvelocity = [0.2, 0, 0]\n",
      "moving.toml");
  const std::vector<WallSurface> w = sceneWallSurfaces(s, sceneBodiesExtent(s));
  ASSERT_EQ(w.size(), 7u) << "a piston, a belt, four box faces, a cylinder";
  EXPECT_EQ(w[0].motion.velocity.z, 0.5f) << "the piston";
  EXPECT_EQ(w[0].motion.stop, 1.0);
  EXPECT_FALSE(w[1].motion.moves()) << "the belt's plane stands still";
  for (std::size_t k = 2; k < 6; ++k) EXPECT_EQ(w[k].motion.velocity.y, 0.5f) << "box face " << k;
  EXPECT_EQ(w[6].motion.velocity.x, 0.2f) << "the cylinder";
  const Vec3f p = wallPose(w[0].motion, 2.0).apply(Vec3f{0, 0, 0});
  EXPECT_FLOAT_EQ(p.z, 0.5f) << "the piston stopped at t = 1, 0.5 m up";

  const Scene h = readSceneFile(std::string(TUMBLE_SOURCE_DIR) + "/scenes/hopper-mesh.toml");
  const std::vector<WallSurface> hw = sceneWallSurfaces(h, sceneBodiesExtent(h));
  const auto mesh = std::find_if(hw.begin(), hw.end(), [](const WallSurface& x) { return x.kind == WallKind::Mesh; });
  ASSERT_NE(mesh, hw.end());
  EXPECT_EQ(mesh->numTriangles(), 480u);
  EXPECT_FALSE(mesh->motion.moves());
}

// A mesh that moves is drawn moving: its motion is its velocity, its angular velocity and its
// pivot (its position unless given), from start to stop; the drawing's pose at a time puts a
// vertex where the kernels' pose (setWallMotion(), MeshPose) has it.
TEST(WallGeometry, AMovingMeshIsDrawnWhereTheKernelsHaveIt) {
  auto tri = std::make_shared<TriangleMesh>();
  tri->file = "plate";
  tri->vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  tri->triangles = {0, 1, 2};
  tri->source = {1};
  WallDef w;
  w.shape = WallDef::Shape::Mesh;
  w.mesh = tri;
  w.contact.enabled = true;
  w.point = {0.5f, -0.25f, 1.0f};
  w.velocity = {0.0f, 0.4f, -0.1f};
  w.meshAngularVelocity = {1.0f, 0.0f, 2.0f};
  w.start = 0.25;
  w.stop = 1.5;
  Scene s;
  s.walls = {w};
  const std::vector<WallSurface> drawn = sceneWallSurfaces(s, Extent{});
  ASSERT_EQ(drawn.size(), 1u);
  const WallMotion& m = drawn[0].motion;
  EXPECT_EQ(m.velocity.y, 0.4f);
  EXPECT_EQ(m.angularVelocity.z, 2.0f);
  EXPECT_EQ(m.pivot.x, 0.5f) << "the pivot by default: its position";
  EXPECT_EQ(m.start, 0.25);
  EXPECT_EQ(m.stop, 1.5);
  std::vector<Wall> walls = kernelWalls(s, LocalFrame{});
  std::vector<MeshPose> pose(1, MeshPose{});
  for (const double t : {0.0, 0.8, 3.0}) {
    setWallMotion(walls, s, t, pose.data());
    const Vec3f y = meshWallTriangles(w)[2];  // (1, 1, 0) placed: (1.5, 0.75, 1)
    const Vec3f drawnAt = wallPose(m, t).apply(y);
    const Vec3f kernels = pose[0].posed ? mul(pose[0].rot, y - pose[0].pivot) + pose[0].centre : y;
    EXPECT_NEAR(drawnAt.x, kernels.x, 1e-6) << "t = " << t;
    EXPECT_NEAR(drawnAt.y, kernels.y, 1e-6) << "t = " << t;
    EXPECT_NEAR(drawnAt.z, kernels.z, 1e-6) << "t = " << t;
  }
}
