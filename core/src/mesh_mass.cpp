// SPDX-License-Identifier: MIT
// The solid a closed triangle mesh bounds: its checks and its mass properties
// (tumble/mesh_mass.hpp).
#include "tumble/mesh_mass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "tumble/error.hpp"

namespace tumble {
namespace {

/// One triangle's use of an edge: the edge's vertices (lower index first), whether the
/// triangle runs it from the lower to the higher, and the triangle.
struct EdgeUse {
  std::uint64_t key;
  bool forward;
  std::uint32_t triangle;
};

/// Throws at the first triangle (in file order) of an edge that does not bound a solid.
void checkClosed(const TriangleMesh& mesh) {
  const std::size_t n = mesh.numTriangles();
  std::vector<EdgeUse> uses;
  uses.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[3 * t + k], b = mesh.triangles[3 * t + (k + 1) % 3];
      uses.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), a < b, std::uint32_t(t)});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& p, const EdgeUse& q) {
    return p.key != q.key ? p.key < q.key : p.triangle < q.triangle;
  });
  std::size_t worst = n;  // the first triangle of a bad edge
  std::string why;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const std::size_t count = j - i;
    const char* problem = count == 1   ? "is open: it borders one triangle, a closed surface has two on every edge"
                          : count > 2  ? "is not manifold: it borders three or more triangles"
                          : uses[i].forward == uses[i + 1].forward
                              ? "is run the same way by both its triangles: their orientations disagree (one is turned "
                                "inside out)"
                              : nullptr;
    if (problem != nullptr && uses[i].triangle < worst) {
      worst = uses[i].triangle;
      const Vec3f a = mesh.vertices[uses[i].key >> 32], b = mesh.vertices[uses[i].key & 0xffffffffu];
      char edge[160];
      std::snprintf(edge, sizeof edge, "its edge from (%.9g, %.9g, %.9g) to (%.9g, %.9g, %.9g) ", double(a.x),
                    double(a.y), double(a.z), double(b.x), double(b.y), double(b.z));
      why = edge + std::string(problem);
      if (count > 1) {  // the other triangles on it
        why += " (with triangle";
        for (std::size_t k = i + 1; k < j && k < i + 4; ++k)
          why += (k > i + 1 ? ", " : " ") + std::to_string(uses[k].triangle + 1) + " at " + mesh.where(uses[k].triangle);
        why += j > i + 4 ? ", ...)" : ")";
      }
    }
    i = j;
  }
  if (worst < n)
    throw InputError(mesh.file, mesh.binary ? 0L : static_cast<long>(mesh.source[worst]),
                     (mesh.binary ? "byte " + std::to_string(mesh.source[worst]) + ": " : std::string()) + "triangle " +
                         std::to_string(worst + 1) + ": " + why +
                         "; a shape needs a closed mesh (a watertight solid: repair it, e.g. in MeshLab or Blender's "
                         "3D-Print toolbox)");
}

