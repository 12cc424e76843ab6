// SPDX-License-Identifier: MIT
// The solid a closed triangle mesh bounds: its checks and its mass properties
// (tumble/mesh_mass.hpp).
#include "tumble/mesh_mass.hpp"

#include <algorithm>
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
    in[1] += d0 * x.f2, in[2] += d1 * y.f2, in[3] += d2 * z.f2;
    in[4] += d0 * x.f3, in[5] += d1 * y.f3, in[6] += d2 * z.f3;
    in[7] += d0 * (p[0][1] * x.g0 + p[1][1] * x.g1 + p[2][1] * x.g2);
    in[8] += d1 * (p[0][2] * y.g0 + p[1][2] * y.g1 + p[2][2] * y.g2);
    in[9] += d2 * (p[0][0] * z.g0 + p[1][0] * z.g1 + p[2][0] * z.g2);
  }
  static constexpr double kMult[10] = {1.0 / 6,   1.0 / 24,  1.0 / 24,  1.0 / 24,  1.0 / 60,
                                       1.0 / 60,  1.0 / 60,  1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) in[i] *= kMult[i];
  if (in[0] < 0.0)  // wound inward: every integral of the outward twin has the other sign
    for (double& v : in) v = -v;
  if (!(in[0] > 0.0))
    throw InputError(mesh.file, 0, "the closed mesh bounds no volume (its triangles enclose nothing)");
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
