// SPDX-License-Identifier: MIT
// A clump of spheres from a closed mesh by the distance-transform method (tumble/clump.hpp).
#include "tumble/clump.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "tumble/error.hpp"

namespace tumble {
namespace {

using D3 = std::array<double, 3>;

D3 sub(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Tri {
  D3 a, b, c;
};

/// The triangles of `mesh`, scaled, in double.
std::vector<Tri> trianglesOf(const TriangleMesh& mesh, const D3& scale) {
  std::vector<Tri> out(mesh.numTriangles());
  for (std::size_t t = 0; t < out.size(); ++t) {
    D3* corner[3] = {&out[t].a, &out[t].b, &out[t].c};
    for (int k = 0; k < 3; ++k) {
      const Vec3f v = mesh.vertices[mesh.triangles[3 * t + k]];
      *corner[k] = {double(v.x) * scale[0], double(v.y) * scale[1], double(v.z) * scale[2]};
    }
  }
  return out;
}

/// The squared distance from p to triangle t (Ericson, Real-Time Collision Detection, 5.1.5).
double distance2(const D3& p, const Tri& t) {
  const D3 ab = sub(t.b, t.a), ac = sub(t.c, t.a), ap = sub(p, t.a);
  const auto at = [&](double v, double w) {  // the point a + v ab + w ac
    const D3 q{t.a[0] + v * ab[0] + w * ac[0], t.a[1] + v * ab[1] + w * ac[1], t.a[2] + v * ab[2] + w * ac[2]};
    const D3 d = sub(p, q);
    return dot(d, d);
  };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return at(0, 0);
  const D3 bp = sub(p, t.b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return at(1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return at(d1 / (d1 - d3), 0);
  const D3 cp = sub(p, t.c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return at(0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return at(0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(1.0 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  return at(vb * denom, vc * denom);
}

double distanceToMesh(const D3& p, const std::vector<Tri>& tris) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : tris) best = std::min(best, distance2(p, t));
  return std::sqrt(best);
}

/// A grid of cubic voxels of edge h over a box, its sample points offset along y and z by
/// small irrational fractions of a voxel (no mesh edge on round coordinates meets their lines).
struct Grid {
  int n[3] = {0, 0, 0};
  double h = 0.0;
  D3 origin{0, 0, 0};
  static constexpr double kShiftY = 1.4142135623730951e-3, kShiftZ = 1.7320508075688772e-3;
  Grid(const D3& lo, const D3& hi, double edge) : h(edge) {
    for (int a = 0; a < 3; ++a) {
      n[a] = int(std::ceil((hi[a] - lo[a]) / h)) + 2;  // a voxel of room on either side
      origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * n[a] * h;
    }
  }
  std::size_t size() const { return std::size_t(n[0]) * n[1] * n[2]; }
  std::size_t index(int i, int j, int k) const { return (std::size_t(k) * n[1] + j) * n[0] + i; }
  double coordinate(int a, int i) const {
    return origin[a] + (i + 0.5 + (a == 1 ? kShiftY : a == 2 ? kShiftZ : 0.0)) * h;
  }
  D3 point(std::size_t v) const {
    const int i = int(v % n[0]), j = int(v / n[0] % n[1]), k = int(v / (std::size_t(n[0]) * n[1]));
    return {coordinate(0, i), coordinate(1, j), coordinate(2, k)};
  }
  /// The voxel range [lo, hi] of coordinates [a, b] along axis `axis`.
  void range(int axis, double a, double b, int* lo, int* hi) const {
    const double shift = axis == 1 ? kShiftY : axis == 2 ? kShiftZ : 0.0;
    *lo = std::max(0, int(std::floor((a - origin[axis]) / h - 0.5 - shift)));
    *hi = std::min(n[axis] - 1, int(std::ceil((b - origin[axis]) / h - 0.5 - shift)));
  }
  /// Marks (in `mark`) every voxel whose sample point lies within r of c; returns how many it newly marked.
  std::size_t markBall(const D3& c, double r, std::vector<std::uint8_t>& mark) const {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) range(a, c[a] - r, c[a] + r, &lo[a], &hi[a]);
    std::size_t fresh = 0;
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const D3 d = sub({coordinate(0, i), coordinate(1, j), coordinate(2, k)}, c);
          if (dot(d, d) > r * r) continue;
          std::uint8_t& m = mark[index(i, j, k)];
          fresh += m == 0;
          m = 1;
        }
    return fresh;
  }
};

/// Which voxels' sample points are inside the closed mesh: per line along x, the parity of the
/// triangles it crosses before each point.
std::vector<std::uint8_t> insideVoxels(const Grid& g, const std::vector<Tri>& tris) {
  std::vector<std::vector<std::uint32_t>> rows(std::size_t(g.n[1]) * g.n[2]);
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const Tri& tr = tris[t];
    int jlo, jhi, klo, khi;
    g.range(1, std::min({tr.a[1], tr.b[1], tr.c[1]}), std::max({tr.a[1], tr.b[1], tr.c[1]}), &jlo, &jhi);
    g.range(2, std::min({tr.a[2], tr.b[2], tr.c[2]}), std::max({tr.a[2], tr.b[2], tr.c[2]}), &klo, &khi);
    for (int k = klo; k <= khi; ++k)
      for (int j = jlo; j <= jhi; ++j) rows[std::size_t(k) * g.n[1] + j].push_back(std::uint32_t(t));
  }
  std::vector<std::uint8_t> inside(g.size(), 0);
  std::vector<double> xs;
  for (int k = 0; k < g.n[2]; ++k)
    for (int j = 0; j < g.n[1]; ++j) {
      const double y = g.coordinate(1, j), z = g.coordinate(2, k);
      xs.clear();
      for (std::uint32_t t : rows[std::size_t(k) * g.n[1] + j]) {
        const Tri& tr = tris[t];
        // Edge functions of (y, z) in the triangle's projection on the yz plane: its barycentric weights.
        const auto edge = [&](const D3& p, const D3& q) { return (q[1] - p[1]) * (z - p[2]) - (q[2] - p[2]) * (y - p[1]); };
        const double wa = edge(tr.b, tr.c), wb = edge(tr.c, tr.a), wc = edge(tr.a, tr.b);
        const double sum = wa + wb + wc;
        if (sum == 0.0 || !((wa >= 0 && wb >= 0 && wc >= 0) || (wa <= 0 && wb <= 0 && wc <= 0))) continue;
        xs.push_back((wa * tr.a[0] + wb * tr.b[0] + wc * tr.c[0]) / sum);
      }
      std::sort(xs.begin(), xs.end());
      std::size_t crossed = 0;
      for (int i = 0; i < g.n[0]; ++i) {
        const double x = g.coordinate(0, i);
        while (crossed < xs.size() && xs[crossed] < x) ++crossed;
        inside[g.index(i, j, k)] = std::uint8_t(crossed % 2);
      }
    }
  return inside;
}

/// The squared distance (in voxels²) of each voxel to the nearest outside voxel, along one line
/// of n values f (0 outside, a large number inside): Felzenszwalb and Huttenlocher's lower
/// envelope of parabolas. d, v, z: room for n, n and n + 1.
void distanceLine(const double* f, double* d, int n, int* v, double* z) {
  constexpr double kInf = 1e30;
  int k = 0;
  v[0] = 0;
  z[0] = -kInf, z[1] = kInf;
  for (int q = 1; q < n; ++q) {
    double s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
    while (s <= z[k]) {
      --k;
      s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
    }
    ++k;
    v[k] = q, z[k] = s, z[k + 1] = kInf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    d[q] = (double(q) - v[k]) * (double(q) - v[k]) + f[v[k]];
  }
}

std::vector<double> squaredDepths(const Grid& g, const std::vector<std::uint8_t>& inside) {
  std::vector<double> d2(g.size());
  for (std::size_t v = 0; v < d2.size(); ++v) d2[v] = inside[v] ? 1e20 : 0.0;
  const int most = std::max({g.n[0], g.n[1], g.n[2]});
  std::vector<double> f(most), d(most), z(most + 1);
  std::vector<int> vv(most);
  const std::size_t stride[3] = {1, std::size_t(g.n[0]), std::size_t(g.n[0]) * g.n[1]};
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int p = 0; p < g.n[a1]; ++p)
      for (int q = 0; q < g.n[a2]; ++q) {
        const std::size_t base = p * stride[a1] + q * stride[a2];
        for (int i = 0; i < g.n[axis]; ++i) f[i] = d2[base + i * stride[axis]];
        distanceLine(f.data(), d.data(), g.n[axis], vv.data(), z.data());
        for (int i = 0; i < g.n[axis]; ++i) d2[base + i * stride[axis]] = d[i];
      }
  }
  return d2;
}

/// The layer's candidates for spheres of radius rho (m) (clump.hpp, the surface fill): the
/// inside voxels at depth rho within half a voxel, and those shallower on the ridge of a thin
/// part (none of the 26 neighbours deeper: a plateau across the part, not the bisector of an
/// edge, which deepens away from both faces), in index order. A voxel's depth to the surface is about half
/// a voxel less than its distance to the nearest outside voxel's point (squaredDepths()).
std::vector<std::size_t> layerCandidates(const Grid& g, const std::vector<std::uint8_t>& inside,
                                         const std::vector<double>& d2, double rho) {
  const double lo = rho / g.h, hi = rho / g.h + 1.0;  // in voxels, of the distance to the outside
  const std::ptrdiff_t sy = g.n[0], sz = std::ptrdiff_t(g.n[0]) * g.n[1];
  // The grid's border voxels are outside (a voxel of room): an inside voxel's neighbours are in it.
  const auto ridge = [&](std::size_t v) {
    for (int k = -1; k <= 1; ++k)
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
          if (d2[std::size_t(std::ptrdiff_t(v) + k * sz + j * sy + i)] > d2[v]) return false;
    return true;
  };
  std::vector<std::size_t> out;
  for (std::size_t v = 0; v < g.size(); ++v) {
    if (!inside[v]) continue;
    const double d = std::sqrt(d2[v]);
    if (d > hi) continue;
    if (d > lo || ridge(v)) out.push_back(v);
  }
  return out;
}

/// The layer's centres by farthest-point sampling: first the candidate farthest from their
/// centroid, then each time the one farthest from every centre chosen, until every candidate is
/// within `spacing` of one (ties: the lowest index). Extremes first (a box's corners, then its
/// edges), where the surface is farthest from the layer. C candidates and K centres: O(K C).
std::vector<std::size_t> coverLayer(const Grid& g, const std::vector<std::size_t>& candidates, double spacing) {
  std::vector<std::size_t> chosen;
  if (candidates.empty()) return chosen;
  std::vector<D3> p(candidates.size());
  D3 mean{0.0, 0.0, 0.0};
  for (std::size_t c = 0; c < p.size(); ++c) {
    p[c] = g.point(candidates[c]);
    for (int a = 0; a < 3; ++a) mean[a] += p[c][a];
  }
  for (int a = 0; a < 3; ++a) mean[a] /= double(p.size());
  std::vector<double> near(p.size(), std::numeric_limits<double>::infinity());
  std::size_t next = 0;
  double far = -1.0;
  for (std::size_t c = 0; c < p.size(); ++c) {
    const D3 d = sub(p[c], mean);
    if (dot(d, d) > far) far = dot(d, d), next = c;
  }
  for (;;) {
    chosen.push_back(candidates[next]);
    const D3 q = p[next];
    far = -1.0;
    for (std::size_t c = 0; c < p.size(); ++c) {
      const D3 d = sub(p[c], q);
      near[c] = std::min(near[c], dot(d, d));
      if (near[c] > far) far = near[c], next = c;
    }
    if (!(far > spacing * spacing)) break;
  }
  return chosen;
}

/// The surface fill (clump.hpp): the layer's radius from the tolerance (measured) and the sphere
/// count, its spheres (and, where it measured them, their quality) into out.
void placeLayer(const TriangleMesh& mesh, const Grid& g, const std::vector<Tri>& tris,
                const std::vector<std::uint8_t>& inside, const std::vector<double>& d2, const ClumpOptions& options,
                const std::array<double, 3>& scale, Clump& out) {
  double deepest = 0.0;
  for (std::size_t v = 0; v < g.size(); ++v)
    if (inside[v]) deepest = std::max(deepest, d2[v]);
  deepest = (std::sqrt(deepest) - 0.5) * g.h;  // the depth of the deepest point (layerCandidates())
  char buf[400];
  if (!(deepest >= 0.5 * g.h)) {
    std::snprintf(buf, sizeof buf, ": the solid is too thin for its voxels (%.4g m: resolution %u), no layer fits; give a "
                  "finer resolution", g.h, options.resolution);
    throw Error(mesh.file + buf);
  }
  const double least = std::min(1.5 * g.h, deepest);  // 1.5 voxels (the depths' grain), or a thin solid's depth
  const double tol = options.tolerance;
  // The tolerance the layer is laid out for: D less 1.5 voxels, what the centres' and the depths'
  // grain adds (measured on boxes).
  const double design = tol - 1.5 * g.h;
  // The centres' spacing for a layer of radius ρ: with a tolerance, √(E² + 2Eρ − 2ρ²) for E the
  // design's, with which a box's corner lies within E of a centre that far along the layer from
  // its own corner (√(3ρ² + s²) − ρ ≤ E; a flat face then within less); for a count alone √2 ρ.
  const auto spheresAt = [&](double rho, bool forTolerance) {
    const double spacing =
        forTolerance ? std::sqrt(std::max(design * design + 2.0 * design * rho - 2.0 * rho * rho, 0.0))
                     : std::sqrt(2.0) * rho;
    std::vector<ClumpSphere> s;
    for (const std::size_t v : coverLayer(g, layerCandidates(g, inside, d2, rho), spacing)) {
      const D3 p = g.point(v);
      const double r = distanceToMesh(p, tris);
      if (r >= 0.5 * g.h) s.push_back({p, r});  // (a sliver of the surface: too small a sphere)
    }
    return s;
  };
  struct Layer {
    double rho = 0.0;
    std::vector<ClumpSphere> spheres;
    ClumpQuality quality;
  };
  Layer best;
  if (tol > 0.0) {
    // Radii from 0.35 E to 1.1 E (at most the solid's depth, at least 1.5 voxels), each layer
    // measured (the corners' share depends on where the centres fall): the one that meets D with
    // the fewest spheres (ties: the larger radius). E must exceed 1.5 voxels (a layer's least).
    if (!(design > 1.5 * g.h)) {
      const double needed = std::ceil(options.resolution * 3.0 * g.h / tol);  // 3 voxels in D
      if (needed > 512)
        std::snprintf(buf, sizeof buf, ": a surface layer for the tolerance %g m needs voxels of a third of it, finer "
                      "than resolution 512 gives; give a larger tolerance", tol);
      else
        std::snprintf(buf, sizeof buf, ": a surface layer for the tolerance %g m needs voxels of a third of it or less "
                      "(they are %.4g m): give a resolution of at least %.0f, or a larger tolerance",
                      tol, g.h, needed);
      throw Error(mesh.file + buf);
    }
    double worst = 0.0;
    bool found = false;
    double last = -1.0;
    for (const double f : {1.1, 0.9, 0.7, 0.5, 0.35}) {
      const double rho = std::clamp(f * design, least, deepest);
      if (rho == last) continue;
      last = rho;
      Layer l{rho, spheresAt(rho, true), {}};
      l.quality = clumpQuality(mesh, l.spheres, g.h, out.solid.volume, scale);
      if (!(l.quality.largestDeviation <= tol)) {
        worst = std::max(worst, l.quality.largestDeviation);
        continue;
      }
      if (!found || l.spheres.size() < best.spheres.size()) best = std::move(l);
      found = true;
    }
    if (!found) {
      std::snprintf(buf, sizeof buf, ": no surface layer meets the tolerance %g m with spheres of %.4g to %.4g m (the "
                    "surface lies up to %.4g m from them): give a finer resolution or a larger tolerance",
                    tol, std::clamp(0.35 * design, least, deepest), std::clamp(1.1 * design, least, deepest), worst);
      throw Error(mesh.file + buf);
    }
    out.quality = best.quality;
  }
  if (options.spheres != 0 && (tol <= 0.0 || best.spheres.size() > options.spheres)) {
    // The smallest radius whose layer has at most that many spheres, by bisection.
    double lo = std::max(best.rho, least), hi = deepest;
    std::vector<ClumpSphere> atHi = spheresAt(hi, false);
    if (atHi.size() > options.spheres) {
      std::snprintf(buf, sizeof buf, ": a layer under the surface needs at least %zu spheres here (of radius %.4g m, "
                    "the solid's depth); allow more spheres", atHi.size(), hi);
      throw Error(mesh.file + buf);
    }
    for (int k = 0; k < 20 && hi - lo > 0.01 * g.h; ++k) {
      const double mid = 0.5 * (lo + hi);
      std::vector<ClumpSphere> c = spheresAt(mid, false);
      if (c.size() <= options.spheres) {
        hi = mid;
        atHi = std::move(c);
      } else {
        lo = mid;
      }
    }
    best.rho = hi;
    best.spheres = std::move(atHi);
    out.quality = ClumpQuality{};  // (measured below)
  }
  out.layerRadius = best.rho;
  out.spheres = std::move(best.spheres);
}

/// The spheres bucketed in cubic cells of edge at least twice the largest radius over a box that
/// holds them and the points asked about: the distance from a point to the union of the spheres,
/// min over them of max(0, |p − c| − r), by rings of cells around the point's until no sphere
/// further out can be nearer. The same value as the loop over every sphere (a minimum of the
/// same numbers), in about a cell's worth of spheres per point.
class SphereGrid {
 public:
  SphereGrid(const std::vector<ClumpSphere>& spheres, D3 lo, D3 hi) : m_spheres(spheres) {
    for (const ClumpSphere& s : spheres) {
      m_rmax = std::max(m_rmax, s.radius);
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], s.centre[a]), hi[a] = std::max(hi[a], s.centre[a]);
    }
    m_lo = lo;
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300});
    // At least 2 r_max, and cells no more than about 8 per sphere (and 2^21 in all).
    m_cell = std::max(2.0 * m_rmax, extent / std::cbrt(std::min(8.0 * double(spheres.size()) + 8.0, 2097152.0)));
    for (int a = 0; a < 3; ++a) m_n[a] = int(std::floor((hi[a] - lo[a]) / m_cell)) + 1;
    m_first.assign(std::size_t(m_n[0]) * m_n[1] * m_n[2] + 1, 0);
    for (const ClumpSphere& s : spheres) ++m_first[cellOf(s.centre) + 1];
    for (std::size_t c = 1; c < m_first.size(); ++c) m_first[c] += m_first[c - 1];
    m_index.resize(spheres.size());
    std::vector<std::size_t> at(m_first.begin(), m_first.end() - 1);
    for (std::size_t k = 0; k < spheres.size(); ++k) m_index[at[cellOf(spheres[k].centre)]++] = k;
  }
  double distance(const D3& p) const {
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor((p[a] - m_lo[a]) / m_cell)), 0, m_n[a] - 1);
    double best = std::numeric_limits<double>::infinity();
    const int most = std::max({m_n[0], m_n[1], m_n[2]});
    for (int k = 0; k < most; ++k) {
      // A sphere in ring k + 1 or further has its centre k cells or more away: no nearer than this.
      for (int z = c[2] - k; z <= c[2] + k; ++z)
        for (int y = c[1] - k; y <= c[1] + k; ++y)
          for (int x = c[0] - k; x <= c[0] + k; ++x) {
            if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != k) continue;
            if (x < 0 || y < 0 || z < 0 || x >= m_n[0] || y >= m_n[1] || z >= m_n[2]) continue;
            const std::size_t cell = (std::size_t(z) * m_n[1] + y) * m_n[0] + x;
            for (std::size_t i = m_first[cell]; i < m_first[cell + 1]; ++i) {
              const ClumpSphere& s = m_spheres[m_index[i]];
              const D3 e = sub(p, s.centre);
              best = std::min(best, std::max(0.0, std::sqrt(dot(e, e)) - s.radius));
            }
          }
      if (best <= double(k) * m_cell - m_rmax) break;
    }
    return best;
  }

 private:
  std::size_t cellOf(const D3& p) const {
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(int(std::floor((p[a] - m_lo[a]) / m_cell)), 0, m_n[a] - 1);
    return (std::size_t(c[2]) * m_n[1] + c[1]) * m_n[0] + c[0];
  }
  const std::vector<ClumpSphere>& m_spheres;
  D3 m_lo{0.0, 0.0, 0.0};
  double m_cell = 1.0, m_rmax = 0.0;
  int m_n[3] = {1, 1, 1};
  std::vector<std::size_t> m_first, m_index;
};

}  // namespace

