// SPDX-License-Identifier: MIT
#include "tumble/validation/brute_force.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include "tumble/factory.hpp"
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

DoublePairs doublePrecisionPairs(const ParticleCloud& c, double band) {
  DoublePairs out;
  for (std::size_t i = 0; i < c.size(); ++i)
    for (std::size_t j = i + 1; j < c.size(); ++j) {
      if (c.body[i] == c.body[j]) continue;
      const double dx = double(c.x[i]) - c.x[j], dy = double(c.y[i]) - c.y[j], dz = double(c.z[i]) - c.z[j];
      const double s = double(c.r[i]) + c.r[j], d2 = dx * dx + dy * dy + dz * dz, s2 = s * s;
      const Pair p{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)};
      if (d2 < s2 * (1.0 - band))
        out.sure.push_back(p);
      else if (d2 <= s2 * (1.0 + band))
        out.unsure.push_back(p);
    }
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
                                                const std::vector<float>& radius, const std::vector<MeshPose>& poses) {
  const std::size_t n = radius.size();
  const std::uint32_t nt = mesh.numTriangles();
  const MeshView v = mesh.view(poses);
  std::vector<std::vector<MeshContact>> rows(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    for (std::uint32_t t = 0; t < nt; ++t) {
      const Vec3f xi = meshPoint(v, v.tri[t].wall, Vec3f{x[3 * i], x[3 * i + 1], x[3 * i + 2]});
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

std::array<double, 3> nearestPointDouble(const double a[3], const double b[3], const double c[3], const double p[3]) {
  const auto sub = [](const double* x, const double* y) { return std::array<double, 3>{x[0] - y[0], x[1] - y[1], x[2] - y[2]}; };
  const auto dotd = [](const std::array<double, 3>& x, const std::array<double, 3>& y) {
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
  };
  const auto at = [&](double u, double v, double w) {
    return std::array<double, 3>{u * a[0] + v * b[0] + w * c[0], u * a[1] + v * b[1] + w * c[1], u * a[2] + v * b[2] + w * c[2]};
  };
  const auto ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dotd(ab, ap), d2 = dotd(ac, ap);
  if (d1 <= 0 && d2 <= 0) return at(1, 0, 0);
  const auto bp = sub(p, b);
  const double d3 = dotd(ab, bp), d4 = dotd(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return at(1 - v, v, 0);
  }
  const auto cp = sub(p, c);
  const double d5 = dotd(ab, cp), d6 = dotd(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return at(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(0, 1 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return at(1 - v - w, v, w);
}

namespace {

// Where a vertex y of mesh wall d (as given, in frame f) is at time t, in double: p + v τ +
// q (y − p) q*, q = (cos θ/2, sin θ/2 k) the rotation by θ = |ω| τ about k = ω / |ω|, p the pivot.
void posedDouble(const WallDef& d, const LocalFrame& f, double t, Vec3f y, double out[3]) {
  const double tau = wallMotionTime(d, t);
  const Vec3f pf = d.meshPivot();
  const double p[3] = {pf.x - f.x, pf.y - f.y, pf.z - f.z};
  double r[3] = {y.x - p[0], y.y - p[1], y.z - p[2]};
  const double w[3] = {d.meshAngularVelocity.x, d.meshAngularVelocity.y, d.meshAngularVelocity.z};
  const double rate = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (rate > 0.0 && tau > 0.0) {
    const double h = 0.5 * rate * tau, s = std::sin(h) / rate, qw = std::cos(h);
    const double q[3] = {s * w[0], s * w[1], s * w[2]};
    const auto cross = [](const double a[3], const double b[3], double c[3]) {
      c[0] = a[1] * b[2] - a[2] * b[1];
      c[1] = a[2] * b[0] - a[0] * b[2];
      c[2] = a[0] * b[1] - a[1] * b[0];
    };
    double u[3], uu[3];
    cross(q, r, u);
    cross(q, u, uu);
    for (int a = 0; a < 3; ++a) r[a] += 2.0 * qw * u[a] + 2.0 * uu[a];
  }
  const double v[3] = {d.velocity.x, d.velocity.y, d.velocity.z};
  for (int a = 0; a < 3; ++a) out[a] = p[a] + v[a] * tau + r[a];
}

}  // namespace

MeshOracleRun meshOracleRun(const World& w, std::uint64_t steps, const PipelineOptions& o) {
  auto p = makePipeline(Backend::Cpu, o);
  p->load(w);
  const KernelMesh mesh = kernelMesh(w.params, p->frame());
  std::vector<Wall> walls = kernelWalls(w.params, p->frame());
  std::vector<MeshPose> poses(meshWallsMove(w.params) ? walls.size() : 0, MeshPose{});
  const std::vector<WallDef> planes = w.params.planes();
  MeshOracleRun out;
  std::vector<float> x;
  for (std::uint64_t s = 0; s < steps; ++s) {
    p->readLocalPositions(x);  // the positions the step decides its contacts on, and its time
    const double t0 = p->time();
    if (!poses.empty()) setWallMotion(walls, w.params, t0, poses.data());
    p->step(1);
    const std::vector<MeshContact> got = p->meshContacts();
    const std::vector<MeshContact> want = bruteForceMeshContacts(mesh, x, w.radius, poses);
    if (got != want) {
      std::size_t k = 0;
      while (k < got.size() && k < want.size() && got[k] == want[k]) ++k;
      const auto at = [&](const std::vector<MeshContact>& v) {
        char buf[64] = "none";
        if (k < v.size()) std::snprintf(buf, sizeof buf, "(%u, %u)", v[k].particle, v[k].triangle);
        return std::string(buf);
      };
      char buf[160];
      std::snprintf(buf, sizeof buf, "step %llu: the pipeline has %zu mesh contacts, the oracle %zu; the first difference: ",
                    static_cast<unsigned long long>(s + 1), got.size(), want.size());
      out.difference = buf + at(got) + " against " + at(want);
      return out;
    }
    if (!poses.empty()) {
      const MeshView v = mesh.view(poses);
      for (const MeshContact& c : got) {
        const Vec3f xi{x[3 * c.particle], x[3 * c.particle + 1], x[3 * c.particle + 2]};
        const std::uint32_t k = v.tri[c.triangle].wall;
        const float kernel = nearestOnTriangle(v, c.triangle, meshPoint(v, k, xi)).dist;
        double corner[3][3];
        for (int j = 0; j < 3; ++j) posedDouble(planes[k], p->frame(), t0,
                                                v.vertices[v.triangles[3 * c.triangle + j]], corner[j]);
        const double at[3] = {xi.x, xi.y, xi.z};
        const auto q = nearestPointDouble(corner[0], corner[1], corner[2], at);
        const double exact = std::sqrt((at[0] - q[0]) * (at[0] - q[0]) + (at[1] - q[1]) * (at[1] - q[1]) +
                                       (at[2] - q[2]) * (at[2] - q[2]));
        out.worstPoseGap = std::max(out.worstPoseGap, std::abs(double(kernel) - exact));
      }
    }
    ++out.steps;
    out.contacts += got.size();
    out.perStep.push_back(got.size());
  }
  out.rebuilds = p->stats().numRebuilds;
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
