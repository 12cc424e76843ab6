// SPDX-License-Identifier: MIT
// Building a World from a Scene: mass properties (SPEC §1) and the ground damping that makes
// each particle's elasticity its coefficient of restitution on the ground (SPEC §2.4).
#include "tumble/world.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>
#include <string>

#include "tumble/error.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble {

void BodyState::resize(std::size_t n) {
  for (auto* c : {&px, &py, &pz, &vx, &vy, &vz, &qw, &qx, &qy, &qz, &lx, &ly, &lz}) c->resize(n);
}

LocalFrame LocalFrame::of(const World& w) {
  const BodyState& s = w.state;
  if (s.size() == 0) return {};
  double lo[3], hi[3];
  const std::vector<float>* col[3] = {&s.px, &s.py, &s.pz};
  for (int a = 0; a < 3; ++a) {
    const auto mm = std::minmax_element(col[a]->begin(), col[a]->end());
    lo[a] = *mm.first;
    hi[a] = *mm.second;
  }
  // What the bodies will move towards belongs to the box too: the ground (a dropped body lands
  // on it) and, on the axes of the pulls that are on, the world origin (they pull there).
  const Scene& p = w.params;
  if (p.ground.enabled) {
    lo[2] = std::min(lo[2], double(p.ground.height));
    hi[2] = std::max(hi[2], double(p.ground.height));
  }
  const bool pullX = (p.pulls.active & (kPullX | kPullSwirl)) != 0, pullY = (p.pulls.active & (kPullY | kPullSwirl)) != 0;
  for (int a = 0; a < 2; ++a)
    if (a == 0 ? pullX : pullY) {
      lo[a] = std::min(lo[a], 0.0);
      hi[a] = std::max(hi[a], 0.0);
    }
  double extent = 2.0 * w.maxRadius;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
  // Per axis: only the coordinates that are far from the origin move.
  double o[3];
  for (int a = 0; a < 3; ++a) {
    const double c = 0.5 * (lo[a] + hi[a]);
    o[a] = std::abs(c) > 4.0 * extent ? double(static_cast<float>(c)) : 0.0;
  }
  // A periodic axis is integrated about its box's centre: the box is [−h, h) there, and the
  // wraps by ±2h are exact (kernels/periodic.hpp).
  for (int a = 0; a < 2; ++a)
    if (p.periodic.on[a]) o[a] = double(static_cast<float>(0.5 * (double(p.periodic.lo[a]) + p.periodic.hi[a])));
  return LocalFrame{o[0], o[1], o[2]};
}

namespace {

// The frame's shift of everything but the body positions: the ground height and the pull centre.
void shiftParams(World& w, const LocalFrame& f) {
  w.params.ground.height = static_cast<float>(double(w.params.ground.height) - f.z);
  const auto shift = [&](Vec3f p) {
    return Vec3f{static_cast<float>(double(p.x) - f.x), static_cast<float>(double(p.y) - f.y),
                 static_cast<float>(double(p.z) - f.z)};
  };
  for (WallDef& wall : w.params.walls) {
    wall.point = shift(wall.point);
    if (wall.pivot) wall.pivot = shift(*wall.pivot);  // a moving mesh's
  }
  w.params.pulls.centre = Vec3f{static_cast<float>(-f.x), static_cast<float>(-f.y), static_cast<float>(-f.z)};
}

}  // namespace

World toLocal(const World& world, const LocalFrame& f) {
  World w = world;
  if (!f.active()) return w;
  const double o[3] = {f.x, f.y, f.z};
  std::vector<float>* col[3] = {&w.state.px, &w.state.py, &w.state.pz};
  for (int a = 0; a < 3; ++a)
    for (float& v : *col[a]) v = static_cast<float>(double(v) - o[a]);
  shiftParams(w, f);
  return w;
}

