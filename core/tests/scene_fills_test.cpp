// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader's [[fill]] tables and the [periodic] box (and a fill in one).
#include "scene_io_test_util.hpp"

using namespace scene_io_test;

// [[fill]]: bodies packed at random in a box or a cylinder. Every sphere lies in the region, no
// two overlap (the test's own grid count), none touches the ground or a wall cutting through the
// region (a plane tilted across the box: the fill must stay on its side); the bodies are the
// same for a given seed and differ for another; shapes come with the odds of their weights and
// sizes within the scale range, masses with the cube of the scale.
TEST(SceneIo, FillPacksWithoutOverlap) {
  const std::string shapes =
      "[[shape]]\nname = \"dimer\"\n[[shape.sphere]]\nradius = 0.3\nmass = 1\noffset = [-0.2, 0, 0]\n"
      "[[shape.sphere]]\nradius = 0.3\nmass = 1\noffset = [0.2, 0, 0]\n"
      "[ground]\n[[wall]]\ntype = \"plane\"\npoint = [0, 0, 6]\nnormal = [0.3, 0, -1]\n";
  const std::string box = "[[fill]]\nshapes = [\"ball\", \"dimer\"]\nweights = [3, 1]\ncount = 600\nregion = \"box\"\n"
                          "min = [-6, -6, -1]\nmax = [6, 6, 8]\nscale = [0.5, 1.0]\nvelocity_jitter = 0.1\n";
  const std::string cyl = "[[fill]]\nshape = \"ball\"\ncount = 40\nregion = \"cylinder\"\npoint = [10, 0, 0.5]\n"
                          "axis = [0, 0, 4]\nradius = 3\nseed = 5\n";
  const Scene s = tumble::parseScene(withExtra(shapes + box + cyl), "test.toml");
  ASSERT_EQ(s.bodies.size(), 1u + 600u + 40u);
  const std::vector<Particle> ps = particlesOf(s);
  EXPECT_EQ(countInitialOverlaps(ps), 0u);
  std::size_t dimers = 0;
  double worstOutside = -1e30;
  for (std::size_t b = 1; b < s.bodies.size(); ++b) {
    const tumble::ShapeDef& sh = s.shapes[s.bodies[b].shape];
    const float scale = sh.spheres[0].radius / (sh.spheres.size() == 2 ? 0.3f : 0.5f);
    if (b <= 600) {
      dimers += sh.spheres.size() == 2;
      EXPECT_GE(scale, 0.5f - 1e-6f);
      EXPECT_LE(scale, 1.0f + 1e-6f);
      EXPECT_NEAR(sh.spheres[0].mass, scale * scale * scale, 1e-5);
    } else {
      EXPECT_EQ(sh.spheres[0].radius, 0.5f) << "no scale: the shape itself";
      EXPECT_EQ(s.bodies[b].shape, 0u);
    }
  }
  for (const Particle& p : ps) {
    if (p.body == 0) continue;
    const bool inBox = p.body <= 600;
    if (inBox) {
      for (const float v : {p.x.x, p.x.y}) worstOutside = std::max(worstOutside, double(std::abs(v) + p.r) - 6.0);
      worstOutside = std::max(worstOutside, double(p.x.z + p.r) - 8.0);
      worstOutside = std::max(worstOutside, -1.0 - double(p.x.z - p.r));
    } else {
      worstOutside = std::max(worstOutside, double(std::hypot(p.x.x - 10.0f, p.x.y) + p.r) - 3.0);
      worstOutside = std::max(worstOutside, 0.5 - double(p.x.z - p.r));
      worstOutside = std::max(worstOutside, double(p.x.z + p.r) - 4.5);
    }
    EXPECT_GT(p.x.z, p.r) << "above the ground";
    // The tilted plane x.n = h with n = (0.3, 0, -1)/|.|: the spheres on its side, not touching.
    const double len = std::hypot(0.3, 1.0), gap = (0.3 * p.x.x - (p.x.z - 6.0)) / len;
    EXPECT_GT(gap, p.r) << "body " << p.body << " touches the tilted wall";
  }
  EXPECT_LE(worstOutside, 1e-5) << "a sphere sticks out of its region";
  std::printf("fill: %zu dimers of 600 (weights 3:1 give 150 +- 11)\n", dimers);
  EXPECT_NEAR(double(dimers), 150.0, 4.0 * 10.6);
  const Scene again = tumble::parseScene(withExtra(shapes + box + cyl), "test.toml");
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    EXPECT_EQ(s.bodies[b].position.x, again.bodies[b].position.x) << "body " << b;
    EXPECT_EQ(s.bodies[b].orientation.w, again.bodies[b].orientation.w) << "body " << b;
    EXPECT_EQ(s.bodies[b].velocity.z, again.bodies[b].velocity.z) << "body " << b;
  }
  const Scene other = tumble::parseScene(withExtra(shapes + box + cyl + "") .replace(
                                              withExtra(shapes + box + cyl).find("seed = 5"), 8, "seed = 6"),
                                          "test.toml");
  EXPECT_EQ(s.bodies[1].position.x, other.bodies[1].position.x) << "the box fill keeps the scene's seed";
  EXPECT_NE(s.bodies[620].position.x, other.bodies[620].position.x) << "the cylinder's seed changed";
  // A World is built from it, and a run starts without overlaps or wall contacts.
  const tumble::World w = tumble::World::fromScene(s);
  EXPECT_EQ(w.numBodies(), 641u);
}

