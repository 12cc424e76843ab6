// SPDX-License-Identifier: MIT
// A shape's mass properties and range checks: its centre of mass, extent and inertia bound,
// and what makes a shape or its angular velocity out of single-precision range (SPEC §1).
#include "tumble/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace tumble {

namespace {

// Centre of mass and total mass of a shape, in double.
double shapeMass(const ShapeDef& shape, double com[3]) {
  double m = 0.0;
  com[0] = com[1] = com[2] = 0.0;
  for (const SphereDef& sp : shape.spheres) {
    m += sp.mass;
    com[0] += double(sp.mass) * sp.offset.x;
    com[1] += double(sp.mass) * sp.offset.y;
    com[2] += double(sp.mass) * sp.offset.z;
  }
  for (int a = 0; a < 3; ++a) com[a] /= m;
  return m;
}

}  // namespace

double shapeExtent(const ShapeDef& shape) {
  double com[3];
  shapeMass(shape, com);
  double reach = 0.0;
  for (const SphereDef& sp : shape.spheres) {
    const double dx = sp.offset.x - com[0], dy = sp.offset.y - com[1], dz = sp.offset.z - com[2];
    reach = std::max(reach, std::sqrt(dx * dx + dy * dy + dz * dz) + sp.radius);
  }
  return reach;
}

double shapeInertiaBound(const ShapeDef& shape) {
  double com[3];
  shapeMass(shape, com);
  double most = 0.0;
  for (const SphereDef& sp : shape.spheres) {
    const double dx = sp.offset.x - com[0], dy = sp.offset.y - com[1], dz = sp.offset.z - com[2];
    most += double(sp.mass) * (0.4 * double(sp.radius) * sp.radius + dx * dx + dy * dy + dz * dz);
  }
  return most;
}

std::string angularVelocityOutOfRange(const ShapeDef& shape, double omega) {
  const double bound = shapeInertiaBound(shape) * omega;
  if (bound <= double(std::numeric_limits<float>::max())) return {};
  char buf[200];
  std::snprintf(buf, sizeof buf, "an angular velocity of %.3g rad/s gives this shape an angular momentum of up to "
                "%.3g kg m^2/s, beyond single precision", omega, bound);
  return buf;
}

std::string shapeOutOfRange(const ShapeDef& shape, bool spheresRotate, Vec3f gravity) {
  if (shape.spheres.empty()) return {};
  constexpr double kMax = std::numeric_limits<float>::max();
  double com[3];
  const double m = shapeMass(shape, com);
  char buf[200];
  if (!(m <= kMax)) {
    std::snprintf(buf, sizeof buf, "the spheres' total mass %.3g kg is beyond single precision (at most %.3g)", m, kMax);
    return buf;
  }
  if (!(1.0 / m <= kMax)) {
    std::snprintf(buf, sizeof buf, "the spheres' total mass %.3g kg is too small for single precision (1/m overflows)", m);
    return buf;
  }
  // Its weight is a force of the first step: beyond single precision it is infinite there.
  const double g = std::sqrt(double(gravity.x) * gravity.x + double(gravity.y) * gravity.y + double(gravity.z) * gravity.z);
  if (!(m * g <= kMax)) {
    std::snprintf(buf, sizeof buf, "its weight m |g| = %.3g N is beyond single precision (at most %.3g); use a smaller mass",
                  m * g, kMax);
    return buf;
  }
  // The largest moment of inertia is at most Σ m (0.4 r² + |u|²); the smallest at least Σ 0.4 m r².
  // Single-sphere bodies do not rotate under the report's law: their inertia is never used.
  if (shape.spheres.size() == 1 && !spheresRotate) return shapeExtent(shape) <= 0.5 * kMax ? std::string() : std::string(
      "its sphere reaches beyond single-precision range");
  const double most = shapeInertiaBound(shape);
  double least = 0.0;
  for (const SphereDef& sp : shape.spheres) least += 0.4 * double(sp.mass) * double(sp.radius) * sp.radius;
  if (!(most <= kMax)) {
    std::snprintf(buf, sizeof buf, "its moment of inertia (up to %.3g kg m^2) is beyond single precision; use smaller "
                  "masses, radii or offsets", most);
    return buf;
  }
  if (!(1.0 / least <= kMax)) {
    std::snprintf(buf, sizeof buf, "its moment of inertia (%.3g kg m^2) is too small for single precision (its inverse "
                  "overflows); use larger masses or radii", least);
    return buf;
  }
  if (!(shapeExtent(shape) <= 0.5 * kMax)) return "its spheres reach beyond single-precision range from its centre of mass";
  return {};
}

}  // namespace tumble