World localWorld(const World& world, LocalFrame* outFrame) {
  const std::size_t nb = world.numBodies(), np = world.numParticles();
  const BodyState& s = world.state;
  for (const auto* c : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz})
    if (c->size() != nb) throw Error("the state has " + std::to_string(c->size()) + " rows for " + std::to_string(nb) + " bodies");
  const std::size_t springs = np * world.params.planes().size();
  for (const auto* c : {&s.groundSpringX, &s.groundSpringY})
    if (!c->empty() && c->size() != springs)
      throw Error("the plane springs have " + std::to_string(c->size()) + " rows for " + std::to_string(np) +
                  " particles on " + std::to_string(springs / std::max<std::size_t>(np, 1)) + " planes");
  for (std::size_t k = 0; k < s.contacts.size(); ++k) {
    const ContactHistory& c = s.contacts[k];
    if (!(c.i < c.j && c.j < np) || (k > 0 && !(s.contacts[k - 1].i < c.i || (s.contacts[k - 1].i == c.i && s.contacts[k - 1].j < c.j))))
      throw Error("contact history " + std::to_string(k) + " (" + std::to_string(c.i) + ", " + std::to_string(c.j) +
                  "): expected pairs i < j < " + std::to_string(np) + " sorted by (i, j)");
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw Error("contact history " + std::to_string(k) + " is not finite");
  }
  const std::uint32_t numTriangles = meshTriangleCount(world.params);
  for (std::size_t k = 0; k < s.meshContacts.size(); ++k) {
    const MeshContactHistory& c = s.meshContacts[k];
    const MeshContactHistory* p = k > 0 ? &s.meshContacts[k - 1] : nullptr;
    if (!(c.particle < np && c.triangle < numTriangles) ||
        (p && !(p->particle < c.particle || (p->particle == c.particle && p->triangle < c.triangle))))
      throw Error("mesh contact history " + std::to_string(k) + " (particle " + std::to_string(c.particle) +
                  ", triangle " + std::to_string(c.triangle) + "): expected particles below " + std::to_string(np) +
                  " and triangles below " + std::to_string(numTriangles) + ", sorted by (particle, triangle)");
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw Error("mesh contact history " + std::to_string(k) + " is not finite");
  }
  if (!s.contacts.empty() && !world.params.contact.hasHistory())
    throw Error(std::string("the state holds contact histories, but the scene's law (") +
                toString(world.params.contact.law) + ") keeps none");
  const PeriodicParams& periodic = world.params.periodic;
  for (int a = 0; a < 2; ++a) {
    const std::vector<std::int32_t>& image = a == 0 ? s.imageX : s.imageY;
    if (!image.empty() && (!periodic.on[a] || image.size() != nb))
      throw Error(std::string("the state has ") + std::to_string(image.size()) + " image counters on " + "xy"[a] +
                  (periodic.on[a] ? " for " + std::to_string(nb) + " bodies" : ", an axis the scene has no periodic boundary on"));
  }
  World w;
  if (world.frame) {
    *outFrame = *world.frame;
    w = world;
    if (outFrame->active()) shiftParams(w, *outFrame);
  } else {
    *outFrame = LocalFrame::of(world);
    w = toLocal(world, *outFrame);
  }
  w.frame.reset();
  for (auto* c : {&w.state.groundSpringX, &w.state.groundSpringY})
    if (c->empty()) c->assign(springs, 0.0f);
  if (periodic.any()) {
    // Inside the box in the frame: a centre that rounds onto its end moves by one period there
    // (the same place), counted as a crossing.
    const PeriodicBox box = kernelPeriodic(w.params, *outFrame);
    std::vector<std::int32_t>* image[2] = {&w.state.imageX, &w.state.imageY};
    for (int a = 0; a < 2; ++a)
      if (periodic.on[a] && image[a]->empty()) image[a]->assign(nb, 0);
    for (std::size_t k = 0; k < nb; ++k) {
      Vec3f x{w.state.px[k], w.state.py[k], w.state.pz[k]};
      std::int32_t n[2] = {periodic.on[0] ? w.state.imageX[k] : 0, periodic.on[1] ? w.state.imageY[k] : 0};
      wrapIntoBox(box, &x, n);
      w.state.px[k] = x.x;
      w.state.py[k] = x.y;
      if (periodic.on[0]) w.state.imageX[k] = n[0];
      if (periodic.on[1]) w.state.imageY[k] = n[1];
    }
  }
  return w;
}

void toWorld(BodyState& s, const LocalFrame& f) {
  if (!f.active()) return;
  const double o[3] = {f.x, f.y, f.z};
  std::vector<float>* col[3] = {&s.px, &s.py, &s.pz};
  for (int a = 0; a < 3; ++a)
    for (float& v : *col[a]) v = static_cast<float>(double(v) + o[a]);
}

Quatf shapeOrientation(const World& world, const BodyState& s, std::size_t k) {
  const Quatf f = world.bodyToShape[k];
  if (f.w == 1.0f && f.x == 0.0f && f.y == 0.0f && f.z == 0.0f) return Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]};
  return normalized(mul(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}, Quatf{f.w, -f.x, -f.y, -f.z}));
}

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
// A plane's h (x·n on it) must be a float the kernels can subtract (found by reading: a point
// near the float limit on a tilted plane gave an h beyond it, and its conversion is undefined).
double checkedHeight(double h, const std::string& where) {
  if (std::abs(h) <= 1.0e38) return h;
  char buf[160];
  std::snprintf(buf, sizeof buf, ": the plane lies %.3g m from the origin, beyond single precision; bring it closer", h);
  throw Error(where + buf);
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
    w.coeffs = GroundCoeffs{0.0f, g.stiffness, kt, g.friction, params.rollingFrictionOf(g)};
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
        w.restCentre = Vec3f{static_cast<float>(checkedHeight(double(q.x) - o[0], d.where)),
                             static_cast<float>(checkedHeight(double(q.y) - o[1], d.where)),
                             static_cast<float>(checkedHeight(double(q.z) - o[2], d.where))};
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
      w.centre = Vec3f{static_cast<float>(checkedHeight(p[0] + along * n[0] - o[0], d.where)),
                       static_cast<float>(checkedHeight(p[1] + along * n[1] - o[1], d.where)),
                       static_cast<float>(checkedHeight(p[2] + along * n[2] - o[2], d.where))};
      w.start = static_cast<float>(checkedHeight(-along, d.where));
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
      w.coeffs.height = w.sign * static_cast<float>(checkedHeight(p[a] - o[a], d.where));
    } else {  // t1, t2 ⟂ n (double), as the sweep frame's p, q
      double t[3], u[3];
      perpendicularPair(n, t, u);
      w.t1 = Vec3f{float(t[0]), float(t[1]), float(t[2])};
      w.t2 = Vec3f{float(u[0]), float(u[1]), float(u[2])};
      // h = (p − o)·n in double, rounded once.
      w.coeffs.height =
          static_cast<float>(checkedHeight((p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2], d.where));
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

const char* toString(RotationScheme s) { return s == RotationScheme::Report ? "report" : "splitting"; }
const char* toString(ContactLaw law) {
  switch (law) {
    case ContactLaw::HookeHistory: return "hooke-history";
    case ContactLaw::HertzMindlin: return "hertz-mindlin";
    default: return "report";
  }
}

std::string materialOutOfRange(const MaterialDef& m) {
  // Y* and G* of the material against itself and against a rigid ground (the largest it can meet).
  for (const HertzPair& p : {materialPair(m, &m), materialPair(m, nullptr)}) {
    if (!(std::isfinite(p.ystar) && std::isfinite(p.gstar) && p.ystar > 0.0f && p.gstar > 0.0f)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "its youngs_modulus %g gives an effective modulus beyond single precision; use "
                    "a smaller one", double(m.youngsModulus));
      return buf;
    }
  }
  return {};
}

