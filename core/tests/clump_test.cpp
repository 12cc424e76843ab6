// SPDX-License-Identifier: MIT
// Tests of clumps of spheres from closed meshes (tumble/clump.hpp): a mesh of a sphere gives one
// sphere; every sphere lies inside the solid (a box: in closed form); the surface deviation
// shrinks as spheres are added; the same spheres every time and on 1 and 2 threads; the shape
// table written is read back bit for bit with the mesh's mass properties; bad requests refused.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "tumble/clump.hpp"
#include "tumble/error.hpp"
#include "tumble/mesh.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"
#include "mesh_test_util.hpp"

namespace {

using mesh_test::objMesh;
using mesh_test::V;

/// A UV sphere of radius R about c: n segments around, n/2 from pole to pole.
tumble::TriangleMesh uvSphere(double R, V c, int n) {
  const double pi = 3.14159265358979323846;
  std::vector<V> vs{{c[0], c[1], c[2] + R}, {c[0], c[1], c[2] - R}};
  const int rings = n / 2 - 1;
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < n; ++j) {
      const double th = pi * i / (n / 2), ph = 2 * pi * j / n;
      vs.push_back({c[0] + R * std::sin(th) * std::cos(ph), c[1] + R * std::sin(th) * std::sin(ph), c[2] + R * std::cos(th)});
    }
  const auto at = [&](int i, int j) { return 2 + (i - 1) * n + (j % n); };
  std::vector<std::array<int, 3>> ts;
  for (int j = 0; j < n; ++j) {
    ts.push_back({0, at(1, j), at(1, j + 1)});
    ts.push_back({1, at(rings, j + 1), at(rings, j)});
    for (int i = 1; i < rings; ++i) {
      ts.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      ts.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return objMesh(vs, ts, "ball.obj");
}

/// A box [0, a] x [0, b] x [0, c].
tumble::TriangleMesh box(double a, double b, double c) {
  std::vector<V> vs;
  std::vector<mesh_test::Tri> ts;
  mesh_test::addBox({0, 0, 0}, {a, b, c}, vs, ts);
  return objMesh(vs, ts, "box.obj");
}

}  // namespace

// A mesh of a sphere (radius 0.5, 64 x 32 facets) with a tolerance of 5 % of its radius: one
// sphere, at the centre within a voxel, its radius the polyhedron's inscribed one (within 0.3 %
// of 0.5), and the surface within the tolerance of it.
TEST(Clump, AMeshOfASphereGivesOneSphere) {
  const V c{0.2, -0.1, 0.3};
  tumble::ClumpOptions o;
  o.tolerance = 0.025;
  const tumble::Clump k = tumble::clumpFromMesh(uvSphere(0.5, c, 64), o);
  ASSERT_EQ(k.spheres.size(), 1u);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(k.spheres[0].centre[a], c[a], k.voxel);
  EXPECT_NEAR(k.spheres[0].radius, 0.5, 0.0015 + k.voxel);
  EXPECT_LT(k.quality.largestDeviation, o.tolerance);
  std::printf("sphere: radius %.5f, surface deviation largest %.5f mean %.5f, volume ratio %.4f\n", k.spheres[0].radius,
              k.quality.largestDeviation, k.quality.meanDeviation, k.quality.volumeRatio);
}

// A box 1 x 0.375 x 0.25 with more and more spheres: each inside the box (c ± r within it, in
// closed form), the largest and the mean surface deviation never larger with more spheres and
// the union's share of the volume never smaller; at 32 spheres the mean deviation is below a
// quarter of the one-sphere clump's. The same spheres again, and on 1 and 2 threads.
TEST(Clump, MoreSpheresFitTheSurfaceCloser) {
  const double dims[3] = {1.0, 0.375, 0.25};  // exact in float, as the mesh keeps them
  const tumble::TriangleMesh mesh = box(dims[0], dims[1], dims[2]);
  double lastLargest = 1e30, lastMean = 1e30, lastVolume = 0.0, firstMean = 0.0;
  for (std::uint32_t n : {1u, 2u, 4u, 8u, 16u, 32u}) {
    tumble::ClumpOptions o;
    o.spheres = n;
    const tumble::Clump k = tumble::clumpFromMesh(mesh, o);
    ASSERT_EQ(k.spheres.size(), n);
    for (const tumble::ClumpSphere& s : k.spheres)
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(s.centre[a] - s.radius, -1e-12) << n << " spheres";
        EXPECT_LE(s.centre[a] + s.radius, dims[a] + 1e-12) << n << " spheres";
      }
    std::printf("box, %2u spheres: surface deviation largest %.4f mean %.4f, volume ratio %.3f\n", n,
                k.quality.largestDeviation, k.quality.meanDeviation, k.quality.volumeRatio);
    EXPECT_LE(k.quality.largestDeviation, lastLargest + 1e-12);
    EXPECT_LE(k.quality.meanDeviation, lastMean + 1e-12);
    EXPECT_GE(k.quality.volumeRatio, lastVolume - 1e-12);
    if (n == 1) firstMean = k.quality.meanDeviation;
    lastLargest = k.quality.largestDeviation, lastMean = k.quality.meanDeviation, lastVolume = k.quality.volumeRatio;
  }
  EXPECT_LT(lastMean, 0.25 * firstMean);
  tumble::ClumpOptions o;
  o.spheres = 12;
  std::vector<tumble::ClumpSphere> one, two;
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
    one = tumble::clumpFromMesh(mesh, o).spheres;
  }
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
    two = tumble::clumpFromMesh(mesh, o).spheres;
  }
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].radius, two[i].radius);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(one[i].centre[a], two[i].centre[a]);
  }
}

