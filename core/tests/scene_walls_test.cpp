// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader's [[wall]] tables: planes, boxes, revolved and moving walls.
#include "scene_io_test_util.hpp"

using namespace scene_io_test;

// [[wall]]: a plane (its normal normalised) and a box of inward planes with its open faces
// left out; each takes the ground's contact keys (stiffness defaults to the contact's, as the
// ground's). Scene::planes() lists the ground first, then the walls.
TEST(SceneIo, Walls) {
  const Scene s = tumble::parseScene(
      withExtra("[ground]\nheight = -1\n"                                                     // 12-13
                "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 3, 4]\n"        // 14-17
                "stiffness = 5e4\nfriction = 0.2\n"                                          // 18-19
                "[[wall]]\ntype = \"box\"\nmin = [-1, -2, 0]\nmax = [1, 2, 3]\nopen = [\"+z\"]\n"),  // 20-24
      "test.toml");
  ASSERT_EQ(s.walls.size(), 6u) << "a plane and a box open at +z";
  EXPECT_EQ(s.walls[0].normal.y, 3.0f) << "as given: normalised in double by kernelWalls()";
  EXPECT_EQ(s.walls[0].normal.z, 4.0f);
  const std::vector<tumble::Wall> pw = tumble::kernelWalls(s, tumble::LocalFrame{});
  ASSERT_EQ(pw.size(), 7u);
  EXPECT_EQ(pw[1].n.y, 0.6f);
  EXPECT_EQ(pw[1].n.z, 0.8f);
  EXPECT_EQ(pw[1].coeffs.height, 0.8f) << "h = p.n";
  EXPECT_EQ(pw[0].coeffs.height, -1.0f) << "the ground";
  EXPECT_EQ(s.walls[0].point.z, 1.0f);
  EXPECT_EQ(s.walls[0].contact.stiffness, 5e4f);
  EXPECT_EQ(s.walls[0].contact.friction, 0.2f);
  EXPECT_EQ(s.walls[0].where, "[[wall]] #1 (test.toml:14)");
  EXPECT_EQ(s.walls[1].contact.stiffness, s.contact.stiffness) << "the contact's stiffness, as the ground's";
  const float faces[5][6] = {{-1, 0, 0, 1, 0, 0}, {1, 0, 0, -1, 0, 0}, {0, -2, 0, 0, 1, 0}, {0, 2, 0, 0, -1, 0},
                             {0, 0, 0, 0, 0, 1}};
  for (int f = 0; f < 5; ++f) {
    const tumble::WallDef& w = s.walls[1 + f];
    const float got[6] = {w.point.x, w.point.y, w.point.z, w.normal.x, w.normal.y, w.normal.z};
    for (int c = 0; c < 6; ++c) EXPECT_EQ(got[c], faces[f][c]) << "face " << f << " component " << c;
  }
  EXPECT_EQ(s.walls[5].where, "[[wall]] #2 (test.toml:20) face -z");
  const std::vector<tumble::WallDef> planes = s.planes();
  ASSERT_EQ(planes.size(), 7u);
  EXPECT_EQ(planes[0].point.z, -1.0f) << "the ground first";
  EXPECT_EQ(planes[0].normal.z, 1.0f);
  EXPECT_EQ(planes[0].where, "[ground]");
}

