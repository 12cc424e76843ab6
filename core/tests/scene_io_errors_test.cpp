// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader: each invalid input gives an InputError at the right line;
// the contact laws and the materials.
#include "scene_io_test_util.hpp"

namespace {

using namespace scene_io_test;

// ---------------------------------------------------------------------------------------
// Errors: each names the problem and the line.

TEST(SceneIoErrors, Syntax) {
  expectError(withLine(3, "steps = = 10"), 3, {"test.toml:3:", "TOML syntax error"});
  expectError(withLine(7, "radius = [0.5"), 8, {"TOML syntax error"});  // unclosed array
  expectError(withLine(11, "position = [0, 0, 1] x"), 11, {"TOML syntax error"});
}

TEST(SceneIoErrors, UnknownKeys) {
  expectError(withLine(3, "stepz = 10"), 3, {"[scene]", "unknown key 'stepz'", "allowed keys: name, dt, steps"});
  expectError(withLine(8, "masss = 1"), 8, {"unknown key 'masss'", "offset, radius, mass, density, elasticity, material"});
  expectError(withLine(11, "positon = [0, 0, 1]"), 11, {"[[body]] #1", "unknown key 'positon'"});
  expectError(withExtra("[grund]\nheight = 0\n"), 12, {"unknown top-level key 'grund'", "[ground]"});
  expectError(withExtra("[ground]\nfriktion = 0.5\n"), 13, {"[ground]", "unknown key 'friktion'", "friction"});
  expectError(withExtra("[[group]]\nshape = \"ball\"\ncount = [1, 1, 1]\nvelocity_jiter = 1\n"), 15,
              {"[[group]] #1", "unknown key 'velocity_jiter'", "velocity_jitter"});
}

TEST(SceneIo, ContactLaws) {
  const Scene report = tumble::parseScene(join(baseLines()), "test.toml");
  EXPECT_EQ(report.contact.law, tumble::ContactLaw::Report);
  EXPECT_FALSE(report.contact.rotatesSpheres());
  EXPECT_EQ(report.groundRollingFriction(), 0.0f);
  const Scene h = tumble::parseScene(
      withExtra("[contact]\nlaw = \"hooke-history\"\nstiffness = 3e4\ngamma_n = 50\nfriction = 0.4\n"
                "rolling_friction = 0.05\n[ground]\nrolling_friction = 0.2\n"),
      "test.toml");
  EXPECT_EQ(h.contact.law, tumble::ContactLaw::HookeHistory);
  EXPECT_TRUE(h.contact.hasHistory());
  EXPECT_EQ(h.contact.stiffness, 3e4f);
  EXPECT_EQ(h.contact.gammaN, 50.0f);
  EXPECT_LT(h.contact.gammaT, 0.0f) << "gamma_t unset: gamma_n / 2 in the kernels";
  EXPECT_EQ(h.contact.friction, 0.4f);
  EXPECT_EQ(h.contact.rollingFriction, 0.05f);
  EXPECT_EQ(h.groundRollingFriction(), 0.2f);
  const Scene g = tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\nrolling_friction = 0.05\n[ground]\n"),
                                     "test.toml");
  EXPECT_EQ(g.groundRollingFriction(), 0.05f) << "the ground takes the contact's by default";
}