// The table tumble clump writes, read back as a scene's shape: the same spheres (bit for bit in
// float) and the mesh's mass properties at the density (a box of 2500 kg/m^3: m = 2500 a b c,
// I_xx = m (b² + c²) / 12), the spheres sharing the mass by volume.
TEST(Clump, TheShapeTableReadsBack) {
  tumble::ClumpOptions o;
  o.spheres = 6;
  const tumble::Clump k = tumble::clumpFromMesh(box(1.0, 0.4, 0.25), o);
  // A name with quotes, a backslash and control characters, a comment with a carriage return
  // and a delete: TOML takes neither raw (a basic string escapes them, a comment cannot hold them).
  const std::string name = "brick \"B\" \\ tab\tbell\x07" "del\x7f";
  const tumble::ShapeDef shape = tumble::clumpShape(k, name, 2500.0);
  const std::string text = "[scene]\ndt = 1e-4\nsteps = 1\n" +
                           tumble::shapeToml(shape, "a comment\r\nof two lines \x7f and a path") +
                           "[[body]]\nshape = \"brick \\\"B\\\" \\\\ tab\\tbell\\u0007del\\u007f\"\nposition = [0, 0, 1]\n";
  const tumble::Scene s = tumble::parseScene(text, "brick.toml");
  ASSERT_EQ(s.shapes.size(), 1u);
  const tumble::ShapeDef& back = s.shapes[0];
  EXPECT_EQ(back.name, name);
  ASSERT_EQ(back.spheres.size(), shape.spheres.size());
  for (std::size_t i = 0; i < back.spheres.size(); ++i) {
    EXPECT_EQ(back.spheres[i].radius, shape.spheres[i].radius);
    EXPECT_EQ(back.spheres[i].offset.x, shape.spheres[i].offset.x);
    EXPECT_EQ(back.spheres[i].offset.z, shape.spheres[i].offset.z);
    EXPECT_EQ(back.spheres[i].mass, shape.spheres[i].mass);
  }
  ASSERT_TRUE(back.solid.has_value());
  const double m = 2500.0 * 1.0 * 0.4 * 0.25;
  EXPECT_NEAR(back.solid->mass, m, 1e-6 * m);
  EXPECT_NEAR(back.solid->centre[0], 0.5, 1e-9);
  EXPECT_NEAR(back.solid->inertia[0], m * (0.16 + 0.0625) / 12, 1e-6 * m);
  EXPECT_NEAR(back.solid->inertia[2], m * (1.0 + 0.16) / 12, 1e-6 * m);
}

