// SPDX-License-Identifier: MIT
/// @file mesh.hpp
/// Triangle-mesh walls as the kernels see them (issue 12, `[[wall]] type = "mesh"`): the point
/// of a triangle nearest a sphere centre and its feature (the face, an edge, a vertex), the rule
/// that counts a sphere once per local minimum of its distance to the mesh, and the query of the
/// static bounding-volume hierarchy that finds each particle's candidate triangles at a rebuild
/// of the candidate list. Written once for both pipelines; the host builds the data
/// (KernelMesh, tumble/mesh.hpp) and the brute-force oracle calls nearestOnTriangle() too.
///
/// Regions. A triangle splits space into the prism over its face (inside the three planes
/// through its edges, `MeshTriangle::m`) and, outside it, the regions of its edges and
/// vertices. Two neighbours must split the space around the edge they share consistently: each
/// evaluates the same arithmetic for it, from the edge's canonical vertex order (the lower
/// vertex index first): the position along the edge α = (x − a)·(b − a) and, for the side, the
/// distance (x − a)·m from the plane through the edge. Where the two triangles are flat or
/// nearly so (their planes within kFlatEdgeAngle), that plane is one plane shared by both, its
/// normal m for one and exactly −m for the other, so that the side test of one is the exact
/// negation of the other's and a point on the plane (a distance of ±0) is outside for both: it
/// belongs to the edge, never to both faces. Elsewhere each triangle's plane is its own (the
/// plane through the edge perpendicular to its face).
///
/// Moving meshes. A mesh's data stays in its own frame (where it was given); a mesh wall that
/// has moved (MeshPose::posed) meets a sphere through its centre taken into that frame,
/// toMeshFrame(), with the pose of the step's start; the nearest point, the feature and the
/// counting rule are evaluated there, and the contact's normal is turned back (the caller).
///
/// Counting. A sphere counts once per local minimum of the distance from its centre to the
/// mesh: a face contact counts when the centre lies in the face's prism; a contact on an edge
/// or a vertex counts only when every triangle incident to that feature also has its nearest
/// point there, and then only for the lowest of them (meshContactCounts()). So a sphere on a
/// convex ridge meets it once (on the edge), a sphere in a concave corner meets both faces, and
/// a sphere above a shared edge or vertex of a flat mesh meets it once.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// The largest angle between the planes of two triangles at an edge that is still flat: their
/// side planes are then one shared plane (see above). Within this angle a face contact may lie
/// beyond its face by h tan(θ/2) (h the distance), which changes the distance by less than
/// h θ² / 8, 1.25e-7 h: within the candidate list's rounding margin.
inline constexpr double kFlatEdgeAngle = 1.0e-3;

/// The feature of a triangle nearest a point.
enum MeshFeature : std::uint32_t { kMeshFace = 0, kMeshEdge = 1, kMeshVertex = 2 };

/// The nearest point of a triangle: its distance from x, the unit normal from it to x (the
/// face's normal, on the side of x, for a face point; the face's normal when x lies on the
/// triangle), and its feature with the feature's global index (edge or vertex id; the triangle
/// for a face).
struct TrianglePoint {
  float dist;
  Vec3f n;
  std::uint32_t feature;
  std::uint32_t index;
};