TEST(SceneIoErrors, Fills) {
  const std::string f = "[[fill]]\nshape = \"ball\"\n";  // lines 12-13
  expectError(withExtra(f + "region = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"), 12, {"missing required key 'count'"});
  expectError(withExtra(f + "count = 2\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"), 12, {"missing required key 'region'"});
  expectError(withExtra(f + "count = 2\nregion = \"sphere\"\n"), 15, {"unknown region \"sphere\""});
  expectError(withExtra(f + "count = 2\nregion = \"box\"\nradius = 1\n"), 16,
              {"radius is not a key of region = \"box\" (its keys: min max)"});
  expectError(withExtra(f + "count = 2\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n"), 17,
              {"max must exceed min on every axis"});
  expectError(withExtra(f + "count = 0\n"), 14, {"count"});
  expectError(withExtra(f + "count = 2\nweights = [1, 2]\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [9, 9, 9]\n"), 15,
              {"weights has 2 entries for 1 shapes"});
  expectError(withExtra(f + "count = 2\nregion = \"cylinder\"\npoint = [0, 0, 0]\naxis = [0, 0, 0]\nradius = 1\n"),
              17, {"axis must be a non-zero, finite vector"});
  expectError(withExtra(f + "count = 2\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [9, 9, 9]\nscale = [2, 1]\n"), 18,
              {"scale = [min, max] needs min <= max"});
  expectError(withExtra(f + "count = 2\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [9, 9, 9]\nscale = 0\n"), 18,
              {"scale"});
  // Too full: 9 unit balls do not fit in a 2 m cube (one fits at most... a few).
  expectError(withExtra(f + "count = 9\nregion = \"box\"\nmin = [0, 0, 2]\nmax = [2, 2, 4]\nattempts = 200\n"), 12,
              {"placed", "of 9 bodies", "in 200 draws", "use a larger region"});
  // A bound on the draws (issue 34, item 11): 2^63 - 1 held the load, and a pour's every batch, for ever.
  expectError(withExtra(f + "count = 2\nregion = \"box\"\nmin = [0, 0, 2]\nmax = [9, 9, 9]\nattempts = 9223372036854775807\n"),
              18, {"attempts must be <= 1000000 (got 9223372036854775807)"});
  expectError(withExtra("[[pour]]\nshape = \"ball\"\ncount = 2\nrate = 10\nregion = \"box\"\nmin = [0, 0, 2]\n"
                        "max = [9, 9, 9]\nattempts = 1000001\n"),
              19, {"[[pour]] #1", "attempts must be <= 1000000"});
  // A region the ground cuts: no body can be placed below it.
  expectError(withExtra("[ground]\nheight = 10\n" + f + "count = 1\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [3, 3, 3]\n"),
              14, {"placed 0 of 1 bodies"});
  // A scene of fills alone has bodies.
  std::vector<std::string> ls = baseLines();
  ls.resize(8);
  const Scene s = tumble::parseScene(join(ls) + f + "count = 3\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [9, 9, 9]\n",
                                     "test.toml");
  EXPECT_EQ(s.bodies.size(), 3u);
}

