// SPDX-License-Identifier: MIT
// The periodic box of a World: the kernels' box in the local frame, unwrapped positions, the
// reach a period must exceed, and the problems of walls, bodies and pulls with periodic axes.
#include "tumble/world.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/sweep_frame.hpp"
#include "world_internal.hpp"

namespace tumble {

namespace detail {

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

}  // namespace detail

using detail::largestExtent;

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

std::string periodicBoxRange(float lo, float hi) {
  if (std::isfinite(hi - lo)) return {};
  return "its length hi - lo is beyond single precision (about 3.4e38 m at most); give a shorter box";
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

}  // namespace tumble