TEST(SceneIoErrors, ContactLaws) {
  expectError(withExtra("[contact]\nlaw = \"hertz\"\n"), 13, {"unknown law \"hertz\"", "hooke-history"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\nshear = 5\n"), 14,
              {"shear is not a parameter of law = \"hooke-history\"", "gamma_n, gamma_t"});
  expectError(withExtra("[contact]\ngamma_n = 5\n"), 13, {"gamma_n is not a parameter of law = \"report\""});
  // An unknown key is told the keys of the law the table chose, not another law's (which the next
  // message would refuse): hooke-history offers no damping or shear.
  try {
    (void)tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\ndampin = 1\n"), "test.toml");
    ADD_FAILURE() << "no error for an unknown [contact] key";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.line(), 14) << m;
    EXPECT_NE(m.find("unknown key 'dampin'; allowed keys under law = \"hooke-history\": law, stiffness, "
                     "tangential_stiffness, gamma_n, gamma_t, friction, rolling_friction"),
              std::string::npos)
        << m;
    EXPECT_EQ(m.find("shear"), std::string::npos) << m;
  }
  expectError(withExtra("[contact]\nlaw = \"hertz-mindlin\"\nstifness = 1\n"), 14,
              {"unknown key 'stifness'; allowed keys under law = \"hertz-mindlin\": law"});
  expectError(withExtra("[contact]\nlaw = 3\n"), 13, {"[contact]: law must be a string (got an integer)"});
  expectError(withExtra("[ground]\nrolling_friction = 0.1\n"), 13, {"rolling_friction needs a contact law that turns spheres"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\nfriction = -1\n"), 14, {"friction"});
}

// Cohesion (docs/model.md#cohesion): the model in [contact], its coefficient per material
// (hertz-mindlin) or in [contact] (hooke-history), a plane's override; pairs mix by the geometric mean.
TEST(SceneIo, Cohesion) {
  const Scene h = tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"sjkr\"\n"
                                               "cohesion_energy_density = 3e4\n[ground]\ncohesion_energy_density = 1e4\n"),
                                     "test.toml");
  EXPECT_EQ(h.contact.cohesion, tumble::Cohesion::Sjkr);
  EXPECT_EQ(h.contact.cohesionValue, 3e4f);
  EXPECT_EQ(h.cohesionOf(h.ground), 1e4f);
  EXPECT_EQ(h.cohesionOf(tumble::GroundParams{}), 3e4f) << "a plane without its own: the contact's";
  const Scene g = tumble::parseScene(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"dmt\"\n" + kGlass +
                                         "surface_energy = 0.04\n" + kSteel + "surface_energy = 0.09\n" +
                                         "[ground]\nmaterial = \"steel\"\n",
                                     "test.toml");
  EXPECT_EQ(g.contact.cohesion, tumble::Cohesion::Dmt);
  EXPECT_EQ(g.materials[0].cohesion, 0.04f);
  const tumble::World w = tumble::World::fromScene(g);
  EXPECT_EQ(w.materialPairs[0 * 3 + 0].cohesion, 0.04f) << "a material with itself: its own";
  EXPECT_NEAR(w.materialPairs[0 * 3 + 1].cohesion, 0.06, 1e-8) << "glass on steel: sqrt(0.04 * 0.09)";
  EXPECT_NEAR(w.materialPairs[0 * 3 + 2].cohesion, 0.06, 1e-8) << "the ground of steel";
  const Scene rigid = tumble::parseScene(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"dmt\"\n" + kGlass +
                                             "surface_energy = 0.04\n[ground]\nsurface_energy = 0.5\n",
                                         "test.toml");
  EXPECT_EQ(tumble::World::fromScene(rigid).materialPairs[1].cohesion, 0.5f) << "the ground's own replaces the pair's";
  const Scene none = tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"none\"\n"), "test.toml");
  EXPECT_EQ(none.contact.cohesion, tumble::Cohesion::None);
  // cohesion = "none" given (--set contact.cohesion='"none"' on a cohesive scene): the coefficients
  // may stay, checked and not read.
  const Scene off = tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"none\"\n"
                                                 "cohesion_energy_density = 3e4\n[ground]\nsurface_energy = 0.2\n"),
                                       "test.toml");
  EXPECT_EQ(off.contact.cohesion, tumble::Cohesion::None);
  EXPECT_EQ(off.contact.cohesionValue, 0.0f);
  EXPECT_EQ(off.cohesionOf(off.ground), 0.0f);
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"none\"\nsurface_energy = -1\n"), 15,
              {"surface_energy"});
  // jkr: hertz-mindlin only (JKR's contact radius is Hertz's), with surface_energy.
  const Scene jkr = tumble::parseScene(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"jkr\"\n" + kGlass +
                                           "surface_energy = 0.05\n",
                                       "test.toml");
  EXPECT_EQ(jkr.contact.cohesion, tumble::Cohesion::Jkr);
  EXPECT_EQ(jkr.materials[0].cohesion, 0.05f);
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"jkr\"\n"), 14,
              {"needs law = \"hertz-mindlin\"", "use \"dmt\" or \"sjkr\""});
  expectError(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"jkr\"\n" + kGlass +
                  "cohesion_energy_density = 3e4\n",
              22, {"cohesion_energy_density is not read under cohesion = \"jkr\"", "give surface_energy"});
}