/// The point of triangle t nearest x (see the file's notes on the regions). Inside the three
/// edge planes: the face, at the distance |(x − v0)·n|. Otherwise the nearest of the nearest
/// points of the edges x lies outside of (each a vertex when α ≤ 0 or α ≥ |b − a|², else the
/// foot on the edge), the first edge on a tie; a vertex computed from either of its edges has
/// the same bits (x − v of the same floats).
TUMBLE_HD_INLINE TrianglePoint nearestOnTriangle(const MeshView& m, std::uint32_t t, Vec3f x) {
  const MeshTriangle& tr = m.tri[t];
  const std::uint32_t* c = m.triangles + 3 * std::size_t(t);
  float d[3];
  bool inside = true;
  for (int j = 0; j < 3; ++j) {
    const std::uint32_t p = c[j], q = c[j == 2 ? 0 : j + 1];
    const Vec3f a = m.vertices[p < q ? p : q];
    d[j] = dot(x - a, tr.m[j]);
    inside = inside && d[j] < 0.0f;
  }
  TrianglePoint out{0.0f, tr.n, kMeshFace, t};
  if (inside) {
    const float h = dot(x - m.vertices[c[0]], tr.n);
    out.dist = h < 0.0f ? -h : h;
    if (h < 0.0f) out.n = -tr.n;
    return out;
  }
  // Infinite until an edge gives a finite squared distance: one that overflows (a point more
  // than 1.8e19 m away), or a NaN, leaves the distance infinite, never a contact.
  float best = INFINITY;
  Vec3f diff{0.0f, 0.0f, 0.0f};
  for (int j = 0; j < 3; ++j) {
    if (d[j] < 0.0f) continue;  // inside this edge's plane (a NaN counts as outside)
    const std::uint32_t p = c[j], q = c[j == 2 ? 0 : j + 1];
    const std::uint32_t ia = p < q ? p : q, ib = p < q ? q : p;
    const Vec3f a = m.vertices[ia], b = m.vertices[ib];
    const Vec3f pa = x - a, e = b - a;
    const float along = dot(pa, e), len2 = dot(e, e);
    Vec3f r;
    std::uint32_t feature, index;
    if (along <= 0.0f) {
      r = pa;
      feature = kMeshVertex;
      index = ia;
    } else if (along >= len2) {
      r = x - b;
      feature = kMeshVertex;
      index = ib;
    } else {
      r = pa - (along / len2) * e;
      feature = kMeshEdge;
      index = m.triEdges[3 * std::size_t(t) + j];
    }
    const float r2 = dot(r, r);
    if (r2 < best) {
      best = r2;
      diff = r;
      out.feature = feature;
      out.index = index;
    }
  }
  out.dist = std::sqrt(best);
  // Divided per component: a point straight above a vertex or an edge of an aligned mesh gets
  // the axis itself, as a plane there would.
  if (out.dist > 0.0f && best < INFINITY) out.n = Vec3f{diff.x / out.dist, diff.y / out.dist, diff.z / out.dist};
  return out;
}

/// Whether triangle t reports its nearest point p to x as a contact (the counting rule of the
/// file's notes): always for a face point; for an edge or vertex point only when t is the
/// lowest triangle incident to that feature and every other incident triangle has its nearest
/// point on the same feature.
TUMBLE_HD_INLINE bool meshContactCounts(const MeshView& m, std::uint32_t t, const TrianglePoint& p, Vec3f x) {
  if (p.feature == kMeshFace) return true;
  const bool edge = p.feature == kMeshEdge;
  const std::uint32_t* offsets = edge ? m.edgeTriOffsets : m.vertexTriOffsets;
  const std::uint32_t* tris = edge ? m.edgeTris : m.vertexTris;
  const std::uint32_t begin = offsets[p.index], end = offsets[p.index + 1];
  if (tris[begin] != t) return false;  // the lowest incident triangle decides
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    const TrianglePoint o = nearestOnTriangle(m, tris[k], x);
    if (o.feature != p.feature || o.index != p.index) return false;
  }
  return true;
}

/// A sphere (centre x, radius r) and triangle t: its nearest point, and whether that is a
/// contact the sphere counts (in contact, dist < r as for two spheres, and counted by
/// meshContactCounts()).
struct MeshHit {
  TrianglePoint p;
  bool counts;
};
TUMBLE_HD_INLINE MeshHit meshHit(const MeshView& m, std::uint32_t t, Vec3f x, float r) {
  MeshHit h{nearestOnTriangle(m, t, x), false};
  h.counts = r - h.p.dist > 0.0f && meshContactCounts(m, t, h.p, x);
  return h;
}

/// Whether the box [lo, hi] comes within `reach` of x on every axis (lo − x ≤ reach and
/// x − hi ≤ reach): the candidate test, the same expression for a node and for a triangle, so
/// that a triangle that passes is never below a node that fails (min and max are exact).
TUMBLE_HD_INLINE bool boxWithin(Vec3f lo, Vec3f hi, Vec3f x, float reach) {
  return lo.x - x.x <= reach && x.x - hi.x <= reach && lo.y - x.y <= reach && x.y - hi.y <= reach &&
         lo.z - x.z <= reach && x.z - hi.z <= reach;
}

