// SPDX-License-Identifier: MIT
// Tests of the solid a closed mesh bounds (tumble/mesh_mass.hpp): volume, centroid and inertia
// against closed forms (a box, a tetrahedron, an L-shaped prism as the union of two boxes by
// the parallel-axis theorem, a torus as its polyhedra converge), and the meshes that bound no
// solid refused at their first triangle.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/mesh.hpp"
#include "tumble/mesh_mass.hpp"
#include "mesh_test_util.hpp"

namespace {

using tumble::SolidProperties;
using mesh_test::addBox;
using mesh_test::objMesh;
using mesh_test::Tri;
using mesh_test::V;

/// A box's properties at density 1 about its centre, in closed form.
SolidProperties boxSolid(V lo, V hi) {
  const double a = hi[0] - lo[0], b = hi[1] - lo[1], c = hi[2] - lo[2], m = a * b * c;
  SolidProperties s;
  s.volume = m;
  s.centroid = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  s.inertia = {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12, 0, 0, 0};
  return s;
}

void expectSolid(const SolidProperties& got, const SolidProperties& want, double tol, const char* what) {
  const double size = std::cbrt(want.volume);
  EXPECT_NEAR(got.volume, want.volume, tol * want.volume) << what << ": volume";
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got.centroid[k], want.centroid[k], tol * size) << what << ": centroid " << k;
  const double scale = want.volume * size * size;
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(got.inertia[k], want.inertia[k], tol * scale) << what << ": inertia " << k;
}

}  // namespace

TEST(SolidProperties, ABoxAsItsClosedForm) {
  std::vector<V> vs;
  std::vector<Tri> ts;
  const V lo{-0.25, 1.0, 2.0}, hi{0.875, 1.5, 4.0};  // exact in float, as the mesh keeps them
  addBox(lo, hi, vs, ts);
  expectSolid(tumble::solidProperties(objMesh(vs, ts)), boxSolid(lo, hi), 1e-12, "box");
  // Scaled per axis: the box [2 lo, 2 hi] x [3 lo, 3 hi] x [0.5 lo, 0.5 hi].
  const SolidProperties scaled = tumble::solidProperties(objMesh(vs, ts), {2.0, 3.0, 0.5});
  expectSolid(scaled, boxSolid({2 * lo[0], 3 * lo[1], 0.5 * lo[2]}, {2 * hi[0], 3 * hi[1], 0.5 * hi[2]}), 1e-12, "scaled box");
  // Wound inward (every triangle reversed): the same solid.
  for (Tri& t : ts) std::swap(t[1], t[2]);
  expectSolid(tumble::solidProperties(objMesh(vs, ts)), boxSolid(lo, hi), 1e-12, "inward box");
}

// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): V = 1/6, centroid 1/4 each, ∫x² = 1/60 and
// ∫xy = 1/120 about the origin, so I_xx = 2/60 − V (1/16 + 1/16) = 1/80 and
// I_xy = −(1/120 − V/16) = 1/480 about the centroid.
TEST(SolidProperties, ATetrahedronAsItsClosedForm) {
  const std::vector<V> vs{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<Tri> ts{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  SolidProperties want;
  want.volume = 1.0 / 6;
  want.centroid = {0.25, 0.25, 0.25};
  want.inertia = {1.0 / 80, 1.0 / 80, 1.0 / 80, 1.0 / 480, 1.0 / 480, 1.0 / 480};
  expectSolid(tumble::solidProperties(objMesh(vs, ts)), want, 1e-12, "tetrahedron");
}

// An L-shaped prism (the L (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), 0.5 thick) as one closed mesh
// against the union of the boxes [0,2]x[0,1] and [0,1]x[1,2] by the parallel-axis theorem.
TEST(SolidProperties, AnLShapeAsTwoBoxes) {
  const double h = 0.5;
  const std::vector<std::array<double, 2>> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  std::vector<V> vs;
  for (double z : {0.0, h})
    for (const auto& p : l) vs.push_back({p[0], p[1], z});
  std::vector<Tri> ts;
  // The caps fanned from the reflex corner (1,1), index 3: bottom seen from below, top from above.
  for (int k : {4, 5, 0, 1}) {
    const int next = (k + 1) % 6;
    ts.push_back({3, next, k});
    ts.push_back({6 + 3, 6 + k, 6 + next});
  }
  for (int k = 0; k < 6; ++k) {  // the sides, outward for a counter-clockwise L
    const int n = (k + 1) % 6;
    ts.push_back({k, n, 6 + n});
    ts.push_back({k, 6 + n, 6 + k});
  }
  const SolidProperties a = boxSolid({0, 0, 0}, {2, 1, h}), b = boxSolid({0, 1, 0}, {1, 2, h});
  SolidProperties want;
  want.volume = a.volume + b.volume;
  for (int k = 0; k < 3; ++k) want.centroid[k] = (a.volume * a.centroid[k] + b.volume * b.centroid[k]) / want.volume;
  for (const SolidProperties* p : {&a, &b}) {  // each box moved to the union's centroid
    const double d[3] = {p->centroid[0] - want.centroid[0], p->centroid[1] - want.centroid[1],
                         p->centroid[2] - want.centroid[2]};
    want.inertia[0] += p->inertia[0] + p->volume * (d[1] * d[1] + d[2] * d[2]);
    want.inertia[1] += p->inertia[1] + p->volume * (d[0] * d[0] + d[2] * d[2]);
    want.inertia[2] += p->inertia[2] + p->volume * (d[0] * d[0] + d[1] * d[1]);
    want.inertia[3] -= p->volume * d[0] * d[1];
    want.inertia[4] -= p->volume * d[0] * d[2];
    want.inertia[5] -= p->volume * d[1] * d[2];
  }
  EXPECT_NE(want.inertia[3], 0.0) << "the L has a product of inertia";
  expectSolid(tumble::solidProperties(objMesh(vs, ts)), want, 1e-12, "L-shape");
}

// A torus of radii R = 1, r = 0.3 about z: V = 2π² R r², I_zz = V (R² + 3r²/4), I_xx = I_yy =
// V (R²/2 + 5r²/8). Its polyhedra (vertices on the torus, n × n/2 quads) approach it as
// 1/n²: within 1e-3 at n = 256 (an inscribed polygon of m sides has (2π/m)²/6 less area), and
// about 4 times closer each time n doubles.
TEST(SolidProperties, ATorusAsItsPolyhedraConverge) {
  const double R = 1.0, r = 0.3, pi = 3.14159265358979323846;
  SolidProperties want;
  want.volume = 2 * pi * pi * R * r * r;
  want.inertia = {want.volume * (R * R / 2 + 5 * r * r / 8), want.volume * (R * R / 2 + 5 * r * r / 8),
                  want.volume * (R * R + 0.75 * r * r), 0, 0, 0};
  double previous = 1.0;
  for (int n : {64, 128, 256}) {
    const int m = n / 2;
    std::vector<V> vs;
    std::vector<Tri> ts;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        const double u = 2 * pi * i / n, v = 2 * pi * j / m;
        vs.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
      }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m, d = i * m + (j + 1) % m;
        ts.push_back({a, b, c});
        ts.push_back({a, c, d});
      }
    const SolidProperties got = tumble::solidProperties(objMesh(vs, ts));
    const double error = std::max({std::fabs(got.volume / want.volume - 1), std::fabs(got.inertia[0] / want.inertia[0] - 1),
                                   std::fabs(got.inertia[2] / want.inertia[2] - 1)});
    std::printf("torus n = %d: %zu triangles, largest relative error %.3e\n", n, ts.size(), error);
    EXPECT_LT(error, previous / 3.5) << "n = " << n;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got.centroid[k], 0.0, 1e-12);
    for (int k = 3; k < 6; ++k) EXPECT_NEAR(got.inertia[k], 0.0, 1e-12);
    previous = error;
  }
  EXPECT_LT(previous, 1e-3);
}