// [periodic] (docs/scenes.md#periodic-periodic-boundaries): the box of each periodic axis, and
// what periodic boundaries refuse (a period too short, bodies outside the box, walls and pulls
// that are not the same one period on), each at its line.
TEST(SceneIo, Periodic) {
  const Scene none = tumble::parseScene(join(baseLines()), "test.toml");
  EXPECT_FALSE(none.periodic.any());
  const Scene x = tumble::parseScene(withExtra("[periodic]\nx = [-2, 3]\n"), "test.toml");
  EXPECT_TRUE(x.periodic.on[0]);
  EXPECT_FALSE(x.periodic.on[1]);
  EXPECT_EQ(x.periodic.lo[0], -2.0f);
  EXPECT_EQ(x.periodic.hi[0], 3.0f);
  EXPECT_EQ(x.periodic.conflictingPulls(), static_cast<std::uint32_t>(tumble::kPullX | tumble::kPullSwirl));
  const Scene xy = tumble::parseScene(withExtra("[periodic]\nx = [-2, 3]\ny = [-1.5, 1.5]\n"), "test.toml");
  EXPECT_TRUE(xy.periodic.on[0] && xy.periodic.on[1]);
  EXPECT_EQ(xy.periodic.lo[1], -1.5f);
  EXPECT_EQ(xy.periodic.hi[1], 1.5f);
  // --set reaches the table like any single one.
  const Scene set = tumble::parseScene(join(baseLines()), "test.toml", {"periodic.y=[-4, 4]"});
  EXPECT_FALSE(set.periodic.on[0]);
  EXPECT_TRUE(set.periodic.on[1]);
  EXPECT_EQ(set.periodic.hi[1], 4.0f);
  // What periodic boundaries allow: a plane containing the periodic axis, a box open across it,
  // a pipe along it reaching half a period beyond the box, a pull along another axis.
  const Scene walls = tumble::parseScene(
      withExtra("[periodic]\nx = [-2, 3]\n[pulls]\non = [\"y\"]\n"
                "[[wall]]\ntype = \"plane\"\npoint = [0, 0, -1]\nnormal = [0, 0.6, 0.8]\n"
                "[[wall]]\ntype = \"box\"\nmin = [-9, -3, -3]\nmax = [9, 3, 3]\nopen = [\"-x\", \"+x\"]\n"
                "[[wall]]\ntype = \"cylinder\"\npoint = [5.5, 0, 0]\naxis = [-11, 0, 0]\nradius = 2.5\n"),
      "test.toml");
  EXPECT_EQ(walls.walls.size(), 6u);
  EXPECT_EQ(walls.pulls.active, static_cast<std::uint32_t>(tumble::kPullY));
  // The shipped chute.
  const Scene chute = tumble::readSceneFile(scenePath("chute.toml"));
  EXPECT_TRUE(chute.periodic.on[0] && chute.periodic.on[1]);
  EXPECT_EQ(chute.bodies.size(), 848u);
  for (const BodyDef& b : chute.bodies) {
    EXPECT_TRUE(b.position.x >= chute.periodic.lo[0] && b.position.x < chute.periodic.hi[0]);
    EXPECT_TRUE(b.position.y >= chute.periodic.lo[1] && b.position.y < chute.periodic.hi[1]);
  }
}