// A sphere count that ends the placement says how deep the part it leaves uncovered is: more than
// the tolerance asked for, or 0 when the tolerance is reached first.
TEST(Clump, SaysWhatTheSphereCountLeavesUncovered) {
  const tumble::TriangleMesh mesh = box(1.0, 0.25, 0.25);
  tumble::ClumpOptions o;
  o.spheres = 1;
  o.tolerance = 0.01;
  const tumble::Clump one = tumble::clumpFromMesh(mesh, o);
  ASSERT_EQ(one.spheres.size(), 1u);
  std::printf("a 1 x 0.25 x 0.25 box, 1 sphere: a part %.4f m deep left uncovered\n", one.uncoveredDepth);
  EXPECT_GT(one.uncoveredDepth, 0.1) << "the box's ends, a half-width deep";
  o.spheres = 200;
  const tumble::Clump many = tumble::clumpFromMesh(mesh, o);
  EXPECT_LT(many.spheres.size(), 200u);
  EXPECT_EQ(many.uncoveredDepth, 0.0) << "the tolerance ended it";
}

// fill = surface (clump.hpp): a layer of spheres of one radius ρ under the surface, at most
// 1.1 (D − 1.5 voxels). On the box: every sphere inside it, nearly all of the layer's radius within 1.5
// voxels, the surface within the tolerance (as measured: the radius is chosen so), no fewer
// spheres for a smaller tolerance; a sphere count alone takes the smallest layer radius whose
// layer fits in it; a tolerance finer than the voxels allow is refused with the resolution it
// needs. A plate 2.5 voxels thick, whose faces the inside fill leaves far from as many spheres,
// gets its layer on its mid-plane. The same spheres every time.
TEST(Clump, ASurfaceLayerCoversFacesAndThinParts) {
  const double dims[3] = {1.0, 0.375, 0.25};
  const tumble::TriangleMesh mesh = box(dims[0], dims[1], dims[2]);
  double last = 0.0;
  for (const double tol : {0.1, 0.06}) {
    tumble::ClumpOptions o;
    o.tolerance = tol;
    o.fill = tumble::ClumpFill::Surface;
    const tumble::Clump k = tumble::clumpFromMesh(mesh, o);
    const double rho = 1.1 * (tol - 1.5 * k.voxel);  // the largest radius tried
    std::size_t off = 0;
    for (const tumble::ClumpSphere& s : k.spheres) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(s.centre[a] - s.radius, -1e-12);
        EXPECT_LE(s.centre[a] + s.radius, dims[a] + 1e-12);
      }
      off += std::abs(s.radius - k.layerRadius) > 1.5 * k.voxel ? 1u : 0u;
    }
    std::printf("box, surface fill, tolerance %g: %zu spheres of radius %.4g (layer %.4g), %zu off by more than 1.5 "
                "voxels (%.4g); surface deviation largest %.4f mean %.4f, volume ratio %.3f\n",
                tol, k.spheres.size(), rho, k.layerRadius, off, k.voxel, k.quality.largestDeviation,
                k.quality.meanDeviation, k.quality.volumeRatio);
    EXPECT_LE(k.layerRadius, rho);
    EXPECT_LT(off, k.spheres.size() / 10 + 1);
    EXPECT_LE(k.quality.largestDeviation, tol);
    EXPECT_GE(k.spheres.size(), last) << "a smaller tolerance, no fewer spheres";
    last = double(k.spheres.size());
  }
  tumble::ClumpOptions o;
  o.fill = tumble::ClumpFill::Surface;
  o.spheres = 100;
  const tumble::Clump counted = tumble::clumpFromMesh(mesh, o);
  std::printf("box, surface fill, at most 100 spheres: %zu of radius %.4g, deviation largest %.4f\n",
              counted.spheres.size(), counted.layerRadius, counted.quality.largestDeviation);
  EXPECT_LE(counted.spheres.size(), 100u);
  EXPECT_GT(counted.spheres.size(), 50u) << "the smallest radius that fits: most of the count used";
  const tumble::Clump again = tumble::clumpFromMesh(mesh, o);
  ASSERT_EQ(again.spheres.size(), counted.spheres.size());
  for (std::size_t i = 0; i < again.spheres.size(); ++i) {
    EXPECT_EQ(again.spheres[i].radius, counted.spheres[i].radius);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(again.spheres[i].centre[a], counted.spheres[i].centre[a]);
  }
  // A tolerance under 1.5 voxels' layer: refused, with the resolution it needs.
  tumble::ClumpOptions fine;
  fine.fill = tumble::ClumpFill::Surface;
  fine.tolerance = 0.01;
  try {
    (void)tumble::clumpFromMesh(mesh, fine);
    ADD_FAILURE() << "a layer finer than the voxels was accepted";
  } catch (const tumble::Error& e) {
    EXPECT_NE(std::string(e.what()).find("give a resolution of at least 300"), std::string::npos) << e.what();
  }
  // The plate: 0.5 x 0.5 x 0.02 (voxels of 1/128 m).
  const tumble::TriangleMesh plate = box(0.5, 0.5, 0.02);
  tumble::ClumpOptions p;
  p.tolerance = 0.04;
  p.fill = tumble::ClumpFill::Surface;
  const tumble::Clump layer = tumble::clumpFromMesh(plate, p);
  tumble::ClumpOptions q;
  q.spheres = std::uint32_t(layer.spheres.size());
  const tumble::Clump filled = tumble::clumpFromMesh(plate, q);
  std::printf("plate 0.02 thick: surface fill %zu spheres, deviation largest %.4f mean %.4f; inside fill %zu spheres, "
              "largest %.4f mean %.4f\n",
              layer.spheres.size(), layer.quality.largestDeviation, layer.quality.meanDeviation, filled.spheres.size(),
              filled.quality.largestDeviation, filled.quality.meanDeviation);
  for (const tumble::ClumpSphere& s : layer.spheres) {
    EXPECT_GE(s.centre[2] - s.radius, -1e-12);
    EXPECT_LE(s.centre[2] + s.radius, 0.02 + 1e-12);
  }
  EXPECT_LT(layer.quality.meanDeviation, 0.5 * filled.quality.meanDeviation);
}

