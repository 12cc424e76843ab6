// SPDX-License-Identifier: MIT
// Placing bodies where they overlap nothing: shared by [[fill]] (fill.cpp) and [[pour]]
// (pour.cpp). Internal to tumble_core.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "tumble/kernels/wall.hpp"
#include "tumble/mesh.hpp"
#include "tumble/math.hpp"
#include "tumble/random.hpp"
#include "tumble/scene.hpp"
#include "tumble/size_distribution.hpp"
#include "tumble/world.hpp"

namespace tumble::detail {

/// A sphere of a body about its centre of mass, in the shape's frame.
struct Ball {
  Vec3f u;
  float r;
};

/// A shape's spheres about its centre of mass (shapeMassProperties()).
std::vector<Ball> ballsOf(const ShapeDef& shape);

/// Spheres placed so far, hashed on a uniform grid of cells as wide as the largest sphere to be
/// placed is across: a sphere of that size overlaps only spheres registered in the 27 cells
/// around its centre. A sphere wider than a cell is registered in every cell its box covers (up
/// to a bound; beyond it, in a list every test reads).
class SphereHash {
 public:
  explicit SphereHash(double cell) : m_cell(cell) {}
  /// Periodic boundaries ([periodic], in the frame of the positions): each sphere added near an
  /// end of a periodic box is also added one period on, so that hits() sees the nearest images,
  /// and a body's centre must lie in the box (centreInBox()).
  void setPeriodic(const PeriodicParams& p, const LocalFrame& frame);
  bool centreInBox(Vec3f x) const;
  void add(Vec3f x, float r);
  /// Whether a sphere at x of radius r (at most half a cell) would overlap one placed, or come
  /// closer to it than a relative margin of 1e-5 (the pipelines rebuild positions with their own
  /// rounding: a body placed exactly touching must not start overlapping).
  bool hits(Vec3f x, float r) const;

 private:
  void addOne(Vec3f x, float r);
  std::int64_t cellOf(double v) const;
  double m_cell;
  bool m_on[2] = {false, false};
  double m_lo[2] = {0, 0}, m_hi[2] = {0, 0};
  std::vector<Vec3f> m_x;
  std::vector<float> m_r;
  std::vector<std::uint32_t> m_big;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> m_cells;
};

/// The scene's mesh walls as what placed bodies keep clear of, in frame f (their kernels' data,
/// kernelMesh(); none when the scene has no mesh), where they were given or, posed(), where
/// they are at a time.
class MeshObstacles {
 public:
  MeshObstacles(const Scene& scene, const LocalFrame& f);
  /// The same meshes where `poses` put them (one per plane, setWallMotion(): a [[pour]]'s batch
  /// at its time); empty: where they were given (a [[fill]], at t = 0). Shares the mesh data.
  MeshObstacles posed(const std::vector<MeshPose>& poses) const;
  /// Whether a sphere at x of radius r meets no mesh triangle (grown by a relative margin of
  /// 1e-5, as SphereHash::hits()).
  bool clear(Vec3f x, float r) const;
  /// Whether x lies inside the closed mesh wall `wall` (an index of Scene::walls;
  /// pointInsideMesh() at x in its frame).
  bool inside(std::size_t wall, Vec3f x) const;
  /// Where a point y of mesh wall `wall` as given is now (its pose; y itself while unposed).
  Vec3f placed(std::size_t wall, Vec3f y) const;

 private:
  const Scene& m_scene;
  std::shared_ptr<const KernelMesh> m_mesh;
  std::vector<MeshPose> m_poses;
};

/// A region with its axis (a cylinder: unit axis a, length, two unit directions across it), or
/// the bounding box of a mesh wall (a mesh region), in frame f.
struct RegionFrame {
  FillRegion region;
  double a[3] = {0, 0, 1}, e1[3] = {1, 0, 0}, e2[3] = {0, 1, 0}, length = 0.0;
  const MeshObstacles* meshes = nullptr;  ///< a mesh region: its inside
  RegionFrame(const FillRegion& g, const Scene& scene, const LocalFrame& f, const MeshObstacles& meshes);
  /// Whether a sphere at x of radius r lies wholly inside the region (a mesh region: its centre
  /// inside the mesh; MeshObstacles::clear() keeps it off the triangles).
  bool inside(Vec3f x, float r) const;
  /// A point of the region from three uniforms in [0, 1): a box's (a mesh's box's) uniform in
  /// it, a cylinder's uniform in its volume (s = L u1, ρ = R √u2, φ = 2π u3).
  Vec3f point(float u1, float u2, float u3) const;
};

/// Draws up to `attempts` positions for a body of spheres `balls` with orientation q in the
/// region (rng: three uniforms each) until every sphere is inside it, clear of the hash and
/// out of contact with every wall and mesh; then registers its spheres in the hash and returns
/// true with *position set. `drawOrientation`: each attempt also draws three uniforms and, when
/// `randomOrientation`, turns *q to randomRotation() of them.
bool placeBody(Rng& rng, const RegionFrame& g, const std::vector<Ball>& balls, SphereHash& hash,
               const std::vector<Wall>& walls, const MeshObstacles& meshes, std::uint64_t attempts,
               bool drawOrientation, bool randomOrientation, Vec3f* position, Quatf* q);

/// A body's shape drawn with the odds of `weights` (one uniform), scaled by a factor drawn from
/// `size` (one more uniform when it varies): the index of the scaled shape in
/// scene.shapes, appended the first time (`scaled` remembers them; named "name x factor";
/// offsets and radii times the factor, masses times its cube). Throws tumble::Error naming
/// `where` when the scaled shape is beyond single precision.
std::uint32_t drawShape(Scene& scene, Rng& rng, const std::vector<std::uint32_t>& shapes,
                        const std::vector<double>& weights, const SizeDistribution& size,
                        std::map<std::pair<std::uint32_t, float>, std::uint32_t>& scaled, const std::string& where);

/// A body's velocity (`velocity` plus a uniform jitter per component, three uniforms) and spin
/// (`spin` about a random axis, two uniforms, taken whether or not spin is 0).
void drawMotion(Rng& rng, Vec3f velocity, float jitter, float spin, BodyDef* b);

}  // namespace tumble::detail