HertzPair planePair(const Scene& scene, const GroundParams& plane, std::size_t a) {
  HertzPair p = materialPair(scene.materials[a], plane.material >= 0 ? &scene.materials[plane.material] : nullptr);
  if (plane.frictionOverride >= 0.0f) p.mu = plane.frictionOverride;
  if (plane.rollingFriction >= 0.0f) p.muR = plane.rollingFriction;
  return p;
}

HertzPair materialPair(const MaterialDef& a, const MaterialDef* b) {
  const auto compliance = [](const MaterialDef& m) {
    const double e = m.youngsModulus, nu = m.poissonRatio;
    return std::pair<double, double>{(1.0 - nu * nu) / e, 2.0 * (2.0 - nu) * (1.0 + nu) / e};
  };
  auto [y, g] = compliance(a);
  double e = a.restitution, mu = a.friction, muR = a.rollingFriction;
  if (b != nullptr) {
    const auto [yb, gb] = compliance(*b);
    y += yb;
    g += gb;
    e = std::min(e, double(b->restitution));
    mu = std::min(mu, double(b->friction));
    muR = std::min(muR, double(b->rollingFriction));
  }
  const double pi = 3.14159265358979323846, le = std::log(e);
  const double beta = le / std::sqrt(le * le + pi * pi);
  return HertzPair{static_cast<float>(1.0 / y), static_cast<float>(1.0 / g),
                   static_cast<float>(-2.0 * std::sqrt(5.0 / 6.0) * beta), static_cast<float>(mu),
                   static_cast<float>(muR)};
}

double dampingForRestitution(double e, double k, double m) {
  if (!(e > 0.0) || e > 1.0) throw Error("elasticity must be in (0, 1], got " + std::to_string(e));
  const double le = std::log(e);
  const double pi = 3.14159265358979323846;
  const double zeta = -le / std::sqrt(pi * pi + le * le);
  return 2.0 * zeta * std::sqrt(k * m);
}

std::string groundDampingOutOfRange(const SphereDef& sphere, const GroundParams& ground, const std::string& where) {
  if (!ground.enabled) return {};
  const double c = dampingForRestitution(sphere.elasticity, ground.stiffness, sphere.mass);
  if (c <= double(std::numeric_limits<float>::max())) return {};
  const bool isGround = where == "[ground]";
  char buf[400];
  std::snprintf(buf, sizeof buf, "its %s damping (elasticity %g, mass %.3g kg, %s stiffness %.3g N/m) is "
                "%.3g N s/m, beyond single precision; use a smaller mass or %s%s", isGround ? "ground" : "wall",
                double(sphere.elasticity), double(sphere.mass), isGround ? "ground" : where.c_str(),
                double(ground.stiffness), c, isGround ? "[ground] stiffness" : "a smaller stiffness of ",
                isGround ? "" : where.c_str());
  return buf;
}

double restitutionForDamping(double c, double k, double m) {
  const double zeta = c / (2.0 * std::sqrt(k * m));
  if (zeta >= 1.0) return 0.0;
  const double pi = 3.14159265358979323846;
  return std::exp(-zeta * pi / std::sqrt(1.0 - zeta * zeta));
}

