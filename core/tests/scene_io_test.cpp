// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader (core/src/scene_io.cpp, docs/scenes.md): every file in
// scenes/ parses with the documented counts and starts without contacts, parsing is
// deterministic, and each invalid input gives an InputError at the right line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/memory.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/world.hpp"

#ifndef TUMBLE_SOURCE_DIR
#error "TUMBLE_SOURCE_DIR must name the source tree (set by core/CMakeLists.txt)"
#endif

namespace {

using tumble::BodyDef;
using tumble::InputError;
using tumble::Scene;
using tumble::Vec3f;

std::string scenePath(const std::string& name) {
  return std::string(TUMBLE_SOURCE_DIR) + "/scenes/" + name;
}

std::uint64_t numParticles(const Scene& s) {
  std::uint64_t n = 0;
  for (const BodyDef& b : s.bodies) n += s.shapes[b.shape].spheres.size();
  return n;
}

/// Joins lines with '\n', so that tests can name line numbers by position (1-based).
std::string lines(std::initializer_list<const char*> ls) {
  std::string out;
  for (const char* l : ls) {
    out += l;
    out += '\n';
  }
  return out;
}

/// A minimal valid scene; tests replace one line at a time (line numbers in the comments).
std::vector<std::string> baseLines() {
  return {
      "[scene]",                  // 1
      "dt = 1e-4",                // 2
      "steps = 10",               // 3
      "[[shape]]",                // 4
      "name = \"ball\"",          // 5
      "[[shape.sphere]]",         // 6
      "radius = 0.5",             // 7
      "mass = 1.0",               // 8
      "[[body]]",                 // 9
      "shape = \"ball\"",         // 10
      "position = [0, 0, 1]",     // 11
  };
}

std::string join(const std::vector<std::string>& ls) {
  std::string out;
  for (const std::string& l : ls) out += l + '\n';
  return out;
}

/// The base scene with line `line` (1-based) replaced by `text`.
std::string withLine(int line, const std::string& text) {
  std::vector<std::string> ls = baseLines();
  ls.at(static_cast<std::size_t>(line - 1)) = text;
  return join(ls);
}

/// The base scene with `extra` appended (its first line is line 12).
std::string withExtra(const std::string& extra) { return join(baseLines()) + extra; }

/// Expects parseScene(text) to throw an InputError at `line` whose message contains every
/// string in `needles`.
void expectError(const std::string& text, long line, std::initializer_list<const char*> needles) {
  try {
    (void)tumble::parseScene(text, "test.toml");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.file(), "test.toml");
    for (const char* n : needles) {
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos)
          << "message lacks \"" << n << "\": " << e.what();
    }
  }
}

/// World-space particle centres: each shape's spheres are placed about their centre of mass
/// (as World::fromScene does), rotated by the body orientation.
struct Particle {
  Vec3f x;
  float r;
  std::uint32_t body;
};

std::vector<Particle> particlesOf(const Scene& s) {
  std::vector<Vec3f> com(s.shapes.size());
  for (std::size_t k = 0; k < s.shapes.size(); ++k) {
    double m = 0, cx = 0, cy = 0, cz = 0;
    for (const auto& sp : s.shapes[k].spheres) {
      m += sp.mass;
      cx += sp.mass * static_cast<double>(sp.offset.x);
      cy += sp.mass * static_cast<double>(sp.offset.y);
      cz += sp.mass * static_cast<double>(sp.offset.z);
    }
    com[k] = Vec3f{static_cast<float>(cx / m), static_cast<float>(cy / m), static_cast<float>(cz / m)};
  }
  std::vector<Particle> out;
  for (std::uint32_t b = 0; b < s.bodies.size(); ++b) {
    const BodyDef& body = s.bodies[b];
    for (const auto& sp : s.shapes[body.shape].spheres) {
      const Vec3f u = sp.offset - com[body.shape];
      out.push_back({body.position + tumble::rotate(body.orientation, u), sp.radius, b});
    }
  }
  return out;
}

