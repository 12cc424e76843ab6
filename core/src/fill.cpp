// SPDX-License-Identifier: MIT
// [[fill]]: random sequential addition of bodies in a region (tumble/fill.hpp), and the
// placement it shares with [[pour]] (placement.hpp).
#include "tumble/fill.hpp"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "placement.hpp"
#include "tumble/error.hpp"
#include "tumble/sweep_frame.hpp"
#include "tumble/world.hpp"

namespace tumble {
namespace detail {

std::vector<Ball> ballsOf(const ShapeDef& sh) {
  const std::array<double, 3> c = shapeMassProperties(sh).centre;
  std::vector<Ball> out;
  for (const SphereDef& s : sh.spheres)
    out.push_back(Ball{Vec3f{float(s.offset.x - c[0]), float(s.offset.y - c[1]), float(s.offset.z - c[2])}, s.radius});
  return out;
}

namespace {
std::uint64_t cellKey(std::int64_t a, std::int64_t b, std::int64_t c) {
  // A mix of the three cell indices; equal keys for other cells only cost a test.
  std::uint64_t h = static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(b) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint64_t>(c) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
  return h;
}
}  // namespace

// Clamped in double to ±2^62 before the conversion (a fill region of radius 1e28 m gave cell
// indices beyond 2^63: undefined, found by the scene fuzzer; NaN goes to the low end): monotone,
// so neighbouring cells stay neighbours, and the cells merged beyond it only cost tests.
std::int64_t SphereHash::cellOf(double v) const {
  constexpr double kLimit = 0x1p62;
  const double c = std::floor(v / m_cell);
  return static_cast<std::int64_t>(!(c > -kLimit) ? -kLimit : c < kLimit ? c : kLimit);
}

void SphereHash::setPeriodic(const PeriodicParams& p, const LocalFrame& frame) {
  const double o[2] = {frame.x, frame.y};
  for (int a = 0; a < 2; ++a) {
    m_on[a] = p.on[a];
    m_lo[a] = double(p.lo[a]) - o[a];
    m_hi[a] = double(p.hi[a]) - o[a];
  }
}

bool SphereHash::centreInBox(Vec3f x) const {
  const float c[2] = {x.x, x.y};
  for (int a = 0; a < 2; ++a)
    if (m_on[a] && !(c[a] >= m_lo[a] && c[a] < m_hi[a])) return false;
  return true;
}

void SphereHash::add(Vec3f x, float r) {
  // Within reach of an end of a periodic box (two cells and the radius), the sphere's image one
  // period on as well, on each axis and across the corner; in a box shorter than twice the reach
  // a sphere may be within reach of both ends, and needs both images.
  const auto imageShifts = [&](int a, float c, float* out) {
    int n = 0;
    out[n++] = 0.0f;
    if (!m_on[a]) return n;
    const double reach = 2.0 * m_cell + r, L = m_hi[a] - m_lo[a];
    if (c - m_lo[a] < reach) out[n++] = float(L);
    if (m_hi[a] - c < reach) out[n++] = float(-L);
    return n;
  };
  float sx[3], sy[3];
  const int nx = imageShifts(0, x.x, sx), ny = imageShifts(1, x.y, sy);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) addOne(Vec3f{x.x + sx[i], x.y + sy[j], x.z}, r);
}

void SphereHash::addOne(Vec3f x, float r) {
  const std::uint32_t k = static_cast<std::uint32_t>(m_x.size());
  m_x.push_back(x);
  m_r.push_back(r);
  const std::int64_t lo[3] = {cellOf(double(x.x) - r), cellOf(double(x.y) - r), cellOf(double(x.z) - r)};
  const std::int64_t hi[3] = {cellOf(double(x.x) + r), cellOf(double(x.y) + r), cellOf(double(x.z) + r)};
  const double cells = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
  if (cells > 512.0) {
    m_big.push_back(k);
    return;
  }
  for (std::int64_t a = lo[0]; a <= hi[0]; ++a)
    for (std::int64_t b = lo[1]; b <= hi[1]; ++b)
      for (std::int64_t c = lo[2]; c <= hi[2]; ++c) m_cells[cellKey(a, b, c)].push_back(k);
}

bool SphereHash::hits(Vec3f x, float r) const {
  const auto near = [&](std::uint32_t k) {
    const double dx = double(x.x) - m_x[k].x, dy = double(x.y) - m_x[k].y, dz = double(x.z) - m_x[k].z;
    const double s = (double(r) + m_r[k]) * (1.0 + 1e-5);
    return dx * dx + dy * dy + dz * dz < s * s;
  };
  for (std::uint32_t k : m_big)
    if (near(k)) return true;
  const std::int64_t c[3] = {cellOf(x.x), cellOf(x.y), cellOf(x.z)};
  for (std::int64_t a = c[0] - 1; a <= c[0] + 1; ++a)
    for (std::int64_t b = c[1] - 1; b <= c[1] + 1; ++b)
      for (std::int64_t d = c[2] - 1; d <= c[2] + 1; ++d) {
        const auto it = m_cells.find(cellKey(a, b, d));
        if (it == m_cells.end()) continue;
        for (std::uint32_t k : it->second)
          if (near(k)) return true;
      }
  return false;
}

MeshObstacles::MeshObstacles(const Scene& scene, const LocalFrame& f)
    : m_scene(scene),
      m_mesh(std::make_shared<const KernelMesh>(meshTriangleCount(scene) > 0 ? kernelMesh(scene, f) : KernelMesh{})) {}

MeshObstacles MeshObstacles::posed(const std::vector<MeshPose>& poses) const {
  MeshObstacles out = *this;
  out.m_poses = poses;
  return out;
}

bool MeshObstacles::clear(Vec3f x, float r) const {
  return m_mesh->numTriangles() == 0 ||
         findMeshContacts(*m_mesh, {x.x, x.y, x.z}, {r * (1.0f + 1e-5f)}, m_poses).empty();
}

bool MeshObstacles::inside(std::size_t wall, Vec3f x) const {
  const MeshView v = m_mesh->view(m_poses);
  const std::uint32_t plane = (m_scene.ground.enabled ? 1u : 0u) + static_cast<std::uint32_t>(wall);
  return pointInsideMesh(*m_mesh, m_scene, wall, meshPoint(v, plane, x));
}

Vec3f MeshObstacles::placed(std::size_t wall, Vec3f y) const {
  const std::size_t plane = (m_scene.ground.enabled ? 1u : 0u) + wall;
  if (plane >= m_poses.size() || m_poses[plane].posed == 0u) return y;
  const MeshPose& p = m_poses[plane];
  return mul(p.rot, y - p.pivot) + p.centre;
}

RegionFrame::RegionFrame(const FillRegion& g, const Scene& scene, const LocalFrame& f, const MeshObstacles& m)
    : region(g), meshes(&m) {
  if (g.kind == FillRegion::Kind::Mesh) {  // sampled in the box of its vertices
    region.min = Vec3f{FLT_MAX, FLT_MAX, FLT_MAX};
    region.max = Vec3f{-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (const Vec3f& v : meshWallVertices(scene.walls[g.wall], f)) {
      region.min = Vec3f{std::min(region.min.x, v.x), std::min(region.min.y, v.y), std::min(region.min.z, v.z)};
      region.max = Vec3f{std::max(region.max.x, v.x), std::max(region.max.y, v.y), std::max(region.max.z, v.z)};
    }
    return;
  }
  if (g.kind != FillRegion::Kind::Cylinder) return;
  length = std::sqrt(double(g.axis.x) * g.axis.x + double(g.axis.y) * g.axis.y + double(g.axis.z) * g.axis.z);
  a[0] = g.axis.x / length, a[1] = g.axis.y / length, a[2] = g.axis.z / length;
  perpendicularPair(a, e1, e2);
}

bool RegionFrame::inside(Vec3f x, float r) const {
  const FillRegion& g = region;
  if (g.kind == FillRegion::Kind::Mesh) return meshes->inside(g.wall, x);
  if (g.kind == FillRegion::Kind::Box)
    return x.x - r >= g.min.x && x.x + r <= g.max.x && x.y - r >= g.min.y && x.y + r <= g.max.y &&
           x.z - r >= g.min.z && x.z + r <= g.max.z;
  const double d[3] = {double(x.x) - g.point.x, double(x.y) - g.point.y, double(x.z) - g.point.z};
  const double s = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
  const double q[3] = {d[0] - s * a[0], d[1] - s * a[1], d[2] - s * a[2]};
  return s >= r && s <= length - r && std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) <= double(g.radius) - r;
}

Vec3f RegionFrame::point(float u1, float u2, float u3) const {
  const FillRegion& g = region;
  if (g.kind != FillRegion::Kind::Cylinder) {
    const Vec3f y{float(g.min.x + double(u1) * (double(g.max.x) - g.min.x)),
                  float(g.min.y + double(u2) * (double(g.max.y) - g.min.y)),
                  float(g.min.z + double(u3) * (double(g.max.z) - g.min.z))};
    return g.kind == FillRegion::Kind::Mesh ? meshes->placed(g.wall, y) : y;  // a mesh's box where it was given
  }
  const double s = double(u1) * length, rho = double(g.radius) * std::sqrt(double(u2));
  const double phi = 6.283185307179586 * double(u3), c = rho * std::cos(phi), d = rho * std::sin(phi);
  return Vec3f{float(g.point.x + s * a[0] + c * e1[0] + d * e2[0]), float(g.point.y + s * a[1] + c * e1[1] + d * e2[1]),
               float(g.point.z + s * a[2] + c * e1[2] + d * e2[2])};
}

bool placeBody(Rng& rng, const RegionFrame& g, const std::vector<Ball>& balls, SphereHash& hash,
               const std::vector<Wall>& walls, const MeshObstacles& meshes, std::uint64_t attempts,
               bool drawOrientation, bool randomOrientation, Vec3f* position, Quatf* q) {
  for (std::uint64_t attempt = 0; attempt < attempts; ++attempt) {
    const float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    const Vec3f x0 = g.point(u1, u2, u3);
    if (drawOrientation) {
      const float o1 = rng.uniform(), o2 = rng.uniform(), o3 = rng.uniform();
      *q = randomOrientation ? randomRotation(o1, o2, o3) : Quatf{1, 0, 0, 0};
    }
    if (!hash.centreInBox(x0)) continue;
    const Mat3f R = rotationMatrix(*q);
    const bool fits = std::all_of(balls.begin(), balls.end(), [&](const Ball& s) {
      const Vec3f x = x0 + mul(R, s.u);
      if (!g.inside(x, s.r) || hash.hits(x, s.r)) return false;
      return std::all_of(walls.begin(), walls.end(), [&](const Wall& w) { return wallGap(w, x) >= s.r; }) &&
             meshes.clear(x, s.r);
    });
    if (!fits) continue;
    for (const Ball& s : balls) hash.add(x0 + mul(R, s.u), s.r);
    *position = x0;
    return true;
  }
  return false;
}

std::uint32_t drawShape(Scene& scene, Rng& rng, const std::vector<std::uint32_t>& shapes,
                        const std::vector<double>& weights, const SizeDistribution& size,
                        std::map<std::pair<std::uint32_t, float>, std::uint32_t>& scaled, const std::string& where) {
  double total = 0.0;
  for (double w : weights) total += w;
  double pick = double(rng.uniform()) * total;
  std::size_t k = 0;
  while (k + 1 < shapes.size() && pick >= weights[k]) pick -= weights[k++];
  const float factor = size.draw(rng);
  const std::uint32_t shape = shapes[k];
  if (factor == 1.0f) return shape;
  const auto [it, fresh] = scaled.try_emplace({shape, factor}, static_cast<std::uint32_t>(scene.shapes.size()));
  if (fresh) {
    ShapeDef sh = scene.shapes[shape];
    char name[64];
    std::snprintf(name, sizeof name, " x %.6g", double(factor));
    sh.name += name;
    const float m = factor * factor * factor;
    for (SphereDef& s : sh.spheres) {
      s.offset = factor * s.offset;
      s.radius *= factor;
      s.mass *= m;
    }
    if (sh.solid) sh.solid = sh.solid->scaled(double(factor));
    if (const std::string why = shapeOutOfRange(sh, scene.contact.rotatesSpheres(), scene.gravity); !why.empty())
      throw Error(where + ": shape '" + printable(sh.name) + "': " + why);
    scene.shapes.push_back(sh);
  }
  return it->second;
}

void drawMotion(Rng& rng, Vec3f velocity, float jitter, float spin, BodyDef* b) {
  const float vx = rng.uniform(-jitter, jitter);
  const float vy = rng.uniform(-jitter, jitter);
  const float vz = rng.uniform(-jitter, jitter);
  b->velocity = Vec3f{velocity.x + vx, velocity.y + vy, velocity.z + vz};
  const float w1 = rng.uniform(), w2 = rng.uniform();
  if (spin > 0.0f) b->angularVelocity = randomDirection(w1, w2, spin);
}

}  // namespace detail