namespace {

bool finite(Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Sym3f toSym(const Eigen::Matrix3d& m) {
  return {static_cast<float>(m(0, 0)), static_cast<float>(m(1, 1)), static_cast<float>(m(2, 2)),
          static_cast<float>(m(0, 1)), static_cast<float>(m(0, 2)), static_cast<float>(m(1, 2))};
}

// The largest shapeExtent over the shapes the scene's bodies use (those that pour in too).
double largestExtent(const Scene& scene) {
  std::vector<char> used(scene.shapes.size(), 0);
  for (const BodyDef& b : scene.bodies) used[b.shape] = 1;
  for (const PourBody& b : scene.pourBodies) used[b.body.shape] = 1;
  double e = 0.0;
  for (std::size_t s = 0; s < used.size(); ++s)
    if (used[s]) e = std::max(e, shapeExtent(scene.shapes[s]));
  return e;
}

// The periodic boundaries of a scene built in code (the scene reader names the line of each);
// `placement`: the bodies' centres in the box too.
void checkPeriodic(const World& w, const Scene& scene, bool placement) {
  const PeriodicParams& p = scene.periodic;
  for (int a = 0; a < 2; ++a)
    if (p.on[a] && !(p.lo[a] < p.hi[a] && std::isfinite(p.lo[a]) && std::isfinite(p.hi[a])))
      throw Error(std::string("periodic ") + "xy"[a] + ": the box [lo, hi) needs finite lo < hi");
  for (std::size_t k = 0; placement && k < scene.bodies.size(); ++k)
    if (const std::string why = outsidePeriodicBox(p, scene.bodies[k].position); !why.empty())
      throw Error("body " + std::to_string(k) + ": " + why);
  if (const std::string why = periodicPullProblem(p, scene.pulls.active); !why.empty()) throw Error(why);
  for (const WallDef& wall : scene.walls)
    if (const std::string why = periodicWallProblem(wall, p); !why.empty())
      throw Error((wall.where.empty() ? std::string("a wall") : wall.where) + ": " + why);
  for (int a = 0; a < 2; ++a)
    if (const std::string why = periodTooShort(p, a, periodReach(w, effectiveSkin(w))); !why.empty()) throw Error(why);
}

}  // namespace

World World::fromScene(const Scene& scene, bool checkPlacement) {
  if (scene.bodies.empty()) throw Error("scene '" + scene.name + "' has no bodies");
  if (!(scene.dt > 0.0f) || !std::isfinite(scene.dt)) throw Error("dt must be a positive number");
  World w;
  w.params = scene;
  w.params.bodies.clear();  // the tables below are the truth; keep the copy small
  w.bodiesExtent = sceneBodiesExtent(scene);
  const auto nb = scene.bodies.size();
  std::size_t np = 0;
  for (const auto& b : scene.bodies) {
    if (b.shape >= scene.shapes.size()) throw Error("body refers to an unknown shape index");
    np += scene.shapes[b.shape].spheres.size();
  }
  if (np == 0) throw Error("scene '" + scene.name + "' has no particles");
  if (np >= (std::size_t{1} << 31)) throw Error("too many particles (limit 2^31)");

  for (auto* c : {&w.radius, &w.mass, &w.elasticity, &w.groundDamping, &w.ux, &w.uy, &w.uz}) c->reserve(np);
  w.body.reserve(np);
  w.bodyMass.resize(nb);
  w.invMass.resize(nb);
  w.invInertia.resize(nb);
  w.inertia.resize(nb);
  w.bodyToShape.resize(nb);
  w.first.resize(nb);
  w.numParticlesOf.resize(nb);
  w.state.resize(nb);

  // Mass properties per shape, computed once (double precision).
  struct ShapeProps {
    double mass;
    Eigen::Vector3d com;
    Eigen::Matrix3d inertia, invInertia;
    Eigen::Matrix3d frame;  ///< columns: the body-frame axes in the shape frame
    Eigen::Matrix3d shapeInertia;  ///< inertia in the shape frame (for L = R I0 Rᵀ ω)
  };
  const bool principal = scene.integrator.rotation == RotationScheme::Splitting;
  std::vector<ShapeProps> props(scene.shapes.size());
  for (std::size_t s = 0; s < scene.shapes.size(); ++s) {
    const auto& sh = scene.shapes[s];
    if (sh.spheres.empty()) throw Error("shape '" + sh.name + "' has no spheres");
    ShapeProps p{0.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                 Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Zero()};
    for (const auto& sp : sh.spheres) {
      if (!(sp.radius > 0.0f) || !std::isfinite(sp.radius)) throw Error("shape '" + sh.name + "': radius must be > 0");
      if (!(sp.mass > 0.0f) || !std::isfinite(sp.mass)) throw Error("shape '" + sh.name + "': mass must be > 0");
      if (!(sp.elasticity > 0.0f) || sp.elasticity > 1.0f) throw Error("shape '" + sh.name + "': elasticity must be in (0, 1]");
      if (!finite(sp.offset)) throw Error("shape '" + sh.name + "': offset is not finite");
      p.mass += sp.mass;
      p.com += sp.mass * Eigen::Vector3d(sp.offset.x, sp.offset.y, sp.offset.z);
    }
    if (const std::string why = shapeOutOfRange(sh, scene.contact.rotatesSpheres()); !why.empty()) throw Error("shape '" + sh.name + "': " + why);
    p.com /= p.mass;
    for (const auto& sp : sh.spheres) {
      const Eigen::Vector3d u = Eigen::Vector3d(sp.offset.x, sp.offset.y, sp.offset.z) - p.com;
      const double r = sp.radius;
      p.inertia += sp.mass * ((0.4 * r * r + u.squaredNorm()) * Eigen::Matrix3d::Identity() - u * u.transpose());
    }
    p.shapeInertia = p.inertia;
    if (principal && sh.spheres.size() > 1) {
      // The splitting integrator rotates about the principal axes: use them as the body frame.
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(p.inertia);
      p.frame = eig.eigenvectors();
      if (p.frame.determinant() < 0.0) p.frame.col(2) = -p.frame.col(2);
      p.inertia = eig.eigenvalues().asDiagonal();
    }
    p.invInertia = p.inertia.inverse();
    if (principal && sh.spheres.size() > 1) {  // exact zeros off the diagonal
      p.invInertia = p.inertia.diagonal().cwiseInverse().asDiagonal();
    }
    props[s] = p;
  }

  const std::vector<WallDef> planes = scene.planes();
  if (planes.size() > 1) w.planeDamping.assign((planes.size() - 1) * np, 0.0f);
  for (std::size_t k = 0; k < nb; ++k) {
    const BodyDef& bd = scene.bodies[k];
    const ShapeDef& sh = scene.shapes[bd.shape];
    const ShapeProps& p = props[bd.shape];
    if (!finite(bd.position) || !finite(bd.velocity) || !finite(bd.angularVelocity))
      throw Error("body " + std::to_string(k) + " has a non-finite position or velocity");
    const Vec3f& om = bd.angularVelocity;
    if (const std::string why = angularVelocityOutOfRange(
            sh, std::sqrt(double(om.x) * om.x + double(om.y) * om.y + double(om.z) * om.z));
        !why.empty())
      throw Error("body " + std::to_string(k) + ": " + why);
    w.first[k] = static_cast<std::uint32_t>(w.radius.size());
    w.numParticlesOf[k] = static_cast<std::uint32_t>(sh.spheres.size());
    if (sh.spheres.size() > 1) w.hasClumps = true;
    for (const auto& sp : sh.spheres) {
      const std::size_t i = w.radius.size();
      float firstDamping = 0.0f;  // plane 0's goes to the own rows (groundDamping), the others' to planeDamping
      for (std::size_t q = 0; q < planes.size(); ++q) {
        const GroundParams& g = planes[q].contact;
        if (const std::string why = groundDampingOutOfRange(sp, g, planes[q].where); !why.empty())
          throw Error("body " + std::to_string(k) + ", a sphere of shape '" + sh.name + "': " + why);
        const float c = static_cast<float>(dampingForRestitution(sp.elasticity, g.stiffness, sp.mass));
        (q == 0 ? firstDamping : w.planeDamping[(q - 1) * np + i]) = c;
      }
      w.radius.push_back(sp.radius);
      w.mass.push_back(sp.mass);
      w.elasticity.push_back(sp.elasticity);
      w.groundDamping.push_back(firstDamping);
      w.body.push_back(static_cast<std::uint32_t>(k));
      const Eigen::Vector3d u = p.frame.transpose() * (Eigen::Vector3d(sp.offset.x, sp.offset.y, sp.offset.z) - p.com);
      w.ux.push_back(static_cast<float>(u.x()));
      w.uy.push_back(static_cast<float>(u.y()));
      w.uz.push_back(static_cast<float>(u.z()));
      w.maxRadius = std::max(w.maxRadius, sp.radius);
    }
    w.bodyMass[k] = static_cast<float>(p.mass);
    w.invMass[k] = static_cast<float>(1.0 / p.mass);
    w.inertia[k] = toSym(p.inertia);
    w.invInertia[k] = toSym(p.invInertia);
    const Quatf qShape = normalized(bd.orientation);
    const Eigen::Quaterniond frame(p.frame);
    w.bodyToShape[k] = Quatf{static_cast<float>(frame.w()), static_cast<float>(frame.x()),
                             static_cast<float>(frame.y()), static_cast<float>(frame.z())};
    const Quatf q = principal ? normalized(mul(qShape, w.bodyToShape[k])) : qShape;
    auto& s = w.state;
    s.px[k] = bd.position.x; s.py[k] = bd.position.y; s.pz[k] = bd.position.z;
    s.vx[k] = bd.velocity.x; s.vy[k] = bd.velocity.y; s.vz[k] = bd.velocity.z;
    s.qw[k] = q.w; s.qx[k] = q.x; s.qy[k] = q.y; s.qz[k] = q.z;
    // L = R I0 Rᵀ ω (world frame).
    const Eigen::Quaterniond qd(qShape.w, qShape.x, qShape.y, qShape.z);
    const Eigen::Matrix3d R = qd.toRotationMatrix();
    const Eigen::Vector3d L = R * p.shapeInertia * R.transpose() *
                              Eigen::Vector3d(bd.angularVelocity.x, bd.angularVelocity.y, bd.angularVelocity.z);
    s.lx[k] = static_cast<float>(L.x()); s.ly[k] = static_cast<float>(L.y()); s.lz[k] = static_cast<float>(L.z());
  }
  w.sizingRadius = detail::sizingRadius(w.radius.data(), w.radius.size());
  w.maxExtent = largestExtent(scene);
  if (scene.periodic.any()) checkPeriodic(w, scene, checkPlacement);
  if (scene.periodic.on[0]) w.state.imageX.assign(nb, 0);
  if (scene.periodic.on[1]) w.state.imageY.assign(nb, 0);
  if (scene.contact.usesMaterials()) {
    const std::size_t m = scene.materials.size();
    if (m == 0) throw Error(std::string("law \"") + toString(scene.contact.law) + "\" needs at least one [[material]]");
    if (m >= 65535) throw Error("too many materials (limit 65534)");
    for (const MaterialDef& md : scene.materials) {
      if (!(md.youngsModulus > 0.0f) || !(md.poissonRatio >= 0.0f && md.poissonRatio < 0.5f) ||
          !(md.restitution > 0.0f && md.restitution <= 1.0f) || !(md.friction >= 0.0f) || !(md.rollingFriction >= 0.0f))
        throw Error("material '" + md.name + "': needs youngs_modulus > 0, 0 <= poisson_ratio < 0.5, restitution in "
                    "(0, 1], friction >= 0 and rolling_friction >= 0");
      if (const std::string why = materialOutOfRange(md); !why.empty()) throw Error("material '" + md.name + "': " + why);
    }
    const int gm = scene.ground.material;
    if (gm >= int(m)) throw Error("the ground's material index is out of range");
    w.materialPairs.resize((m + 1) * (m + 1), HertzPair{0.0f, 0.0f, 0.0f, 0.0f, 0.0f});
    for (std::size_t a = 0; a < m; ++a) {
      for (std::size_t b = 0; b < m; ++b)
        w.materialPairs[materialPairIndex(a, b, m)] = materialPair(scene.materials[a], &scene.materials[b]);
      w.materialPairs[materialPairIndex(a, m, m)] = planePair(scene, scene.ground, a);
    }
    w.planeHertz.reserve(planes.size() * m);
    for (const WallDef& p : planes) {
      if (p.contact.material >= int(m)) throw Error(p.where + ": the material index is out of range");
      for (std::size_t a = 0; a < m; ++a) w.planeHertz.push_back(planePair(scene, p.contact, a));
    }
    w.material.reserve(np);
    for (const BodyDef& bd : scene.bodies)
      for (const SphereDef& sp : scene.shapes[bd.shape].spheres) {
        if (sp.material >= m) throw Error("shape '" + scene.shapes[bd.shape].name + "': material index out of range");
        w.material.push_back(static_cast<std::uint16_t>(sp.material));
      }
  }

  // A sphere whose centre is behind a wall would be pushed through it from the wrong side: a
  // box that does not enclose its bodies, or a plane whose normal points away from them.
  if (!checkPlacement) return w;
  const std::vector<Wall> walls = tumble::kernelWalls(w.params, LocalFrame{});
  for (std::size_t q = scene.ground.enabled ? 1 : 0; q < walls.size(); ++q) {
    const Wall& pw = walls[q];
    if (pw.axis == kRevolvedWall || pw.axis == kMeshWall) continue;  // thin surfaces, met from either side
    for (std::uint32_t k = 0; k < nb; ++k) {
      const BodyState& s = w.state;
      const Mat3f R = rotationMatrix(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]});
      for (std::uint32_t i = w.first[k], e = i + w.numParticlesOf[k]; i < e; ++i) {
        const Vec3f x = particlePosition(Vec3f{s.px[k], s.py[k], s.pz[k]}, R, Vec3f{w.ux[i], w.uy[i], w.uz[i]});
        const double d = double(x.x) * pw.n.x + double(x.y) * pw.n.y + double(x.z) * pw.n.z - pw.coeffs.height;
        if (d < 0.0) {
          char buf[200];
          std::snprintf(buf, sizeof buf, ": body %u has a sphere whose centre is %.3g m behind the wall (at %.9g, %.9g, %.9g)",
                        k, -d, double(x.x), double(x.y), double(x.z));
          throw Error(planes[q].where + buf + "; a box must enclose its bodies, and a plane's normal points towards them");
        }
      }
    }
  }
  return w;
}