/// Number of overlapping particle pairs of different bodies (uniform grid, cell = 2 r_max).
std::uint64_t countInitialOverlaps(const std::vector<Particle>& ps) {
  float rMax = 0;
  for (const Particle& p : ps) rMax = std::max(rMax, p.r);
  const float cell = 2.0f * rMax;
  auto cellOf = [&](float v) { return static_cast<std::int64_t>(std::floor(v / cell)); };
  auto key = [](std::int64_t a, std::int64_t b, std::int64_t c) {
    return (static_cast<std::uint64_t>(a & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(b & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(c & 0x1FFFFF);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (std::uint32_t i = 0; i < ps.size(); ++i) {
    grid[key(cellOf(ps[i].x.x), cellOf(ps[i].x.y), cellOf(ps[i].x.z))].push_back(i);
  }
  std::uint64_t overlaps = 0;
  for (std::uint32_t i = 0; i < ps.size(); ++i) {
    const std::int64_t a = cellOf(ps[i].x.x), b = cellOf(ps[i].x.y), c = cellOf(ps[i].x.z);
    for (std::int64_t da = -1; da <= 1; ++da) {
      for (std::int64_t db = -1; db <= 1; ++db) {
        for (std::int64_t dc = -1; dc <= 1; ++dc) {
          const auto it = grid.find(key(a + da, b + db, c + dc));
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            if (j <= i || ps[j].body == ps[i].body) continue;
            const float rr = ps[i].r + ps[j].r;
            if (tumble::norm2(ps[i].x - ps[j].x) < rr * rr) ++overlaps;
          }
        }
      }
    }
  }
  return overlaps;
}

bool sameBits(const Scene& a, const Scene& b) {
  if (a.bodies.size() != b.bodies.size() || a.shapes.size() != b.shapes.size()) return false;
  static_assert(sizeof(BodyDef) == 14 * 4, "BodyDef has padding; compare field by field");
  if (std::memcmp(a.bodies.data(), b.bodies.data(), a.bodies.size() * sizeof(BodyDef)) != 0) return false;
  for (std::size_t k = 0; k < a.shapes.size(); ++k) {
    if (a.shapes[k].name != b.shapes[k].name) return false;
    if (a.shapes[k].spheres.size() != b.shapes[k].spheres.size()) return false;
    if (std::memcmp(a.shapes[k].spheres.data(), b.shapes[k].spheres.data(),
                    a.shapes[k].spheres.size() * sizeof(tumble::SphereDef)) != 0) {
      return false;
    }
  }
  return true;
}

// ---------------------------------------------------------------------------------------
// The shipped scenes.

TEST(SceneFiles, EveryFileParses) {
  int numFiles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(TUMBLE_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    ++numFiles;
    const Scene s = tumble::readSceneFile(entry.path().string());
    EXPECT_FALSE(s.bodies.empty());
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
                       "record_steps = 600", "debug = true", "steps_per_frame = 5"})),
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
  expectError(withExtra("[ground]\nrolling_friction = 0.1\n"), 13, {"rolling_friction needs a contact law that turns spheres"});
  expectError(withExtra("[contact]\nlaw = \"hooke-history\"\nfriction = -1\n"), 14, {"friction"});
}

namespace {
const char* kGlass = "[[material]]\nname = \"glass\"\ndensity = 2500\nyoungs_modulus = 6.3e10\npoisson_ratio = 0.23\n"
                     "restitution = 0.9\nfriction = 0.3\n";
const char* kSteel = "[[material]]\nname = \"steel\"\ndensity = 7800\nyoungs_modulus = 2e11\npoisson_ratio = 0.3\n"
                     "restitution = 0.8\nrolling_friction = 0.01\n";
const char* kHertz = "[contact]\nlaw = \"hertz-mindlin\"\n";
}  // namespace

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
  // Under a law that turns spheres a single sphere's inertia is used, so it must fit a float.
  std::string heavy = withLine(8, "mass = 1e38") + kHertz + kGlass;
  heavy.replace(heavy.find("radius = 0.5"), 12, "radius = 100");  // I = 0.4 m r^2 = 4e41 kg m^2
  expectError(heavy, 4, {"moment of inertia", "beyond single precision"});
  std::string heavyReport = withLine(8, "mass = 1e38");
  heavyReport.replace(heavyReport.find("radius = 0.5"), 12, "radius = 100");
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
  expectError(withLine(7, "radius = 1e39"), 7, {"out of single-precision range"});
  std::vector<std::string> ls = baseLines();
  ls.insert(ls.begin() + 3, "gravity = [0,\n 0,\n nan]");  // elements on their own lines
  expectError(join(ls), 6, {"component z of gravity must be a finite number"});
}