using D3 = std::array<double, 3>;
D3 corner(const TriangleMesh& mesh, std::size_t t, int k) {
  const Vec3f v = mesh.vertices[mesh.triangles[3 * t + std::size_t(k)]];
  return {double(v.x), double(v.y), double(v.z)};
}
D3 sub3(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
D3 cross3(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Where triangle p, at signed distances s from the other triangle's plane, meets that plane:
// the segment's ends projected on the line direction d, [*lo, *hi]; false when it does not cross
// it (all on one side) or only touches it at a point.
bool planeCrossing(const D3 p[3], const double s[3], const D3& d, double* lo, double* hi) {
  double t[6];
  int m = 0;
  for (int k = 0; k < 3; ++k) {
    const int l = (k + 1) % 3;
    if (s[k] == 0.0) t[m++] = dot3(p[k], d);
    if ((s[k] < 0.0 && s[l] > 0.0) || (s[k] > 0.0 && s[l] < 0.0)) {
      const double f = s[k] / (s[k] - s[l]);
      const D3 x = {p[k][0] + f * (p[l][0] - p[k][0]), p[k][1] + f * (p[l][1] - p[k][1]), p[k][2] + f * (p[l][2] - p[k][2])};
      t[m++] = dot3(x, d);
    }
  }
  if (m < 2) return false;
  *lo = *std::min_element(t, t + m);
  *hi = *std::max_element(t, t + m);
  return *hi > *lo;
}

// Whether triangles a and b (sharing no vertex) cross: each has corners strictly on both sides of
// the other's plane, and the segments where they meet the other's plane overlap on the planes'
// common line by more than a rounding (Möller, "A Fast Triangle-Triangle Intersection Test",
// 1997). Triangles that only touch (a corner or an edge in the other's plane, one side
// otherwise), or lie in one plane, are not counted: two solids resting on each other are one.
bool trianglesCross(const D3 a[3], const D3 b[3]) {
  const D3 na = cross3(sub3(a[1], a[0]), sub3(a[2], a[0])), nb = cross3(sub3(b[1], b[0]), sub3(b[2], b[0]));
  double sa[3], sb[3];
  for (int k = 0; k < 3; ++k) sa[k] = dot3(nb, sub3(a[k], b[0])), sb[k] = dot3(na, sub3(b[k], a[0]));
  const auto straddles = [](const double s[3]) {
    return (s[0] > 0.0 || s[1] > 0.0 || s[2] > 0.0) && (s[0] < 0.0 || s[1] < 0.0 || s[2] < 0.0);
  };
  if (!straddles(sa) || !straddles(sb)) return false;
  const D3 d = cross3(na, nb);
  const double dd = dot3(d, d);
  if (!(dd > 0.0)) return false;  // parallel planes: coplanar or apart
  double loA, hiA, loB, hiB;
  if (!planeCrossing(a, sa, d, &loA, &hiA) || !planeCrossing(b, sb, d, &loB, &hiB)) return false;
  const double size = std::max({std::fabs(loA), std::fabs(hiA), std::fabs(loB), std::fabs(hiB)});
  return std::min(hiA, hiB) - std::max(loA, loB) > 1e-9 * size;
}

/// Throws at the first pair of triangles (in the file's order) that cross each other: a surface
/// that passes through itself counts the overlap twice. Pairs that share a vertex are not tested
/// (a fold at a vertex goes unseen). Candidates by a sweep over the triangles' boxes along the
/// axis where they are thinnest for the mesh's size (a cylinder's side along its axis would pair
/// every triangle with every other along that axis).
void checkNoSelfIntersection(const TriangleMesh& mesh) {
  const std::size_t n = mesh.numTriangles();
  struct Box {
    double lo[3], hi[3];
    std::uint32_t t;
  };
  std::vector<Box> boxes(n);
  for (std::size_t t = 0; t < n; ++t) {
    Box& b = boxes[t];
    b.t = std::uint32_t(t);
    for (int a = 0; a < 3; ++a) b.lo[a] = INFINITY, b.hi[a] = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      const D3 p = corner(mesh, t, k);
      for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], p[a]), b.hi[a] = std::max(b.hi[a], p[a]);
    }
  }
  // The sweep's axis: the one along which the fewest pairs of boxes overlap (counted by a binary
  // search per box in the boxes sorted along it).
  int axis = 0;
  std::uint64_t fewest = ~std::uint64_t{0};
  for (int a = 0; a < 3; ++a) {
    std::vector<double> lo(n);
    for (std::size_t t = 0; t < n; ++t) lo[t] = boxes[t].lo[a];
    std::sort(lo.begin(), lo.end());
    std::uint64_t pairs = 0;
    for (std::size_t t = 0; t < n; ++t)
      pairs += std::uint64_t(std::upper_bound(lo.begin(), lo.end(), boxes[t].hi[a]) -
                             std::lower_bound(lo.begin(), lo.end(), boxes[t].lo[a]));
    if (pairs < fewest) fewest = pairs, axis = a;
  }
  const int u1 = (axis + 1) % 3, u2 = (axis + 2) % 3;
  std::sort(boxes.begin(), boxes.end(),
            [axis](const Box& p, const Box& q) { return p.lo[axis] != q.lo[axis] ? p.lo[axis] < q.lo[axis] : p.t < q.t; });
  std::size_t first = n, second = n;  // the first crossing pair, in file order
  for (std::size_t i = 0; i < n; ++i) {
    const Box& p = boxes[i];
    for (std::size_t j = i + 1; j < n && boxes[j].lo[axis] <= p.hi[axis]; ++j) {
      const Box& q = boxes[j];
      if (q.lo[u1] > p.hi[u1] || q.hi[u1] < p.lo[u1] || q.lo[u2] > p.hi[u2] || q.hi[u2] < p.lo[u2]) continue;
      const std::size_t s = std::min(p.t, q.t), u = std::max(p.t, q.t);
      if (s > first || (s == first && u >= second)) continue;  // not before the one found
      bool shared = false;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) shared |= mesh.triangles[3 * s + std::size_t(k)] == mesh.triangles[3 * u + std::size_t(l)];
      if (shared) continue;
      const D3 a[3] = {corner(mesh, s, 0), corner(mesh, s, 1), corner(mesh, s, 2)};
      const D3 b[3] = {corner(mesh, u, 0), corner(mesh, u, 1), corner(mesh, u, 2)};
      if (trianglesCross(a, b)) first = s, second = u;
    }
  }
  if (first < n)
    throw InputError(mesh.file, mesh.binary ? 0L : static_cast<long>(mesh.source[first]),
                     (mesh.binary ? "byte " + std::to_string(mesh.source[first]) + ": " : std::string()) + "triangle " +
                         std::to_string(first + 1) + " crosses triangle " + std::to_string(second + 1) + " at " +
                         mesh.where(second) +
                         ": the surface passes through itself, so the solid's integrals would count the overlap "
                         "twice; a shape needs a mesh that bounds one solid (repair it, e.g. MeshLab's \"Remove "
                         "self-intersecting faces\" or Blender's 3D-Print toolbox)");
}