TEST(SceneIoErrors, Walls) {
  expectError(withExtra("[[wall]]\npoint = [0, 0, 0]\n"), 12, {"[[wall]] #1", "missing required key 'type'"});
  expectError(withExtra("[[wall]]\ntype = \"mesh\"\n"), 12, {"[[wall]] #1", "missing required key 'file'"});
  expectError(withExtra("[[wall]]\ntype = \"pipe\"\n"), 13, {"unknown wall type \"pipe\"", "\"mesh\""});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\n"), 15,
              {"normal must be a non-zero"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\n"), 12, {"missing required key 'normal'"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\nnormal = [0, 0, 1]\n"), 12, {"missing required key 'point'"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\nmin = [0, 0, 0]\n"), 14, {"min is not a key of type = \"plane\""});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n"), 15,
              {"max must exceed min on every axis"});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nopen = [\"+z\",\n \"top\"]\n"),
              17, {"unknown face \"top\""});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nnormal = [0, 0, 1]\n"), 14, {"normal is not a key of type = \"box\""});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nopen = [\"+z\", \"+z\"]\n"), 16,
              {"face \"+z\" is listed twice"});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
                        "open = [\"+z\", \"-z\", \"+x\", \"-x\", \"+y\", \"-y\"]\n"),
              16, {"every face is open"});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [100000000, 0, 0]\nmax = [100000001, 1, 1]\n"), 15,
              {"as single-precision numbers: min [100000000"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\nheight = 1\n"), 14, {"unknown key 'height'"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\nstiffness = -1\n"), 14, {"stiffness"});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\nrolling_friction = 0.1\n"), 14,
              {"rolling_friction needs a contact law that turns spheres"});
  expectError(withExtra(std::string(kHertz) + kGlass + "[[wall]]\ntype = \"plane\"\nstiffness = 1e5\n"), 23,
              {"stiffness is not read under law = \"hertz-mindlin\": the wall's contact comes from its material"});
  expectError(withExtra(std::string(kHertz) + kGlass + "[[wall]]\ntype = \"plane\"\nmaterial = \"wood\"\n"), 23,
              {"wood"});
  expectError(withExtra("[wall]\ntype = \"plane\"\n"), 12, {"wall"});
  // Revolved walls and motion.
  const std::string cyl = "[[wall]]\ntype = \"cylinder\"\npoint = [0, 0, 0]\n";  // lines 12-14
  expectError(withExtra(cyl + "radius = 1\n"), 12, {"missing required key 'axis'"});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\n"), 12, {"missing required key 'radius'"});
  expectError(withExtra(cyl + "axis = [0, 0, 0]\nradius = 1\n"), 15, {"axis must be a non-zero, finite vector"});
  expectError(withExtra(cyl + "axis = [0, 0, 1e-50]\nradius = 1\n"), 15, {"axis must be a non-zero"});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\nradius = 0\n"), 16, {"radius must be > 0"});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\nradius = 1\nnormal = [0, 0, 1]\n"), 17,
              {"normal is not a key of type = \"cylinder\" (its keys: point axis radius"});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\nradius = 1\nnormal = [1, 0, 0]\n"), 17,
              {"normal is not a key of type = \"cylinder\""});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\nradius = 1\nstop = 2\n"), 17,
              {"stop times a wall's motion, and this wall does not move"});
  expectError(withExtra(cyl + "axis = [0, 0, 1]\nradius = 1\nangular_velocity = 2\nstart = 3\nstop = 2\n"), 19,
              {"stop must be after start (got start = 3, stop = 2)"});
  const std::string cone = "[[wall]]\ntype = \"cone\"\npoint = [0, 0, 0]\naxis = [0, 0, 1]\n";  // 12-15
  expectError(withExtra(cone + "radius = 1\n"), 16, {"radius must be an array of 2 numbers"});
  expectError(withExtra(cone + "radius = [1, 2, 3]\n"), 16, {"(got 3 elements)"});
  expectError(withExtra(cone + "radius = [1, -2]\n"), 16, {"radius[1] must be >= 0"});
  expectError(withExtra(cone + "radius = [1, 1]\n"), 16, {"a cone's two radii must differ"});
  const std::string disk = "[[wall]]\ntype = \"disk\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n";  // 12-15
  expectError(withExtra(disk + "radius = 1\ninner_radius = 1\n"), 17,
              {"inner_radius (the hole) must be below radius (got 1 and 1)"});
  expectError(withExtra(disk + "radius = 1\naxis = [0, 0, 1]\n"), 17, {"axis is not a key of type = \"disk\""});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nangular_velocity = 1\n"),
              16, {"angular_velocity is not a key of type = \"plane\""});
  expectError(withExtra("[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nvelocity = [1, 0, nan]\n"),
              16, {"velocity"});
  expectError(withExtra("[[wall]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nangular_velocity = 1\n"), 16,
              {"angular_velocity is not a key of type = \"box\""});
}

