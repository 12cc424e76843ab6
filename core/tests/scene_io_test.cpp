// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader (core/src/scene_io.cpp, docs/scenes.md): every file in
// scenes/ parses with the documented counts and starts without contacts, parsing is
// deterministic, and the tables read as documented. Errors: scene_io_errors_test.cpp.
#include "scene_io_test_util.hpp"

namespace {

using namespace scene_io_test;

// ---------------------------------------------------------------------------------------
// The shipped scenes.

TEST(SceneFiles, EveryFileParses) {
  int numFiles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(TUMBLE_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    ++numFiles;
    const Scene s = tumble::readSceneFile(entry.path().string());
    EXPECT_FALSE(s.bodies.empty() && s.pourBodies.empty()) << "bodies at the start, or poured (scenes/pour.toml)";
    EXPECT_GT(s.dt, 0.0f);
    EXPECT_GE(s.steps, 1u);
    EXPECT_TRUE(s.ground.enabled || !s.walls.empty()) << "something to land on";
    EXPECT_EQ(s.sourceFile, entry.path().string());
    EXPECT_EQ(s.name, entry.path().stem().string());
    for (const BodyDef& b : s.bodies) {
      ASSERT_LT(b.shape, s.shapes.size());
      const tumble::Quatf q = b.orientation;
      EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0f, 1e-5f);
    }
  }
  EXPECT_GE(numFiles, 5);
}

TEST(SceneFiles, Spheres) {
  const Scene s = tumble::readSceneFile(scenePath("spheres.toml"));
  EXPECT_EQ(s.bodies.size(), 4000u);
  EXPECT_EQ(numParticles(s), 4000u);
  ASSERT_EQ(s.shapes.size(), 2u);
  std::size_t numSmall = 0;
  for (const BodyDef& b : s.bodies) numSmall += b.shape == 0 ? 1 : 0;
  // Both kinds are picked, roughly half each.
  EXPECT_GT(numSmall, 1800u);
  EXPECT_LT(numSmall, 2200u);
  for (const auto& shape : s.shapes) EXPECT_EQ(shape.spheres.size(), 1u);
  EXPECT_TRUE(s.recordFile.empty());
  EXPECT_EQ(s.ground.stiffness, s.contact.stiffness);  // default: the contact stiffness
}

TEST(SceneFiles, Molecules) {
  const Scene s = tumble::readSceneFile(scenePath("molecules.toml"));
  EXPECT_EQ(s.bodies.size(), 1522u);  // 20 x 19 x 4 lattice + 2 explicit rings
  const std::uint64_t n = numParticles(s);
  EXPECT_EQ(n, 6124u);
  EXPECT_GE(n, 6000u);
  EXPECT_LE(n, 10000u);
  EXPECT_EQ(s.steps, 3000u);
  EXPECT_EQ(s.recordFile, "molecules.bin");
  EXPECT_EQ(s.recordSteps, 3000u);
  EXPECT_EQ(s.stepsPerFrame, 10);
  EXPECT_GE(s.shapes.size(), 4u);
  float rMin = 1e30f, rMax = 0, eMin = 1, eMax = 0, mMin = 1e30f;
  for (const auto& shape : s.shapes) {
    EXPECT_GE(shape.spheres.size(), 2u);
    EXPECT_LE(shape.spheres.size(), 6u);
    for (const auto& sp : shape.spheres) {
      rMin = std::min(rMin, sp.radius);
      rMax = std::max(rMax, sp.radius);
      eMin = std::min(eMin, sp.elasticity);
      eMax = std::max(eMax, sp.elasticity);
      mMin = std::min(mMin, sp.mass);
    }
  }
  EXPECT_NEAR(rMax / rMin, 2.0f, 1e-5f);
  EXPECT_LE(eMin, 0.2f);
  EXPECT_GE(eMax, 0.9f);
  // dt is at most 1/20 of the contact time of the two lightest particles.
  const double tc = 3.14159265358979 * std::sqrt(0.5 * mMin / s.contact.stiffness);
  EXPECT_LE(s.dt, tc / 20.0);
  // Every shape is used, and the explicit bodies come after the group (file order).
  std::vector<int> used(s.shapes.size(), 0);
  for (const BodyDef& b : s.bodies) used[b.shape] = 1;
  for (int u : used) EXPECT_EQ(u, 1);
  EXPECT_EQ(s.shapes[s.bodies[1520].shape].name, "ring");
  EXPECT_FLOAT_EQ(s.bodies[1521].position.z, 2.9f);
}