TEST(Clump, BadRequestsAreRefused) {
  const tumble::TriangleMesh mesh = box(1, 1, 1);
  EXPECT_THROW(tumble::clumpFromMesh(mesh, tumble::ClumpOptions{}), tumble::Error);
  tumble::ClumpOptions o;
  o.spheres = 3;
  o.resolution = 4;
  EXPECT_THROW(tumble::clumpFromMesh(mesh, o), tumble::Error);
  // An open box: refused by the solid's checks, with the file.
  const std::string open = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n";
  o.resolution = 32;
  try {
    tumble::clumpFromMesh(tumble::parseMesh(open, "open.obj"), o);
    ADD_FAILURE() << "an open mesh was accepted";
  } catch (const tumble::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open.obj:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is open"), std::string::npos) << e.what();
  }
}

namespace {
// A scratch folder of this test binary, with the brick [0, 0.25] x [0, 0.125] x [0, 0.0625] (exact in float).
std::string brickFolder() {
  static const std::string d = [] {
    const std::string p = ::testing::TempDir() + "tumble_clump_" + std::to_string(::getpid());
    std::filesystem::create_directories(p);
    std::ofstream out(p + "/brick.obj");
    out << "v 0 0 0\nv 0.25 0 0\nv 0 0.125 0\nv 0.25 0.125 0\nv 0 0 0.0625\nv 0.25 0 0.0625\nv 0 0.125 0.0625\n"
           "v 0.25 0.125 0.0625\nf 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::ofstream open(p + "/open.obj");
    open << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n";
    return p;
  }();
  return d;
}
const char* kHead = "[scene]\ndt = 1e-4\nsteps = 10\n[ground]\n";  // lines 1-4
const char* kBody = "[[body]]\nshape = \"brick\"\nposition = [0, 0, 1]\n";
}  // namespace