// Cylinders, cones and disks are revolved segments (WallDef): (0, r)–(|axis|, r), (0, r0)–(|axis|,
// r1), (0, inner)–(0, radius) about the axis or normal; motion keys as given.
TEST(SceneIo, RevolvedWalls) {
  const Scene s = tumble::parseScene(
      withExtra("[[wall]]\ntype = \"cylinder\"\npoint = [0, -1, 0]\naxis = [0, 3, 4]\nradius = 0.5\n"
                "angular_velocity = 2.5\nstart = 1\nstop = 4\nfriction = 0.3\n"
                "[[wall]]\ntype = \"cone\"\npoint = [0, 0, 1]\naxis = [0, 0, 2]\nradius = [0.1, 0.9]\n"
                "[[wall]]\ntype = \"disk\"\npoint = [0, 0, 0]\nnormal = [0, 0, -1]\nradius = 1\ninner_radius = 0.2\n"
                "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nvelocity = [1.5, -2, 0]\n"),
      "test.toml");
  ASSERT_EQ(s.walls.size(), 4u);
  const tumble::WallDef& c = s.walls[0];
  EXPECT_EQ(c.shape, tumble::WallDef::Shape::Revolved);
  EXPECT_EQ(c.length, 5.0f);
  EXPECT_EQ(c.radius0, 0.5f);
  EXPECT_EQ(c.radius1, 0.5f);
  EXPECT_EQ(c.angularVelocity, 2.5f);
  EXPECT_EQ(c.start, 1.0);
  EXPECT_EQ(c.stop, 4.0);
  EXPECT_EQ(c.contact.friction, 0.3f);
  EXPECT_TRUE(c.moves());
  EXPECT_EQ(s.walls[1].radius0, 0.1f);
  EXPECT_EQ(s.walls[1].radius1, 0.9f);
  EXPECT_EQ(s.walls[1].length, 2.0f);
  EXPECT_FALSE(s.walls[1].moves());
  EXPECT_EQ(s.walls[1].stop, std::numeric_limits<double>::infinity()) << "by default a wall moves for ever";
  EXPECT_EQ(s.walls[2].length, 0.0f);
  EXPECT_EQ(s.walls[2].radius0, 0.2f);
  EXPECT_EQ(s.walls[2].radius1, 1.0f);
  EXPECT_EQ(s.walls[3].shape, tumble::WallDef::Shape::Plane);
  EXPECT_EQ(s.walls[3].velocity.y, -2.0f);
  EXPECT_TRUE(s.wallsMove());
  std::vector<tumble::Wall> kw = tumble::kernelWalls(s, tumble::LocalFrame{});
  ASSERT_EQ(kw.size(), 4u) << "no ground in withExtra's scene";
  EXPECT_EQ(kw[0].axis, tumble::kRevolvedWall);
  EXPECT_EQ(kw[0].n.y, 0.6f);
  EXPECT_EQ(kw[0].n.z, 0.8f);
  // The axis's point nearest the origin, (0, -0.64, 0.48), and the segment's start from it, -0.6.
  EXPECT_FLOAT_EQ(kw[0].centre.y, -0.64f);
  EXPECT_FLOAT_EQ(kw[0].centre.z, 0.48f);
  EXPECT_FLOAT_EQ(kw[0].start, -0.6f);
  // The motion window: the cylinder turns while 1 <= t < 4, the belt always.
  for (const double t : {0.0, 1.0, 3.999, 4.0}) {
    tumble::setWallMotion(kw, s, t);
    EXPECT_EQ(kw[0].moving, t >= 1.0 && t < 4.0 ? 1u : 0u) << "t = " << t;
    EXPECT_EQ(kw[1].moving, 0u);
    EXPECT_EQ(kw[3].moving, 1u);
  }
}

// Walls that move: a plane with a velocity along its normal (a piston), a box moving as a whole
// (every face with the velocity and the window), a cylinder moving across its axis; posed by
// setWallMotion() at a time: the plane's h, the box's faces, the cylinder's centre and start.
TEST(SceneIo, MovingWalls) {
  const Scene s = tumble::parseScene(
      withExtra("[[wall]]\ntype = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 0, 2]\nvelocity = [0.5, 0, -2]\n"
                "start = 1\nstop = 3\n"
                "[[wall]]\ntype = \"box\"\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\nopen = [\"+z\"]\nvelocity = [0, 1, 0]\n"
                "[[wall]]\ntype = \"cylinder\"\npoint = [0, 0, 0]\naxis = [0, 0, 4]\nradius = 1\nvelocity = [1, 0, 2]\n"),
      "test.toml");
  ASSERT_EQ(s.walls.size(), 7u) << "a plane, five faces, a cylinder";
  EXPECT_EQ(s.walls[0].velocity.z, -2.0f);
  EXPECT_EQ(s.walls[0].start, 1.0);
  for (std::size_t k = 1; k <= 5; ++k) {
    EXPECT_EQ(s.walls[k].velocity.y, 1.0f) << "face " << k;
    EXPECT_TRUE(s.walls[k].moves());
  }
  std::vector<tumble::Wall> kw = tumble::kernelWalls(s, tumble::LocalFrame{});
  tumble::setWallMotion(kw, s, 2.0);  // the plane has moved for 1 s, the rest for 2 s
  EXPECT_EQ(kw[0].coeffs.height, -1.0f) << "h = 1 - 2 x 1 (the belt part, 0.5 along x, moves no plane)";
  EXPECT_EQ(kw[3].coeffs.height, 1.0f) << "the -y face (normal +y) at y = -1 + 2";
  EXPECT_EQ(kw[4].coeffs.height, -3.0f) << "the +y face (normal -y) at y = 1 + 2";
  EXPECT_EQ(kw[1].coeffs.height, -1.0f) << "the -x face does not move";
  EXPECT_EQ(kw[6].centre.x, 2.0f) << "the axis moved across by 2 m";
  EXPECT_EQ(kw[6].start, 4.0f) << "and along by 4 m";
  tumble::setWallMotion(kw, s, 10.0);
  EXPECT_EQ(kw[0].coeffs.height, -3.0f) << "stopped at t = 3";
  EXPECT_EQ(kw[0].moving, 0u);
}