// What World::fromScene refuses (the reader cannot: it needs the radii and the pairs' moduli).
TEST(SceneIoErrors, CohesionThatNoOverlapBalances) {
  // Two spheres, so that a pair of them can touch (the base scene has one).
  const auto refused = [](const std::string& text, const std::string& part) {
    const Scene s = tumble::parseScene(text + "[[body]]\nshape = \"ball\"\nposition = [3, 0, 1]\n", "test.toml");
    try {
      (void)tumble::World::fromScene(s);
      ADD_FAILURE() << "no error; expected one with: " << part;
    } catch (const tumble::Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  // hooke-history: sjkr's attraction grows by 2 pi k_c R* = 2 pi 2e4 0.25 = 31 kN/m against k 20 kN/m.
  refused(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"sjkr\"\ncohesion_energy_density = 2e4\n"),
          "pulls harder than the spring");
  (void)tumble::World::fromScene(tumble::parseScene(
      withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"sjkr\"\ncohesion_energy_density = 1e4\n"
                "[[body]]\nshape = \"ball\"\nposition = [3, 0, 1]\n"),
      "test.toml"));
  // dmt at rest 2 pi gamma / k = 63 % of R* deep; hertz-mindlin sjkr (3 pi k_c / (2 Y*))^2 = 72 % (pairs) and 72 % (the
  // rigid ground, 1.2e10 against twice the pair's Y*).
  refused(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"dmt\"\nsurface_energy = 2000\n"),
          "% of R* deep at rest");
  refused(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"sjkr\"\n" + kGlass + "cohesion_energy_density = 6e9\n",
          "materials 'glass' and 'glass': cohesion_energy_density 6e+09 alone pulls");
  refused(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"sjkr\"\n" + kGlass +
              "cohesion_energy_density = 1e8\n[ground]\ncohesion_energy_density = 1.2e10\n",
          "material 'glass' on [ground]");
  // hertz-mindlin jkr: at zero load ½ c (3/2 c R*)^{1/3}, c = √(2 π γ / Y*): γ 1.2e9 J/m², 54 % of R*.
  refused(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"jkr\"\n" + kGlass + "surface_energy = 1.2e9\n",
          "materials 'glass' and 'glass': surface_energy 1.2e+09 alone pulls a contact of R* 0.25 m 5");
  // hertz-mindlin dmt: (3 pi gamma / (2 Y* R*))^(2/3) = 68 % of R* (R* 0.25 m, Y* 3.3e10 Pa).
  refused(withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"dmt\"\n" + kGlass + "surface_energy = 1e9\n",
          "materials 'glass' and 'glass': surface_energy 1e+09 alone pulls a contact of R* 0.25 m 68");
  // A material with itself at its two smallest spheres of two bodies: a small sphere (r 0.05) and
  // two balls (r 0.5) rest 40 % of R* deep under dmt (R* 0.045 m), where two small spheres would
  // rest 60 % deep (R* 0.025 m): accepted; with a second small sphere, refused. And two small
  // spheres of one clump never touch.
  const std::string small = "[[shape]]\nname = \"small\"\n[[shape.sphere]]\nradius = 0.05\nmaterial = \"glass\"\n";
  const std::string dmt = withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"dmt\"\n" + kGlass +
                          "surface_energy = 8.2e7\n" + small;
  const std::string ball = "[[body]]\nshape = \"ball\"\nposition = [3, 0, 1]\n";
  const std::string smallBody = "[[body]]\nshape = \"small\"\nposition = [6, 0, 1]\n";
  (void)tumble::World::fromScene(tumble::parseScene(dmt + ball + smallBody, "test.toml"));
  try {
    (void)tumble::World::fromScene(
        tumble::parseScene(dmt + ball + smallBody + "[[body]]\nshape = \"small\"\nposition = [9, 0, 1]\n", "test.toml"));
    ADD_FAILURE() << "two small spheres resting 60 % of R* deep: no error";
  } catch (const tumble::Error& e) {
    EXPECT_NE(std::string(e.what()).find("R* 0.025 m"), std::string::npos) << e.what();
  }
  (void)tumble::World::fromScene(tumble::parseScene(
      withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"dmt\"\n" + kGlass + "surface_energy = 8.2e7\n" +
          "[[shape]]\nname = \"pair\"\n[[shape.sphere]]\nradius = 0.05\noffset = [-0.04, 0, 0]\nmaterial = \"glass\"\n"
          "[[shape.sphere]]\nradius = 0.05\noffset = [0.04, 0, 0]\nmaterial = \"glass\"\n"
          "[[body]]\nshape = \"pair\"\nposition = [6, 0, 1]\n",
      "test.toml"));
  // An unknown model set in code.
  tumble::Scene coded = tumble::parseScene(withExtra("[contact]\nlaw = \"hooke-history\"\n"), "test.toml");
  coded.contact.cohesion = static_cast<tumble::Cohesion>(7);
  EXPECT_THROW((void)tumble::World::fromScene(coded), tumble::Error);
  // Only the contacts the scene can have: steel, of no sphere here, may be as sticky as it likes
  // (steel on steel and glass on steel cannot happen), and so may a plane of it against glass, where
  // the pair's mean is what counts.
  (void)tumble::World::fromScene(tumble::parseScene(
      withLine(8, "material = \"glass\"") + kHertz + "cohesion = \"sjkr\"\n" + kGlass + "cohesion_energy_density = 1e3\n" +
          kSteel + "cohesion_energy_density = 1e14\n[[body]]\nshape = \"ball\"\nposition = [3, 0, 1]\n",
      "test.toml"));
}

TEST(SceneIoErrors, Cohesion) {
  expectError(withExtra("[contact]\ncohesion = \"sjkr\"\n"), 13,
              {"cohesion needs a law with history", "hooke-history"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"jkr2\"\n"), 14,
              {"unknown cohesion \"jkr2\"", "\"sjkr\"", "\"dmt\""});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\nsurface_energy = 0.1\n"), 14,
              {"surface_energy needs a cohesion model", "cohesion = \"dmt\""});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"sjkr\"\nsurface_energy = 0.1\n"), 15,
              {"surface_energy is not read under cohesion = \"sjkr\"", "cohesion_energy_density"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"dmt\"\nsurface_energy = -0.1\n"), 15,
              {"surface_energy"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"dmt\"\n[ground]\ncohesion_energy_density = 1\n"),
              16, {"[ground]", "cohesion_energy_density is not read under cohesion = \"dmt\"", "surface_energy"});
  expectError(withExtra("[ground]\nsurface_energy = 0.1\n"), 13, {"[ground]", "needs a cohesion model"});
  // The other model's key beside the model's own, and its value unchecked otherwise.
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"sjkr\"\ncohesion_energy_density = 1e3\n"
                        "surface_energy = -5\n"),
              16, {"surface_energy is not read under cohesion = \"sjkr\""});
  expectError(withExtra(std::string(kHertz) + "cohesion = \"dmt\"\nsurface_energy = 0.1\n" + kGlass), 15,
              {"surface_energy is not a parameter of law = \"hertz-mindlin\"", "[[material]]"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\ncohesion = \"dmt\"\n[[material]]\nname = \"m\"\n"
                        "density = 10\nsurface_energy = 0.1\n"),
              18, {"surface_energy is read under [contact] law = \"hertz-mindlin\" only"});
}