void fillScene(Scene& scene, const FillDef& def) {
  using namespace detail;
  if (def.count == 0) return;
  // The spheres each shape puts about its centre of mass; the scaled shapes made so far.
  std::vector<std::vector<Ball>> balls(scene.shapes.size());
  for (std::size_t s = 0; s < scene.shapes.size(); ++s) balls[s] = ballsOf(scene.shapes[s]);
  float largest = 0.0f;
  for (std::uint32_t s : def.shapes)
    for (const Ball& b : balls[s]) largest = std::max(largest, b.r);
  SphereHash hash(2.0 * double(largest) * std::max(1.0f, def.size.max()));
  hash.setPeriodic(scene.periodic, LocalFrame{});
  for (const BodyDef& b : scene.bodies) {
    const Mat3f R = rotationMatrix(b.orientation);
    for (const Ball& s : balls[b.shape]) hash.add(b.position + mul(R, s.u), s.r);
  }
  // The ground, the walls and the meshes where they are at t = 0.
  const std::vector<Wall> walls = kernelWalls(scene, LocalFrame{});
  const MeshObstacles meshes(scene, LocalFrame{});
  const RegionFrame g(def.region, scene, LocalFrame{}, meshes);
  std::map<std::pair<std::uint32_t, float>, std::uint32_t> scaled;  // (shape, factor) → index
  Rng rng(def.seed);
  for (std::uint64_t n = 0; n < def.count; ++n) {
    BodyDef b;
    b.shape = drawShape(scene, rng, def.shapes, def.weights, def.size, scaled, def.where);
    if (b.shape >= balls.size()) balls.push_back(ballsOf(scene.shapes[b.shape]));
    if (!placeBody(rng, g, balls[b.shape], hash, walls, meshes, def.attempts, true, def.randomOrientation,
                   &b.position, &b.orientation)) {
      char buf[320];
      std::snprintf(buf, sizeof buf, ": placed %llu of %llu bodies; body %llu found no free place in %llu draws: the "
                    "region is too full for random packing (it reaches about a third of the volume at most); use a "
                    "larger region, fewer or smaller bodies, or more attempts",
                    static_cast<unsigned long long>(n), static_cast<unsigned long long>(def.count),
                    static_cast<unsigned long long>(n + 1), static_cast<unsigned long long>(def.attempts));
      throw Error(def.where + buf);
    }
    drawMotion(rng, def.velocity, def.velocityJitter, def.spin, &b);
    scene.bodies.push_back(b);
  }
}

}  // namespace tumble
