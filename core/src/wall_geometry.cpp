// SPDX-License-Identifier: MIT
// Walls as triangles for drawing (wall_geometry.hpp).
//
// Design notes
// - Planes. A plane is infinite; what is drawn is what the other planes leave of it: a square
//   10⁶ times larger than the scene, clipped (Sutherland–Hodgman, in double) by every other
//   plane's half-space n·x ≥ h. A face cut on every side by others (a box's) comes out exact:
//   none of its corners is left on the square's border. What still reaches the border is
//   unbounded (a lone plane, the walls of an open box) and is cut by the drawing region too, so
//   it ends near the scene instead of at the horizon. Each clip keeps a sliver eps outside the
//   clipping plane, so that faces meeting at an edge keep that edge (and coinciding planes both
//   stay); eps is 10⁻⁹ of the scene's size, far below what a float vertex holds.
// - Revolved walls. The segment (0, r0)–(L, r1) of (s, ρ) turned about the axis: one ring of
//   points per end, each computed once, so neighbouring triangles share their corners' bits (a
//   player can weld them to smooth the shading). Winding: the default (b − a) × (c − a) of the
//   quad (θ_k, θ_k+1) points along m = (−(r1 − r0), L) in (s, ρ), the segment's direction turned
//   by +90°; it is reversed when the focus centre lies on the other side of the segment's line.
// - Output floats. Vertices are rounded to float once; a triangle with a non-finite corner
//   (a scene beyond single precision) is left out rather than drawn wrong.
#include "tumble/wall_geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"
#include "tumble/world.hpp"