const char* toString(ClumpFill fill) { return fill == ClumpFill::Surface ? "surface" : "inside"; }

ClumpQuality clumpQuality(const TriangleMesh& mesh, const std::vector<ClumpSphere>& spheres, double voxel,
                          double meshVolume, std::array<double, 3> scale) {
  const std::vector<Tri> tris = trianglesOf(mesh, scale);
  ClumpQuality q;
  // The union's volume: the sample points of a grid over the spheres inside any of them.
  if (!spheres.empty()) {
    D3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    D3 hi{-lo[0], -lo[1], -lo[2]};
    for (const ClumpSphere& s : spheres)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], s.centre[a] - s.radius), hi[a] = std::max(hi[a], s.centre[a] + s.radius);
    const Grid g(lo, hi, voxel);
    std::vector<std::uint8_t> in(g.size(), 0);
    std::size_t count = 0;
    for (const ClumpSphere& s : spheres) count += g.markBall(s.centre, s.radius, in);
    q.volumeRatio = double(count) * voxel * voxel * voxel / meshVolume;
  }
  // The distance from points on every triangle (at most a voxel apart) to the union of the
  // spheres: min over them of max(0, |p − c| − r), exact outside the union. The mean weighs each
  // triangle by its area.
  double sum = 0.0, area = 0.0;
  D3 lo = tris.empty() ? D3{0.0, 0.0, 0.0} : tris[0].a, hi = lo;
  for (const Tri& t : tris)
    for (const D3* c : {&t.a, &t.b, &t.c})
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], (*c)[a]), hi[a] = std::max(hi[a], (*c)[a]);
  const SphereGrid near(spheres, lo, hi);
  for (const Tri& t : tris) {
    const D3 ab = sub(t.b, t.a), ac = sub(t.c, t.a), bc = sub(t.c, t.b);
    const double longest = std::sqrt(std::max({dot(ab, ab), dot(ac, ac), dot(bc, bc)}));
    const int k = std::max(1, int(std::ceil(longest / voxel)));
    const D3 cr{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
    const double a = 0.5 * std::sqrt(dot(cr, cr));
    double local = 0.0;
    int points = 0;
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        const double v = double(i) / k, w = double(j) / k;
        const D3 p{t.a[0] + v * ab[0] + w * ac[0], t.a[1] + v * ab[1] + w * ac[1], t.a[2] + v * ab[2] + w * ac[2]};
        const double d = near.distance(p);
        q.largestDeviation = std::max(q.largestDeviation, d);
        local += d;
        ++points;
      }
    q.samples += std::size_t(points);
    sum += a * local / points;
    area += a;
  }
  q.meanDeviation = sum / area;
  return q;
}