struct BenchCase {
  const char* file;
  std::size_t numBodies;
};

TEST(SceneFiles, Bench) {
  for (const BenchCase& c : {BenchCase{"bench-16k.toml", 2000}, BenchCase{"bench-128k.toml", 16000},
                             BenchCase{"bench-960k.toml", 120000}}) {
    SCOPED_TRACE(c.file);
    const Scene s = tumble::readSceneFile(scenePath(c.file));
    ASSERT_EQ(s.shapes.size(), 1u);
    ASSERT_EQ(s.shapes[0].spheres.size(), 8u);
    EXPECT_EQ(s.bodies.size(), c.numBodies);
    EXPECT_EQ(numParticles(s), c.numBodies * 8);
    EXPECT_FLOAT_EQ(s.dt, 5e-4f);
    EXPECT_FLOAT_EQ(s.contact.stiffness, 2e4f);
    EXPECT_FLOAT_EQ(s.ground.friction, 0.5f);
    EXPECT_FLOAT_EQ(s.gravity.z, -9.81f);
    EXPECT_TRUE(s.recordFile.empty());
    for (const auto& sp : s.shapes[0].spheres) {
      EXPECT_EQ(sp.radius, 0.5f);
      EXPECT_EQ(sp.mass, 1.0f);
      EXPECT_EQ(std::fabs(sp.offset.x), 0.25f);
      EXPECT_EQ(std::fabs(sp.offset.y), 0.25f);
      EXPECT_EQ(std::fabs(sp.offset.z), 0.25f);
    }
    // Lattice as gen_init.py: first site at (0.825, 0.825, 0.8) ± 0.025, x fastest.
    const BodyDef& b0 = s.bodies[0];
    EXPECT_NEAR(b0.position.x, 0.825f, 0.0251f);
    EXPECT_NEAR(b0.position.y, 0.825f, 0.0251f);
    EXPECT_NEAR(b0.position.z, 0.8f, 0.0251f);
    EXPECT_NEAR(s.bodies[1].position.x, 0.825f + 1.65f, 0.0501f);
    float zMin = 1e30f;
    for (const BodyDef& b : s.bodies) {
      zMin = std::min(zMin, b.position.z);
      EXPECT_LE(std::fabs(b.velocity.x), 0.5f);
      EXPECT_EQ(b.orientation.w, 1.0f);
      EXPECT_EQ(b.angularVelocity.x, 0.0f);
    }
    EXPECT_GE(zMin - 0.75f, 0.05f - 0.0251f);
  }
}

TEST(SceneFiles, NoInitialContactsAndAboveGround) {
  for (const char* f : {"spheres.toml", "molecules.toml", "bench-16k.toml", "chute.toml"}) {
    SCOPED_TRACE(f);
    const Scene s = tumble::readSceneFile(scenePath(f));
    const std::vector<Particle> ps = particlesOf(s);
    EXPECT_EQ(countInitialOverlaps(ps), 0u);
    for (const Particle& p : ps) EXPECT_GT(p.x.z - p.r, s.ground.height);
  }
}

TEST(SceneFiles, Deterministic) {
  for (const char* f : {"spheres.toml", "molecules.toml", "bench-16k.toml", "chute.toml"}) {
    SCOPED_TRACE(f);
    const Scene a = tumble::readSceneFile(scenePath(f));
    const Scene b = tumble::readSceneFile(scenePath(f));
    EXPECT_TRUE(sameBits(a, b));
  }
}

