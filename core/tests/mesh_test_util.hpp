// SPDX-License-Identifier: MIT
// Closed meshes for the tests of solids and clumps (mesh_mass_test.cpp, clump_test.cpp), written
// as OBJ text and read by tumble's own reader.
#pragma once
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "tumble/mesh.hpp"

namespace mesh_test {

using V = std::array<double, 3>;
using Tri = std::array<int, 3>;  // 0-based vertex indices, counter-clockwise seen from outside

/// An OBJ of the vertices and triangles, read by tumble's reader as `name`.
inline tumble::TriangleMesh objMesh(const std::vector<V>& vs, const std::vector<Tri>& ts,
                                    const char* name = "solid.obj") {
  std::string text;
  char line[128];
  for (const V& v : vs) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", v[0], v[1], v[2]);
    text += line;
  }
  for (const Tri& t : ts) text += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  return tumble::parseMesh(text, name);
}

/// A box [lo, hi] as 12 outward triangles, appended.
inline void addBox(V lo, V hi, std::vector<V>& vs, std::vector<Tri>& ts) {
  const int b = int(vs.size());
  for (int k = 0; k < 8; ++k) vs.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    ts.push_back({b + f[0], b + f[1], b + f[2]});
    ts.push_back({b + f[0], b + f[2], b + f[3]});
  }
}

}  // namespace mesh_test