TEST(SceneIoErrors, Periodic) {
  const std::string p = "[periodic]\n";  // line 12
  expectError(withExtra(p), 12, {"[periodic]: give x = [x0, x1] and/or y = [y0, y1]"});
  expectError(withExtra(p + "z = [0, 1]\n"), 13, {"[periodic]: unknown key 'z'; allowed keys: x, y"});
  expectError(withExtra(p + "x = 4\n"), 13, {"x must be an array of 2 numbers [x0, x1]"});
  expectError(withExtra(p + "y = [0, 1, 2]\n"), 13, {"y must be an array of 2 numbers [y0, y1]", "(got 3 elements)"});
  expectError(withExtra(p + "x = [0, \"1\"]\n"), 13, {"x[1] must be a number"});
  expectError(withExtra(p + "x = [nan, 1]\n"), 13, {"x[0] must be a finite number"});
  expectError(withExtra(p + "x = [-1e39, 1]\n"), 13, {"x[0] must be within +-2^60 m (1.15e18)", "got -1e+39"});
  expectError(withExtra(p + "x = [3, 3]\n"), 13, {"x = [x0, x1] needs x1 > x0 (got [3, 3])"});
  expectError(withExtra(p + "x = [-3, 3]\ny = [2, -2]\n"), 14, {"needs y1 > y0 (got [2, -2])"});
  // The period: 2 × (extent 0.5 + radius 0.5 + automatic skin 0.25) = 2.5 m; a given skin counts.
  expectError(withExtra(p + "x = [-1, 1]\n"), 13,
              {"[periodic] x spans 2 m, not more than the shortest period this scene allows, 2.5 m = 2 x (the "
               "largest body's extent 0.5 m + the largest radius 0.5 m + the skin 0.25 m)", "widen the box"});
  expectError(withExtra(p + "x = [-1.25, 1.25]\n"), 13, {"spans 2.5 m, not more than"});
  expectError(withExtra("[broadphase]\nskin = 2\n" + p + "y = [-2, 3]\n"), 15,
              {"[periodic] y spans 5 m", "6 m", "the skin 2 m", "[broadphase] skin"});
  EXPECT_NO_THROW((void)tumble::parseScene(withExtra(p + "x = [-1.3, 1.3]\n"), "test.toml"));
  // Bodies start inside [x0, x1): the body at x = 0 (line 11), and a lattice's site.
  expectError(withExtra(p + "x = [2, 10]\n"), 11,
              {"[[body]] #1: its centre x = 0 lies outside the periodic box [2, 10) of [periodic] x"});
  expectError(withExtra(p + "x = [-10, 0]\n"), 11, {"x = 0 lies outside the periodic box [-10, 0)"});
  EXPECT_NO_THROW((void)tumble::parseScene(withExtra(p + "x = [0, 10]\n"), "test.toml")) << "x0 is inside";
  expectError(withExtra(p + "y = [-3, 3]\n[[group]]\nshape = \"ball\"\ncount = [1, 3, 1]\nspacing = 3\norigin = [0, -2, 4]\n"),
              14, {"[[group]] #1: the body at site (0, 2, 0) (0-based): its centre y = 4"});
  // Walls must be the same one period on.
  expectError(withExtra(p + "x = [-3, 3]\n[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0.1, 0, 1]\n"), 14,
              {"[[wall]] #1: a plane across the periodic x axis (its normal has an x component)"});
  expectError(withExtra(p + "y = [-3, 3]\n[[wall]]\ntype = \"box\"\nmin = [-5, -5, -5]\nmax = [5, 5, 5]\n"
                        "open = [\"+z\"]\n"),
              14, {"[[wall]] #1: face -y: a plane across the periodic y axis", "open = [\"-y\", \"+y\"]"});
  expectError(withExtra(p + "x = [-3, 3]\n[[wall]]\ntype = \"cylinder\"\npoint = [0, 0, -5]\naxis = [0, 0, 10]\n"
                        "radius = 2\n"),
              14, {"only a cylinder whose axis lies along the periodic x axis is the same one period on"});
  expectError(withExtra(p + "x = [-3, 3]\n[[wall]]\ntype = \"cylinder\"\npoint = [-5, 0, 0]\naxis = [10, 0, 0]\n"
                        "radius = 2\n"),
              14, {"the cylinder spans x from -5 to 5", "from -6 to 6 or further"});
  expectError(withExtra(p + "x = [-3, 3]\n[[wall]]\ntype = \"cone\"\npoint = [-9, 0, 0]\naxis = [18, 0, 0]\n"
                        "radius = [1, 2]\n"),
              14, {"a cone, a disk or another axis is not"});
  expectError(withExtra(p + "x = [-3, 3]\n[[wall]]\ntype = \"disk\"\npoint = [0, 0, 0]\nnormal = [1, 0, 0]\n"
                        "radius = 2\n"),
              14, {"a cone, a disk or another axis is not"});
  expectError(withExtra(p + "x = [-3, 3]\ny = [-3, 3]\n[[wall]]\ntype = \"cylinder\"\npoint = [-9, 0, 0]\n"
                        "axis = [18, 0, 0]\nradius = 2\n"),
              15, {"not the same one period on along both periodic axes"});
  // Pulls along a periodic axis (and the swirl) have no period.
  expectError(withExtra(p + "x = [-3, 3]\n[pulls]\non = [\"y\",\n \"x\"]\n"), 16,
              {"[pulls]: the pulls \"x\" pull along a periodic axis"});
  expectError(withExtra(p + "y = [-3, 3]\n[pulls]\non = [\"swirl\"]\n"), 15, {"the pulls \"swirl\" pull along"});
  // Overrides name themselves.
  expectSetError(join(baseLines()), {"periodic.x=[1, -1]"}, "periodic.x=[1, -1]", {"needs x1 > x0"});
  expectSetError(join(baseLines()), {"periodic.x=[-1, 1]"}, "periodic.x=[-1, 1]", {"not more than the shortest period"});
}