namespace tumble {
namespace {

using V3 = std::array<double, 3>;
using Polygon = std::vector<V3>;

V3 plus(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 scale(double s, const V3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 of(Vec3f v) { return {v.x, v.y, v.z}; }
bool finite(const V3& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

// A unit vector along v, or false for a zero or non-finite one.
bool unit(Vec3f v, V3* out) {
  const V3 d = of(v);
  const double len = std::sqrt(dot(d, d));
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  *out = scale(1.0 / len, d);
  return true;
}

// The half-space n·x ≥ h (n unit): where a plane's bodies are.
struct HalfSpace {
  V3 n;
  double h;
};

// Keeps the part of `poly` with n·x ≥ h − eps.
void clip(Polygon& poly, const HalfSpace& s, double eps) {
  if (poly.empty()) return;
  Polygon out;
  out.reserve(poly.size() + 1);
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const V3& a = poly[k];
    const V3& b = poly[(k + 1) % poly.size()];
    const double da = dot(s.n, a) - s.h + eps, db = dot(s.n, b) - s.h + eps;
    if (da >= 0.0) out.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) out.push_back(plus(a, scale(da / (da - db), sub(b, a))));
  }
  poly = std::move(out);
}

// Appends triangle (a, b, c) as floats unless a corner does not fit a float.
void emit(const V3& a, const V3& b, const V3& c, std::vector<float>& out) {
  float f[9];
  const V3* corners[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) {
      f[3 * k + i] = static_cast<float>((*corners[k])[i]);
      if (!std::isfinite(f[3 * k + i])) return;
    }
  out.insert(out.end(), f, f + 9);
}

// A convex polygon (counter-clockwise about n) as a fan; nothing when it has no area.
void fan(const Polygon& poly, const V3& n, std::vector<float>& out) {
  if (poly.size() < 3) return;
  for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
    const V3 e1 = sub(poly[k], poly[0]), e2 = sub(poly[k + 1], poly[0]);
    const V3 c = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    if (dot(c, n) > 0.0) emit(poly[0], poly[k], poly[k + 1], out);
  }
}

struct Region {
  V3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  bool empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
  void add(const V3& p) {
    if (!finite(p)) return;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  V3 centre() const { return empty() ? V3{0, 0, 0} : scale(0.5, plus(lo, hi)); }
  double diagonal() const { return empty() ? 0.0 : std::sqrt(dot(sub(hi, lo), sub(hi, lo))); }
};

WallKind kindOf(const WallDef& w) {
  if (w.shape == WallDef::Shape::Plane) return WallKind::Plane;
  if (w.shape == WallDef::Shape::Mesh) return WallKind::Mesh;
  if (w.length == 0.0f) return WallKind::Disk;
  return w.radius0 == w.radius1 ? WallKind::Cylinder : WallKind::Cone;
}

// How a wall's drawing moves (WallDef::velocity, angularVelocity): a revolved wall turns about
// its axis and translates with its velocity; a plane translates with its velocity when it moves
// along its normal (a piston) or is a face of a box that moves (its faces along the motion
// then travel with the others), and stands still when only its surface moves (a belt); a mesh
// moves as a whole, turning about its pivot and translating (the pose of WallDef's mesh motion).
WallMotion motionOf(const WallDef& w) {
  WallMotion m;
  V3 a;
  if (!(w.stop > w.start)) return m;
  if (w.shape == WallDef::Shape::Mesh) {
    m.velocity = w.velocity;
    m.angularVelocity = w.meshAngularVelocity;
    m.pivot = w.meshPivot();
    m.start = w.start;
    m.stop = w.stop;
    return m.moves() && finite(of(m.velocity)) && finite(of(m.angularVelocity)) && finite(of(m.pivot)) ? m : WallMotion{};
  }
  if (!unit(w.normal, &a)) return m;
  const V3 v = of(w.velocity);
  if (w.shape == WallDef::Shape::Revolved && w.angularVelocity != 0.0f && std::isfinite(w.angularVelocity)) {
    m.angularVelocity = Vec3f{static_cast<float>(a[0] * w.angularVelocity), static_cast<float>(a[1] * w.angularVelocity),
                              static_cast<float>(a[2] * w.angularVelocity)};
    m.pivot = w.point;
  }
  if (w.shape == WallDef::Shape::Revolved || w.boxFace || dot(v, a) != 0.0) m.velocity = w.velocity;
  m.start = w.start;
  m.stop = w.stop;
  return m.moves() ? m : WallMotion{};
}

// A revolved wall's triangles, wound towards `inside` (its centre when there is no focus).
void revolved(const WallDef& w, const V3* inside, int segments, std::vector<float>& out) {
  V3 a;
  const V3 p = of(w.point);
  const double r0 = w.radius0, r1 = w.radius1, len = w.length;
  if (!unit(w.normal, &a) || !finite(p) || !(r0 >= 0.0 && r1 >= 0.0 && len >= 0.0) || !std::isfinite(r0 + r1 + len) ||
      (r0 == 0.0 && r1 == 0.0) || (len == 0.0 && r0 == r1))
    return;
  V3 t, u;
  perpendicularPair(a.data(), t.data(), u.data());
  // Which side is inner: m = (−(r1 − r0), L) in (s, ρ) against the centre's (s_c, ρ_c) − (0, r0).
  const V3 c = inside ? *inside : plus(p, scale(0.5 * len, a));
  const V3 d = sub(c, p);
  const double sc = dot(d, a);
  const V3 radial = sub(d, scale(sc, a));
  const double rc = std::sqrt(dot(radial, radial));
  const bool flip = -(r1 - r0) * sc + len * (rc - r0) < 0.0;
  const int n = std::max(3, segments);
  std::vector<V3> ring0(static_cast<std::size_t>(n)), ring1(static_cast<std::size_t>(n));
  const double kTwoPi = 6.283185307179586;
  for (int k = 0; k < n; ++k) {
    const double th = kTwoPi * k / n;
    const V3 e = plus(scale(std::cos(th), t), scale(std::sin(th), u));
    ring0[static_cast<std::size_t>(k)] = plus(p, scale(r0, e));
    ring1[static_cast<std::size_t>(k)] = plus(plus(p, scale(len, a)), scale(r1, e));
  }
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k), j = static_cast<std::size_t>((k + 1) % n);
    // Quad A = ring0[i], B = ring0[j], C = ring1[j], D = ring1[i]; a zero radius makes one end a point.
    if (r0 > 0.0) flip ? emit(ring0[i], ring1[j], ring0[j], out) : emit(ring0[i], ring0[j], ring1[j], out);
    if (r1 > 0.0) flip ? emit(ring0[i], ring1[i], ring1[j], out) : emit(ring0[i], ring1[j], ring1[i], out);
  }
}

}  // namespace

