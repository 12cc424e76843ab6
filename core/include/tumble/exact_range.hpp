// SPDX-License-Identifier: MIT
/// @file exact_range.hpp
/// The range of geometry whose contacts the single-precision kernels decide right (issue 34,
/// item 7), refused outside it at load with the file and line.
///
/// - Spheres (kernels/overlap.hpp): |x_i − x_j|² < (r_i + r_j)² in float. With every coordinate
///   and radius within ±2^60 m, a difference is within 2^61, its square within 2^122 and their
///   sum within 2^124: finite (float reaches 2^128). With every radius at least 2^-60 m,
///   (r_i + r_j)² ≥ 2^-118 is a normal number: a square that underflows to 0 is of a distance far
///   below the radii, and 0 < (r_i + r_j)² still says "overlap". Beyond 2^60 a square overflows
///   (spheres of 1.5e19 m 2e19 m apart were missed); below 2^-60 the radii's square underflows
///   (coincident spheres of 1e-23 m were missed).
/// - Meshes (kernels/mesh.hpp): the nearest point of a triangle is computed from differences to
///   its vertices, with a rounding error of a few 2^-24 of the triangle's size. A triangle at
///   most kMaxTriangleToRadius (2^15) times as long as the smallest sphere radius keeps that
///   error within 2^-7 (0.8 %) of every radius; a plate of 2.8e6 m triangles lost a ball of
///   0.05 m near their shared edge, where the error was 3 times its radius.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>

namespace tumble {

/// The largest |coordinate| + radius of a sphere, and |coordinate| of a wall or mesh vertex, in m.
inline constexpr double kMaxCoordinate = 0x1p60;
/// The smallest sphere radius, in m.
inline constexpr double kMinRadius = 0x1p-60;
/// The longest edge of a mesh triangle, in radii of the smallest sphere of the scene.
inline constexpr double kMaxTriangleToRadius = 0x1p15;

/// Within ±kMaxCoordinate (and not NaN).
inline bool withinExactRange(double v) { return v >= -kMaxCoordinate && v <= kMaxCoordinate; }

/// Empty when a sphere at (x, y, z) of radius r lies in the range; else what is wrong ("its
/// radius 1e-23 m is outside [2^-60, 2^60] m …", "it reaches beyond ±2^60 m along x …"): for the
/// readers of spheres that have no scene file (the particle CSV, Python's find_pairs).
inline std::string sphereOutOfRange(double x, double y, double z, double r) {
  char buf[200];
  if (!(r >= kMinRadius && r <= kMaxCoordinate)) {
    std::snprintf(buf, sizeof buf, "its radius %g m is outside [2^-60, 2^60] m (8.7e-19 to 1.15e18)", r);
    return std::string(buf) + ", the range whose contacts single precision decides right";
  }
  const double c[3] = {x, y, z};
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(c[a]) + r <= kMaxCoordinate)) {
      std::snprintf(buf, sizeof buf, "it reaches beyond +-2^60 m (1.15e18) along %c (%c = %g m, r = %g m)", "xyz"[a],
                    "xyz"[a], c[a], r);
      return std::string(buf) + ", the range whose contacts single precision decides right";
    }
  return {};
}

}  // namespace tumble
