// SPDX-License-Identifier: MIT
// Tests of shapes with mass properties of their own ([[shape]] mass, centre_of_mass, inertia:
// a solid such as tumble clump writes from a mesh): the bodies take them instead of the
// spheres' sums, the spheres share the mass by volume, a fill's sizes scale them, and what is
// not a solid's is refused at its line.
#include <cmath>
#include <string>

#include "scene_io_test_util.hpp"
#include "tumble/world.hpp"

using namespace scene_io_test;

namespace {
// A rod of three spheres (from line 12) whose solid is a box 0.6 x 0.2 x 0.2 of 24 kg, its centre
// 0.05 m off the spheres' middle along x.
const char* kRod =
    "[[shape]]\nname = \"rod\"\nmass = 24\ncentre_of_mass = [0.05, 0, 0]\n"
    "inertia = [0.16, 0.8, 0.8, 0, 0, 0]\n"
    "[[shape.sphere]]\noffset = [-0.2, 0, 0]\nradius = 0.1\n"
    "[[shape.sphere]]\noffset = [0, 0, 0]\nradius = 0.2\n"
    "[[shape.sphere]]\noffset = [0.2, 0, 0]\nradius = 0.1\n"
    "[[body]]\nshape = \"rod\"\nposition = [0, 0, 2]\n";
}  // namespace

TEST(SceneIo, ASolidShapeGivesTheBodyItsMassProperties) {
  const Scene s = tumble::parseScene(withExtra(kRod), "test.toml");
  const tumble::ShapeDef& rod = s.shapes.at(1);
  ASSERT_TRUE(rod.solid.has_value());
  // The spheres share the 24 kg by volume: 1 : 8 : 1.
  EXPECT_FLOAT_EQ(rod.spheres[0].mass, 2.4f);
  EXPECT_FLOAT_EQ(rod.spheres[1].mass, 19.2f);
  EXPECT_FLOAT_EQ(rod.spheres[2].mass, 2.4f);
  const tumble::World w = tumble::World::fromScene(s);
  EXPECT_FLOAT_EQ(w.bodyMass[1], 24.0f);
  // The solid's inertia, not the spheres' (theirs: 0.4 m r^2 summed, about 0.33 about x).
  EXPECT_FLOAT_EQ(w.inertia[1].xx, 0.16f);
  EXPECT_FLOAT_EQ(w.inertia[1].yy, 0.8f);
  EXPECT_FLOAT_EQ(w.inertia[1].zz, 0.8f);
  // The body's position is the solid's centre: the middle sphere sits 0.05 m behind it.
  const std::size_t middle = w.first[1] + 1;
  EXPECT_FLOAT_EQ(w.ux[middle], -0.05f);
  // A fill of it at sizes 0.5 to 1: mass times f^3, inertia times f^5, centre times f.
  const std::string fill = std::string(kRod) +
                           "[[fill]]\nshape = \"rod\"\ncount = 20\nregion = \"box\"\nmin = [-9, -9, 3]\nmax = [9, 9, 9]\n"
                           "size = { distribution = \"uniform\", min = 0.5, max = 1 }\n";
  const Scene f = tumble::parseScene(withExtra(fill), "test.toml");
  for (std::size_t b = 2; b < f.bodies.size(); ++b) {
    const tumble::ShapeDef& sh = f.shapes[f.bodies[b].shape];
    ASSERT_TRUE(sh.solid.has_value());
    const double k = double(sh.spheres[1].radius) / 0.2;
    EXPECT_NEAR(sh.solid->mass, 24.0 * k * k * k, 1e-6 * sh.solid->mass);  // k from float radii
    EXPECT_NEAR(sh.solid->centre[0], 0.05 * k, 1e-8);
    EXPECT_NEAR(sh.solid->inertia[1], 0.8 * std::pow(k, 5), 1e-6 * sh.solid->inertia[1]);
  }
}

TEST(SceneIoErrors, SolidShapes) {
  const std::string rod = kRod;
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = rod;
    t.replace(t.find(from), from.size(), to);
    return withExtra(t);
  };
  expectError(replaced("mass = 24\n", ""), 12, {"give the shape's mass, centre_of_mass and inertia together"});
  expectError(replaced("inertia = [0.16, 0.8, 0.8, 0, 0, 0]\n", "inertia = [0.16, 0.8, 0.8]\n"), 16,
              {"inertia must be an array of 6 numbers [xx, yy, zz, xy, xz, yz]"});
  expectError(replaced("inertia = [0.16, 0.8, 0.8, 0, 0, 0]\n", "inertia = [0.1, 0.2, 0.8, 0, 0, 0]\n"), 12,
              {"principal moments", "are not a solid's"});
  expectError(replaced("inertia = [0.16, 0.8, 0.8, 0, 0, 0]\n", "inertia = [0.16, 0.8, 0.8, 0.5, 0, 0]\n"), 12,
              {"principal moments", "are not a solid's"});
  expectError(replaced("radius = 0.2\n", "radius = 0.2\nmass = 19.2\n"), 23,
              {"the shape gives the mass", "remove this sphere's mass"});
  expectError(replaced("mass = 24\n", "mass = -1\n"), 14, {"mass"});
  // One sphere: a body of one sphere has its particle at its centre of mass (the pipelines'), so
  // a solid of one sphere must have it there; its inertia is checked under every law.
  const std::string one = "[[shape]]\nname = \"one\"\nmass = 4\ncentre_of_mass = [0, 0, 0.05]\n"
                          "inertia = [0.02, 0.02, 0.02, 0, 0, 0]\n[[shape.sphere]]\nradius = 0.1\n";
  expectError(withExtra(one), 12, {"its one sphere's centre lies 0.05 m from its centre_of_mass"});
  std::string bad = one;
  bad.replace(bad.find("[0, 0, 0.05]"), 12, "[0, 0, 0]").replace(bad.find("[0.02, 0.02, 0.02"), 17, "[1, 1, 5");
  expectError(withExtra(bad), 12, {"are not a solid's"});
}