// A [[fill]] in a periodic box places every centre in the box and no two spheres overlapping
// through the boundaries (the nearest images, brute force).
TEST(SceneIo, FillInAPeriodicBox) {
  const Scene s = tumble::parseScene(
      withExtra("[periodic]\nx = [-2, 2]\ny = [-1.5, 1.5]\n[[fill]]\nshape = \"ball\"\ncount = 15\nregion = \"box\"\n"
                "min = [-2.4, -1.9, 2]\nmax = [2.4, 1.9, 5]\n"),
      "test.toml");
  ASSERT_EQ(s.bodies.size(), 16u);
  const std::vector<Particle> ps = particlesOf(s);
  std::size_t overlaps = 0, across = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(ps[i].x.x, -2.0f);
      EXPECT_LT(ps[i].x.x, 2.0f);
      EXPECT_GE(ps[i].x.y, -1.5f);
      EXPECT_LT(ps[i].x.y, 1.5f);
    }
    for (std::size_t j = i + 1; j < ps.size(); ++j) {
      double d[2] = {double(ps[i].x.x) - ps[j].x.x, double(ps[i].x.y) - ps[j].x.y};
      const double L[2] = {4.0, 3.0};
      bool wrapped = false;
      for (int a = 0; a < 2; ++a)
        if (std::abs(d[a]) > 0.5 * L[a]) d[a] -= std::copysign(L[a], d[a]), wrapped = true;
      const double dz = double(ps[i].x.z) - ps[j].x.z, dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + dz * dz);
      overlaps += dist < ps[i].r + ps[j].r;
      across += wrapped && dist < 3.0 * (ps[i].r + ps[j].r);
    }
  }
  std::printf("periodic fill: %zu pairs near each other across a boundary, %zu overlapping\n", across, overlaps);
  EXPECT_EQ(overlaps, 0u);
  EXPECT_GT(across, 0u) << "the test sees pairs across the boundaries";
}