/// A point x (the frame the pipeline integrates in) in the frame of a posed mesh:
/// pivot + rotᵀ (x − centre), one fixed sequence of float operations.
TUMBLE_HD_INLINE Vec3f toMeshFrame(const MeshPose& p, Vec3f x) { return mulTransposed(p.rot, x - p.centre) + p.pivot; }

/// A point x as the mesh of wall k (a plane index) sees it: toMeshFrame() when that mesh is
/// posed, x itself while it is where it was given or when no mesh moves (m.poses null).
TUMBLE_HD_INLINE Vec3f meshPoint(const MeshView& m, std::uint32_t k, Vec3f x) {
  if (m.poses == nullptr || m.poses[k].posed == 0u) return x;
  return toMeshFrame(m.poses[k], x);
}

/// The deepest hierarchy KernelMesh builds (its stack in forTrianglesNear()).
inline constexpr int kMeshBvhMaxDepth = 60;

/// Calls f(t) for every triangle t whose (grown) box comes within `reach` of x
/// (boxWithin()): a set that depends on the triangles alone, not on the hierarchy, in the
/// hierarchy's order. A stack of node indices, no recursion (device code).
template <class F>
TUMBLE_HD_INLINE void forTrianglesNear(const MeshView& m, Vec3f x, float reach, F&& f) {
  if (m.numTriangles == 0) return;
  std::uint32_t stack[kMeshBvhMaxDepth + 2];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const MeshBvhNode& node = m.nodes[stack[--top]];
    if (!boxWithin(node.lo, node.hi, x, reach)) continue;
    if (node.count == 0) {
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
      continue;
    }
    for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
      const std::uint32_t t = m.prims[k];
      if (boxWithin(m.tri[t].lo, m.tri[t].hi, x, reach)) f(t);
    }
  }
}

/// forTrianglesNear() of a sphere centre x with the meshes posed (m.poses): each triangle is
/// tested against x as its wall sees it (meshPoint()). The walls where they were given share
/// one query at x; each posed wall has its own at x in its frame, for its triangles only. Each
/// triangle is reported at most once; the order is not that of the triangles (callers sort).
template <class F>
TUMBLE_HD_INLINE void forPosedTrianglesNear(const MeshView& m, Vec3f x, float reach, F&& f) {
  forTrianglesNear(m, x, reach, [&](std::uint32_t t) {
    if (m.poses[m.tri[t].wall].posed == 0u) f(t);
  });
  for (std::uint32_t k = 0; k < m.numPoses; ++k) {
    if (m.poses[k].posed == 0u) continue;
    forTrianglesNear(m, toMeshFrame(m.poses[k], x), reach, [&](std::uint32_t t) {
      if (m.tri[t].wall == k) f(t);
    });
  }
}

/// Particle i's row of the mesh candidate list at a rebuild (its position p there): f(t) for
/// every triangle within p.r + grow (forTrianglesNear(); kPosed: some mesh moves, each where
/// the view's poses put it, forPosedTrianglesNear()). Both pipelines' count → scan → fill; the
/// fill sorts the row by triangle (detail::sortRow), so that it does not depend on the hierarchy.
template <bool kPosed, class F>
TUMBLE_HD_INLINE void forMeshRow(const MeshView& m, const PosRow& p, float grow, F&& f) {
  const Vec3f x{p.x, p.y, p.z};
  if constexpr (kPosed)
    forPosedTrianglesNear(m, x, p.r + grow, f);
  else
    forTrianglesNear(m, x, p.r + grow, f);
}

/// The triangles of particle i's mesh row (offsets, tri: the mesh candidate list) that its
/// sphere at p meets (meshHit().counts), f(t) in row order: Pipeline::meshContacts().
template <class F>
TUMBLE_HD_INLINE void forMeshHits(const MeshView& m, const std::uint32_t* offsets, const std::uint32_t* tri,
                                  const PosRow& p, std::uint32_t i, F&& f) {
  const Vec3f x{p.x, p.y, p.z};
  for (std::uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
    const std::uint32_t t = tri[e];
    if (meshHit(m, t, meshPoint(m, m.tri[t].wall, x), p.r).counts) f(t);
  }
}

}  // namespace tumble