const char* toString(WallKind kind) {
  switch (kind) {
    case WallKind::Plane: return "plane";
    case WallKind::Cylinder: return "cylinder";
    case WallKind::Cone: return "cone";
    case WallKind::Disk: return "disk";
    case WallKind::Mesh: return "mesh";
  }
  return "unknown";
}

bool WallMotion::moves() const {
  const bool any = velocity.x != 0.0f || velocity.y != 0.0f || velocity.z != 0.0f || angularVelocity.x != 0.0f ||
                   angularVelocity.y != 0.0f || angularVelocity.z != 0.0f;
  return any && stop > start;
}

bool WallPose::identity() const {
  return rotation.w == 1.0f && rotation.x == 0.0f && rotation.y == 0.0f && rotation.z == 0.0f &&
         translation.x == 0.0f && translation.y == 0.0f && translation.z == 0.0f;
}

WallPose wallPose(const WallMotion& m, double t) {
  WallPose pose;
  pose.pivot = m.pivot;
  if (!m.moves()) return pose;
  const double tau = std::clamp(t - m.start, 0.0, m.stop - m.start);
  if (!(tau > 0.0)) return pose;
  const V3 w = of(m.angularVelocity);
  const double speed = std::sqrt(dot(w, w));
  if (speed > 0.0) {
    const double half = 0.5 * speed * tau, s = std::sin(half) / speed;
    pose.rotation = Quatf{static_cast<float>(std::cos(half)), static_cast<float>(s * w[0]), static_cast<float>(s * w[1]),
                          static_cast<float>(s * w[2])};
  }
  pose.translation = Vec3f{static_cast<float>(m.velocity.x * tau), static_cast<float>(m.velocity.y * tau),
                           static_cast<float>(m.velocity.z * tau)};
  return pose;
}

void Extent::add(Vec3f p, float r) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(r)) return;
  lo = Vec3f{std::min(lo.x, p.x - r), std::min(lo.y, p.y - r), std::min(lo.z, p.z - r)};
  hi = Vec3f{std::max(hi.x, p.x + r), std::max(hi.y, p.y + r), std::max(hi.z, p.z + r)};
}