TEST(SceneIo, MaterialsAndDensity) {
  // One material: every sphere is made of it; the sphere's own mass wins over the density.
  const Scene one = tumble::parseScene(withExtra(std::string(kHertz) + kGlass), "test.toml");
  EXPECT_EQ(one.contact.law, tumble::ContactLaw::HertzMindlin);
  EXPECT_TRUE(one.contact.usesMaterials());
  ASSERT_EQ(one.materials.size(), 1u);
  EXPECT_EQ(one.materials[0].name, "glass");
  EXPECT_EQ(one.materials[0].youngsModulus, 6.3e10f);
  EXPECT_EQ(one.materials[0].poissonRatio, 0.23f);
  EXPECT_EQ(one.materials[0].restitution, 0.9f);
  EXPECT_EQ(one.materials[0].friction, 0.3f);
  EXPECT_EQ(one.materials[0].rollingFriction, 0.0f);
  EXPECT_EQ(one.shapes[0].spheres[0].material, 0u);
  EXPECT_EQ(one.shapes[0].spheres[0].mass, 1.0f);
  EXPECT_EQ(one.shapes[0].spheres[0].elasticity, 0.9f) << "the restitution, for colours and exports";
  // The mass from a density: the sphere's, or its material's.
  const float volume = float(4.0 / 3.0 * 3.14159265358979 * 0.125);
  const Scene dense = tumble::parseScene(withLine(8, "density = 2000"), "test.toml");
  EXPECT_NEAR(dense.shapes[0].spheres[0].mass, 2000.0f * volume, 1e-3f);
  const Scene fromMaterial = tumble::parseScene(withLine(8, "material = \"steel\"") + kHertz + kGlass + kSteel, "test.toml");
  EXPECT_EQ(fromMaterial.shapes[0].spheres[0].material, 1u);
  EXPECT_NEAR(fromMaterial.shapes[0].spheres[0].mass, 7800.0f * volume, 1e-2f);
  EXPECT_EQ(fromMaterial.materials[1].rollingFriction, 0.01f);
  EXPECT_EQ(fromMaterial.ground.material, -1) << "no [ground] material: a rigid ground";
  // Under the other laws a material gives a density only.
  const Scene report = tumble::parseScene(withLine(8, "material = \"sand\"") + "[[material]]\nname = \"sand\"\ndensity = 1600\n",
                                          "test.toml");
  EXPECT_NEAR(report.shapes[0].spheres[0].mass, 1600.0f * volume, 1e-3f);
  const Scene ground = tumble::parseScene(withLine(8, "material = \"glass\"") + kHertz + kGlass + kSteel +
                                              "[ground]\nmaterial = \"steel\"\n",
                                          "test.toml");
  EXPECT_EQ(ground.ground.material, 1);
  // The mixing rule (docs/model.md#materials): Y* and G* from both materials, the smaller
  // restitution, friction and rolling friction; the ground's friction may replace the mixed one.
  const tumble::World w = tumble::World::fromScene(ground);
  ASSERT_EQ(w.materialPairs.size(), 9u) << "(2 materials + the ground)^2";
  const tumble::HertzPair& gs = w.materialPairs[0 * 3 + 1];  // glass on steel
  const double ystar = 1.0 / ((1 - 0.23 * 0.23) / 6.3e10 + (1 - 0.3 * 0.3) / 2e11);
  const double gstar = 1.0 / (2 * (2 - 0.23) * (1 + 0.23) / 6.3e10 + 2 * (2 - 0.3) * (1 + 0.3) / 2e11);
  EXPECT_NEAR(gs.ystar, ystar, 1e-6 * ystar);
  EXPECT_NEAR(gs.gstar, gstar, 1e-6 * gstar);
  EXPECT_EQ(gs.mu, 0.3f);
  EXPECT_EQ(gs.muR, 0.0f);
  const double le = std::log(0.8), beta = le / std::sqrt(le * le + 3.14159265358979 * 3.14159265358979);
  EXPECT_NEAR(gs.damp, -2.0 * std::sqrt(5.0 / 6.0) * beta, 1e-6) << "the smaller restitution, 0.8";
  EXPECT_EQ(w.materialPairs[1 * 3 + 0].ystar, gs.ystar) << "symmetric";
  EXPECT_EQ(w.materialPairs[0 * 3 + 2].ystar, gs.ystar) << "the ground of steel";
  EXPECT_EQ(w.material, (std::vector<std::uint16_t>{0}));
  const Scene rough = tumble::parseScene(withLine(8, "material = \"glass\"") + kHertz + kGlass + kSteel +
                                             "[ground]\nmaterial = \"steel\"\nfriction = 0.9\nrolling_friction = 0.2\n",
                                         "test.toml");
  const tumble::World wr = tumble::World::fromScene(rough);
  EXPECT_EQ(wr.materialPairs[0 * 3 + 2].mu, 0.9f) << "the ground's friction replaces the mixed one";
  EXPECT_EQ(wr.materialPairs[0 * 3 + 2].muR, 0.2f);
  EXPECT_EQ(wr.materialPairs[0 * 3 + 1].mu, 0.3f) << "between particles it does not";
  const tumble::World rigid = tumble::World::fromScene(one);
  EXPECT_NEAR(rigid.materialPairs[1].ystar, 6.3e10 / (1 - 0.23 * 0.23), 1e3) << "a rigid ground: the sphere's E alone";
}