/// The connected pieces of a closed mesh (triangles joined by their edges): each triangle's piece,
/// numbered in the order of their first triangles.
std::vector<std::uint32_t> pieces(const TriangleMesh& mesh) {
  const std::size_t n = mesh.numTriangles();
  std::vector<std::uint32_t> parent(n);
  for (std::size_t t = 0; t < n; ++t) parent[t] = std::uint32_t(t);
  const auto find = [&](std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  edges.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[3 * t + std::size_t(k)], b = mesh.triangles[3 * t + std::size_t(k + 1) % 3];
      edges.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), std::uint32_t(t)});
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 1; i < edges.size(); ++i)
    if (edges[i].first == edges[i - 1].first) {
      const std::uint32_t x = find(edges[i].second), y = find(edges[i - 1].second);
      parent[std::max(x, y)] = std::min(x, y);  // the lowest triangle is the root
    }
  std::vector<std::uint32_t> piece(n), number(n, ~0u);
  std::uint32_t next = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint32_t r = find(std::uint32_t(t));
    if (number[r] == ~0u) number[r] = next++;
    piece[t] = number[r];
  }
  return piece;
}

/// Whether point p lies inside the triangles `tris` of one piece (the parity of the crossings of
/// a ray from p in a direction no mesh of round coordinates lines up with).
bool insidePiece(const TriangleMesh& mesh, const std::vector<std::uint32_t>& tris, const D3& p) {
  const D3 dir = {0.5773502691896258, 0.5773502691896257 * 1.0000001234567, 0.5773502691896256 * 0.99999987654321};
  bool inside = false;
  for (const std::uint32_t t : tris) {
    const D3 a = corner(mesh, t, 0), e1 = sub3(corner(mesh, t, 1), a), e2 = sub3(corner(mesh, t, 2), a);
    const D3 h = cross3(dir, e2);
    const double det = dot3(e1, h);
    if (det == 0.0) continue;
    const D3 s = sub3(p, a);
    const double u = dot3(s, h) / det;
    if (u < 0.0 || u > 1.0) continue;
    const D3 q = cross3(s, e1);
    const double v = dot3(dir, q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    if (dot3(e2, q) / det > 0.0) inside = !inside;
  }
  return inside;
}

/// Eberly's subexpressions of one coordinate over a triangle's three corners.
struct Sub {
  double f1, f2, f3, g0, g1, g2;
};
Sub subexpressions(double w0, double w1, double w2) {
  const double t0 = w0 + w1, f1 = t0 + w2, t1 = w0 * w0, t2 = t1 + w1 * t0;
  const double f2 = t2 + w2 * f1, f3 = w0 * t1 + w1 * t2 + w2 * f2;
  return {f1, f2, f3, f2 + w0 * (f1 + w0), f2 + w1 * (f1 + w1), f2 + w2 * (f1 + w2)};
}

}  // namespace

