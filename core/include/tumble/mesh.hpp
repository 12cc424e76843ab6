// SPDX-License-Identifier: MIT
/// @file mesh.hpp
/// Triangle-mesh walls on the host (issue 12, `[[wall]] type = "mesh"`, docs/scenes.md): the
/// reader of STL (binary and ASCII) and OBJ files, the kernels' data of a scene's meshes in the
/// frame a pipeline integrates in (KernelMesh: vertices, triangle planes, adjacency, a bounding
/// volume hierarchy; kernels/mesh.hpp reads it), the mesh contacts of a set of spheres, the
/// triangles of a mesh wall in world coordinates (for drawing), and whether a point lies inside
/// a closed mesh.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "tumble/kernels/mesh.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// A triangle mesh as its file gives it: the vertices welded (corners with bit-identical
/// coordinates, −0 and +0 alike, are one vertex: STL repeats them per facet), three vertex
/// indices per triangle, and where each triangle was written (its line, or its byte offset in a
/// binary STL) for messages.
struct TriangleMesh {
  std::string file;                     ///< the path (or name) it was read from
  std::vector<Vec3f> vertices;          ///< file coordinates
  std::vector<std::uint32_t> triangles; ///< 3 per triangle, in the file's order
  std::vector<std::uint64_t> source;    ///< per triangle: its line (ASCII STL: its `facet` line; OBJ: its `f` line), or its byte offset (binary STL)
  bool binary = false;                  ///< `source` holds byte offsets
  std::size_t numTriangles() const { return triangles.size() / 3; }
  /// "FILE:LINE" or "FILE: byte OFFSET" of triangle t (0-based; messages count from 1).
  std::string where(std::size_t t) const;
};

/// Reads a mesh file: binary or ASCII STL (`.stl`, told apart by their content: a file whose
/// size is that of a binary STL of the triangle count at byte 80 is binary, else one that
/// starts with `solid` is ASCII) or OBJ (`.obj`: `v` and `f` lines, polygons fanned into
/// triangles, negative indices relative to the vertices so far, `v/vt/vn` forms; other
/// statements ignored). Throws tumble::InputError naming the file and the line (text) or the
/// byte offset (binary STL), what is wrong and what to do, for an unreadable file, a truncated
/// binary STL, a coordinate that is not finite or beyond single precision, an index out of
/// range, a degenerate triangle (a repeated vertex or zero area), or no triangles.
TriangleMesh readMeshFile(const std::string& path);

/// The same on bytes in memory; `name` gives the format (its extension) and names the file in
/// messages.
TriangleMesh parseMesh(std::string_view bytes, const std::string& name);

/// A mesh wall's vertices in frame f (world coordinates for an inactive frame): position +
/// R(orientation) (scale ⊙ v) − origin, in double, rounded to float. Throws tumble::Error when
/// one leaves single precision.
std::vector<Vec3f> meshWallVertices(const WallDef& wall, const LocalFrame& f = {});

/// A mesh wall's triangles in world coordinates, three corners per triangle in the file's
/// order (what the viewer and `tumble render` draw).
std::vector<Vec3f> meshWallTriangles(const WallDef& wall);

/// The number of triangles of a scene's mesh walls (their global numbering: wall by wall in
/// the scene's order, each in its file's order).
std::uint32_t meshTriangleCount(const Scene& scene);

/// Triangle t of a scene's mesh walls (meshTriangleCount()'s numbering) for messages: its
/// wall, and its number and line in its file ("[[wall]] #2 (scene.toml:14), triangle 7 of
/// hopper.stl (hopper.stl:44)").
std::string meshTriangleWhere(const Scene& scene, std::uint32_t t);

/// What the kernels read of every mesh wall of a scene (MeshView), in frame f, with one
/// numbering of vertices, edges and triangles (meshTriangleCount()). Built on the host at load:
/// the triangles' normals and edge planes (shared by the two triangles of a flat edge,
/// kernels/mesh.hpp), their boxes grown by a bound on the kernels' rounding (64 u × the box's
/// diagonal), the edges and vertices with their incident triangles, and a bounding volume
/// hierarchy (median splits of the triangles' centres along the longest axis, 4 per leaf).
/// Empty for a scene without meshes.
struct KernelMesh {
  std::vector<Vec3f> vertices;
  std::vector<std::uint32_t> triangles;
  std::vector<MeshTriangle> tri;
  std::vector<std::uint32_t> triEdges, edgeTriOffsets, edgeTris, vertexTriOffsets, vertexTris;
  std::vector<MeshBvhNode> nodes;
  std::vector<std::uint32_t> prims;
  std::uint32_t numTriangles() const { return static_cast<std::uint32_t>(tri.size()); }
  MeshView view() const;
  /// The view with the meshes posed (MeshView::poses; one pose per plane, setWallMotion());
  /// empty `poses`: every mesh where it was given, view().
  MeshView view(const std::vector<MeshPose>& poses) const;
};