TEST(SceneIoErrors, Materials) {
  expectError(withExtra(kHertz), 6, {"law = \"hertz-mindlin\" needs a [[material]]"});
  expectError(withExtra(std::string(kHertz) + kGlass + kSteel), 6, {"several [[material]] tables", "material = \"glass\""});
  expectError(withLine(8, "material = \"wood\"") + kHertz + kGlass, 8, {"unknown material \"wood\"", "\"glass\""});
  expectError(withLine(8, "mass = 1.0\ndensity = 5"), 9, {"give mass or density, not both"});
  expectError(withExtra(std::string("[[material]]\nname = \"sand\"\nyoungs_modulus = 1e9\n")), 14,
              {"youngs_modulus is read under [contact] law = \"hertz-mindlin\" only"});
  expectError(withExtra(std::string(kHertz) + "[[material]]\nname = \"x\"\npoisson_ratio = 0.3\nrestitution = 0.5\n"), 14,
              {"missing", "youngs_modulus"});
  expectError(withExtra(std::string(kHertz) + "[[material]]\nname = \"x\"\nyoungs_modulus = 1e9\npoisson_ratio = 0.5\n"
                        "restitution = 0.5\n"),
              17, {"poisson_ratio must be in [0, 0.5)"});
  expectError(withExtra(std::string(kHertz) + kGlass + kGlass), 22, {"material name \"glass\" is already used"});
  expectError(withExtra(std::string(kHertz) + "[[material]]\nname = \"x\"\nyoungs_modulus = 3.3e38\npoisson_ratio = 0.45\n"
                        "restitution = 0.5\n"),
              14, {"youngs_modulus 3.3e+38 gives an effective modulus beyond single precision"});
  // Too small is not "use a smaller one" (issue 34, item 12).
  expectError(withExtra(std::string(kHertz) + "[[material]]\nname = \"x\"\nyoungs_modulus = 1e-45\npoisson_ratio = 0.45\n"
                        "restitution = 0.5\n"),
              14, {"gives an effective modulus too small for single precision; use a larger one"});
  // Under a law that turns spheres a single sphere's inertia is used, so it must fit a float.
  std::string heavy = withLine(8, "mass = 1e37") + kHertz + kGlass;  // (1e38 kg weighs beyond a float)
  heavy.replace(heavy.find("radius = 0.5"), 12, "radius = 1000");  // I = 0.4 m r^2 = 4e42 kg m^2
  expectError(heavy, 4, {"moment of inertia", "beyond single precision"});
  std::string heavyReport = withLine(8, "mass = 1e37");
  heavyReport.replace(heavyReport.find("radius = 0.5"), 12, "radius = 1000");
  EXPECT_NO_THROW(tumble::parseScene(heavyReport, "test.toml")) << "under the report's law a single sphere's inertia is never used";
  expectError(withExtra(std::string(kHertz) + "stiffness = 1e5\n" + kGlass), 14,
              {"stiffness is not a parameter of law = \"hertz-mindlin\"", "[[material]]"});
  expectError(withExtra(std::string(kHertz) + kGlass + "[ground]\nstiffness = 1e5\n"), 22,
              {"stiffness is not read under law = \"hertz-mindlin\"", "material"});
  expectError(withExtra(std::string("[ground]\nmaterial = \"x\"\n")), 13, {"material is read under law = \"hertz-mindlin\" only"});
  expectError(withExtra(std::string(kHertz) + kGlass + "[ground]\nmaterial = \"steel\"\n"), 22, {"unknown material \"steel\""});
  expectError(withLine(8, "mass = 1.0\nelasticity = 0.5") + kHertz + kGlass, 9,
              {"elasticity is not read under law = \"hertz-mindlin\""});
}

TEST(SceneIoErrors, WrongTypes) {
  expectError(withLine(2, "dt = \"fast\""), 2, {"dt must be a number (got a string)"});
  expectError(withLine(3, "steps = 1.5"), 3, {"steps must be an integer (got 1.5)"});
  expectError(withLine(5, "name = 3"), 5, {"name must be a string"});
  expectError(withLine(11, "position = [0, 0]"), 11, {"position must be an array of 3 numbers", "got 2 elements"});
  expectError(withLine(11, "position = 1"), 11, {"position must be an array of 3 numbers"});
  expectError(withLine(11, "position = [0, \"a\", 1]"), 11, {"component y of position must be a number"});
  expectError(withExtra("[ground]\nenabled = 1\n"), 13, {"enabled must be true or false"});
  expectError(withExtra("[scene.sub]\n"), 12, {"unknown key 'sub'"});
  expectError(withLine(4, "[shape]"), 4, {"'shape' must be an array of tables", "[[shape]]"});
}

TEST(SceneIoErrors, NonFinite) {
  expectError(withLine(2, "dt = nan"), 2, {"dt must be a finite number (got nan)"});
  expectError(withLine(7, "radius = inf"), 7, {"radius must be a finite number (got inf)"});
  expectError(withLine(11, "position = [0, -inf, 1]"), 11, {"component y of position", "finite"});
  expectError(withLine(7, "radius = 1e39"), 7, {"radius must be in [2^-60, 2^60] m", "got 1e+39"});
  expectError(withLine(11, "position = [0, 1e38, 1]"), 11, {"component y of position must be within +-2^60 m"});
  std::vector<std::string> ls = baseLines();
  ls.insert(ls.begin() + 3, "gravity = [0,\n 0,\n nan]");  // elements on their own lines
  expectError(join(ls), 6, {"component z of gravity must be a finite number"});
}