SolidProperties solidProperties(const TriangleMesh& mesh, std::array<double, 3> scale) {
  checkClosed(mesh);
  checkNoSelfIntersection(mesh);
  const std::vector<std::uint32_t> piece = pieces(mesh);
  const std::uint32_t numPieces = piece.empty() ? 0u : *std::max_element(piece.begin(), piece.end()) + 1;
  std::vector<double> pieceVolume(numPieces, 0.0);  // 6 × each piece's signed volume
  // The integrals of 1, x, y, z, x², y², z², xy, yz, zx over the solid (times 6, 24, 60, 120).
  // About the first vertex (a point of the solid): about the origin, a solid far from it loses
  // its inertia to cancellation (1e5 m out, a 1-m ellipsoid's came out negative).
  double in[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  const Vec3f o = mesh.vertices[mesh.triangles[0]];
  const double ref[3] = {double(o.x) * scale[0], double(o.y) * scale[1], double(o.z) * scale[2]};
  for (std::size_t t = 0; t < mesh.numTriangles(); ++t) {
    double p[3][3];
    for (int k = 0; k < 3; ++k) {
      const Vec3f v = mesh.vertices[mesh.triangles[3 * t + k]];
      p[k][0] = double(v.x) * scale[0] - ref[0], p[k][1] = double(v.y) * scale[1] - ref[1];
      p[k][2] = double(v.z) * scale[2] - ref[2];
    }
    const double a1 = p[1][0] - p[0][0], b1 = p[1][1] - p[0][1], c1 = p[1][2] - p[0][2];
    const double a2 = p[2][0] - p[0][0], b2 = p[2][1] - p[0][1], c2 = p[2][2] - p[0][2];
    const double d0 = b1 * c2 - b2 * c1, d1 = a2 * c1 - a1 * c2, d2 = a1 * b2 - a2 * b1;
    const Sub x = subexpressions(p[0][0], p[1][0], p[2][0]);
    const Sub y = subexpressions(p[0][1], p[1][1], p[2][1]);
    const Sub z = subexpressions(p[0][2], p[1][2], p[2][2]);
    in[0] += d0 * x.f1;
    pieceVolume[piece[t]] += d0 * x.f1;
    in[1] += d0 * x.f2, in[2] += d1 * y.f2, in[3] += d2 * z.f2;
    in[4] += d0 * x.f3, in[5] += d1 * y.f3, in[6] += d2 * z.f3;
    in[7] += d0 * (p[0][1] * x.g0 + p[1][1] * x.g1 + p[2][1] * x.g2);
    in[8] += d1 * (p[0][2] * y.g0 + p[1][2] * y.g1 + p[2][2] * y.g2);
    in[9] += d2 * (p[0][0] * z.g0 + p[1][0] * z.g1 + p[2][0] * z.g2);
  }
  static constexpr double kMult[10] = {1.0 / 6,   1.0 / 24,  1.0 / 24,  1.0 / 24,  1.0 / 60,
                                       1.0 / 60,  1.0 / 60,  1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) in[i] *= kMult[i];
  const bool woundOutward = in[0] > 0.0;  // the whole, as written
  if (in[0] < 0.0)  // wound inward: every integral of the outward twin has the other sign
    for (double& v : in) v = -v;
  if (!(in[0] > 0.0))
    throw InputError(mesh.file, 0, "the closed mesh bounds no volume (its triangles enclose nothing)");
  // Pieces: each must be wound as its place says, outward (as the whole) where it lies inside an
  // even number of the others (a part of the solid), inward where an odd number (a cavity).
  if (numPieces > 1) {
    // Each piece's triangles and box; its test point the centroid of its first triangle (not a
    // corner, which may lie on a piece it touches).
    std::vector<std::vector<std::uint32_t>> tris(numPieces);
    std::vector<std::array<double, 6>> box(numPieces, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
    for (std::size_t t = 0; t < mesh.numTriangles(); ++t) {
      tris[piece[t]].push_back(std::uint32_t(t));
      for (int k = 0; k < 3; ++k) {
        const D3 p = corner(mesh, t, k);
        for (int a = 0; a < 3; ++a)
          box[piece[t]][a] = std::min(box[piece[t]][a], p[a]), box[piece[t]][a + 3] = std::max(box[piece[t]][a + 3], p[a]);
      }
    }
    for (std::uint32_t c = 0; c < numPieces; ++c) {
      const std::size_t t = tris[c][0];
      const D3 a = corner(mesh, t, 0), b = corner(mesh, t, 1), d = corner(mesh, t, 2);
      const D3 p = {(a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0, (a[2] + b[2] + d[2]) / 3.0};
      int depth = 0;
      for (std::uint32_t o = 0; o < numPieces; ++o) {
        if (o == c) continue;
        bool inBox = true;
        for (int k = 0; k < 3; ++k) inBox = inBox && p[k] >= box[o][k] && p[k] <= box[o][k + 3];
        if (inBox && insidePiece(mesh, tris[o], p)) ++depth;
      }
      const bool asWhole = (pieceVolume[c] > 0.0) == woundOutward;  // wound as the mesh's outside is
      if (asWhole != (depth % 2 == 0)) {
        throw InputError(mesh.file, mesh.binary ? 0L : static_cast<long>(mesh.source[t]),
                         (mesh.binary ? "byte " + std::to_string(mesh.source[t]) + ": " : std::string()) +
                             "the piece of triangle " + std::to_string(t + 1) + " (piece " + std::to_string(c + 1) +
                             " of " + std::to_string(numPieces) + ") lies inside " + std::to_string(depth) +
                             " of the others, so it is " + (depth % 2 == 0 ? "a part of the solid" : "a cavity") +
                             ", but it is wound " + (asWhole ? "as" : "against") +
                             " the mesh's outside: turn its triangles the other way (a cavity is wound against the "
                             "outside, a part as it)");
      }
    }
  }
  SolidProperties s;
  s.volume = in[0];
  const double cx = in[1] / in[0], cy = in[2] / in[0], cz = in[3] / in[0];  // about ref
  s.centroid = {cx + ref[0], cy + ref[1], cz + ref[2]};
  const double m = in[0];
  s.inertia = {in[5] + in[6] - m * (cy * cy + cz * cz), in[4] + in[6] - m * (cz * cz + cx * cx),
               in[4] + in[5] - m * (cx * cx + cy * cy), -(in[7] - m * cx * cy),
               -(in[9] - m * cz * cx),                  -(in[8] - m * cy * cz)};
  return s;
}

}  // namespace tumble
