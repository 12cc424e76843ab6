// SPDX-License-Identifier: MIT
/// @file camera.hpp
/// A z-up orbit camera (target, yaw, pitch, distance) and the 4×4 matrices the renderer needs.
/// Plain C++ (no OpenGL), so tests can project points to pixels.
#pragma once
#include <array>

#include "tumble/math.hpp"

namespace tumble::viewer {

/// Column-major 4×4 matrix, as OpenGL expects.
struct Mat4 {
  std::array<float, 16> m{};
  static Mat4 identity();
  float& at(int row, int col) { return m[static_cast<std::size_t>(col * 4 + row)]; }
  float at(int row, int col) const { return m[static_cast<std::size_t>(col * 4 + row)]; }
};
Mat4 operator*(const Mat4& a, const Mat4& b);
/// Right-handed perspective (OpenGL clip space, depth −1…1); fovY in radians.
Mat4 perspective(float fovY, float aspect, float zNear, float zFar);
/// View matrix looking from eye to target, `up` roughly up.
Mat4 lookAt(Vec3f eye, Vec3f target, Vec3f up);

/// Axis-aligned box of the scene (particle centres ± radius).
struct Bounds {
  Vec3f lo{0, 0, 0}, hi{0, 0, 0};
  bool empty = true;
  void add(Vec3f p, float r);
};

/// Orbit camera around a target point, z up. Yaw turns about z, pitch is the elevation of the
/// eye above the target (radians).
class Camera {
 public:
  Vec3f target{0, 0, 0};
  float yaw = -1.0f;      ///< eye direction from the target, radians about +z from +x
  float pitch = 0.45f;    ///< elevation, radians, kept in (−1.5, 1.5)
  float distance = 10.0f;
  float fovY = 0.7854f;   ///< 45°

  /// A camera that sees the whole box from the default direction.
  static Camera framing(const Bounds& b);

  Vec3f eye() const;
  Mat4 view() const;
  Mat4 projection(float aspect) const;
  Mat4 viewProjection(float aspect) const { return projection(aspect) * view(); }

  /// Mouse orbit: dx, dy in pixels.
  void orbit(float dx, float dy);
  /// Mouse wheel: each notch zooms by 10 %.
  void zoom(float notches);
  /// Keyboard motion over `seconds`: forward/right in the ground plane relative to the view,
  /// up along z, turn about the eye (the target moves, the eye stays).
  void move(float forward, float right, float up, float turn, float seconds);

  /// Projects a world point to pixel coordinates (x right, y down from the top-left corner) of
  /// a w × h image. False when the point is behind the camera.
  bool project(Vec3f p, int w, int h, float& outX, float& outY) const;
};

}  // namespace tumble::viewer
