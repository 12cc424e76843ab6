// SPDX-License-Identifier: MIT
// Helpers shared by the cases of the validation study (study_physics.cpp, study_stability.cpp):
// constants, float rounding, checks, shapes and scene set-up, and small linear algebra.
// Internal: not installed, not API.
#pragma once
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "tumble/scene.hpp"
#include "tumble/validation/study.hpp"
#include "tumble/world.hpp"

namespace tumble::validation::study::detail {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kG = 9.81;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// One unit in the last place of x as a float (the spacing of floats at |x|).
inline double ulpf(double x) {
  const float f = std::abs(static_cast<float>(x));
  return double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
}

/// The value the simulation actually uses for a double parameter.
inline double asFloat(double x) { return static_cast<double>(static_cast<float>(x)); }

/// Steps of dt in `seconds`, rounded to the nearest.
inline std::uint64_t stepsFor(double seconds, double dt) {
  return static_cast<std::uint64_t>(std::llround(seconds / dt));
}

/// printf into a std::string (up to 4095 characters).
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline std::string fmt(const char* f, ...) {
  char buf[4096];
  va_list ap;
  va_start(ap, f);
  std::vsnprintf(buf, sizeof buf, f, ap);
  va_end(ap);
  return buf;
}

// ---------------------------------------------------------------------------------------------
// Checks: each passes when its error is finite and ≤ its tolerance.

/// A check whose `error` is compared with `tolerance`.
inline Check mkCheck(std::string name, std::string formula, double measured, double expected, double error,
                     double tolerance, std::string unit) {
  Check c;
  c.name = std::move(name);
  c.formula = std::move(formula);
  c.measured = measured;
  c.expected = expected;
  c.error = error;
  c.tolerance = tolerance;
  c.unit = std::move(unit);
  c.pass = std::isfinite(error) && error <= tolerance;
  return c;
}
/// |measured − expected| / |expected| against a relative tolerance.
inline Check relCheck(std::string name, std::string formula, double measured, double expected, double tol) {
  return mkCheck(std::move(name), std::move(formula), measured, expected,
                 std::abs(measured - expected) / std::abs(expected), tol, "relative");
}
/// |measured − expected| against an absolute tolerance in `unit`.
inline Check absCheck(std::string name, std::string formula, double measured, double expected, double tol,
                      std::string unit) {
  return mkCheck(std::move(name), std::move(formula), measured, expected, std::abs(measured - expected), tol,
                 std::move(unit));
}
/// |measured| ≤ bound.
inline Check boundCheck(std::string name, std::string formula, double measured, double bound, std::string unit) {
  return mkCheck(std::move(name), std::move(formula), measured, kNaN, std::abs(measured), bound, std::move(unit));
}
/// A count of violations that must be zero.
inline Check zeroCheck(std::string name, std::string formula, double count) {
  return mkCheck(std::move(name), std::move(formula), count, 0.0, count, 0.0, "count");
}

// ---------------------------------------------------------------------------------------------
// Shapes, bodies, scenes.

/// One sphere of radius r, mass m and elasticity e at the body's centre.
inline ShapeDef sphereShape(double r, double m, double e) {
  return ShapeDef{"sphere", {SphereDef{{0, 0, 0}, float(r), float(m), float(e)}}};
}

/// An asymmetric clump (distinct principal moments), as in physics_test.cpp.
inline ShapeDef oddShape() {
  return ShapeDef{"odd",
                  {SphereDef{{0, 0, 0}, 0.3f, 2.0f, 0.5f}, SphereDef{{0.5f, 0, 0}, 0.2f, 1.0f, 0.5f},
                   SphereDef{{0, 0.35f, 0.1f}, 0.15f, 0.5f, 0.5f}, SphereDef{{-0.2f, -0.1f, 0.4f}, 0.25f, 1.5f, 0.5f}}};
}

/// A body of shape `shape` at (x, y, z) moving at (vx, vy, vz).
inline BodyDef bodyAt(std::uint32_t shape, double x, double y, double z, double vx = 0, double vy = 0,
                      double vz = 0) {
  BodyDef b;
  b.shape = shape;
  b.position = {float(x), float(y), float(z)};
  b.velocity = {float(vx), float(vy), float(vz)};
  return b;
}

/// A scene of `shape` over the ground (stiffness k; friction left at its default) under
/// `gravity`, at dt with rotation scheme rs. The caller adds the bodies.
inline Scene groundScene(Vec3f gravity, double k, const ShapeDef& shape, double dt,
                         RotationScheme rs = RotationScheme::Report) {
  Scene s;
  s.gravity = gravity;
  s.ground.enabled = true;
  s.ground.stiffness = float(k);
  s.shapes = {shape};
  s.integrator.rotation = rs;
  s.dt = float(dt);
  return s;
}

/// |L| of body i, in double.
inline double angularMomentumNorm(const BodyState& s, std::size_t i) {
  return std::sqrt(double(s.lx[i]) * s.lx[i] + double(s.ly[i]) * s.ly[i] + double(s.lz[i]) * s.lz[i]);
}

// ---------------------------------------------------------------------------------------------
// Linear algebra.

/// One Jacobi sweep over the off-diagonal pairs of a symmetric 3×3 matrix: A ← Jᵀ A J for each
/// rotation J that zeroes A[p][q], and the rotations accumulated into the columns of V.
inline void jacobiSweep(double A[3][3], double V[3][3]) {
  for (int p = 0; p < 2; ++p)
    for (int q = p + 1; q < 3; ++q) {
      if (std::abs(A[p][q]) < 1e-300) continue;
      const double th = 0.5 * std::atan2(2 * A[p][q], A[q][q] - A[p][p]);
      const double c = std::cos(th), s = std::sin(th);
      for (int k = 0; k < 3; ++k) {
        const double akp = A[k][p], akq = A[k][q];
        A[k][p] = c * akp - s * akq;
        A[k][q] = s * akp + c * akq;
      }
      for (int k = 0; k < 3; ++k) {
        const double apk = A[p][k], aqk = A[q][k];
        A[p][k] = c * apk - s * aqk;
        A[q][k] = s * apk + c * aqk;
      }
      for (int k = 0; k < 3; ++k) {
        const double vkp = V[k][p], vkq = V[k][q];
        V[k][p] = c * vkp - s * vkq;
        V[k][q] = s * vkp + c * vkq;
      }
    }
}

}  // namespace tumble::validation::study::detail