// solidProperties() of the mesh must refuse it, its message holding each of `parts`.
void expectRefused(const std::vector<V>& vs, const std::vector<Tri>& ts, const std::vector<std::string>& parts) {
  try {
    tumble::solidProperties(objMesh(vs, ts));
    ADD_FAILURE() << "accepted; expected " << parts.back();
  } catch (const tumble::InputError& e) {
    const std::string m = e.what();
    std::printf("refused: %s\n", m.c_str());
    for (const std::string& part : parts) EXPECT_NE(m.find(part), std::string::npos) << m;
  }
}

// Meshes that bound no solid: refused at the first triangle of the bad edge, with the edge.
TEST(SolidProperties, MeshesThatBoundNoSolidAreRefused) {
  const auto refused = [](const std::vector<V>& vs, const std::vector<Tri>& ts, const std::string& where,
                          const std::string& what) { expectRefused(vs, ts, {where, "its edge from (", what}); };
  std::vector<V> vs;
  std::vector<Tri> ts;
  addBox({0, 0, 0}, {1, 1, 1}, vs, ts);
  // Open: the last face's two triangles missing (the first triangle on an open edge is the
  // first that borders the hole). OBJ lines: 8 vertices, then face k on line 9 + k.
  std::vector<Tri> open(ts.begin(), ts.end() - 2);
  refused(vs, open, "solid.obj:", "is open");
  // One triangle reversed: its edges are run the same way as its neighbours'.
  std::vector<Tri> flipped = ts;
  std::swap(flipped[5][1], flipped[5][2]);
  refused(vs, flipped, "solid.obj:", "orientations disagree");
  // Two boxes sharing an edge: four triangles on it.
  std::vector<V> two = vs;
  std::vector<Tri> both = ts;
  addBox({1, 1, 0}, {2, 2, 1}, two, both);
  refused(two, both, "solid.obj:", "is not manifold");
}