Clump clumpFromMesh(const TriangleMesh& mesh, const ClumpOptions& options, std::array<double, 3> scale) {
  if (options.spheres == 0 && !(options.tolerance > 0.0))
    throw Error("a clump needs a number of spheres or a tolerance (the deepest a voxel may stay uncovered)");
  if (options.resolution < 8 || options.resolution > 512)
    throw Error("the resolution must be from 8 to 512 voxels along the longest side (got " +
                std::to_string(options.resolution) + ")");
  Clump out;
  out.solid = solidProperties(mesh, scale);
  const std::vector<Tri> tris = trianglesOf(mesh, scale);
  D3 lo = tris[0].a, hi = tris[0].a;
  for (const Tri& t : tris)
    for (const D3* p : {&t.a, &t.b, &t.c})
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], (*p)[a]), hi[a] = std::max(hi[a], (*p)[a]);
  out.voxel = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) / options.resolution;
  const Grid g(lo, hi, out.voxel);
  const std::vector<std::uint8_t> inside = insideVoxels(g, tris);
  const std::vector<double> d2 = squaredDepths(g, inside);
  if (options.fill == ClumpFill::Surface) placeLayer(mesh, g, tris, inside, d2, options, scale, out);
  // The inside fill: the inside voxels, deepest first (ties: the lowest index).
  std::vector<std::size_t> order;
  for (std::size_t v = 0; v < inside.size() && options.fill == ClumpFill::Inside; ++v)
    if (inside[v]) order.push_back(v);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return d2[a] > d2[b]; });
  std::vector<std::uint8_t> covered(g.size(), 0);
  for (std::size_t v : order) {
    if (covered[v]) continue;
    // Its depth in voxels is at least its point's distance to the surface (the segment to the
    // nearest outside point crosses it): below the tolerance, so is every uncovered point's.
    const double depth = std::sqrt(d2[v]) * out.voxel;
    if (options.tolerance > 0.0 && depth <= options.tolerance) break;
    if (options.spheres != 0 && out.spheres.size() == options.spheres) {
      out.uncoveredDepth = depth;  // the deepest voxel left: the order is by depth
      break;
    }
    covered[v] = 1;
    D3 p = g.point(v);
    // A sphere that reaches less than a quarter voxel out of one placed before adds nothing: its
    // voxels are covered with it (the shell a sphere leaves under a curved surface, in one go).
    const auto contained = [&](double radius) {
      return std::any_of(out.spheres.begin(), out.spheres.end(), [&](const ClumpSphere& s) {
        const D3 d = sub(p, s.centre);
        return std::sqrt(dot(d, d)) + radius <= s.radius + 0.25 * out.voxel;
      });
    };
    // First by its depth, which bounds its distance to the surface from above: most of such a
    // shell is passed over without a look at the triangles.
    if (contained(depth)) {
      g.markBall(p, depth, covered);
      continue;
    }
    double r = distanceToMesh(p, tris);
    if (r < 0.5 * out.voxel) continue;                               // a sliver of the surface: too small a sphere
    if (options.tolerance > 0.0 && r <= options.tolerance) continue;  // within the tolerance of the surface
    if (contained(r)) {
      g.markBall(p, r, covered);
      continue;
    }
    // The centre moved to where the sphere is largest near it, within a voxel of its point (a
    // voxel's point is up to half a voxel off the medial axis; further, it would climb out of a
    // tip into the sphere of the bulk): steps along ±x, ±y, ±z, the best taken, halved when none
    // grows the sphere, none longer than half the radius (the sphere stays in the solid).
    const D3 start = p;
    for (double step = 0.5 * out.voxel; step > out.voxel / 64.0;) {
      const double len = std::min(step, 0.5 * r);
      D3 best = p;
      double bestR = r;
      for (int a = 0; a < 3; ++a)
        for (const double sign : {-1.0, 1.0}) {
          D3 q = p;
          q[a] += sign * len;
          const D3 moved = sub(q, start);
          if (dot(moved, moved) > out.voxel * out.voxel) continue;
          const double rq = distanceToMesh(q, tris);
          if (rq > bestR) best = q, bestR = rq;
        }
      if (bestR > r)
        p = best, r = bestR;
      else
        step *= 0.5;
    }
    if (contained(r)) {  // it climbed back into one
      g.markBall(p, r, covered);
      continue;
    }
    out.spheres.push_back({p, r});
    g.markBall(p, r, covered);
  }
  if (out.spheres.empty())
    throw Error(mesh.file + (options.tolerance > 0.0
                                 ? ": the whole solid lies within the tolerance of its surface: give a smaller tolerance"
                                 : ": no sphere of at least half a voxel fits in the solid; use a finer resolution"));
  if (out.quality.samples == 0) out.quality = clumpQuality(mesh, out.spheres, out.voxel, out.solid.volume, scale);
  return out;
}