// ---------------------------------------------------------------------------------------
// Values, defaults and generation.

TEST(SceneIo, MinimalSceneAndDefaults) {
  const Scene s = tumble::parseScene(join(baseLines()), "dir/minimal.toml");
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.sourceFile, "dir/minimal.toml");
  EXPECT_FLOAT_EQ(s.dt, 1e-4f);
  EXPECT_EQ(s.steps, 10u);
  EXPECT_FLOAT_EQ(s.gravity.z, -9.81f);
  EXPECT_FALSE(s.ground.enabled);  // no [ground] table
  EXPECT_EQ(s.pulls.active, 0u);
  EXPECT_TRUE(s.recordFile.empty());
  EXPECT_EQ(s.stepsPerFrame, 10);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_FLOAT_EQ(s.bodies[0].position.z, 1.0f);
  EXPECT_EQ(s.bodies[0].orientation.w, 1.0f);
  const tumble::SphereDef& sp = s.shapes[0].spheres[0];
  EXPECT_EQ(sp.radius, 0.5f);  // written as a float
  EXPECT_EQ(sp.elasticity, 0.5f);
  EXPECT_EQ(sp.offset.x, 0.0f);
}

TEST(SceneIo, AllSections) {
  const Scene s = tumble::parseScene(
      withExtra(lines({"[contact]", "stiffness = 1e5", "damping = 3", "shear = 2", "[ground]",
                       "height = -1", "friction = 0.3", "tangential_stiffness = 7", "[pulls]",
                       "x = 1", "y = 2", "swirl = -3", "on = [\"x\", \"swirl\"]", "[broadphase]",
                       "cell_size = 2.5", "pca_every = 1", "[output]", "record = \"out/r.bin\"",
                       "record_steps = 600", "debug = true", "contacts = true", "steps_per_frame = 5"})),
      "t.toml");
  EXPECT_EQ(s.contact.stiffness, 1e5f);
  EXPECT_EQ(s.contact.damping, 3.0f);
  EXPECT_EQ(s.contact.shear, 2.0f);
  EXPECT_TRUE(s.ground.enabled);
  EXPECT_EQ(s.ground.height, -1.0f);
  EXPECT_EQ(s.ground.stiffness, 1e5f);  // defaults to the contact stiffness
  EXPECT_EQ(s.ground.friction, 0.3f);
  EXPECT_EQ(s.ground.tangentialStiffness, 7.0f);
  EXPECT_EQ(s.pulls.x, 1.0f);
  EXPECT_EQ(s.pulls.swirl, -3.0f);
  EXPECT_EQ(s.pulls.active, static_cast<std::uint32_t>(tumble::kPullX | tumble::kPullSwirl));
  EXPECT_EQ(s.broadphase.cellSize, 2.5f);
  EXPECT_EQ(s.broadphase.pcaEvery, 1);
  EXPECT_EQ(s.recordFile, "out/r.bin");
  EXPECT_EQ(s.recordSteps, 600u);
  EXPECT_TRUE(s.recordDebug);
  EXPECT_TRUE(s.recordContacts);
  EXPECT_EQ(s.stepsPerFrame, 5);

  const Scene off = tumble::parseScene(withExtra("[ground]\nenabled = false\n"), "t.toml");
  EXPECT_FALSE(off.ground.enabled);
}

TEST(SceneIo, OrientationIsNormalised) {
  const Scene s = tumble::parseScene(
      withExtra(lines({"[[body]]", "shape = \"ball\"", "position = [0, 0, 3]", "orientation = [2, 0, 0, 0]",
                       "[[body]]", "shape = \"ball\"", "position = [0, 0, 5]", "orientation = [1, 1, 0, 0]",
                       "angular_velocity = [0, 0, 4]", "velocity = [1, 2, 3]"})),
      "t.toml");
  ASSERT_EQ(s.bodies.size(), 3u);
  EXPECT_EQ(s.bodies[1].orientation.w, 1.0f);
  EXPECT_EQ(s.bodies[1].orientation.x, 0.0f);
  EXPECT_NEAR(s.bodies[2].orientation.w, 0.70710678f, 1e-7f);
  EXPECT_NEAR(s.bodies[2].orientation.x, 0.70710678f, 1e-7f);
  EXPECT_EQ(s.bodies[2].angularVelocity.z, 4.0f);
  EXPECT_EQ(s.bodies[2].velocity.y, 2.0f);
}

