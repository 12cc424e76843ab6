// SPDX-License-Identifier: MIT
// A shape's mass properties and range checks: its centre of mass, extent and inertia bound,
// and what makes a shape or its angular velocity out of single-precision range (SPEC §1).
#include "tumble/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <Eigen/Dense>

namespace tumble {

ShapeSolid shapeMassProperties(const ShapeDef& shape) {
  if (shape.solid) return *shape.solid;
  ShapeSolid p;
  for (const SphereDef& sp : shape.spheres) {
    p.mass += sp.mass;
    p.centre[0] += double(sp.mass) * sp.offset.x;
    p.centre[1] += double(sp.mass) * sp.offset.y;
    p.centre[2] += double(sp.mass) * sp.offset.z;
  }
  for (double& c : p.centre) c /= p.mass;
  for (const SphereDef& sp : shape.spheres) {
    const double u[3] = {sp.offset.x - p.centre[0], sp.offset.y - p.centre[1], sp.offset.z - p.centre[2]};
    // (Summed as World::fromScene summed them with Eigen, m ((0.4 r² + |u|²) 1 − u uᵀ), bit for bit.)
    const double m = sp.mass, d = 0.4 * double(sp.radius) * sp.radius + (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    p.inertia[0] += m * (d - u[0] * u[0]), p.inertia[1] += m * (d - u[1] * u[1]), p.inertia[2] += m * (d - u[2] * u[2]);
    p.inertia[3] -= m * (u[0] * u[1]), p.inertia[4] -= m * (u[0] * u[2]), p.inertia[5] -= m * (u[1] * u[2]);
  }
  return p;
}

void shareMassByVolume(ShapeDef& shape) {
  if (!shape.solid) return;
  double total = 0.0;
  for (const SphereDef& sd : shape.spheres) total += double(sd.radius) * sd.radius * sd.radius;
  for (SphereDef& sd : shape.spheres)
    sd.mass = float(shape.solid->mass * (double(sd.radius) * sd.radius * sd.radius / total));
}

namespace {

/// A solid's principal moments, ascending.
Eigen::Vector3d principalMoments(const ShapeSolid& s) {
  Eigen::Matrix3d I;
  I << s.inertia[0], s.inertia[3], s.inertia[4], s.inertia[3], s.inertia[1], s.inertia[5], s.inertia[4], s.inertia[5],
      s.inertia[2];
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
}

}  // namespace

double shapeExtent(const ShapeDef& shape) {
  const ShapeSolid p = shapeMassProperties(shape);
  double reach = 0.0;
  for (const SphereDef& sp : shape.spheres) {
    const double dx = sp.offset.x - p.centre[0], dy = sp.offset.y - p.centre[1], dz = sp.offset.z - p.centre[2];
    reach = std::max(reach, std::sqrt(dx * dx + dy * dy + dz * dz) + sp.radius);
  }
  return reach;
}

double shapeInertiaBound(const ShapeDef& shape) {
  const ShapeSolid p = shapeMassProperties(shape);
  // A solid's largest principal moment is at most the sum of the other two: half the trace.
  if (shape.solid) return 0.5 * (p.inertia[0] + p.inertia[1] + p.inertia[2]);
  double most = 0.0;
  for (const SphereDef& sp : shape.spheres) {
    const double dx = sp.offset.x - p.centre[0], dy = sp.offset.y - p.centre[1], dz = sp.offset.z - p.centre[2];
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
  const double m = shapeMassProperties(shape).mass;
  char buf[200];
  if (!(m <= kMax)) {
    std::snprintf(buf, sizeof buf, "the shape's total mass %.3g kg is beyond single precision (at most %.3g)", m, kMax);
    return buf;
  }
  if (!(1.0 / m <= kMax)) {
    std::snprintf(buf, sizeof buf, "the shape's total mass %.3g kg is too small for single precision (1/m overflows)", m);
    return buf;
  }
  // Its weight is a force of the first step: beyond single precision it is infinite there.
  const double g = std::sqrt(double(gravity.x) * gravity.x + double(gravity.y) * gravity.y + double(gravity.z) * gravity.z);
  if (!(m * g <= kMax)) {
    std::snprintf(buf, sizeof buf, "its weight m |g| = %.3g N is beyond single precision (at most %.3g); use a smaller mass",
                  m * g, kMax);
    return buf;
  }
  // A solid's inertia: positive, and each principal moment at most the sum of the other two; a
  // solid of one sphere has its centre of mass at the sphere's centre (a one-sphere body's
  // particle sits at its centre of mass in the pipelines).
  if (shape.solid) {
    const Eigen::Vector3d l = principalMoments(*shape.solid);
    if (!(l[0] > 0.0) || !(l[2] <= (l[0] + l[1]) * (1.0 + 1e-6))) {
      std::snprintf(buf, sizeof buf, "its inertia's principal moments (%.6g, %.6g, %.6g kg m^2) are not a solid's: "
                    "each must be positive and at most the sum of the other two", l[0], l[1], l[2]);
      return buf;
    }
    const SphereDef& sp = shape.spheres[0];
    const double d[3] = {sp.offset.x - shape.solid->centre[0], sp.offset.y - shape.solid->centre[1],
                         sp.offset.z - shape.solid->centre[2]};
    const double off = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (shape.spheres.size() == 1 && !(off <= 1e-3 * sp.radius)) {
      std::snprintf(buf, sizeof buf, "its one sphere's centre lies %.6g m from its centre_of_mass: a body of one "
                    "sphere has it there; put the centre there, or add spheres", off);
      return buf;
    }
  }
  // The largest moment of inertia is at most Σ m (0.4 r² + |u|²); the smallest at least Σ 0.4 m r².
  // Single-sphere bodies do not rotate under the report's law: their inertia is never used.
  if (shape.spheres.size() == 1 && !spheresRotate) return shapeExtent(shape) <= 0.5 * kMax ? std::string() : std::string(
      "its sphere reaches beyond single-precision range");
  const double most = shapeInertiaBound(shape);
  double least = 0.0;
  if (shape.solid) {
    least = principalMoments(*shape.solid)[0];
  } else {
    for (const SphereDef& sp : shape.spheres) least += 0.4 * double(sp.mass) * double(sp.radius) * sp.radius;
  }
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