ShapeDef clumpShape(const Clump& clump, const std::string& name, double density) {
  ShapeDef shape;
  shape.name = name;
  for (const ClumpSphere& c : clump.spheres) {
    SphereDef sd;
    sd.offset = Vec3f{float(c.centre[0]), float(c.centre[1]), float(c.centre[2])};
    sd.radius = float(c.radius);
    shape.spheres.push_back(sd);
  }
  ShapeSolid solid;
  solid.mass = density * clump.solid.volume;
  solid.centre = clump.solid.centroid;
  for (int k = 0; k < 6; ++k) solid.inertia[k] = density * clump.solid.inertia[k];
  shape.solid = solid;
  shareMassByVolume(shape);
  return shape;
}

std::string shapeToml(const ShapeDef& shape, const std::string& comment) {
  std::string out;
  std::size_t at = 0;
  while (at < comment.size()) {
    const std::size_t end = std::min(comment.find('\n', at), comment.size());
    out += "# ";
    for (std::size_t k = at; k < end; ++k) {  // TOML comments take no control character but tab
      const auto c = static_cast<unsigned char>(comment[k]);
      out.push_back((c < 0x20 && c != '\t') || c == 0x7f ? '?' : comment[k]);
    }
    out.push_back('\n');
    at = end + 1;
  }
  char line[256];
  const auto text = [](double v, int digits) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", digits, v + 0.0);  // (-0 as 0)
    return std::string(b);
  };
  const auto g = [&](float v) { return text(v, 9); };   // a float, read back bit for bit
  const auto d = [&](double v) { return text(v, 17); };  // a double, read back bit for bit
  out += "[[shape]]\nname = \"";
  for (const char c : shape.name) {  // a TOML basic string: quotes, backslashes and control characters escaped
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out.push_back('\\');
      out.push_back(c);
    } else if (u < 0x20 || u == 0x7f) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", unsigned(u));
      out += esc;
    } else {
      out.push_back(c);
    }
  }
  out += "\"\n";
  if (shape.solid) {
    const ShapeSolid& s = *shape.solid;
    out += "mass = " + d(s.mass) + "\n";
    out += "centre_of_mass = [" + d(s.centre[0]) + ", " + d(s.centre[1]) + ", " + d(s.centre[2]) + "]\n";
    out += "inertia = [" + d(s.inertia[0]) + ", " + d(s.inertia[1]) + ", " + d(s.inertia[2]) + ", " + d(s.inertia[3]) +
           ", " + d(s.inertia[4]) + ", " + d(s.inertia[5]) + "]  # kg m^2 about the centre of mass: xx, yy, zz, xy, xz, yz\n";
  }
  for (const SphereDef& sd : shape.spheres) {
    std::snprintf(line, sizeof line, "[[shape.sphere]]\noffset = [%s, %s, %s]\nradius = %s\n", g(sd.offset.x).c_str(),
                  g(sd.offset.y).c_str(), g(sd.offset.z).c_str(), g(sd.radius).c_str());
    out += line;
    if (!shape.solid) out += "mass = " + g(sd.mass) + "\n";
  }
  return out;
}

}  // namespace tumble
