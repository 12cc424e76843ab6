// SPDX-License-Identifier: MIT
#include "tumble/validation/brute_force.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

#include "tumble/kernels/integrate.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/periodic.hpp"

namespace tumble::validation {

std::vector<Pair> bruteForcePairs(const ParticleCloud& c) {
  const std::size_t n = c.size();
  std::vector<std::vector<Pair>> rows(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    for (std::size_t j = i + 1; j < n; ++j)
      if (c.body[i] != c.body[j] &&
          spheresOverlap(c.periodic, c.x[i], c.y[i], c.z[i], c.r[i], c.x[j], c.y[j], c.z[j], c.r[j]))
        rows[i].push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
  });
  std::vector<Pair> out;
  for (auto& r : rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

namespace {

// The vertices of the feature of a nearest point of triangle t: an edge's two (lower first),
// a vertex's one (twice); none for a face.
std::pair<std::uint32_t, std::uint32_t> featureVertices(const KernelMesh& m, std::uint32_t t, const TrianglePoint& p) {
  if (p.feature == kMeshVertex) return {p.index, p.index};
  const std::uint32_t* c = &m.triangles[3 * std::size_t(t)];
  for (int j = 0; j < 3; ++j)
    if (m.triEdges[3 * std::size_t(t) + j] == p.index) {
      const std::uint32_t a = c[j], b = c[(j + 1) % 3];
      return {std::min(a, b), std::max(a, b)};
    }
  return {~0u, ~0u};
}

bool hasVertex(const KernelMesh& m, std::uint32_t t, std::uint32_t v) {
  const std::uint32_t* c = &m.triangles[3 * std::size_t(t)];
  return c[0] == v || c[1] == v || c[2] == v;
}

}  // namespace

std::vector<MeshContact> bruteForceMeshContacts(const KernelMesh& mesh, const std::vector<float>& x,
                                                const std::vector<float>& radius) {
  const std::size_t n = radius.size();
  const std::uint32_t nt = mesh.numTriangles();
  const MeshView v = mesh.view();
  std::vector<std::vector<MeshContact>> rows(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    const Vec3f xi{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    for (std::uint32_t t = 0; t < nt; ++t) {
      const TrianglePoint p = nearestOnTriangle(v, t, xi);
      if (!(radius[i] - p.dist > 0.0f)) continue;
      bool counts = true;
      if (p.feature != kMeshFace) {
        const auto f = featureVertices(mesh, t, p);
        for (std::uint32_t u = 0; u < nt && counts; ++u) {
          if (u == t || !hasVertex(mesh, u, f.first) || !hasVertex(mesh, u, f.second)) continue;
          if (u < t) counts = false;  // a lower triangle shares the feature: it reports, or no one
          const TrianglePoint q = nearestOnTriangle(v, u, xi);
          if (q.feature != p.feature || featureVertices(mesh, u, q) != f) counts = false;
        }
      }
      if (counts) rows[i].push_back(MeshContact{static_cast<std::uint32_t>(i), t});
    }
  });
  std::vector<MeshContact> out;
  for (auto& r : rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

ParticleCloud cloudOf(const World& w, const BodyState& s) {
  ParticleCloud c;
  const std::uint32_t n = w.numParticles();
  c.x.resize(n); c.y.resize(n); c.z.resize(n);
  c.r = w.radius;
  c.body = w.body;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = w.body[i];
    const Vec3f X{s.px[k], s.py[k], s.pz[k]};
    // The pipelines' expression (particlePosition), so that the oracle sees the same bits.
    const Vec3f x = w.hasClumps ? particlePosition(X, rotationMatrix(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}),
                                                   Vec3f{w.ux[i], w.uy[i], w.uz[i]})
                                : X;
    c.x[i] = x.x;
    c.y[i] = x.y;
    c.z[i] = x.z;
  }
  return c;
}

}  // namespace tumble::validation
