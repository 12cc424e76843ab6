// SPDX-License-Identifier: MIT
// Camera matrices. The formulas are the classic gluPerspective / gluLookAt ones.
#include "tumble/viewer/camera.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::viewer {

Mat4 Mat4::identity() {
  Mat4 r;
  for (int i = 0; i < 4; ++i) r.at(i, i) = 1.0f;
  return r;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      float s = 0.0f;
      for (int k = 0; k < 4; ++k) s += a.at(i, k) * b.at(k, j);
      r.at(i, j) = s;
    }
  return r;
}

Mat4 perspective(float fovY, float aspect, float zNear, float zFar) {
  const float f = 1.0f / std::tan(fovY / 2.0f);
  Mat4 r;
  r.at(0, 0) = f / aspect;
  r.at(1, 1) = f;
  r.at(2, 2) = (zFar + zNear) / (zNear - zFar);
  r.at(2, 3) = 2.0f * zFar * zNear / (zNear - zFar);
  r.at(3, 2) = -1.0f;
  return r;
}

Mat4 lookAt(Vec3f eye, Vec3f target, Vec3f up) {
  const Vec3f f = (1.0f / norm(target - eye)) * (target - eye);
  Vec3f s = cross(f, up);
  s = (1.0f / norm(s)) * s;
  const Vec3f u = cross(s, f);
  Mat4 r = Mat4::identity();
  r.at(0, 0) = s.x; r.at(0, 1) = s.y; r.at(0, 2) = s.z;
  r.at(1, 0) = u.x; r.at(1, 1) = u.y; r.at(1, 2) = u.z;
  r.at(2, 0) = -f.x; r.at(2, 1) = -f.y; r.at(2, 2) = -f.z;
  r.at(0, 3) = -dot(s, eye);
  r.at(1, 3) = -dot(u, eye);
  r.at(2, 3) = dot(f, eye);
  return r;
}

void Bounds::add(Vec3f p, float r) {
  const Vec3f lo2{p.x - r, p.y - r, p.z - r}, hi2{p.x + r, p.y + r, p.z + r};
  if (empty) {
    lo = lo2;
    hi = hi2;
    empty = false;
    return;
  }
  lo = {std::min(lo.x, lo2.x), std::min(lo.y, lo2.y), std::min(lo.z, lo2.z)};
  hi = {std::max(hi.x, hi2.x), std::max(hi.y, hi2.y), std::max(hi.z, hi2.z)};
}

Vec3f upFromGravity(Vec3f g) {
  const float n = norm(g);
  if (!(n > 0.0f) || (g.x == 0.0f && g.y == 0.0f && g.z < 0.0f)) return {0, 0, 1};
  return (-1.0f / n) * g;
}

void Camera::setUp(Vec3f u) {
  up = u;
  // Rodrigues' rotation about k = (z × up) / s by the angle whose cosine is c = up.z, sine s.
  const float c = u.z, s = std::sqrt(u.x * u.x + u.y * u.y);
  if (!(s > 1e-7f)) {
    ex = {1, 0, 0};
    ey = {0.0f, c < 0.0f ? -1.0f : 1.0f, 0.0f};  // upside down: half a turn about x
    return;
  }
  const float kx = -u.y / s, ky = u.x / s;
  ex = {c + (1.0f - c) * kx * kx, (1.0f - c) * kx * ky, -u.x};
  ey = {(1.0f - c) * kx * ky, c + (1.0f - c) * ky * ky, -u.y};
}

Camera Camera::framing(const Bounds& b) {
  Camera c;
  if (b.empty) return c;
  c.target = 0.5f * (b.lo + b.hi);
  const float radius = std::max(0.5f * norm(b.hi - b.lo), 1e-3f);
  // The bounding sphere fits in the vertical field of view, with a 10 % margin.
  c.distance = 1.1f * radius / std::sin(c.fovY / 2.0f);
  return c;
}

Vec3f Camera::eye() const {
  // In the default frame each term adds exact zeros: the z-up camera's numbers, bit for bit.
  const float cp = std::cos(pitch);
  return target + distance * ((cp * std::cos(yaw)) * ex + (cp * std::sin(yaw)) * ey + std::sin(pitch) * up);
}

Mat4 Camera::view() const { return lookAt(eye(), target, up); }

Mat4 Camera::projection(float aspect) const {
  return perspective(fovY, aspect, std::max(1e-4f, 0.01f * distance), 200.0f * distance);
}

void Camera::orbit(float dx, float dy) {
  yaw -= 0.008f * dx;
  pitch = std::clamp(pitch + 0.008f * dy, -1.5f, 1.5f);
}

void Camera::zoom(float notches) { distance = std::max(1e-3f, distance * std::pow(0.9f, notches)); }

void Camera::move(float forward, float right, float rise, float turn, float seconds) {
  // Speed scales with the distance so that small and large scenes feel the same.
  const float step = 0.6f * distance * seconds;
  const Vec3f fwd = (-std::cos(yaw)) * ex + (-std::sin(yaw)) * ey;
  const Vec3f rgt = (-std::sin(yaw)) * ex + std::cos(yaw) * ey;
  target += (forward * step) * fwd + (right * step) * rgt + (rise * step) * up;
  if (turn != 0.0f) {
    // Turn in place: keep the eye, swing the target around it.
    const Vec3f e = eye();
    yaw += turn * 1.2f * seconds;
    target = e - (eye() - target);
  }
}

bool Camera::project(Vec3f p, int w, int h, float& outX, float& outY) const {
  const Mat4 vp = viewProjection(float(w) / float(h));
  float c[4];
  for (int i = 0; i < 4; ++i) c[i] = vp.at(i, 0) * p.x + vp.at(i, 1) * p.y + vp.at(i, 2) * p.z + vp.at(i, 3);
  if (c[3] <= 0.0f) return false;
  outX = (c[0] / c[3] * 0.5f + 0.5f) * float(w);
  outY = (1.0f - (c[1] / c[3] * 0.5f + 0.5f)) * float(h);
  return true;
}

}  // namespace tumble::viewer
