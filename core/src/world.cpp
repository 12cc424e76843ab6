// SPDX-License-Identifier: MIT
// Building a World from a Scene: mass properties (SPEC §1) and the ground damping that makes
// each particle's elasticity its coefficient of restitution on the ground (SPEC §2.4).
// This file: the body state, the local frame, World::fromScene and the state's energy and hash;
// the rest of the World's building by concern: world_walls.cpp, world_contact.cpp,
// world_shapes.cpp, world_periodic.cpp.
#include "tumble/world.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <string>

#include "tumble/error.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/mesh.hpp"
#include "tumble/sweep_frame.hpp"
#include "world_internal.hpp"

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

namespace {

using detail::largestExtent;

bool finite(Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Sym3f toSym(const Eigen::Matrix3d& m) {
  return {static_cast<float>(m(0, 0)), static_cast<float>(m(1, 1)), static_cast<float>(m(2, 2)),
          static_cast<float>(m(0, 1)), static_cast<float>(m(0, 2)), static_cast<float>(m(1, 2))};
}

// The periodic boundaries of a scene built in code (the scene reader names the line of each);
// `placement`: the bodies' centres in the box too.
void checkPeriodic(const World& w, const Scene& scene, bool placement) {
  const PeriodicParams& p = scene.periodic;
  for (int a = 0; a < 2; ++a)
    if (p.on[a] && !(p.lo[a] < p.hi[a] && std::isfinite(p.lo[a]) && std::isfinite(p.hi[a])))
      throw Error(std::string("periodic ") + "xy"[a] + ": the box [lo, hi) needs finite lo < hi");
    else if (const std::string why = p.on[a] ? periodicBoxRange(p.lo[a], p.hi[a]) : std::string(); !why.empty())
      throw Error(std::string("periodic ") + "xy"[a] + ": " + why);
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

// How deep cohesion alone pulls a contact at rest (docs/model.md#cohesion): the overlap δ₀ > 0
// where the spring balances the attraction without load, which must stay below half of R*
// (Hertz's and Hooke's laws are laws of small overlaps; LIGGGHTS's sjkr comparison,
// validation/liggghts, rests 12 % deep). δ₀ / R*: hertz-mindlin sjkr (3 π k_c / (2 Y*))², dmt
// (3 π γ / (2 Y* R*))^{2/3}; hooke-history dmt 2 π γ / k. Under hooke-history sjkr's attraction
// grows by 2 π k_c R* per metre of overlap: at or above the spring's k no overlap balances it and
// the contact collapses. Checked for the contacts the scene can have: each pair of materials that
// spheres are made of (a material with itself when two bodies have it: its two largest and its
// two smallest spheres), each such material on each plane, at the largest and the smallest radii
// of those spheres; a bound suggested for [contact]'s k_c is the smallest over every contact that
// takes it (the pairs, and the planes without their own).
void checkRestOverlap(const Scene& scene, const World& w, const std::vector<WallDef>& planes) {
  const ContactParams& c = scene.contact;
  if (c.cohesion == Cohesion::None || w.radius.empty()) return;
  const double pi = 3.14159265358979323846;
  const bool sjkr = c.cohesion == Cohesion::Sjkr;
  const std::string key = cohesionKey(c.cohesion);
  const auto g = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
  };
  const auto planeName = [&](std::size_t q) { return planes[q].where.empty() ? std::string("a plane") : planes[q].where; };
  // The spheres of each material (one class under hooke-history): how many, the smallest and the
  // largest, and the smallest and the largest of another body than theirs (a clump's spheres never
  // touch each other): the least and the greatest R* of two spheres of the material that can touch.
  const bool hertz = c.usesMaterials();
  const std::size_t m = hertz ? scene.materials.size() : 1;
  struct Spheres {
    std::size_t count = 0;
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {0.0, 0.0};  ///< [1]: of another body than [0]'s
    std::uint32_t loBody = 0, hiBody = 0;
    bool bodies() const { return lo[1] < HUGE_VAL; }  ///< of two bodies or more
  };
  std::vector<Spheres> sp(m);
  const auto materialOfParticle = [&](std::size_t i) { return hertz ? std::size_t(w.material[i]) : std::size_t(0); };
  for (std::size_t i = 0; i < w.radius.size(); ++i) {
    Spheres& e = sp[materialOfParticle(i)];
    const double r = w.radius[i];
    ++e.count;
    if (r < e.lo[0]) e.lo[0] = r, e.loBody = w.body[i];
    if (r > e.hi[0]) e.hi[0] = r, e.hiBody = w.body[i];
  }
  for (std::size_t i = 0; i < w.radius.size(); ++i) {
    Spheres& e = sp[materialOfParticle(i)];
    const double r = w.radius[i];
    if (w.body[i] != e.loBody) e.lo[1] = std::min(e.lo[1], r);
    if (w.body[i] != e.hiBody) e.hi[1] = std::max(e.hi[1], r);
  }
  // Under hooke-history sjkr a plane without its own k_c takes [contact]'s: the bound suggested for
  // that value is the smallest of every check it meets.
  double contactLimit = HUGE_VAL;
  if (c.law == ContactLaw::HookeHistory && sjkr && sp[0].count > 0) {
    if (sp[0].bodies()) contactLimit = c.stiffness / (2.0 * pi * 0.5 * sp[0].hi[0]);
    for (const WallDef& p : planes)
      if (!(p.contact.cohesion >= 0.0f)) contactLimit = std::min(contactLimit, p.contact.stiffness / (2.0 * pi * sp[0].hi[0]));
  }
  // A contact of coefficient v, stiffness k (hooke-history) or Y* (hertz-mindlin), at R*; inherits:
  // the coefficient is [contact]'s (a pair, or a plane without its own).
  const auto check = [&](double v, double k, double ystar, double reff, const std::string& where, bool inherits) {
    if (!(v > 0.0)) return;
    double depth;  // δ₀ / R*
    if (c.law == ContactLaw::HookeHistory) {
      if (sjkr) {
        if (2.0 * pi * v * reff < k) return;
        const double limit = inherits ? contactLimit : k / (2.0 * pi * reff);
        throw Error(where + ": " + key + " " + g(v) + (inherits && where != "[contact]" ? " ([contact]'s)" : "") +
                    " pulls harder than the spring " + g(k) + " N/m can push (2 pi k_c R* = " +
                    g(2.0 * pi * v * reff) + " N/m at R* " + g(reff) + " m): no overlap balances it; use k_c below " +
                    g(limit) + " J/m^3" + (inherits ? " (for every contact that takes it)" : "") +
                    " (docs/model.md#cohesion)");
      }
      depth = 2.0 * pi * v / k;
    } else if (c.cohesion == Cohesion::Jkr) {  // F = 0 at s³ = 3/2 c R*: δ₀ = ½ c s
      const double cc = std::sqrt(2.0 * pi * v / ystar);
      depth = 0.5 * cc * std::cbrt(1.5 * cc * reff) / reff;
    } else {
      depth = sjkr ? std::pow(3.0 * pi * v / (2.0 * ystar), 2.0) : std::pow(3.0 * pi * v / (2.0 * ystar * reff), 2.0 / 3.0);
    }
    if (depth > 0.5)
      throw Error(where + ": " + key + " " + g(v) + " alone pulls a contact of R* " + g(reff) + " m " +
                  g(100.0 * depth) + " % of R* deep at rest (tumble allows 50 %: overlaps that deep are outside what "
                  "the contact law models); use a smaller " + key + " (docs/model.md#cohesion)");
  };
  for (std::size_t a = 0; a < m; ++a) {
    if (sp[a].count == 0) continue;
    const std::string what = hertz ? "material '" + scene.materials[a].name + "' on " : std::string();
    for (std::size_t q = 0; q < planes.size(); ++q)
      for (const double r : {sp[a].hi[0], sp[a].lo[0]}) {
        if (hertz) {
          const HertzPair& hp = w.planeHertz[q * m + a];
          check(hp.cohesion, 0.0, hp.ystar, r, what + planeName(q), false);
        } else {
          check(scene.cohesionOf(planes[q].contact), planes[q].contact.stiffness, 0.0, r, planeName(q),
                !(planes[q].contact.cohesion >= 0.0f));
        }
      }
  }
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t b = a; b < m; ++b) {
      // A material with itself: its smallest (largest) sphere and the smallest (largest) of another body.
      if (sp[a].count == 0 || sp[b].count == 0 || (a == b && !sp[a].bodies())) continue;
      for (const bool large : {true, false}) {
        const double ra = large ? sp[a].hi[0] : sp[a].lo[0];
        const double rb = a == b ? (large ? sp[a].hi[1] : sp[a].lo[1]) : (large ? sp[b].hi[0] : sp[b].lo[0]);
        const double reff = ra * rb / (ra + rb);
        if (!hertz) {
          check(c.cohesionValue, c.stiffness, 0.0, reff, "[contact]", true);
          continue;
        }
        const HertzPair& hp = w.materialPairs[materialPairIndex(a, b, m)];
        check(hp.cohesion, 0.0, hp.ystar, reff,
              "materials '" + scene.materials[a].name + "' and '" + scene.materials[b].name + "'", false);
      }
    }
}

// The cohesion of a scene built in code (the scene reader names the line of each): a law with
// history, and every coefficient finite and not negative (a plane's negative: not given).
void checkCohesion(const Scene& scene, const std::vector<WallDef>& planes) {
  const ContactParams& c = scene.contact;
  if (c.cohesion == Cohesion::None) return;
  if (c.cohesion != Cohesion::Sjkr && c.cohesion != Cohesion::Dmt && c.cohesion != Cohesion::Jkr)
    throw Error("unknown cohesion model " + std::to_string(int(c.cohesion)) + " (Cohesion::None, Sjkr, Dmt or Jkr)");
  if (!c.hasHistory()) throw Error("cohesion needs a contact law with history (hooke-history or hertz-mindlin)");
  if (c.cohesion == Cohesion::Jkr && c.law != ContactLaw::HertzMindlin)
    throw Error("cohesion \"jkr\" needs law \"hertz-mindlin\" (JKR's contact radius comes from Hertz's elasticity)");
  if (c.cohesion == Cohesion::Jkr)
    for (const WallDef& p : planes)
      if (p.shape == WallDef::Shape::Mesh)
        throw Error(p.where + ": cohesion \"jkr\" does not reach mesh walls yet (a mesh contact does not keep the "
                    "neck that holds beyond touching); use \"dmt\" with meshes, or planes and cylinders "
                    "(docs/model.md#cohesion)");
  const auto bad = [](float v) { return !(v >= 0.0f) || !std::isfinite(v); };
  const std::string what = cohesionKey(c.cohesion);
  if (bad(c.cohesionValue)) throw Error("[contact] " + what + " must be finite and >= 0");
  for (const MaterialDef& m : scene.materials)
    if (bad(m.cohesion)) throw Error("material '" + m.name + "': " + what + " must be finite and >= 0");
  for (const WallDef& p : planes)
    if (!std::isfinite(p.contact.cohesion))
      throw Error((p.where.empty() ? std::string("a plane") : p.where) + ": " + what + " must be finite");
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
    }
    if (const std::string why = shapeOutOfRange(sh, scene.contact.rotatesSpheres(), scene.gravity); !why.empty()) throw Error("shape '" + sh.name + "': " + why);
    const ShapeSolid solid = shapeMassProperties(sh);
    p.mass = solid.mass;
    p.com = Eigen::Vector3d(solid.centre[0], solid.centre[1], solid.centre[2]);
    const auto& I = solid.inertia;
    p.inertia << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
    p.shapeInertia = p.inertia;
    if (principal && (sh.spheres.size() > 1 || sh.solid)) {
      // The splitting integrator rotates about the principal axes: use them as the body frame
      // (a solid of one sphere too: its inertia need not be diagonal).
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(p.inertia);
      p.frame = eig.eigenvectors();
      if (p.frame.determinant() < 0.0) p.frame.col(2) = -p.frame.col(2);
      p.inertia = eig.eigenvalues().asDiagonal();
    }
    p.invInertia = p.inertia.inverse();
    if (principal && (sh.spheres.size() > 1 || sh.solid)) {  // exact zeros off the diagonal
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
  checkCohesion(scene, planes);
  if (!scene.contact.usesMaterials()) checkRestOverlap(scene, w, planes);  // hertz-mindlin: with its pairs, below
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
    checkRestOverlap(scene, w, planes);
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