namespace {

// hertz-mindlin: the shortest Hertz contact time t_c = 2.87 (m*² / (R* Y*² v))^{1/5} of the scene,
// for the lightest mass and the largest radius of each material against each other and every plane (the
// ground, the walls), at
// the fastest impact its start suggests: v = max(1 m/s, |V|max + √(2 |g| H) + the fastest
// moving wall's approach, wallApproachSpeed()), H the largest height of a body above the ground
// (without one, the bodies' vertical extent).
double hertzContactTime(const World& w) {
  const std::size_t m = w.params.materials.size();
  // t_c grows with m*^{2/5} and falls with R*^{1/5}: the lightest mass with the largest radius.
  std::vector<double> mMin(m, std::numeric_limits<double>::infinity()), rMax(m, 0.0);
  for (std::size_t i = 0; i < w.radius.size(); ++i) {
    mMin[w.material[i]] = std::min(mMin[w.material[i]], double(w.mass[i]));
    rMax[w.material[i]] = std::max(rMax[w.material[i]], double(w.radius[i]));
  }
  const BodyState& s = w.state;
  double vmax = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < s.size(); ++k) {
    vmax = std::max(vmax, std::sqrt(double(s.vx[k]) * s.vx[k] + double(s.vy[k]) * s.vy[k] + double(s.vz[k]) * s.vz[k]));
    lo = std::min(lo, double(s.pz[k]));
    hi = std::max(hi, double(s.pz[k]));
  }
  if (w.params.ground.enabled) lo = std::min(lo, double(w.params.ground.height));
  const Vec3f g = w.params.gravity;
  const double gz = std::sqrt(double(g.x) * g.x + double(g.y) * g.y + double(g.z) * g.z);
  double walls = 0.0;
  for (const WallDef& d : w.params.walls) walls = std::max(walls, wallApproachSpeed(d));
  const double v = std::max(1.0, vmax + std::sqrt(2.0 * gz * std::max(0.0, hi - lo)) + walls);
  double tc = std::numeric_limits<double>::infinity();
  const auto contact = [&](double meff, double reff, double ystar) {
    tc = std::min(tc, 2.87 * std::pow(meff * meff / (reff * ystar * ystar * v), 0.2));
  };
  for (std::size_t a = 0; a < m; ++a) {
    if (!std::isfinite(mMin[a])) continue;
    for (std::size_t b = a; b < m; ++b)
      if (std::isfinite(mMin[b]) && (a != b || w.numBodies() > 1))
        contact(mMin[a] * mMin[b] / (mMin[a] + mMin[b]), rMax[a] * rMax[b] / (rMax[a] + rMax[b]),
                w.materialPairs[materialPairIndex(a, b, m)].ystar);
    for (std::size_t q = 0; q * m < w.planeHertz.size(); ++q) contact(mMin[a], rMax[a], w.planeHertz[q * m + a].ystar);
  }
  return tc;
}

}  // namespace

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