TEST(SceneIo, LatticeOrderXFastest) {
  const Scene s = tumble::parseScene(
      withExtra(lines({"[[group]]", "shape = \"ball\"", "count = [3, 2, 2]", "spacing = [1, 10, 100]",
                       "origin = [0.5, 0, 2]"})),
      "t.toml");
  ASSERT_EQ(s.bodies.size(), 13u);
  int n = 1;
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 3; ++i, ++n) {
        const BodyDef& b = s.bodies[static_cast<std::size_t>(n)];
        EXPECT_EQ(b.position.x, 0.5f + static_cast<float>(i));
        EXPECT_EQ(b.position.y, 10.0f * static_cast<float>(j));
        EXPECT_EQ(b.position.z, 2.0f + 100.0f * static_cast<float>(k));
        EXPECT_EQ(b.velocity.x, 0.0f);
        EXPECT_EQ(b.orientation.w, 1.0f);
        EXPECT_EQ(b.angularVelocity.z, 0.0f);
      }
    }
  }
  // A scalar spacing applies to every axis.
  const Scene t = tumble::parseScene(
      withExtra(lines({"[[group]]", "shape = \"ball\"", "count = [2, 2, 1]", "spacing = 3"})), "t.toml");
  EXPECT_EQ(t.bodies[4].position.x, 3.0f);
  EXPECT_EQ(t.bodies[4].position.y, 3.0f);
}

TEST(SceneIo, FileOrderOfBodiesAndGroups) {
  // body (z=1), group (z=7), body (z=9): bodies come out in that order.
  const Scene s = tumble::parseScene(
      withExtra(lines({"[[group]]", "shape = \"ball\"", "count = [2, 1, 1]", "spacing = 2",
                       "origin = [0, 0, 7]", "[[body]]", "shape = \"ball\"", "position = [0, 0, 9]"})),
      "t.toml");
  ASSERT_EQ(s.bodies.size(), 4u);
  EXPECT_EQ(s.bodies[0].position.z, 1.0f);
  EXPECT_EQ(s.bodies[1].position.z, 7.0f);
  EXPECT_EQ(s.bodies[2].position.z, 7.0f);
  EXPECT_EQ(s.bodies[3].position.z, 9.0f);
}