std::vector<WallSurface> wallSurfaces(const std::vector<WallDef>& walls, const Extent& focus,
                                      const WallTessellation& options) {
  std::vector<WallSurface> out(walls.size());
  Region region;
  if (!focus.empty()) {
    region.add(of(focus.lo));
    region.add(of(focus.hi));
  }
  const V3 focusCentre = region.centre();
  // Revolved walls and meshes first: their extents join the drawing region. A mesh is drawn as
  // its file winds it (its triangles in world coordinates).
  for (std::size_t k = 0; k < walls.size(); ++k) {
    out[k].kind = kindOf(walls[k]);
    out[k].motion = motionOf(walls[k]);
    if (walls[k].shape == WallDef::Shape::Mesh) {
      for (const Vec3f& c : meshWallTriangles(walls[k]))
        for (const float x : {c.x, c.y, c.z}) out[k].triangles.push_back(x);
    } else if (walls[k].shape == WallDef::Shape::Revolved) {
      revolved(walls[k], focus.empty() ? nullptr : &focusCentre, options.segments, out[k].triangles);
    } else {
      continue;
    }
    const std::vector<float>& tri = out[k].triangles;
    for (std::size_t i = 0; i + 2 < tri.size(); i += 3) region.add(V3{tri[i], tri[i + 1], tri[i + 2]});
  }

  // Planes: each as the square clipped by the others' half-spaces.
  std::vector<std::size_t> planes;
  std::vector<HalfSpace> half(walls.size());
  double reach = region.diagonal();
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const WallDef& w = walls[k];
    V3 n;
    if (w.shape != WallDef::Shape::Plane || !unit(w.normal, &n) || !finite(of(w.point))) continue;
    half[k] = HalfSpace{n, dot(n, of(w.point))};
    reach = std::max(reach, std::abs(half[k].h));
    planes.push_back(k);
  }
  if (planes.empty()) return out;
  const double big = 1e6 * std::max(reach, 1e-3);
  const double eps = 1e-15 * big;
  std::vector<Polygon> polys(walls.size());
  std::vector<bool> bounded(walls.size(), false);
  for (const std::size_t k : planes) {
    const HalfSpace& s = half[k];
    V3 t, u;
    perpendicularPair(s.n.data(), t.data(), u.data());  // (t, u, n) right-handed: counter-clockwise about n
    const V3 o = plus(focusCentre, scale(s.h - dot(s.n, focusCentre), s.n));  // the centre projected on the plane
    Polygon& poly = polys[k];
    for (const auto& [a, b] : {std::pair{-1.0, -1.0}, std::pair{1.0, -1.0}, std::pair{1.0, 1.0}, std::pair{-1.0, 1.0}})
      poly.push_back(plus(o, plus(scale(a * big, t), scale(b * big, u))));
    for (const std::size_t j : planes)
      if (j != k) clip(poly, half[j], eps);
    bounded[k] = !poly.empty() && std::all_of(poly.begin(), poly.end(), [&](const V3& v) {
      const V3 d = sub(v, o);
      return std::abs(dot(d, t)) < 0.5 * big && std::abs(dot(d, u)) < 0.5 * big;
    });
    if (bounded[k])
      for (const V3& v : poly) region.add(v);
  }
  if (region.empty())
    for (const std::size_t k : planes) region.add(of(walls[k].point));
  // The drawing region, grown; it cuts what is still unbounded.
  double side = 0.0;
  for (int a = 0; a < 3; ++a) side = std::max(side, region.hi[a] - region.lo[a]);
  const double grow = side > 0.0 ? options.margin * side : 1.0;
  for (int a = 0; a < 3; ++a) {
    region.lo[a] -= grow;
    region.hi[a] += grow;
  }
  for (const std::size_t k : planes) {
    if (!bounded[k]) {
      // The region's box, stretched to hold its corners' projections on the plane: a plane
      // beside the region (a floor below the bodies) is cut across, not away.
      Region cut = region;
      for (int c = 0; c < 8; ++c) {
        const V3 q = {c & 1 ? region.hi[0] : region.lo[0], c & 2 ? region.hi[1] : region.lo[1],
                      c & 4 ? region.hi[2] : region.lo[2]};
        cut.add(plus(q, scale(half[k].h - dot(half[k].n, q), half[k].n)));
      }
      for (int a = 0; a < 3; ++a) {
        V3 e{0, 0, 0};
        e[a] = 1.0;
        clip(polys[k], HalfSpace{e, cut.lo[a]}, 0.0);
        e[a] = -1.0;
        clip(polys[k], HalfSpace{e, -cut.hi[a]}, 0.0);
      }
    }
    fan(polys[k], half[k].n, out[k].triangles);
  }
  return out;
}

Extent sceneBodiesExtent(const Scene& scene) {
  Extent e;
  for (const BodyDef& b : scene.bodies)
    if (b.shape < scene.shapes.size()) e.add(b.position, static_cast<float>(shapeExtent(scene.shapes[b.shape])));
  return e;
}

std::vector<WallSurface> sceneWallSurfaces(const Scene& scene, const Extent& focus, const WallTessellation& options) {
  std::vector<WallSurface> all = wallSurfaces(scene.planes(), focus, options);
  if (scene.ground.enabled) all.erase(all.begin());
  return all;
}

}  // namespace tumble