double shortestContactTime(const World& w) {
  const double pi = 3.14159265358979323846;
  double tc = std::numeric_limits<double>::infinity();
  if (w.radius.empty()) return tc;
  if (w.params.contact.usesMaterials()) return hertzContactTime(w);
  const double mMin = *std::min_element(w.mass.begin(), w.mass.end());
  if (w.numBodies() > 1 && w.params.contact.stiffness > 0.0f)
    tc = std::min(tc, pi * std::sqrt(0.5 * mMin / double(w.params.contact.stiffness)));
  for (const WallDef& p : w.params.planes())  // the ground and the walls
    if (p.contact.stiffness > 0.0f) tc = std::min(tc, pi * std::sqrt(mMin / double(p.contact.stiffness)));
  return tc;
}

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

std::string shapeOutOfRange(const ShapeDef& shape, bool spheresRotate) {
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

std::string timeStepWarning(const World& w) {
  const double tc = shortestContactTime(w);
  const double dt = w.params.dt;
  if (!(dt > tc / 10.0)) return {};
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "dt = %g s resolves the shortest contact (t_c = %.3g s, lightest particle %g kg) with only %.1f steps; "
                "contacts may be inaccurate or unstable: use dt <= %.3g s (t_c / 20)",
                dt, tc, double(*std::min_element(w.mass.begin(), w.mass.end())), tc / dt, tc / 20.0);
  return buf;
}