TEST(SceneIoErrors, PhysicalRanges) {
  expectError(withLine(7, "radius = -1"), 7, {"shape \"ball\"", "radius must be > 0 (got -1)"});
  expectError(withLine(7, "radius = 0"), 7, {"radius must be > 0 (got 0)"});
  expectError(withLine(7, "radius = 1e-50"), 7, {"radius must be in [2^-60, 2^60] m", "got 1e-50"});
  // The range whose contacts single precision decides right (exact_range.hpp): beyond it a
  // pair's squares overflow or underflow.
  expectError(withLine(7, "radius = 1e-20"), 7, {"radius must be in [2^-60, 2^60] m", "got 1e-20"});
  expectError(withLine(7, "radius = 1.5e19"), 7, {"radius must be in [2^-60, 2^60] m", "got 1.5e+19"});
  EXPECT_NO_THROW((void)tumble::parseScene(withLine(7, "radius = 8.7e-19"), "test.toml"));
  expectError(withLine(8, "mass = 0"), 8, {"mass must be > 0 (got 0)"});
  expectError(withLine(8, "mass = -2.5"), 8, {"mass must be > 0 (got -2.5)"});
  expectError(withExtra("[[shape]]\nname = \"e\"\n[[shape.sphere]]\nradius = 1\nmass = 1\nelasticity = 1.5\n"), 17,
              {"elasticity must be in (0, 1]", "got 1.5"});
  expectError(withExtra("[[shape]]\nname = \"e\"\n[[shape.sphere]]\nradius = 1\nmass = 1\nelasticity = 0\n"), 17,
              {"elasticity must be in (0, 1]", "got 0"});
  expectError(withLine(2, "dt = 0"), 2, {"dt must be > 0 (got 0)"});
  expectError(withLine(2, "dt = -1e-4"), 2, {"dt must be > 0 (got -0.0001)"});
  expectError(withLine(3, "steps = 0"), 3, {"steps must be >= 1 (got 0)"});
  expectError(withExtra("[contact]\nstiffness = 0\n"), 13, {"stiffness must be > 0"});
  expectError(withExtra("[contact]\ndamping = -1\n"), 13, {"damping must be >= 0"});
  expectError(withExtra("[ground]\nfriction = -0.1\n"), 13, {"friction must be >= 0"});
  expectError(withExtra("[broadphase]\npca_every = 0\n"), 13, {"pca_every must be >= 1 (got 0)"});
  expectError(withExtra("[broadphase]\ncell_size = -1\n"), 13, {"cell_size must be >= 0"});
  expectError(withExtra("[output]\nsteps_per_frame = 0\n"), 13, {"steps_per_frame must be >= 1"});
  expectError(withExtra("[output]\nrecord_steps = -5\n"), 13, {"record_steps must be >= 0"});
  expectError(withExtra("[pulls]\non = [\"x\", \"z\"]\n"), 13, {"unknown pull \"z\"", "\"swirl\""});
  expectError(withLine(3, "steps = 10\nseed = -1"), 4, {"seed must be >= 0"});
}

TEST(SceneIoErrors, Groups) {
  const std::string head = join(baseLines()) + "[[group]]\nshape = \"ball\"\n";  // group at line 12
  expectError(head + "count = [4, 0, 2]\nspacing = 1\n", 14, {"[[group]] #1", "component y of count must be >= 1 (got 0)"});
  expectError(head + "count = [4, 4]\nspacing = 1\n", 14, {"count must be an array of 3 integers"});
  expectError(head + "count = [4, 4, 1.5]\nspacing = 1\n", 14, {"component z of count must be an integer"});
  expectError(head + "spacing = 1\n", 12, {"missing required key 'count'"});
  expectError(head + "count = [2, 1, 1]\n", 12, {"missing required key 'spacing'"});
  expectError(head + "count = [2, 1, 1]\nspacing = [1, 0, 1]\n", 15, {"component y of spacing must be > 0"});
  expectError(head + "count = [2, 1, 1]\nspacing = 1\njitter = -0.1\n", 16, {"jitter must be >= 0"});
  expectError(head + "count = [2, 1, 1]\nspacing = 1\nspin = -1\n", 16, {"spin must be >= 0"});
  expectError(head + "count = [1, 1, 1]\nshapes = [\"ball\"]\n", 15, {"either shape", "not both"});
  expectError(withExtra("[[group]]\ncount = [1, 1, 1]\n"), 12, {"missing the shape"});
  expectError(withExtra("[[group]]\nshapes = []\ncount = [1, 1, 1]\n"), 13, {"at least one"});
  expectError(withExtra("[[group]]\nshapes = [\"ball\", \"cube\"]\ncount = [1, 1, 1]\n"), 13,
              {"unknown shape \"cube\"", "defined shapes: \"ball\""});
}

TEST(SceneIoErrors, Shapes) {
  expectError(withLine(10, "shape = \"cube\""), 10, {"[[body]] #1", "unknown shape \"cube\"", "defined shapes: \"ball\""});
  // A shape without spheres is reported at its [[shape]] header.
  expectError(withExtra("[[shape]]\nname = \"empty\"\n"), 12, {"shape \"empty\" has no spheres", "[[shape.sphere]]"});
  expectError(withExtra("[[shape]]\nname = \"empty\"\nsphere = []\n"), 14, {"has no spheres"});
  expectError(withExtra("[[shape]]\nsphere = [{radius = 1, mass = 1}]\n"), 12, {"missing required key 'name'"});
  expectError(withExtra("[[shape]]\nname = \"ball\"\n[[shape.sphere]]\nradius = 1\nmass = 1\n"), 13,
              {"\"ball\" is already used"});
  expectError(withLine(8, "elasticity = 0.5"), 6, {"the sphere needs its mass (mass = 1.0, in kg) or a density"});
}

TEST(SceneIoErrors, Bodies) {
  expectError(withLine(11, "velocity = [0, 0, 1]"), 9, {"[[body]] #1", "missing required key 'position'"});
  expectError(withLine(10, "velocity = [0, 0, 1]"), 9, {"missing required key 'shape'"});
  expectError(withExtra("orientation = [0, 0, 0, 0]\n"), 12, {"zero quaternion", "[1, 0, 0, 0]"});
  expectError(withExtra("orientation = [1, 0, 0]\n"), 12, {"orientation must be an array of 4 numbers [w, x, y, z]"});
}