TEST(SceneIo, RandomGroupWithinBounds) {
  const std::string text =
      lines({"[scene]", "dt = 1e-4", "steps = 1", "seed = 7", "[[shape]]", "name = \"a\"", "[[shape.sphere]]",
             "radius = 1", "mass = 1", "[[shape]]", "name = \"b\"", "sphere = [{radius = 1, mass = 1}, "
             "{offset = [1, 0, 0], radius = 0.5, mass = 2, elasticity = 1}]",
             "[[group]]", "shapes = [\"a\", \"b\"]", "count = [10, 10, 10]", "spacing = [5, 6, 7]",
             "origin = [1, 2, 3]", "jitter = 0.25", "velocity = [1, 0, -1]", "velocity_jitter = 0.5",
             "random_orientation = true", "spin = 2"});
  const Scene s = tumble::parseScene(text, "t.toml");
  ASSERT_EQ(s.bodies.size(), 1000u);
  ASSERT_EQ(s.shapes[1].spheres.size(), 2u);
  EXPECT_EQ(s.shapes[1].spheres[1].elasticity, 1.0f);
  std::size_t numA = 0;
  double meanQw = 0;
  std::size_t i = 0;
  for (int z = 0; z < 10; ++z) {
    for (int y = 0; y < 10; ++y) {
      for (int x = 0; x < 10; ++x, ++i) {
        const BodyDef& b = s.bodies[i];
        numA += b.shape == 0 ? 1 : 0;
        EXPECT_LE(std::fabs(b.position.x - (1.0f + 5.0f * static_cast<float>(x))), 0.25f + 1e-5f);
        EXPECT_LE(std::fabs(b.position.y - (2.0f + 6.0f * static_cast<float>(y))), 0.25f + 1e-5f);
        EXPECT_LE(std::fabs(b.position.z - (3.0f + 7.0f * static_cast<float>(z))), 0.25f + 1e-5f);
        EXPECT_LE(std::fabs(b.velocity.x - 1.0f), 0.5f);
        EXPECT_LE(std::fabs(b.velocity.y), 0.5f);
        EXPECT_LE(std::fabs(b.velocity.z + 1.0f), 0.5f);
        const tumble::Quatf q = b.orientation;
        EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0f, 1e-5f);
        meanQw += std::fabs(q.w);
        EXPECT_NEAR(tumble::norm(b.angularVelocity), 2.0f, 1e-5f);
      }
    }
  }
  EXPECT_GT(numA, 400u);
  EXPECT_LT(numA, 600u);
  // A component of a uniform unit quaternion has density (2/pi) sqrt(1 - w^2), so
  // E|w| = 4 / (3 pi) ≈ 0.424 (the identity would give 1).
  meanQw /= 1000.0;
  EXPECT_NEAR(meanQw, 4.0 / (3.0 * 3.14159265358979), 0.03);

  // Same text, same bits; another seed, other values.
  EXPECT_TRUE(sameBits(s, tumble::parseScene(text, "t.toml")));
  std::string reseeded = text;
  reseeded.replace(reseeded.find("seed = 7"), 8, "seed = 8");
  EXPECT_FALSE(sameBits(s, tumble::parseScene(reseeded, "t.toml")));
}

TEST(SceneIo, GroupsAreIndependent) {
  // A body inserted before a group, or a change in a second group, leaves the first group's
  // bodies bit-identical.
  const std::string group1 =
      lines({"[[group]]", "shape = \"ball\"", "count = [4, 4, 4]", "spacing = 3", "jitter = 0.1",
             "velocity_jitter = 1", "random_orientation = true", "spin = 1"});
  const Scene a = tumble::parseScene(join(baseLines()) + group1, "t.toml");
  const Scene b = tumble::parseScene(
      join(baseLines()) + group1 +
          lines({"[[group]]", "shape = \"ball\"", "count = [2, 2, 2]", "spacing = 3", "origin = [0, 0, 50]",
                 "jitter = 0.2"}),
      "t.toml");
  const Scene c = tumble::parseScene(
      join(baseLines()) + lines({"[[body]]", "shape = \"ball\"", "position = [0, 0, 9]"}) + group1, "t.toml");
  ASSERT_EQ(a.bodies.size(), 65u);
  ASSERT_EQ(b.bodies.size(), 73u);
  ASSERT_EQ(c.bodies.size(), 66u);
  EXPECT_EQ(std::memcmp(a.bodies.data(), b.bodies.data(), 65 * sizeof(BodyDef)), 0);
  EXPECT_EQ(std::memcmp(a.bodies.data() + 1, c.bodies.data() + 2, 64 * sizeof(BodyDef)), 0);
}

TEST(SceneIo, ReadFileAndMissingFile) {
  const std::string path = ::testing::TempDir() + "scene_io_test_tmp.toml";
  {
    std::ofstream out(path);
    out << join(baseLines());
  }
  const Scene s = tumble::readSceneFile(path);
  EXPECT_EQ(s.name, "scene_io_test_tmp");
  EXPECT_EQ(s.sourceFile, path);
  std::remove(path.c_str());

  try {
    (void)tumble::readSceneFile(path);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 0);
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find("cannot open: No such file or directory"), std::string::npos)
        << e.what();
  }
}

}  // namespace