double kineticEnergy(const World& world, const BodyState& s) {
  double e = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double m = world.bodyMass[k];
    e += 0.5 * m * (double(s.vx[k]) * s.vx[k] + double(s.vy[k]) * s.vy[k] + double(s.vz[k]) * s.vz[k]);
    if (world.bodyRotates(k)) {
      const Quatf q{s.qw[k], s.qx[k], s.qy[k], s.qz[k]};
      const Vec3f Lb = rotateInv(q, Vec3f{s.lx[k], s.ly[k], s.lz[k]});
      const Vec3f wb = mul(world.invInertia[k], Lb);
      e += 0.5 * (double(wb.x) * Lb.x + double(wb.y) * Lb.y + double(wb.z) * Lb.z);
    }
  }
  return e;
}

PeriodicBox kernelPeriodic(const Scene& scene, const LocalFrame& f) {
  PeriodicBox box;
  const PeriodicParams& p = scene.periodic;
  const double o[2] = {f.x, f.y};
  for (int a = 0; a < 2; ++a) {
    if (!p.on[a]) continue;
    const double centre = double(static_cast<float>(0.5 * (double(p.lo[a]) + p.hi[a])));
    if (o[a] != centre)
      throw Error(std::string("the run's frame is not centred on the periodic box along ") + "xy"[a] +
                  " (a frame chosen for another scene)");
    box.axes |= 1u << a;
    box.half[a] = static_cast<float>(0.5 * (double(p.hi[a]) - p.lo[a]));
    box.length[a] = 2.0f * box.half[a];
  }
  return box;
}

void unwrappedPosition(const BodyState& s, std::size_t k, const PeriodicBox& box, double out[3]) {
  out[0] = s.px[k];
  out[1] = s.py[k];
  out[2] = s.pz[k];
  if (box.on(0)) out[0] += double(s.imageX[k]) * box.length[0];
  if (box.on(1)) out[1] += double(s.imageY[k]) * box.length[1];
}

PeriodReach periodReach(const Scene& scene) {
  std::vector<float> radii;
  float rMax = 0.0f;
  const auto add = [&](const BodyDef& b) {
    for (const SphereDef& sp : scene.shapes[b.shape].spheres) {
      radii.push_back(sp.radius);
      rMax = std::max(rMax, sp.radius);
    }
  };
  for (const BodyDef& b : scene.bodies) add(b);
  for (const PourBody& b : scene.pourBodies) add(b.body);  // they enter during the run
  const float sizing = detail::sizingRadius(radii.data(), radii.size());
  return PeriodReach{largestExtent(scene), rMax, effectiveSkin(scene.broadphase.skin, sizing, rMax)};
}

PeriodReach periodReach(const World& w, float skin) { return PeriodReach{w.maxExtent, w.maxRadius, skin}; }

std::string periodTooShort(const PeriodicParams& p, int a, const PeriodReach& reach) {
  if (!p.on[a]) return {};
  const double length = double(p.hi[a]) - p.lo[a];
  if (length > reach.minimum()) return {};
  char buf[480];
  std::snprintf(buf, sizeof buf,
                "[periodic] %c spans %.6g m, not more than the shortest period this scene allows, %.6g m = 2 x (the "
                "largest body's extent %.6g m + the largest radius %.6g m + the skin %.6g m): a shorter period lets a "
                "body meet its own image; widen the box to more than %.6g m, or use a smaller skin ([broadphase] skin, --skin)",
                "xy"[a], length, reach.minimum(), reach.extent, reach.radius, reach.skin, reach.minimum());
  return buf;
}

void requirePeriodsFit(const World& world) {
  const PeriodReach reach = periodReach(world, effectiveSkin(world));
  for (int a = 0; a < 2; ++a)
    if (const std::string why = periodTooShort(world.params.periodic, a, reach); !why.empty()) throw Error(why);
}