TEST(SceneIoErrors, PhysicalRanges) {
  expectError(withLine(7, "radius = -1"), 7, {"shape \"ball\"", "radius must be > 0 (got -1)"});
  expectError(withLine(7, "radius = 0"), 7, {"radius must be > 0 (got 0)"});
  expectError(withLine(7, "radius = 1e-50"), 7, {"radius must be > 0 (got 1e-50)"});  // rounds to 0 in float
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
  expectError(withExtra("[[shape]]\nname = \"far\"\n[[shape.sphere]]\nradius = 1\nmass = 1\n"
                        "[[shape.sphere]]\noffset = [3e38, 0, 0]\nradius = 1\nmass = 1\n"),
              12, {"shape \"far\"", "moment of inertia"});
  // A clump of tiny spheres: the inverse of the inertia overflows. (A single sphere never
  // rotates: its inertia is not checked, so the same ball alone is accepted.)
  expectError(withExtra("[[shape]]\nname = \"tiny\"\n[[shape.sphere]]\nradius = 1e-20\nmass = 1\n"
                        "[[shape.sphere]]\nradius = 1e-20\nmass = 1\n"),
              12, {"shape \"tiny\"", "too small for single precision"});
  EXPECT_NO_THROW((void)tumble::parseScene(withLine(7, "radius = 1e-20"), "test.toml"));
  // A body whose sphere reaches past the float range from its position.
  {
    std::vector<std::string> ls = baseLines();
    ls[6] = "radius = 1e38";
    ls[7] = "mass = 3e-38";
    ls[10] = "position = [3e38, 0, 0]";
    expectError(join(ls), 9, {"reach beyond single-precision range"});
  }
  // A lattice whose jitter, or whose velocity jitter, overflows.
  const std::string group = "[[group]]\nshape = \"ball\"\ncount = [2, 1, 1]\nspacing = 1\n";
  expectError(withExtra(group + "origin = [3.4e38, 0, 0]\njitter = 1e38\n"), 12, {"lattice reaches beyond", "jitter"});
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
  ls.push_back("[ground]");
  ls.push_back("stiffness = 3e38");
  expectError(join(ls), 6, {"[[shape.sphere]] #1: its ground damping", "beyond single precision"});
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
// std::bad_alloc after minutes (2e9 bodies need over a terabyte).
TEST(SceneIoErrors, ALatticeTooBigForTheMemory) {
  const auto have = tumble::availableMemory();
  if (!have) GTEST_SKIP() << "no /proc/meminfo";
  if (*have > (std::uint64_t{1} << 40)) GTEST_SKIP() << "this machine has more than a terabyte available";
  expectError(withExtra("[[group]]\nshape = \"ball\"\ncount = [1000, 1000, 2000]\nspacing = 1\n"), 14,
              {"a run of 2000000001 bodies", "needs at least", "this machine has available", "use a smaller count"});
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

// toml++ 3.3.0 parses a dotted key by recursion and overflowed the stack (SIGSEGV) on a key or
// header of 40 000 parts: refused before it parses, with the line; 63 parts still reach it (and
// its own message), and dots in values, strings and comments do not count.
TEST(SceneIo, DeepDottedKeysAreRefusedBeforeTomlParsesThem) {
  std::string deep;
  for (int k = 0; k < 40000; ++k) deep += "x.";
  // (Strings built by +=: GCC 12 warns falsely, -Wrestrict, on some chains of +.)
  std::string key = deep, header = "z = 1\n[";
  key += "y = 1\n";
  header += deep;
  header += "y]\n";
  expectError(withExtra(key), 12, {"dotted key or table header of more than 64 parts"});
  expectError(withExtra(header), 13, {"more than 64 parts"});
  // Below the bound, in comments and strings, and in values: toml++ and the reader decide (here
  // an unknown key of [[body]]), not the bound.
  std::string parts63, dotty = "# ";
  for (int k = 0; k < 63; ++k) parts63 += "x.";
  parts63 += "y = 1\n";
  dotty += deep;
  dotty += "\nnote = \"";
  dotty += deep;
  dotty += "\"\n";
  for (int k = 0; k < 100; ++k) {
    dotty += 'v';
    dotty += std::to_string(k);
    dotty += " = [1.5, 2.5, 3.5]\n";
  }
  for (const std::string& extra : {parts63, dotty}) {
    try {
      (void)tumble::parseScene(withExtra(extra), "test.toml");
      ADD_FAILURE() << "an unknown key was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("parts"), std::string::npos) << e.what();
    }
  }
}

// A [[fill]] region of radius 1e28 m (found by the scene fuzzer): the placement's cell indices
// went beyond 2^63 (undefined, UBSan in the sanitizer build); they are clamped, and the fill
// places its bodies.
TEST(SceneIo, AFillRegionBeyondTheCellIndexRangePlacesItsBodies) {
  const std::string text = join({"[scene]", "dt = 1e-4", "steps = 1", "seed = 3", "[[shape]]", "name = \"small\"",
                                 "[[shape.sphere]]", "radius = 0.01", "mass = 0.01", "[[fill]]", "shapes = [\"small\"]",
                                 "count = 87", "region = \"cylinder\"", "point = [0, 0, 0]", "axis = [0, 0, 0.5]",
                                 "radius = 9999999999999999999999999990.1"});
  const tumble::Scene s = tumble::parseScene(text, "test.toml");
  ASSERT_EQ(s.bodies.size(), 87u);
  for (const tumble::BodyDef& b : s.bodies) EXPECT_TRUE(std::isfinite(b.position.x) && std::isfinite(b.position.y));
}

// toml++ 3.3.0 has undefined behaviour for some non-ASCII code points where it expects
// whitespace ("Ñ", found by UBSan): they are refused, with the line, before it parses; in
// strings (all four kinds) and comments they are fine.
TEST(SceneIo, NonAsciiOutsideStringsIsRefusedWithTheLine) {
  expectError(withExtra("# note\nfoo =\xc3\x91 1\n"), 13, {"non-ASCII character outside a string or comment"});
  expectError(withExtra("x = '''a\n\xc3\x91'''\ny = 1 \xc3\x91\n"), 14, {"non-ASCII"});
  const std::string ok = withExtra("# comentario: a\xc3\xb1o\n");
  EXPECT_NO_THROW((void)tumble::parseScene(ok, "test.toml"));
  std::vector<std::string> ls = baseLines();
  ls.at(4) = "name = \"\xc3\xb1" "and\xc3\xba \\\" \xc3\x91\"";   // the shape's name, with an escaped quote
  ls.at(9) = "shape = '\xc3\xb1" "and\xc3\xba \" \xc3\x91'";        // a literal string naming it
  EXPECT_EQ(tumble::parseScene(join(ls), "test.toml").shapes.at(0).name, "\xc3\xb1" "and\xc3\xba \" \xc3\x91");
}

TEST(SceneIo, AsciiCheckFollowsTomlStrings) {
  // A byte-order mark is skipped (as toml++ does).
  EXPECT_NO_THROW((void)tumble::parseScene("\xEF\xBB\xBF" + join(baseLines()), "test.toml"));
  // A multi-line string may end in one or two quotes before its closing three: the scan must not
  // close it early and take the rest of the line for string content.
  expectError(withExtra("x = \"\"\"a\"\"\"\" \xc3\x91\n"), 12, {"non-ASCII"});
  // A line-ending backslash in a multi-line basic string still counts its line.
  expectError(withExtra("x = \"\"\"a \\\nb\"\"\"\ny = \xc3\x91\n"), 14, {"non-ASCII"});
}

// ---------------------------------------------------------------------------------------
// --set overrides (docs/scenes.md, "Overriding keys on the command line").

namespace {

Scene withSets(const std::string& text, const std::vector<std::string>& sets) {
  return tumble::parseScene(text, "test.toml", sets);
}

/// Expects the overrides to be refused with an error at their origin "command line, --set SPEC"
/// (no line: it is not a line of the file) whose message contains every string in `needles`.
void expectSetError(const std::string& text, const std::vector<std::string>& sets, const std::string& spec,
                    std::initializer_list<const char*> needles) {
  try {
    (void)withSets(text, sets);
    ADD_FAILURE() << "no error for --set " << spec;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set " + spec) << e.what();
    EXPECT_EQ(e.line(), 0) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("command line, --set " + spec + ": ", 0), 0u) << e.what();
    for (const char* n : needles) {
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << "message lacks \"" << n << "\": " << e.what();
    }
  }
}

}  // namespace

TEST(SceneOverrides, ChangeTheParsedValues) {
  const std::string file = withExtra("[ground]\nfriction = 0.9\n[output]\nrecord = \"a.bin\"\n");
  const Scene s = withSets(file, {"ground.friction=0.3", "scene.gravity=[0, 0, -9.8]", "output.record=\"x.bin\"",
                                  "output.debug=true", "integrator.rotation='splitting'", " scene.steps = 20"});
  EXPECT_EQ(s.ground.friction, 0.3f);
  EXPECT_EQ(s.gravity.x, 0.0f);
  EXPECT_EQ(s.gravity.z, -9.8f);
  EXPECT_EQ(s.recordFile, "x.bin");
  EXPECT_TRUE(s.recordDebug);
  EXPECT_EQ(s.integrator.rotation, tumble::RotationScheme::Splitting);
  EXPECT_EQ(s.steps, 20u);
  EXPECT_TRUE(s.ground.enabled);
  EXPECT_EQ(s.dt, 1e-4f) << "keys not set keep the file's values";
  // Tables the file lacks are added ([ground]'s presence turns the ground on, as in a file).
  const Scene t = withSets(join(baseLines()), {"contact.damping=2", "pulls.on=[\"x\"]", "ground.height=-1"});
  EXPECT_EQ(t.contact.damping, 2.0f);
  EXPECT_EQ(t.contact.stiffness, 2.0e4f);
  EXPECT_EQ(t.pulls.active, static_cast<std::uint32_t>(tumble::kPullX));
  EXPECT_TRUE(t.ground.enabled);
  EXPECT_EQ(t.ground.height, -1.0f);
  // The last of a key wins; an integer is a number, as in a file.
  EXPECT_EQ(withSets(file, {"ground.friction=0.3", "ground.friction=1"}).ground.friction, 1.0f);
  EXPECT_EQ(withSets(file, {"ground.enabled=false"}).ground.enabled, false);
}

TEST(SceneOverrides, SameSceneAsTheFileEditedTheSameWay) {
  const std::string group = "[[group]]\nshape = \"ball\"\ncount = [3, 3, 2]\nspacing = 2\njitter = 0.3\n"
                            "random_orientation = true\n";
  const Scene set = withSets(withExtra(group), {"scene.seed=7"});
  std::vector<std::string> ls = baseLines();
  ls.insert(ls.begin() + 1, "seed = 7");
  const Scene file = tumble::parseScene(join(ls) + group, "test.toml");
  EXPECT_TRUE(sameBits(set, file));
  EXPECT_FALSE(sameBits(set, tumble::parseScene(withExtra(group), "test.toml"))) << "the seed changes the groups";
  // No overrides: the scene of the file alone.
  EXPECT_TRUE(sameBits(tumble::readSceneFile(scenePath("molecules.toml"), {}),
                       tumble::readSceneFile(scenePath("molecules.toml"))));
}

TEST(SceneOverrides, ErrorsNameTheOriginAndNoLine) {
  const std::string base = join(baseLines());
  expectSetError(base, {"ground.friction=-1"}, "ground.friction=-1", {"[ground]: friction must be >= 0 (got -1)"});
  expectSetError(base, {"ground.frictoin=0.3"}, "ground.frictoin=0.3",
                 {"[ground]: unknown key 'frictoin'; allowed keys: enabled, height, stiffness, friction"});
  expectSetError(base, {"scene.steps=1.5"}, "scene.steps=1.5", {"[scene]: steps must be an integer (got 1.5)"});
  expectSetError(base, {"scene.gravity=[0, 0]"}, "scene.gravity=[0, 0]", {"gravity must be an array of 3 numbers"});
  expectSetError(base, {"pulls.on=[\"z\"]"}, "pulls.on=[\"z\"]", {"unknown pull \"z\""});
  // A table made by --set: its problems name the override that made it.
  std::vector<std::string> noScene = baseLines();
  noScene.erase(noScene.begin(), noScene.begin() + 3);
  expectSetError(join(noScene), {"scene.dt=1e-3"}, "scene.dt=1e-3", {"[scene]: missing required key 'steps'"});
  // The override that is wrong is named, not the first one.
  expectSetError(base, {"ground.friction=0.3", "contact.shear=-2"}, "contact.shear=-2", {"shear must be >= 0"});
}

TEST(SceneOverrides, OnlyTheSingleTablesCanBeSet) {
  const std::string base = join(baseLines());
  expectSetError(base, {"grund.friction=1"}, "grund.friction=1",
                 {"unknown section 'grund'", "--set can change the keys of [scene], [contact], [ground], [pulls], "
                  "[broadphase], [integrator], [output]"});
  expectSetError(base, {"shape.name=\"x\""}, "shape.name=\"x\"", {"[[shape]] entries cannot be set", "[scene]"});
  expectSetError(base, {"body.position=[0, 0, 2]"}, "body.position=[0, 0, 2]", {"[[body]] entries cannot be set"});
  expectSetError(base, {"group.count=[1, 1, 1]"}, "group.count=[1, 1, 1]", {"[[group]] entries cannot be set"});
}

TEST(SceneOverrides, MalformedOrNotTomlIsRefused) {
  const std::string base = join(baseLines());
  for (const char* spec : {"foo", "=1", "a.b.c=1", "ground=1", "ground.=1", ".friction=1", "ground.friction",
                           "ground.\"friction\"=1", "ground.fri ction=1"}) {
    expectSetError(base, {spec}, spec, {"expected SECTION.KEY=VALUE", "--set ground.friction=0.3"});
  }
  expectSetError(base, {"output.record=x.bin"}, "output.record=x.bin",
                 {"TOML syntax error", "a string needs quotes, e.g. --set output.record='\"run.bin\"'"});
  expectSetError(base, {"ground.friction="}, "ground.friction=", {"TOML syntax error", "a string needs quotes"});
  try {
    (void)withSets(base, {"scene.gravity=[0, 0"});
    ADD_FAILURE() << "no error for an unclosed array";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set scene.gravity=[0, 0");
    EXPECT_NE(std::string(e.what()).find("TOML syntax error"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("needs quotes"), std::string::npos) << "not a bare word: " << e.what();
  }
  expectSetError(base, {"ground.friction=1\nheight = 2"}, "ground.friction=1\nheight = 2",
                 {"VALUE must be one TOML value"});
  expectSetError(base, {"ground.friction=1\n[scene]"}, "ground.friction=1\n[scene]", {"VALUE must be one TOML value"});
  // Non-ASCII outside a string is refused as in a file; in a string it is fine.
  expectSetError(base, {"scene.name=\xc3\x91"}, "scene.name=\xc3\x91", {"non-ASCII character outside a string"});
  EXPECT_EQ(withSets(base, {"scene.name=\"a\xc3\xb1o\""}).name, "a\xc3\xb1o");
}

TEST(SceneOverrides, FileErrorsStayTheFiles) {
  // A problem in the file is reported at its line, overrides or not.
  expectError(withLine(7, "radius = -1"), 7, {"radius must be > 0"});
  try {
    (void)withSets(withLine(7, "radius = -1"), {"ground.friction=0.3"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.toml");
    EXPECT_EQ(e.line(), 7);
  }
  try {
    (void)withSets("ground = 3\n" + join(baseLines()), {"ground.friction=0.3"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.toml");
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("'ground' must be a table"), std::string::npos) << e.what();
  }
  // A malformed override is reported before the file is read (here: a missing file).
  try {
    (void)tumble::readSceneFile("/nonexistent/scene.toml", {"foo"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set foo");
  }
}

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
  expectError(withExtra(p + "x = [-1e39, 1]\n"), 13, {"x[0] is out of single-precision range"});
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
