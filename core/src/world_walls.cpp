// SPDX-License-Identifier: MIT
// The planes and walls of a World: the scene's planes, the kernels' walls in the local frame,
// the walls' motion windows and poses in time, and the fastest wall's approach speed.
#include "tumble/world.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/mesh.hpp"

namespace tumble {

std::vector<WallDef> Scene::planes() const {
  std::vector<WallDef> out;
  out.reserve(walls.size() + 1);
  if (ground.enabled) {
    WallDef g;
    g.point = Vec3f{0.0f, 0.0f, ground.height};
    g.contact = ground;
    g.where = "[ground]";
    out.push_back(g);
  }
  for (const WallDef& w : walls) {
    out.push_back(w);
    out.back().contact.enabled = true;
    if (w.where.empty()) out.back().where = "wall " + std::to_string(out.size() - (ground.enabled ? 1 : 0));
  }
  return out;
}

namespace {
// A plane's h (x·n on it), a cylinder's axis or a mesh's pivot must be a float the kernels can
// subtract (found by reading: a point near the float limit on a tilted plane gave an h beyond it,
// and its conversion is undefined). `what` names it: "the plane", "the cylinder's axis", …
double checkedHeight(double h, const std::string& where, const char* what) {
  if (std::abs(h) <= 1.0e38) return h;
  char buf[200];
  std::snprintf(buf, sizeof buf, ": %s lies %.3g m from the origin, beyond single precision; bring it closer", what, h);
  throw Error(where + buf);
}

// What a revolved wall is, as its [[wall]] type says.
const char* revolvedKind(const WallDef& d) {
  if (d.length == 0.0f) return "disk";
  return d.radius0 == d.radius1 ? "cylinder" : "cone";
}
}  // namespace

std::vector<Wall> kernelWalls(const Scene& params, const LocalFrame& f) {
  std::vector<Wall> out;
  for (const WallDef& d : params.planes()) {
    const GroundParams& g = d.contact;
    Wall w{};
    const double len = std::sqrt(double(d.normal.x) * d.normal.x + double(d.normal.y) * d.normal.y +
                                 double(d.normal.z) * d.normal.z);
    if ((!(len > 0.0) || !std::isfinite(len)) && d.shape != WallDef::Shape::Mesh)
      throw Error(d.where + (d.shape == WallDef::Shape::Plane ? ": the normal" : ": the axis") +
                  " must be a non-zero, finite vector");
    if (const std::string why = wallMotionOutOfRange(d); !why.empty()) throw Error(d.where + ": " + why);
    const double n[3] = {d.normal.x / len, d.normal.y / len, d.normal.z / len};
    const double o[3] = {f.x, f.y, f.z}, p[3] = {d.point.x, d.point.y, d.point.z};
    w.n = Vec3f{float(n[0]), float(n[1]), float(n[2])};
    const float kt = g.tangentialStiffness > 0.0f ? g.tangentialStiffness : g.stiffness * (2.0f / 7.0f);
    w.coeffs = GroundCoeffs{0.0f, g.stiffness, kt, g.friction, params.rollingFrictionOf(g), params.cohesionOf(g)};
    w.velocity = d.velocity;
    w.omega = d.angularVelocity;
    if (d.shape == WallDef::Shape::Mesh) {  // its triangles: kernelMesh()
      if (!d.mesh) throw Error(d.where + ": a mesh wall needs a mesh (WallDef::mesh)");
      w.axis = kMeshWall;
      w.sign = 1.0f;
      if (d.moves()) {  // its material's velocity, v + |ω| n × (p − centre): n the unit ω, centre the pivot
        const Vec3f& om = d.meshAngularVelocity;
        const double rate = std::sqrt(double(om.x) * om.x + double(om.y) * om.y + double(om.z) * om.z);
        w.omega = static_cast<float>(rate);
        if (rate > 0.0) w.n = Vec3f{float(om.x / rate), float(om.y / rate), float(om.z / rate)};
        const Vec3f q = d.meshPivot();
        const char* pivot = "the mesh's pivot";
        w.restCentre = Vec3f{static_cast<float>(checkedHeight(double(q.x) - o[0], d.where, pivot)),
                             static_cast<float>(checkedHeight(double(q.y) - o[1], d.where, pivot)),
                             static_cast<float>(checkedHeight(double(q.z) - o[2], d.where, pivot))};
        w.centre = w.restCentre;
      }
      out.push_back(w);
      continue;
    }
    if (d.shape == WallDef::Shape::Revolved) {
      w.axis = kRevolvedWall;
      w.sign = 1.0f;
      double t[3], u[3];
      perpendicularPair(n, t, u);
      w.t1 = Vec3f{float(t[0]), float(t[1]), float(t[2])};
      w.t2 = Vec3f{float(u[0]), float(u[1]), float(u[2])};
      // The axis's point nearest the frame's origin, and the segment's start from it, in double.
      const double along = (o[0] - p[0]) * n[0] + (o[1] - p[1]) * n[1] + (o[2] - p[2]) * n[2];
      const std::string axis = std::string("the ") + revolvedKind(d) + "'s axis";
      const std::string point = std::string("the ") + revolvedKind(d) + "'s point";
      w.centre = Vec3f{static_cast<float>(checkedHeight(p[0] + along * n[0] - o[0], d.where, axis.c_str())),
                       static_cast<float>(checkedHeight(p[1] + along * n[1] - o[1], d.where, axis.c_str())),
                       static_cast<float>(checkedHeight(p[2] + along * n[2] - o[2], d.where, axis.c_str()))};
      w.start = static_cast<float>(checkedHeight(-along, d.where, point.c_str()));
      const double l2 = double(d.length) * d.length + (double(d.radius1) - d.radius0) * (double(d.radius1) - d.radius0);
      if (!(d.length >= 0.0f && d.radius0 >= 0.0f && d.radius1 >= 0.0f && std::isfinite(l2) &&
            static_cast<float>(l2) >= std::numeric_limits<float>::min()))
        throw Error(d.where + ": a cylinder, cone or disk needs a length and radii >= 0, finite, and a segment "
                              "(length, radius1 - radius0) of normal float size");
      w.length = d.length;
      w.radius0 = d.radius0;
      w.radius1 = d.radius1;
      w.restCentre = w.centre;
      w.restStart = w.start;
      out.push_back(w);
      continue;
    }
    const float nv[3] = {w.n.x, w.n.y, w.n.z};
    w.axis = kGeneralPlane;
    w.sign = 1.0f;
    for (int a = 0; a < 3; ++a)
      if (nv[(a + 1) % 3] == 0.0f && nv[(a + 2) % 3] == 0.0f && (nv[a] == 1.0f || nv[a] == -1.0f)) {
        w.axis = a;
        w.sign = nv[a];
      }
    if (w.axis >= 0) {  // the exact frame: t1 = e_b, t2 = sign e_c (b, c the next axes), n = sign e_a
      const int a = w.axis, b = (a + 1) % 3, c = (a + 2) % 3;
      float t1[3] = {0, 0, 0}, t2[3] = {0, 0, 0};
      t1[b] = 1.0f;
      t2[c] = w.sign;
      w.t1 = Vec3f{t1[0], t1[1], t1[2]};
      w.t2 = Vec3f{t2[0], t2[1], t2[2]};
      // The ground's height as toLocal() shifts it (h − o_z rounded to float), with the sign.
      w.coeffs.height = w.sign * static_cast<float>(checkedHeight(p[a] - o[a], d.where, "the plane"));
    } else {  // t1, t2 ⟂ n (double), as the sweep frame's p, q
      double t[3], u[3];
      perpendicularPair(n, t, u);
      w.t1 = Vec3f{float(t[0]), float(t[1]), float(t[2])};
      w.t2 = Vec3f{float(u[0]), float(u[1]), float(u[2])};
      // h = (p − o)·n in double, rounded once.
      w.coeffs.height =
          static_cast<float>(checkedHeight((p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2], d.where, "the plane"));
    }
    w.restHeight = w.coeffs.height;
    out.push_back(w);
  }
  return out;
}

std::string wallMotionOutOfRange(const WallDef& d) {
  const auto finite = [](Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const Vec3f& om = d.meshAngularVelocity;
  const bool turns = om.x != 0.0f || om.y != 0.0f || om.z != 0.0f;
  if (!finite(om)) return "angular_velocity must be finite";
  if (d.shape == WallDef::Shape::Mesh) {
    if (d.angularVelocity != 0.0f)
      return "a mesh turns about a vector, angular_velocity = [x, y, z] (WallDef::meshAngularVelocity), not a number";
    if (d.pivot && !finite(*d.pivot)) return "pivot must be finite";
    if (d.pivot && !turns)
      return "pivot is the point a mesh turns about, and this mesh does not turn (give it an angular_velocity)";
  } else if (turns || d.pivot) {
    return "only a mesh turns about a vector angular_velocity and a pivot (a cylinder, cone or disk turns about its "
           "own axis: its angular_velocity is a number)";
  }
  if (!std::isfinite(d.angularVelocity)) return "angular_velocity must be finite";
  if (d.shape == WallDef::Shape::Plane && d.angularVelocity != 0.0f)
    return "a plane does not turn (angular_velocity is for cylinders, cones and disks)";
  const Vec3f& u = d.velocity;
  if (!(std::isfinite(u.x) && std::isfinite(u.y) && std::isfinite(u.z))) return "velocity must be finite";
  if (!(d.start >= 0.0 && d.stop > d.start)) return "the motion must start at t >= 0 and stop after it starts";
  return {};
}

double wallMotionTime(const WallDef& d, double t) { return std::min(std::max(t - d.start, 0.0), d.stop - d.start); }

bool meshWallsMove(const Scene& scene) {
  return std::any_of(scene.walls.begin(), scene.walls.end(),
                     [](const WallDef& w) { return w.shape == WallDef::Shape::Mesh && w.moves(); });
}

bool Scene::wallsMove() const {
  return std::any_of(walls.begin(), walls.end(), [](const WallDef& w) { return w.moves(); });
}

bool Scene::wallsMoveDuring(double t0, double t1) const {
  return std::any_of(walls.begin(), walls.end(),
                     [&](const WallDef& w) { return w.moves() && w.start < t1 && w.stop > t0; });
}

namespace {

// A mesh wall's pose at time t (MeshPose): the rotation by θ = |ω| τ about the unit ω, R = I +
// sin θ [k]× + 2 sin²(θ/2) [k]×² (Rodrigues), and the pivot moved by v τ, all in double from
// the time, the given floats and the pivot in the run's frame (Wall::restCentre), rounded once.
MeshPose meshPoseAt(const WallDef& d, const Wall& w, double t) {
  MeshPose pose{};
  pose.rot = Mat3f{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f};
  pose.pivot = w.restCentre;
  pose.centre = w.restCentre;
  const double tau = wallMotionTime(d, t);
  if (!d.moves() || !(tau > 0.0)) return pose;
  pose.posed = 1u;
  const Vec3f& v = d.velocity;
  pose.centre = Vec3f{static_cast<float>(double(w.restCentre.x) + double(v.x) * tau),
                      static_cast<float>(double(w.restCentre.y) + double(v.y) * tau),
                      static_cast<float>(double(w.restCentre.z) + double(v.z) * tau)};
  const Vec3f& om = d.meshAngularVelocity;
  const double rate = std::sqrt(double(om.x) * om.x + double(om.y) * om.y + double(om.z) * om.z);
  if (!(rate > 0.0)) return pose;
  const double k[3] = {om.x / rate, om.y / rate, om.z / rate}, theta = rate * tau;
  const double s = std::sin(theta), h = std::sin(0.5 * theta), c2 = 2.0 * h * h;  // 1 − cos θ
  // K = [k]×, the cross product with k: R = I + sin θ K + (1 − cos θ) K².
  const double K[3][3] = {{0.0, -k[2], k[1]}, {k[2], 0.0, -k[0]}, {-k[1], k[0], 0.0}};
  float r[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double k2 = K[i][0] * K[0][j] + K[i][1] * K[1][j] + K[i][2] * K[2][j];
      r[3 * i + j] = static_cast<float>((i == j ? 1.0 : 0.0) + s * K[i][j] + c2 * k2);
    }
  pose.rot = Mat3f{r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8]};
  return pose;
}

bool samePose(const MeshPose& a, const MeshPose& b) {
  const float* x = &a.rot.xx;
  const float* y = &b.rot.xx;
  for (int i = 0; i < 9; ++i)
    if (x[i] != y[i]) return false;
  return a.posed == b.posed && a.centre.x == b.centre.x && a.centre.y == b.centre.y && a.centre.z == b.centre.z &&
         a.pivot.x == b.pivot.x && a.pivot.y == b.pivot.y && a.pivot.z == b.pivot.z;
}

}  // namespace

bool setWallMotion(std::vector<Wall>& walls, const Scene& scene, double t, MeshPose* meshPoses) {
  bool changed = false;
  const std::size_t first = walls.size() - scene.walls.size();  // after the ground
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const WallDef& d = scene.walls[k];
    Wall& w = walls[first + k];
    const std::uint32_t on = d.moves() && t >= d.start && t < d.stop ? 1u : 0u;
    changed = changed || w.moving != on;
    w.moving = on;
    if (d.shape == WallDef::Shape::Mesh) {  // posed as a whole: its pivot now, and its pose
      if (!d.moves()) continue;
      const MeshPose pose = meshPoseAt(d, w, t);
      w.centre = pose.centre;
      if (meshPoses != nullptr) {
        changed = changed || !samePose(meshPoses[first + k], pose);
        meshPoses[first + k] = pose;
      }
      continue;
    }
    const Vec3f& v = d.velocity;
    if (v.x == 0.0f && v.y == 0.0f && v.z == 0.0f) continue;
    // The shift v τ, in double from the given velocity and the unit normal (or axis) in double,
    // added to the rest geometry and rounded once: the same bits at time t for any history.
    const double tau = wallMotionTime(d, t);
    const double len = std::sqrt(double(d.normal.x) * d.normal.x + double(d.normal.y) * d.normal.y +
                                 double(d.normal.z) * d.normal.z);
    const double n[3] = {d.normal.x / len, d.normal.y / len, d.normal.z / len};
    const double vn = double(v.x) * n[0] + double(v.y) * n[1] + double(v.z) * n[2];
    if (d.shape == WallDef::Shape::Plane) {  // the normal part moves the plane; the rest is a belt
      const float h = static_cast<float>(double(w.restHeight) + vn * tau);
      changed = changed || w.coeffs.height != h;
      w.coeffs.height = h;
    } else {  // the axis moves: across it the centre, along it the segment's start
      const Vec3f c{static_cast<float>(double(w.restCentre.x) + (double(v.x) - vn * n[0]) * tau),
                    static_cast<float>(double(w.restCentre.y) + (double(v.y) - vn * n[1]) * tau),
                    static_cast<float>(double(w.restCentre.z) + (double(v.z) - vn * n[2]) * tau)};
      const float s = static_cast<float>(double(w.restStart) + vn * tau);
      changed = changed || c.x != w.centre.x || c.y != w.centre.y || c.z != w.centre.z || s != w.start;
      w.centre = c;
      w.start = s;
    }
  }
  return changed;
}

double wallApproachSpeed(const WallDef& d) {
  if (!d.moves()) return 0.0;
  const Vec3f& v = d.velocity;
  const double speed = std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
  if (d.shape == WallDef::Shape::Plane) {
    const double len = std::sqrt(double(d.normal.x) * d.normal.x + double(d.normal.y) * d.normal.y +
                                 double(d.normal.z) * d.normal.z);
    const double along = double(v.x) * d.normal.x + double(v.y) * d.normal.y + double(v.z) * d.normal.z;
    return len > 0.0 ? std::abs(along) / len : 0.0;
  }
  if (d.shape == WallDef::Shape::Revolved || !d.mesh) return speed;
  const Vec3f& om = d.meshAngularVelocity;
  const Vec3f p = d.meshPivot();
  double far = 0.0;
  for (const Vec3f& y : meshWallVertices(d)) {
    const double e[3] = {double(y.x) - p.x, double(y.y) - p.y, double(y.z) - p.z};
    far = std::max(far, std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]));
  }
  return speed + std::sqrt(double(om.x) * om.x + double(om.y) * om.y + double(om.z) * om.z) * far;
}

}  // namespace tumble