// Values that are each finite but whose derived values overflow single precision are refused at
// the line of their table (they used to surface as a non-finite body with no file or line).
TEST(SceneIoErrors, DerivedValuesBeyondSinglePrecision) {
  // Two 3e38 kg spheres: the body's mass overflows.
  expectError(withExtra("[[shape]]\nname = \"heavy\"\n[[shape.sphere]]\nradius = 1\nmass = 3e38\n"
                        "[[shape.sphere]]\noffset = [1, 0, 0]\nradius = 1\nmass = 3e38\n"),
              12, {"shape \"heavy\"", "total mass 6e+38 kg is beyond single precision"});
  // A far offset: the inertia overflows.
  expectError(withExtra("[[shape]]\nname = \"far\"\n[[shape.sphere]]\nradius = 1\nmass = 1e15\n"
                        "[[shape.sphere]]\noffset = [1e12, 0, 0]\nradius = 1\nmass = 1e15\n"),
              12, {"shape \"far\"", "moment of inertia"});
  expectError(withExtra("[[shape]]\nname = \"far\"\n[[shape.sphere]]\nradius = 1\nmass = 1\n"
                        "[[shape.sphere]]\noffset = [3e38, 0, 0]\nradius = 1\nmass = 1\n"),
              18, {"shape \"far\"", "component x of offset must be within +-2^60 m"});
  // A clump of tiny spheres: the inverse of the inertia overflows. (A single sphere never
  // rotates: its inertia is not checked, so the same ball alone is accepted.)
  expectError(withExtra("[[shape]]\nname = \"tiny\"\n[[shape.sphere]]\nradius = 1e-18\nmass = 1e-4\n"
                        "[[shape.sphere]]\nradius = 1e-18\nmass = 1e-4\n"),
              12, {"shape \"tiny\"", "too small for single precision"});
  EXPECT_NO_THROW((void)tumble::parseScene(withLine(7, "radius = 1e-18"), "test.toml"));
  // A body whose sphere reaches past the float range from its position.
  {
    std::vector<std::string> ls = baseLines();
    ls[6] = "radius = 1e18";
    ls[10] = "position = [1e18, 0, 0]";
    expectError(join(ls), 9, {"reach beyond +-2^60 m (1.15e18) from this position"});
  }
  // A lattice whose jitter, or whose velocity jitter, overflows.
  const std::string group = "[[group]]\nshape = \"ball\"\ncount = [2, 1, 1]\nspacing = 1\n";
  expectError(withExtra(group + "origin = [1e18, 0, 0]\njitter = 2e17\n"), 12, {"lattice reaches beyond +-2^60 m", "jitter"});
  expectError(withExtra(group + "origin = [3.4e38, 0, 0]\n"), 16, {"component x of origin must be within +-2^60 m"});
  expectError(withExtra(group + "velocity = [3e38, 0, 0]\nvelocity_jitter = 1e38\n"), 12,
              {"velocity with velocity_jitter"});
  // A spin whose angular momentum I ω overflows: at the key's line, for a body and for a lattice
  // (a clump of two 100 kg spheres: I ω up to 5.8e38 at 3e38 rad/s). Before, the body's L became
  // infinite at load and the run stopped at step 10 with "try dt = …".
  const std::string heavy =
      "[[shape]]\nname = \"heavy\"\nsphere = [{radius = 0.1, mass = 100}, {offset = [0.15, 0, 0], radius = 0.1, "
      "mass = 100}]\n";
  expectError(withExtra(heavy + "[[body]]\nshape = \"heavy\"\nposition = [0, 0, 1]\nangular_velocity = [0, 0, 3e38]\n"),
              18, {"angular_velocity", "angular momentum of up to 5.78e+38", "beyond single precision"});
  expectError(withExtra(heavy + "[[group]]\nshape = \"heavy\"\ncount = [2, 1, 1]\nspacing = 1\nspin = 3e38\n"), 19,
              {"spin", "beyond single precision", "shape 'heavy'"});
  EXPECT_NO_THROW((void)tumble::parseScene(
      withExtra(heavy + "[[body]]\nshape = \"heavy\"\nposition = [0, 0, 1]\nangular_velocity = [0, 0, 1e36]\n"),
      "test.toml"));
}

// A ground damping c = 2 ζ √(k m) beyond single precision (a 3e38 kg sphere of elasticity 1e-6 on
// a 3e38 N/m ground: 5.9e38 N s/m): refused at the sphere's table, and by World::fromScene for a
// scene built in code. Before, the damping was infinite and the first ground contact gave NaN.
TEST(SceneIoErrors, GroundDampingBeyondSinglePrecision) {
  std::vector<std::string> ls = baseLines();
  ls[7] = "mass = 3e38";
  ls.insert(ls.begin() + 8, "elasticity = 1e-6");
  ls.insert(ls.begin() + 3, "gravity = [0, 0, 0]");  // a 3e38 kg sphere's weight is beyond a float too
  ls.push_back("[ground]");
  ls.push_back("stiffness = 3e38");
  expectError(join(ls), 7, {"[[shape.sphere]] #1: its ground damping", "beyond single precision"});
  try {
    (void)tumble::parseScene(join(ls), "test.toml");
  } catch (const tumble::InputError& e) {  // the place is named once
    const std::string m = e.what();
    EXPECT_EQ(m.find("[[shape.sphere]]"), m.rfind("[[shape.sphere]]")) << m;
  }
  ls.push_back("enabled = false");  // no ground, no ground damping
  EXPECT_NO_THROW((void)tumble::parseScene(join(ls), "test.toml"));
  ls.pop_back();
  ls.back() = "stiffness = 1e30";
  tumble::Scene scene = tumble::parseScene(join(ls), "test.toml");
  EXPECT_NO_THROW((void)tumble::World::fromScene(scene));
  scene.ground.stiffness = 3e38f;
  try {
    (void)tumble::World::fromScene(scene);
    ADD_FAILURE() << "an infinite ground damping was accepted";
  } catch (const tumble::Error& e) {
    EXPECT_NE(std::string(e.what()).find("ground damping"), std::string::npos) << e.what();
  }
}