// [[shape]] mesh = "FILE": the clump tumble clump writes, made at load: the same spheres, the
// mesh's mass properties at the density (m = 2000 a b c, I_zz = m (a² + b²) / 12), the shape's
// elasticity on every sphere, twice scaled: 8 times the mass.
TEST(Clump, AShapeFromAMeshFile) {
  const std::string shape = "[[shape]]\nname = \"brick\"\nmesh = \"brick.obj\"\nspheres = 5\ndensity = 2000\nelasticity = 0.3\n";
  const tumble::Scene s =
      tumble::parseScene(std::string(kHead) + shape + kBody, "bricks.toml", {}, tumble::OverrideSource::CommandLine,
                         brickFolder());
  ASSERT_EQ(s.shapes.size(), 1u);
  const tumble::ShapeDef& sh = s.shapes[0];
  tumble::ClumpOptions o;
  o.spheres = 5;
  const tumble::ShapeDef want =
      tumble::clumpShape(tumble::clumpFromMesh(tumble::readMeshFile(brickFolder() + "/brick.obj"), o), "brick", 2000.0);
  ASSERT_EQ(sh.spheres.size(), want.spheres.size());
  for (std::size_t i = 0; i < sh.spheres.size(); ++i) {
    EXPECT_EQ(sh.spheres[i].radius, want.spheres[i].radius);
    EXPECT_EQ(sh.spheres[i].offset.y, want.spheres[i].offset.y);
    EXPECT_EQ(sh.spheres[i].elasticity, 0.3f);
  }
  ASSERT_TRUE(sh.solid.has_value());
  const double m = 2000.0 * 0.25 * 0.125 * 0.0625;
  EXPECT_NEAR(sh.solid->mass, m, 1e-12);
  EXPECT_NEAR(sh.solid->inertia[2], m * (0.0625 + 0.015625) / 12, 1e-12);
  EXPECT_EQ(sh.meshFile, brickFolder() + "/brick.obj");
  // fill = "surface" (of at most 20 spheres: the layer needs 13 at least): the layer clumpFromMesh() gives.
  std::string surface = shape;
  surface.replace(surface.find("spheres = 5"), 11, "spheres = 20");
  const tumble::Scene layered = tumble::parseScene(std::string(kHead) + surface + "fill = \"surface\"\n" + kBody,
                                                   "bricks.toml", {}, tumble::OverrideSource::CommandLine, brickFolder());
  o.fill = tumble::ClumpFill::Surface;
  o.spheres = 20;
  const tumble::ShapeDef layer =
      tumble::clumpShape(tumble::clumpFromMesh(tumble::readMeshFile(brickFolder() + "/brick.obj"), o), "brick", 2000.0);
  ASSERT_EQ(layered.shapes[0].spheres.size(), layer.spheres.size());
  for (std::size_t i = 0; i < layer.spheres.size(); ++i) EXPECT_EQ(layered.shapes[0].spheres[i].radius, layer.spheres[i].radius);
  const tumble::Scene big = tumble::parseScene(std::string(kHead) + shape + "scale = 2\n" + kBody, "bricks.toml", {},
                                               tumble::OverrideSource::CommandLine, brickFolder());
  EXPECT_NEAR(big.shapes[0].solid->mass, 8 * m, 1e-12);
  // Turned a quarter about z after the scale: the inertia about x and y trade places.
  const tumble::Scene turned = tumble::parseScene(
      std::string(kHead) + shape + "scale = 2\norientation = [0.7071067811865476, 0, 0, 0.7071067811865476]\n" + kBody,
      "bricks.toml", {}, tumble::OverrideSource::CommandLine, brickFolder());
  const tumble::ShapeSolid &a = *big.shapes[0].solid, &b = *turned.shapes[0].solid;
  EXPECT_NEAR(b.mass, a.mass, 1e-6 * a.mass);
  EXPECT_NEAR(b.inertia[0], a.inertia[1], 1e-6 * a.inertia[2]);
  EXPECT_NEAR(b.inertia[1], a.inertia[0], 1e-6 * a.inertia[2]);
  EXPECT_NEAR(b.inertia[2], a.inertia[2], 1e-6 * a.inertia[2]);
  EXPECT_NEAR(b.centre[0], -a.centre[1], 1e-6);  // (x, y) → (−y, x)
  EXPECT_NEAR(b.centre[1], a.centre[0], 1e-6);
  const tumble::World w = tumble::World::fromScene(s);
  EXPECT_FLOAT_EQ(w.bodyMass[0], float(m));
}

