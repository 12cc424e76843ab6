// SPDX-License-Identifier: MIT
/// @file camera.hpp
/// An orbit camera (target, yaw, pitch, distance) about the scene's up, z or opposite a tilted
/// gravity, and the 4×4 matrices the renderer needs. Plain C++ (no OpenGL), so tests can project
/// points to pixels.
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

/// The scene's up for a gravity `g`: z when g is zero or along −z (x and y exactly 0), else −g
/// normalised (a chute's tilted gravity: its bed is then drawn as a slope).
Vec3f upFromGravity(Vec3f g);

/// Orbit camera around a target point. Up on screen is `up` (z unless setUp() says otherwise):
/// yaw turns about it, pitch is the elevation of the eye above the plane across it (radians).
class Camera {
 public:
  Vec3f target{0, 0, 0};
  float yaw = -1.0f;      ///< eye direction from the target, radians about `up` from `ex`
  float pitch = 0.45f;    ///< elevation, radians, kept in (−1.5, 1.5)
  float distance = 10.0f;
  float fovY = 0.7854f;   ///< 45°
  /// The frame yaw and pitch are measured in: `up`, and `ex`, `ey` (yaw 0 and 90°) across it;
  /// z, x and y by default, so that a camera of a scene with gravity along −z is z-up.
  Vec3f up{0, 0, 1}, ex{1, 0, 0}, ey{0, 1, 0};

  /// Sets `up` (a unit vector) and turns `ex` and `ey` with it by the smallest rotation that takes
  /// z to `up` (about z × up): the directions across a tilted gravity that are nearest x and y.
  /// `up` = z gives the default frame exactly.
  void setUp(Vec3f up);

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
  /// Keyboard motion over `seconds`: forward/right in the plane across `up` relative to the view,
  /// `rise` along `up`, turn about the eye (the target moves, the eye stays).
  void move(float forward, float right, float rise, float turn, float seconds);

  /// Projects a world point to pixel coordinates (x right, y down from the top-left corner) of
  /// a w × h image. False when the point is behind the camera.
  bool project(Vec3f p, int w, int h, float& outX, float& outY) const;
};

}  // namespace tumble::viewer