// A lattice the machine could never run is refused at its count, at once, instead of ending in
// std::bad_alloc after minutes (2e9 bodies need over 3 TB), with the sizes: the bodies,
// the particles, the estimate of the run's peak (tumble/run_memory.hpp) and what is available.
// So is a pour, whose bodies the run holds by the end.
TEST(SceneIoErrors, ALatticeTooBigForTheMemory) {
  const auto have = tumble::availableMemory();
  if (!have) GTEST_SKIP() << "no /proc/meminfo";
  if (*have > (std::uint64_t{1} << 40)) GTEST_SKIP() << "this machine has more than a terabyte available";
  expectError(withExtra("[[group]]\nshape = \"ball\"\ncount = [1000, 1000, 2000]\nspacing = 1\n"), 14,
              {"a run of 2000000001 bodies and 2000000001 particles needs about 3", " GiB at its peak",
               "more than the ", "this machine has available", "use a smaller count"});
  expectError(withExtra("[[pour]]\nshape = \"ball\"\ncount = 2000000000\nrate = 1\nregion = \"box\"\n"
                        "min = [0, 0, 0]\nmax = [1, 1, 1]\n"),
              14, {"[[pour]] #1", "a run of 2000000001 bodies and 2000000001 particles needs about ", " GiB at its peak"});
}

TEST(SceneIoErrors, WholeFile) {
  // Missing [scene], and no bodies at all: the file as a whole (line 0).
  std::vector<std::string> ls = baseLines();
  ls.erase(ls.begin(), ls.begin() + 3);
  expectError(join(ls), 0, {"missing the [scene] table"});
  ls = baseLines();
  ls.resize(8);
  expectError(join(ls), 0, {"no bodies", "[[body]]", "[[group]]"});
  expectError(withLine(2, "name = \"x\""), 1, {"[scene]", "missing required key 'dt'"});
}

TEST(SceneIoErrors, TooManyParticles) {
  // 2^31 + 2^21 lone spheres: rejected at the count line before anything is generated.
  expectError(withExtra("[[group]]\nshape = \"ball\"\ncount = [2048, 1024, 1025]\nspacing = 1\n"), 14,
              {"more than 2^31"});
  // 2^30 sites of a 2-sphere shape.
  expectError(withExtra(lines({"[[shape]]", "name = \"pair\"", "sphere = [{radius = 1, mass = 1}, {radius = 1, mass = 1}]",
                               "[[group]]", "shape = \"pair\"", "count = [1024, 1024, 1025]", "spacing = 1"})),
              17, {"more than 2^31 particles"});
  expectError(withExtra("[[group]]\nshape = \"ball\"\ncount = [4294967296, 1, 1]\nspacing = 1\n"), 14,
              {"more than 2^31"});
}

}  // namespace

// Derived values that overflow are refused at load, at their line (issue 34, item 8): they were
// found only by the run ("particle 0 has a non-finite position", or a guard advising a smaller dt).
TEST(SceneIoErrors, OverflowsFoundOnlyByTheRunAreRefusedAtLoad) {
  expectError(withExtra("[periodic]\nx = [-3.4e38, 3.4e38]\n"), 13, {"[periodic]: x[0] must be within +-2^60 m"});
  expectError(withLine(8, "mass = 1e38"), 4, {"its weight m |g| = 9.81e+38 N is beyond single precision"});
  std::vector<std::string> weightless = baseLines();
  weightless[7] = "mass = 1e38";
  weightless[1] = "dt = 1e-4\ngravity = [0, 0, 0]";
  EXPECT_NO_THROW((void)tumble::parseScene(join(weightless), "test.toml")) << "no gravity: no weight to overflow";
}

// Review of issue 34, item 7: a [[fill]] or [[pour]] cylinder whose point, axis and radius
// together reach beyond ±2^60 m (its bodies were placed at 7.7e29 and 1.69e18 m), and a
// revolved wall more than 2^15 times the smallest radius (a 0.05 m ball fell through a cylinder
// of 1e7 m, and rested 5 mm off on one of 1e5 m) are refused at their line.
TEST(SceneIoErrors, RegionsAndRevolvedWallsWithinTheExactRange) {
  const std::string fill = "[[fill]]\nshape = \"ball\"\ncount = 3\nregion = \"cylinder\"\n";  // line 12
  expectError(withExtra(fill + "point = [0, 0, 0]\naxis = [0, 0, 10]\nradius = 1e30\n"), 18,
              {"[[fill]] #1: the cylinder (point, axis and radius) reaches beyond +-2^60 m"});
  expectError(withExtra(fill + "point = [1.1e18, 0, 0]\naxis = [1.1e18, 0, 0]\nradius = 10\n"), 18,
              {"reaches beyond +-2^60 m"});
  EXPECT_NO_THROW((void)tumble::parseScene(withExtra(fill + "point = [0, 0, 5]\naxis = [0, 0, 10]\nradius = 10\n"),
                                           "test.toml"));
  // The ball's radius is 0.5 m: at most 2^14 m.
  expectError(withExtra("[[wall]]\ntype = \"cylinder\"\npoint = [0, -1, 0]\naxis = [0, 2, 0]\nradius = 1e5\n"), 12,
              {"[[wall]] #1: its radius or length, 1e+05 m, is more than 2^15 = 32768 times the smallest sphere's "
               "radius (0.5 m)", "at most 1.638e+04 m"});
  expectError(withExtra("[[wall]]\ntype = \"cylinder\"\npoint = [0, 0, 0]\naxis = [0, 0, 2e4]\nradius = 3\n"), 12,
              {"its radius or length, 2e+04 m"});
  EXPECT_NO_THROW((void)tumble::parseScene(
      withExtra("[[wall]]\ntype = \"cylinder\"\npoint = [0, -1, 0]\naxis = [0, 2, 0]\nradius = 1.6e4\n"), "test.toml"));
}