// A mesh of several pieces bounds one solid when they do not cross and each is wound as its
// place says: outward where it lies inside an even number of the others (a part), inward where
// an odd number (a cavity). Overlapping pieces, a cavity wound outward (its volume would count
// twice) and a separate part wound inward (it would be subtracted) are refused.
TEST(SolidProperties, PiecesMustBoundOneSolid) {
  const auto inward = [](std::vector<Tri> ts, std::size_t from) {
    for (std::size_t k = from; k < ts.size(); ++k) std::swap(ts[k][1], ts[k][2]);
    return ts;
  };
  const auto refusedWith = [](const std::vector<V>& vs, const std::vector<Tri>& ts, const std::string& what) {
    expectRefused(vs, ts, {what});
  };
  // A hollow box: the cavity wound inward.
  std::vector<V> vs;
  std::vector<Tri> ts;
  addBox({0, 0, 0}, {1, 1, 1}, vs, ts);
  addBox({0.25, 0.25, 0.25}, {0.75, 0.75, 0.75}, vs, ts);
  const SolidProperties outer = boxSolid({0, 0, 0}, {1, 1, 1}), inner = boxSolid({0.25, 0.25, 0.25}, {0.75, 0.75, 0.75});
  SolidProperties hollow;
  hollow.volume = outer.volume - inner.volume;
  hollow.centroid = outer.centroid;
  for (int k = 0; k < 6; ++k) hollow.inertia[k] = outer.inertia[k] - inner.inertia[k];
  expectSolid(tumble::solidProperties(objMesh(vs, inward(ts, 12))), hollow, 1e-12, "hollow box");
  // The same cavity wound outward, as a part of the solid: refused at its first triangle (line 29:
  // 16 vertices, then the outer box's 12 triangles).
  refusedWith(vs, ts, "solid.obj:29: the piece of triangle 13 (piece 2 of 2) lies inside 1 of the others, so it is a "
                      "cavity, but it is wound as the mesh's outside");
  // Two separate boxes, the second wound inward: refused; both outward: their sum.
  std::vector<V> two;
  std::vector<Tri> apart;
  addBox({0, 0, 0}, {1, 1, 1}, two, apart);
  addBox({2, 0, 0}, {2.5, 0.5, 0.5}, two, apart);
  refusedWith(two, inward(apart, 12), "lies inside 0 of the others, so it is a part of the solid, but it is wound against");
  EXPECT_NEAR(tumble::solidProperties(objMesh(two, apart)).volume, 1.125, 1e-12);
  // Two boxes that overlap: the first pair of crossing triangles.
  std::vector<V> over;
  std::vector<Tri> cross;
  addBox({0, 0, 0}, {1, 1, 1}, over, cross);
  addBox({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}, over, cross);
  refusedWith(over, cross, "crosses triangle");
  refusedWith(over, cross, "the surface passes through itself");
  // Pieces that only touch are one solid (a reviewer's cases): a box resting on another, offset
  // (faces in one plane, edges on faces); two tetrahedra meeting at a vertex ("a bowtie");
  // a cavity touching the box's face at its first corner, on either side (mirror images agree).
  std::vector<V> stack;
  std::vector<Tri> stacked;
  addBox({0, 0, 0}, {1, 1, 1}, stack, stacked);
  addBox({0.5, 0.5, 1}, {1.5, 1.5, 2}, stack, stacked);
  EXPECT_NEAR(tumble::solidProperties(objMesh(stack, stacked)).volume, 2.0, 1e-12);
  const std::vector<V> bow = {{0, 0, 0}, {-2, -1, -1}, {-1, -2, -1}, {-1, -1, -2}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}};
  const std::vector<Tri> tie = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}};
  EXPECT_NEAR(tumble::solidProperties(objMesh(bow, tie)).volume, 4.0 / 3.0, 1e-12) << "two tetrahedra of |det| / 6 = 2/3";
  for (const double face : {0.0, 4.0}) {
    std::vector<V> vs2;
    std::vector<Tri> ts2;
    addBox({0, 0, 0}, {4, 4, 4}, vs2, ts2);
    const int o = int(vs2.size());
    for (const V& v : std::vector<V>{{face, 2, 2}, {2, 1, 1}, {2, 3, 1}, {2, 2, 3}}) vs2.push_back(v);
    // The cavity's four faces, wound against the outside (inward: seen from inside the tetrahedron).
    std::vector<Tri> cav = {{o, o + 1, o + 2}, {o, o + 2, o + 3}, {o, o + 3, o + 1}, {o + 1, o + 3, o + 2}};
    const double vol = tumble::solidProperties(objMesh(std::vector<V>(vs2.begin() + o, vs2.end()),
                                                       {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}}))
                           .volume;
    std::vector<Tri> with = ts2;
    // Orient the cavity against the outside whatever the corner order gives.
    const bool outwardAsListed = [&] {
      std::vector<Tri> alone = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
      const tumble::TriangleMesh m = objMesh(std::vector<V>(vs2.begin() + o, vs2.end()), alone);
      // the signed volume of the listed winding: positive means outward
      double sv = 0.0;
      for (std::size_t t = 0; t < m.numTriangles(); ++t) {
        const auto c = [&](int k) { const tumble::Vec3f p = m.vertices[m.triangles[3 * t + std::size_t(k)]]; return V{p.x, p.y, p.z}; };
        const V a = c(0), bb = c(1), d = c(2);
        sv += a[0] * (bb[1] * d[2] - bb[2] * d[1]) - a[1] * (bb[0] * d[2] - bb[2] * d[0]) + a[2] * (bb[0] * d[1] - bb[1] * d[0]);
      }
      return sv > 0.0;
    }();
    for (Tri t : cav) {
      if (outwardAsListed) std::swap(t[1], t[2]);
      with.push_back(t);
    }
    const SolidProperties h = tumble::solidProperties(objMesh(vs2, with));
    EXPECT_NEAR(h.volume, 64.0 - vol, 1e-9) << "a cavity touching the face x = " << face;
  }
}