TEST(ClumpErrors, AShapeFromAMeshFile) {
  const auto refused = [](const std::string& shape, long line, const std::string& needle) {
    try {
      (void)tumble::parseScene(std::string(kHead) + shape + kBody, "bricks.toml", {}, tumble::OverrideSource::CommandLine,
                               brickFolder());
      ADD_FAILURE() << "accepted: " << shape;
    } catch (const tumble::InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const std::string head = "[[shape]]\nname = \"brick\"\nmesh = \"brick.obj\"\n";  // lines 5-7
  refused(head + "density = 2000\n", 5, "needs spheres = N");
  refused(head + "spheres = 3\n", 5, "needs its density");
  refused(head + "spheres = 3\ndensity = 2000\nmass = 1\n", 10, "mass is not a key of a shape made from a mesh");
  refused(head + "spheres = 3\ndensity = 2000\nfill = \"hollow\"\n", 10, "unknown fill \"hollow\"; use \"inside\"");
  refused("[[shape]]\nname = \"brick\"\nspheres = 3\n[[shape.sphere]]\nradius = 0.1\nmass = 1\n", 7,
          "spheres is a key of a shape made from a mesh");
  refused("[[shape]]\nname = \"brick\"\nmesh = \"nope.obj\"\nspheres = 3\ndensity = 1\n", 7, "looked for at");
  refused("[[shape]]\nname = \"brick\"\nmesh = \"open.obj\"\nspheres = 3\ndensity = 1\n", 5, "is open");
  refused(head + "spheres = 3\ndensity = 2000\nresolution = 4\n", 10, "resolution");
  refused(head + "spheres = 3\ndensity = 2000\norientation = [0, 0, 0, 0]\n", 10, "zero quaternion");
  refused("[[shape]]\nname = \"brick\"\norientation = [1, 0, 0, 0]\n[[shape.sphere]]\nradius = 0.1\nmass = 1\n", 7,
          "orientation is a key of a shape made from a mesh");
  // An output over the mesh a shape reads is refused (tumble run --state-out brick.obj).
  const tumble::Scene s = tumble::parseScene(std::string(kHead) + head + "spheres = 2\ndensity = 2000\n" + kBody,
                                             "bricks.toml", {}, tumble::OverrideSource::CommandLine, brickFolder());
  EXPECT_THROW(tumble::refuseSceneInput(s, brickFolder() + "/brick.obj", "--state-out"), tumble::Error);
}