/// The MeshView of a mesh's arrays wherever they live: m has the members of KernelMesh (on the
/// host) or the same names in device buffers (the CUDA pipeline's), each with data(), and
/// numTriangles(). No triangles: an empty view.
template <class M>
MeshView meshViewOf(const M& m) {
  MeshView v;
  if (m.numTriangles() == 0) return v;
  v.vertices = m.vertices.data();
  v.triangles = m.triangles.data();
  v.tri = m.tri.data();
  v.triEdges = m.triEdges.data();
  v.edgeTriOffsets = m.edgeTriOffsets.data();
  v.edgeTris = m.edgeTris.data();
  v.vertexTriOffsets = m.vertexTriOffsets.data();
  v.vertexTris = m.vertexTris.data();
  v.nodes = m.nodes.data();
  v.prims = m.prims.data();
  v.numTriangles = m.numTriangles();
  return v;
}

/// The thinnest triangle a mesh may have: its smallest height over its longest edge. Thinner,
/// the orientation of its edges' planes (computed in double at load) and the kernels' tests (in
/// float) cannot tell it from a line.
inline constexpr double kThinnestTriangle = 0x1p-30;

/// Why the triangle of corners p, q, r (floats, as the kernels see them) cannot be a mesh
/// wall's, as a phrase ("its corners 1 and 2 are the same point (…)"): two corners equal, an
/// edge whose squared length is 0 in single precision, no area, or thinner than
/// kThinnestTriangle (in double); empty when it can. The reader refuses such a triangle in the
/// file, the scene reader and kernelMesh() once it is scaled and placed.
std::string degenerateTriangle(Vec3f p, Vec3f q, Vec3f r);

/// Builds the KernelMesh of a scene's mesh walls in frame f. Throws tumble::Error naming the
/// wall and the triangle (its file and line) when a triangle is degenerate in single precision
/// there (a scale that shrinks it to nothing, coordinates too large for its size).
KernelMesh kernelMesh(const Scene& scene, const LocalFrame& f);

/// The mesh contacts of spheres at positions x (3 floats per particle, in the frame of `mesh`)
/// with radii r: every (particle, triangle) that meshHit() counts, sorted; found through the
/// hierarchy (the guard's, before a pipeline has stepped). With `poses` (one per plane,
/// setWallMotion()) each mesh wall is where its pose puts it (meshPoint()); empty: where given.
std::vector<MeshContact> findMeshContacts(const KernelMesh& mesh, const std::vector<float>& x,
                                          const std::vector<float>& radius, const std::vector<MeshPose>& poses = {});

/// The skin test's bound on the motion of the moving mesh walls (docs/model.md#mesh-walls).
/// A particle's candidate triangles are found at a rebuild within r + skin/2 + margin of its
/// centre in the mesh's frame; since then the centre, seen from the mesh, has moved by its own
/// displacement plus the mesh's: at most |v| Δτ + |ω| Δτ (D + r_max) for a sphere touching
/// the mesh (D the largest distance of a vertex from the pivot; a chord of the turn is shorter
/// than its arc), plus the rounding of the two transforms into the mesh's frame, 16 u (D +
/// 2 (r_max + skin) + |pivot| + |v| τ) each (u = 2⁻²⁴). closure() is twice the largest of these
/// over the moving mesh walls, added to the particles' closure (2 max |Δx|, wallClosureOf()):
/// the list is kept while max |Δx| + the mesh's motion stays below skin/2 − margin. A function of
/// the two times only (a max over the walls): the same decision for any thread count.
class MeshMotionBound {
 public:
  MeshMotionBound() = default;
  /// The moving mesh walls of `scene` (their triangles in `mesh`, their pivots in `planes`,
  /// kernelWalls() in the same frame), for spheres of radius up to maxRadius and the skin.
  MeshMotionBound(const Scene& scene, const KernelMesh& mesh, const std::vector<Wall>& planes, float maxRadius,
                  float skin);
  /// Some mesh wall moves.
  bool any() const { return !m_walls.empty(); }
  /// Twice the largest motion of a moving mesh relative to a sphere near it between a rebuild
  /// at t0 and a step at t1 [m]; 0 while every mesh stays where it was given at both.
  double closure(double t0, double t1) const;

 private:
  struct Moving {
    WallDef def;         // its motion (wallMotionTime())
    double speed, rate;  // |v|, |ω|
    double reach;        // D + r_max
    double rounding;     // 16 u (D + 2 (r_max + skin) + |pivot|), to which 16 u |v| τ is added
  };
  std::vector<Moving> m_walls;
};

/// Whether p lies inside the closed surface of mesh wall `wall` (index into the scene's walls;
/// its triangles in `mesh`): the parity of the crossings of a ray from p with its triangles,
/// in double, through the hierarchy; a ray that meets an edge or a vertex within rounding is
/// cast again in another fixed direction. For a mesh that is not closed the answer is that of
/// its parity. p in the mesh's frame.
bool pointInsideMesh(const KernelMesh& mesh, const Scene& scene, std::size_t wall, Vec3f p);

}  // namespace tumble