std::string periodicWallProblem(const WallDef& wall, const PeriodicParams& p) {
  if (!p.any()) return {};
  const float n[2] = {wall.normal.x, wall.normal.y};
  if (wall.shape == WallDef::Shape::Plane) {
    for (int a = 0; a < 2; ++a)
      if (p.on[a] && n[a] != 0.0f)
        return std::string("a plane across the periodic ") + "xy"[a] + " axis (its normal has an " + "xy"[a] +
               " component): a periodic scene's planes must contain its periodic axes (a box: open its faces there, "
               "open = [\"-" + "xy"[a] + "\", \"+" + "xy"[a] + "\"])";
    return {};
  }
  if (wall.shape == WallDef::Shape::Mesh)
    return "a triangle mesh is not the same one period on: a periodic scene's walls are planes containing its "
           "periodic axes and pipes along one";
  // A revolved wall: only a cylinder along the one periodic axis is the same one period on.
  const int a = p.on[0] ? 0 : 1;
  const bool along = wall.normal.z == 0.0f && n[1 - a] == 0.0f && n[a] != 0.0f;
  if (p.on[0] && p.on[1])
    return "a cylinder, cone or disk is not the same one period on along both periodic axes (x and y); only planes "
           "containing both can be used";
  if (!along || wall.length == 0.0f || wall.radius0 != wall.radius1)
    return std::string("only a cylinder whose axis lies along the periodic ") + "xy"[a] +
           " axis is the same one period on (a pipe); a cone, a disk or another axis is not";
  if ((a == 0 ? wall.velocity.x : wall.velocity.y) != 0.0f)
    return std::string("a pipe along the periodic ") + "xy"[a] + " axis may not move along it (it would leave the box " +
           "uncovered): give its velocity no " + "xy"[a] + " component";
  // Its axis must cover the box and half a period beyond each end: no body reaches further.
  const double p0 = a == 0 ? wall.point.x : wall.point.y, end = p0 + (n[a] > 0.0f ? 1.0 : -1.0) * wall.length;
  const double s0 = std::min(p0, end), s1 = std::max(p0, end);
  const double half = 0.5 * (double(p.hi[a]) - p.lo[a]);
  if (s0 <= p.lo[a] - half && s1 >= p.hi[a] + half) return {};
  char buf[320];
  std::snprintf(buf, sizeof buf, "the cylinder spans %c from %.6g to %.6g; along the periodic axis it must reach "
                "half a period beyond each end of the box, from %.6g to %.6g or further", "xy"[a], s0, s1,
                p.lo[a] - half, p.hi[a] + half);
  return buf;
}

std::string outsidePeriodicBox(const PeriodicParams& p, Vec3f x) {
  const float c[2] = {x.x, x.y};
  for (int a = 0; a < 2; ++a)
    if (p.on[a] && !(c[a] >= p.lo[a] && c[a] < p.hi[a])) {
      char buf[240];
      std::snprintf(buf, sizeof buf, "its centre %c = %.9g lies outside the periodic box [%.9g, %.9g) of [periodic] %c; "
                    "start every body inside it", "xy"[a], double(c[a]), double(p.lo[a]), double(p.hi[a]), "xy"[a]);
      return buf;
    }
  return {};
}

std::string periodicPullProblem(const PeriodicParams& p, std::uint32_t active) {
  const std::uint32_t bad = active & p.conflictingPulls();
  if (bad == 0) return {};
  std::string names;
  for (const auto& [bit, name] : {std::pair<std::uint32_t, const char*>{kPullX, "x"}, {kPullY, "y"}, {kPullSwirl, "swirl"}})
    if (bad & bit) names += std::string(names.empty() ? "\"" : ", \"") + name + "\"";
  return "the pulls " + names + " pull along a periodic axis, where their potential has no period; leave them off "
         "with [periodic] (or drop the periodic axis)";
}

std::uint64_t stateHash(const BodyState& s) {
  std::uint64_t h = 1469598103934665603ull;
  auto mixWord = [&](std::uint32_t u) {
    for (int b = 0; b < 4; ++b) {
      h ^= (u >> (8 * b)) & 0xFFu;
      h *= 1099511628211ull;
    }
  };
  auto mixFloat = [&](float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    mixWord(u);
  };
  auto mix = [&](const std::vector<float>& col) {
    for (float f : col) mixFloat(f);
  };
  for (const auto* c : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz,
                        &s.groundSpringX, &s.groundSpringY})
    mix(*c);
  // Contact histories (none under the report's law, whose hashes therefore stay as they were),
  // then the mesh springs (none without meshes).
  for (const ContactHistory& c : s.contacts) {
    mixWord(c.i);
    mixWord(c.j);
    mixFloat(c.x);
    mixFloat(c.y);
    mixFloat(c.z);
  }
  // Image counters (periodic boundaries only: the other scenes' hashes stay as they were).
  for (const auto* c : {&s.imageX, &s.imageY})
    for (std::int32_t n : *c) mixWord(static_cast<std::uint32_t>(n));
  for (const MeshContactHistory& c : s.meshContacts) {
    mixWord(c.particle);
    mixWord(c.triangle);
    mixFloat(c.x);
    mixFloat(c.y);
    mixFloat(c.z);
  }
  return h;
}

}  // namespace tumble
