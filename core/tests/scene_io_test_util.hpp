// SPDX-License-Identifier: MIT
// What the scene reader's tests share (scene_io_test.cpp, scene_io_errors_test.cpp,
// scene_io_toml_test.cpp, scene_walls_test.cpp, scene_fills_test.cpp): scene text built line
// by line, the expected InputError, the particles of a scene and their overlaps.
#pragma once
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

namespace scene_io_test {

using tumble::BodyDef;
using tumble::InputError;
using tumble::Scene;
using tumble::Vec3f;

inline std::string scenePath(const std::string& name) {
  return std::string(TUMBLE_SOURCE_DIR) + "/scenes/" + name;
}

inline std::uint64_t numParticles(const Scene& s) {
  std::uint64_t n = 0;
  for (const BodyDef& b : s.bodies) n += s.shapes[b.shape].spheres.size();
  return n;
}

/// Joins lines with '\n', so that tests can name line numbers by position (1-based).
inline std::string lines(std::initializer_list<const char*> ls) {
  std::string out;
  for (const char* l : ls) {
    out += l;
    out += '\n';
  }
  return out;
}

/// A minimal valid scene; tests replace one line at a time (line numbers in the comments).
inline std::vector<std::string> baseLines() {
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

inline std::string join(const std::vector<std::string>& ls) {
  std::string out;
  for (const std::string& l : ls) out += l + '\n';
  return out;
}

/// The base scene with line `line` (1-based) replaced by `text`.
inline std::string withLine(int line, const std::string& text) {
  std::vector<std::string> ls = baseLines();
  ls.at(static_cast<std::size_t>(line - 1)) = text;
  return join(ls);
}

/// The base scene with `extra` appended (its first line is line 12).
inline std::string withExtra(const std::string& extra) { return join(baseLines()) + extra; }

/// Expects parseScene(text) to throw an InputError at `line` whose message contains every
/// string in `needles`.
inline void expectError(const std::string& text, long line, std::initializer_list<const char*> needles) {
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

inline std::vector<Particle> particlesOf(const Scene& s) {
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
inline std::uint64_t countInitialOverlaps(const std::vector<Particle>& ps) {
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

inline bool sameBits(const Scene& a, const Scene& b) {
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

// --set overrides (scene_io_toml_test.cpp, scene_fills_test.cpp).

inline Scene withSets(const std::string& text, const std::vector<std::string>& sets) {
  return tumble::parseScene(text, "test.toml", sets);
}

/// Expects the overrides to be refused with an error at their origin "command line, --set SPEC"
/// (no line: it is not a line of the file) whose message contains every string in `needles`.
inline void expectSetError(const std::string& text, const std::vector<std::string>& sets, const std::string& spec,
                    std::initializer_list<const char*> needles) {
  try {
    (void)withSets(text, sets);
    ADD_FAILURE() << "no error for --set " << spec;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set " + spec) << e.what();
    EXPECT_EQ(e.line(), 0) << e.what();
    // what() shows the spec printable() (a newline in it as \n: the message stays one line).
    EXPECT_EQ(std::string(e.what()).rfind("command line, --set " + tumble::printable(spec) + ": ", 0), 0u) << e.what();
    for (const char* n : needles) {
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << "message lacks \"" << n << "\": " << e.what();
    }
  }
}

// Materials and the hertz-mindlin law (scene_io_errors_test.cpp, scene_walls_test.cpp).
inline const char* kGlass = "[[material]]\nname = \"glass\"\ndensity = 2500\nyoungs_modulus = 6.3e10\npoisson_ratio = 0.23\n"
                     "restitution = 0.9\nfriction = 0.3\n";
inline const char* kSteel = "[[material]]\nname = \"steel\"\ndensity = 7800\nyoungs_modulus = 2e11\npoisson_ratio = 0.3\n"
                     "restitution = 0.8\nrolling_friction = 0.01\n";
inline const char* kHertz = "[contact]\nlaw = \"hertz-mindlin\"\n";

}  // namespace scene_io_test
