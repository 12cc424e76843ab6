// SPDX-License-Identifier: MIT
/// @file wall_geometry.hpp
/// The walls of a scene as triangles for drawing (the viewer, `tumble render`, `tumble export`):
/// revolved walls tessellated by angle, each plane as the polygon that remains of a large square
/// once the other planes' half-spaces have clipped it, with the motion that poses a wall at any
/// time. The recording stores these surfaces (docs/recording.md, version 2). Host code only; the
/// kernels never see it.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "tumble/math.hpp"
#include "tumble/scene.hpp"

namespace tumble {

/// What a drawn wall is: the kind id of the recording (a player's colour). Mesh: a triangle-mesh
/// wall (its triangles stored as they are).
enum class WallKind : std::uint32_t { Plane = 0, Cylinder = 1, Cone = 2, Disk = 3, Mesh = 4 };
/// Kinds a reader accepts: ids below this.
inline constexpr std::uint32_t kNumWallKinds = 5;
/// "plane", "cylinder", "cone", "disk", "mesh" ("unknown" for any other id).
const char* toString(WallKind kind);

/// How a wall's drawing moves. Its pose at time t is the rotation about `pivot` by the angle
/// |ω| τ about ω, then the translation v τ, with τ = clamp(t − start, 0, stop − start): at rest
/// (the identity) up to `start`, held from `stop` on. A drum turning about its axis has ω (its
/// axis times its angular velocity, pivot a point of the axis); a belt moves its surface, not
/// the plane, so its drawing stands still; a moving mesh has its velocity, angular velocity and
/// pivot (WallDef), the pose the kernels give it (setWallMotion()).
struct WallMotion {
  Vec3f velocity{0.0f, 0.0f, 0.0f};         ///< v [m/s]
  Vec3f angularVelocity{0.0f, 0.0f, 0.0f};  ///< ω [rad/s], right-handed
  Vec3f pivot{0.0f, 0.0f, 0.0f};            ///< a point of the rotation axis [m]
  double start = 0.0;                       ///< [s]
  double stop = 0.0;                        ///< [s], ≥ start; +∞: never stops
  /// Some pose differs from the identity: v or ω is not zero and stop > start.
  bool moves() const;
};

/// A rigid motion of a wall's drawing: x ↦ R (x − pivot) + pivot + translation.
struct WallPose {
  Quatf rotation{1.0f, 0.0f, 0.0f, 0.0f};
  Vec3f pivot{0.0f, 0.0f, 0.0f};
  Vec3f translation{0.0f, 0.0f, 0.0f};
  Vec3f apply(Vec3f x) const { return rotate(rotation, x - pivot) + pivot + translation; }
  bool identity() const;
};

/// The pose of `motion` at time t (WallMotion). The angle is computed in double.
WallPose wallPose(const WallMotion& motion, double t);

/// One wall as drawn.
struct WallSurface {
  WallKind kind = WallKind::Plane;
  /// 9 floats per triangle (the corners a, b, c, x y z each) [m], at the pose of t ≤ start,
  /// counter-clockwise seen from the wall's inner side (its normal (b − a) × (c − a) points
  /// there): the side the bodies are on (a plane: its normal's side; a revolved wall: the side
  /// of the focus box's centre). Empty for a plane that the others clip away entirely or a
  /// degenerate wall (a zero normal, zero radii).
  std::vector<float> triangles;
  WallMotion motion;
  std::size_t numTriangles() const { return triangles.size() / 9; }
};

/// An axis-aligned box [lo, hi]; empty until something is added.
struct Extent {
  Vec3f lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
           std::numeric_limits<float>::infinity()};
  Vec3f hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
           -std::numeric_limits<float>::infinity()};
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  /// Grows the box to hold the ball of radius r about p (non-finite values are left out).
  void add(Vec3f p, float r = 0.0f);
};

/// Knobs of wallSurfaces().
struct WallTessellation {
  int segments = 96;     ///< revolved walls: segments per full turn (3.75°; at least 3)
  float margin = 0.25f;  ///< the drawing region grows by this fraction of its largest side on every side
};

/// Each wall of `walls` (a plane or a revolved wall; Scene::planes() order, say) as triangles,
/// one surface per wall in the same order:
/// - a cylinder, cone, disk or ring: its segment (0, radius0)–(length, radius1) turned about
///   its axis in `options.segments` steps per turn, wound towards the focus box's centre;
/// - a plane: a square about the focus box's centre, far larger than everything (10⁶ times),
///   clipped by the half-spaces of all the other planes (where the bodies may be). When what
///   remains is bounded (a box's face: the other faces cut it on every side) it is the face
///   itself; otherwise (a lone plane, the sides of an open box) it is cut further by the drawing
///   region: the focus box, the revolved walls and the bounded faces, grown by `options.margin`
///   of its largest side. So a box's six planes give its six faces, an open box its container
///   without a lid, and the ground inside a box only the floor within it.
/// Revolved walls are not clipped. A revolved wall that turns gets the motion ω =
/// angular_velocity × its unit axis about its point, from start to stop; a moving mesh its own
/// (v, ω about its pivot); a plane moving along its normal and a moving box's faces their
/// velocity; a belt stands still (it moves its surface only). `focus` is what the walls are drawn around (the bodies'
/// extent, sceneBodiesExtent()); empty: the walls alone, or the planes' points when nothing is
/// bounded. Degenerate walls (a zero or non-finite normal or point, zero radii) give no
/// triangles; neither does a plane that the others cut away. Deterministic (double arithmetic,
/// no library order).
///
/// A mesh wall is kind Mesh: its triangles as given (meshWallTriangles()), its extent added to
/// the drawing region like a revolved wall's.
std::vector<WallSurface> wallSurfaces(const std::vector<WallDef>& walls, const Extent& focus,
                                      const WallTessellation& options = {});

/// The bodies of a scene where they are created: each body's position ± its shape's reach
/// (shapeExtent). Empty for a scene without bodies.
Extent sceneBodiesExtent(const Scene& scene);

/// The walls of a scene as drawn: one surface per entry of scene.walls, in order (a box's faces
/// are walls of their own), from wallSurfaces(scene.planes(), focus); the ground clips the
/// planes but is not among them (players draw it as a plane of its own). `focus`: the bodies'
/// extent, sceneBodiesExtent(scene) or World::bodiesExtent (a World's scene keeps no bodies).
std::vector<WallSurface> sceneWallSurfaces(const Scene& scene, const Extent& focus,
                                           const WallTessellation& options = {});

}  // namespace tumble
