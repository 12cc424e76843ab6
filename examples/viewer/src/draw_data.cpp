// SPDX-License-Identifier: MIT
// Building the renderer's input on the CPU: particle centres, colours, force lines and walls.
#include "tumble/viewer/draw_data.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <utility>

#include "tumble/error.hpp"

namespace tumble::viewer {
namespace {

// Twelve well-separated body colours (plain mode), medium brightness so lighting reads well.
constexpr Rgb kPalette[] = {{0.90f, 0.45f, 0.35f}, {0.35f, 0.65f, 0.90f}, {0.95f, 0.75f, 0.30f},
                            {0.45f, 0.80f, 0.45f}, {0.75f, 0.50f, 0.85f}, {0.30f, 0.80f, 0.80f},
                            {0.95f, 0.55f, 0.70f}, {0.70f, 0.70f, 0.35f}, {0.55f, 0.55f, 0.95f},
                            {0.90f, 0.60f, 0.20f}, {0.50f, 0.85f, 0.65f}, {0.85f, 0.40f, 0.55f}};

Rgb lerp(Rgb a, Rgb b, float t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }

// Normalised value in [0, 1] over the column's range (0.5 when every value is equal).
std::vector<float> normalised(const std::vector<float>& v) {
  std::vector<float> t(v.size(), 0.5f);
  if (v.empty()) return t;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  if (*hi > *lo)
    for (std::size_t i = 0; i < v.size(); ++i) t[i] = (v[i] - *lo) / (*hi - *lo);
  return t;
}

}  // namespace

std::optional<Rgb> rgbFromString(const std::string& text) {
  if (text == "black") return Rgb{0.0f, 0.0f, 0.0f};
  if (text == "white") return Rgb{1.0f, 1.0f, 1.0f};
  if (text == "grey" || text == "gray") return Rgb{0.5f, 0.5f, 0.5f};
  if (text.size() != 7 || text[0] != '#') return std::nullopt;
  const auto digit = [](char h) {
    if (h >= '0' && h <= '9') return h - '0';
    if (h >= 'a' && h <= 'f') return h - 'a' + 10;
    if (h >= 'A' && h <= 'F') return h - 'A' + 10;
    return -1;
  };
  float c[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const int hi = digit(text[1 + 2 * i]), lo = digit(text[2 + 2 * i]);
    if (hi < 0 || lo < 0) return std::nullopt;
    c[i] = float(16 * hi + lo) / 255.0f;
  }
  return Rgb{c[0], c[1], c[2]};
}

Look parseLook(const std::string& background, const std::string& ground) {
  static const std::string colours = "black, white, grey (gray) or #RRGGBB (hex, e.g. #ffffff)";
  Look look;
  if (background != "default") {
    const auto c = rgbFromString(background);
    if (!c) throw Error("--background " + background + ": expected default or a colour: " + colours);
    look.background = *c;
  }
  if (ground == "off") {
    look.ground = false;
  } else if (ground != "on") {
    const auto c = rgbFromString(ground);
    if (!c) throw Error("--ground " + ground + ": expected on (coloured by the pulls), off or a colour: " + colours);
    look.groundColor = c;
  }
  return look;
}

void applyLook(const Look& look, DrawData& d) {
  d.background = look.background;
  d.groundColor = look.groundColor;
  d.groundEnabled = d.groundEnabled && look.ground;
}

Rgb rampColor(ColorMode mode, float t) {
  switch (mode) {
    case ColorMode::Mass: return lerp({1.0f, 0.93f, 0.70f}, {0.55f, 0.05f, 0.05f}, t);    // cream → dark red
    case ColorMode::Speed: return lerp({0.88f, 0.97f, 0.72f}, {0.05f, 0.38f, 0.15f}, t);   // pale → dark green
    case ColorMode::Height: return lerp({0.93f, 0.86f, 1.0f}, {0.32f, 0.05f, 0.45f}, t);   // lilac → deep purple
    case ColorMode::User:  // yellow → teal → dark purple (viridis, reversed: light to dark)
      return t < 0.5f ? lerp({0.99f, 0.91f, 0.15f}, {0.13f, 0.57f, 0.55f}, 2.0f * t)
                      : lerp({0.13f, 0.57f, 0.55f}, {0.27f, 0.0f, 0.33f}, 2.0f * t - 1.0f);
    default: return lerp({0.80f, 0.95f, 1.0f}, {0.05f, 0.15f, 0.55f}, t);                   // ice → navy
  }
}

std::vector<std::uint32_t> bodyShapes(const ParticleTable& table) {
  std::uint32_t numBodies = 0;
  for (const std::uint32_t b : table.body) numBodies = std::max(numBodies, b + 1);
  std::vector<std::vector<float>> key(numBodies);
  for (std::size_t i = 0; i < table.size(); ++i)
    key[table.body[i]].insert(key[table.body[i]].end(), {table.ux[i], table.uy[i], table.uz[i], table.radius[i],
                                                         table.mass[i], table.elasticity[i]});
  std::map<std::vector<float>, std::uint32_t> shapes;
  std::vector<std::uint32_t> out(numBodies);
  for (std::uint32_t b = 0; b < numBodies; ++b)
    out[b] = shapes.emplace(std::move(key[b]), static_cast<std::uint32_t>(shapes.size())).first->second;
  return out;
}

std::vector<float> bodySpeeds(const RecordedFrame& f, const RecordedFrame& other) {
  std::vector<float> v(f.numBodies(), 0.0f);
  const double dt = std::abs(f.time - other.time);
  if (!(dt > 0.0)) return v;
  for (std::size_t k = 0; k < std::min(f.numBodies(), other.numBodies()); ++k)
    v[k] = static_cast<float>(norm(Vec3f{f.px[k] - other.px[k], f.py[k] - other.py[k], f.pz[k] - other.pz[k]}) / dt);
  return v;
}

void frameValues(ColorMode mode, const ParticleTable& table, const std::vector<float>& spheres,
                 const std::vector<float>& speeds, std::vector<float>& out) {
  const std::size_t n = spheres.size() / 4;
  out.assign(n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    if (mode == ColorMode::Height) out[i] = spheres[4 * i + 2];
    else if (mode == ColorMode::Speed && table.body[i] < speeds.size()) out[i] = speeds[table.body[i]];
  }
}

void rampColors(ColorMode mode, const std::vector<float>& values, float lo, float hi, std::vector<float>& out) {
  out.resize(3 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float t = hi > lo ? std::clamp((values[i] - lo) / (hi - lo), 0.0f, 1.0f) : 0.5f;
    const Rgb c = rampColor(mode, t);
    out[3 * i] = c.r;
    out[3 * i + 1] = c.g;
    out[3 * i + 2] = c.b;
  }
}

float quantile(std::vector<float>& v, double q) {
  if (v.empty()) return 0.0f;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(std::clamp(q, 0.0, 1.0) * double(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

ParticleTable ParticleTable::from(const Recording& rec) {
  return {rec.radius, rec.mass, rec.elasticity, rec.body, rec.ux, rec.uy, rec.uz};
}

ParticleTable ParticleTable::from(const World& w) { return {w.radius, w.mass, w.elasticity, w.body, w.ux, w.uy, w.uz}; }

float ParticleTable::maxRadius() const {
  return radius.empty() ? 0.0f : *std::max_element(radius.begin(), radius.end());
}

std::vector<float> particleColors(const ParticleTable& table, ColorMode mode) {
  const std::size_t n = table.size();
  std::vector<float> out(3 * n);
  std::vector<float> t(n, 0.0f);
  if (mode == ColorMode::Mass) t = normalised(table.mass);
  if (mode == ColorMode::Elasticity) t = normalised(table.elasticity);
  const std::vector<std::uint32_t> shape = mode == ColorMode::Shape ? bodyShapes(table) : std::vector<std::uint32_t>();
  for (std::size_t i = 0; i < n; ++i) {
    const Rgb c = mode == ColorMode::Plain   ? kPalette[(table.body[i] * 7u + 3u) % std::size(kPalette)]
                  : mode == ColorMode::Shape ? kPalette[shape[table.body[i]] % std::size(kPalette)]
                                             : rampColor(mode, t[i]);
    out[3 * i] = c.r;
    out[3 * i + 1] = c.g;
    out[3 * i + 2] = c.b;
  }
  return out;
}

void particleSpheres(const ParticleTable& table, const float* px, const float* py, const float* pz,
                     const float* qw, const float* qx, const float* qy, const float* qz, std::vector<float>& out,
                     std::size_t count) {
  const std::size_t n = std::min(count, table.size());
  out.resize(4 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t k = table.body[i];
    const Vec3f x = Vec3f{px[k], py[k], pz[k]} +
                    rotate(Quatf{qw[k], qx[k], qy[k], qz[k]}, Vec3f{table.ux[i], table.uy[i], table.uz[i]});
    out[4 * i] = x.x;
    out[4 * i + 1] = x.y;
    out[4 * i + 2] = x.z;
    out[4 * i + 3] = table.radius[i];
  }
}

void forceLines(const ParticleTable& table, const std::vector<float>& spheres, const ParticleDebug& debug,
                const bool show[kNumForces], std::vector<float>& outLines) {
  outLines.clear();
  const std::size_t n = std::min(table.size(), spheres.size() / 4);  // the particles present
  // A robust scale: the 90th percentile of the non-zero magnitudes (over the shown kinds) is
  // drawn 2.5 largest radii long, and no line is longer than 6 radii. Scaling by the maximum
  // would let one hard impact shrink every other line inside its sphere.
  std::vector<float> mags;
  for (int k = 0; k < kNumForces; ++k) {
    if (!show[k] || debug.force[k].size() != 3 * n) continue;
    const auto& f = debug.force[k];
    for (std::size_t i = 0; i < n; ++i) {
      const float m = norm(Vec3f{f[3 * i], f[3 * i + 1], f[3 * i + 2]});
      if (m > 0.0f) mags.push_back(m);
    }
  }
  if (mags.empty()) return;
  const auto p90 = mags.begin() + static_cast<std::ptrdiff_t>(mags.size() * 9 / 10);
  std::nth_element(mags.begin(), p90, mags.end());
  const float rMax = table.maxRadius();
  const float scale = 2.5f * rMax / *p90, maxLen = 6.0f * rMax;
  for (int k = 0; k < kNumForces; ++k) {
    if (!show[k] || debug.force[k].size() != 3 * n) continue;
    const auto& f = debug.force[k];
    const Rgb c = forceColor(k);
    for (std::size_t i = 0; i < n; ++i) {
      if (f[3 * i] == 0.0f && f[3 * i + 1] == 0.0f && f[3 * i + 2] == 0.0f) continue;
      const float x = spheres[4 * i], y = spheres[4 * i + 1], z = spheres[4 * i + 2];
      const Vec3f fv{f[3 * i], f[3 * i + 1], f[3 * i + 2]};
      const float len = std::min(maxLen, scale * norm(fv));
      const Vec3f e = (len / norm(fv)) * fv;
      outLines.insert(outLines.end(), {x, y, z, c.r, c.g, c.b, x + e.x, y + e.y, z + e.z, c.r, c.g, c.b});
    }
  }
}

Bounds sphereBounds(const std::vector<float>& spheres) {
  Bounds b;
  for (std::size_t i = 0; i + 3 < spheres.size(); i += 4)
    b.add(Vec3f{spheres[i], spheres[i + 1], spheres[i + 2]}, spheres[i + 3]);
  return b;
}

Bounds robustBounds(const std::vector<float>& spheres) {
  const std::size_t n = spheres.size() / 4;
  if (n < 100) return sphereBounds(spheres);
  const std::size_t lo = n / 100, hi = n - 1 - n / 100;
  Bounds b;
  std::vector<float> v(n);
  float out[2][3];
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side < 2; ++side) {
      const float sign = side == 0 ? -1.0f : 1.0f;
      for (std::size_t i = 0; i < n; ++i) v[i] = spheres[4 * i + a] + sign * spheres[4 * i + 3];
      const auto at = v.begin() + static_cast<std::ptrdiff_t>(side == 0 ? lo : hi);
      std::nth_element(v.begin(), at, v.end());
      out[side][a] = *at;
    }
  }
  b.add(Vec3f{out[0][0], out[0][1], out[0][2]}, 0.0f);
  b.add(Vec3f{out[1][0], out[1][1], out[1][2]}, 0.0f);
  return b;
}

Bounds recordingBounds(RecordingReader& rec, const ParticleTable& table, std::vector<double>* times,
                       std::vector<Bounds>* perFrame,
                       const std::function<void(const RecordedFrame&, const std::vector<float>&)>& visit,
                       std::size_t first, std::size_t last) {
  Bounds b;
  std::vector<float> s;
  RecordedFrame f;
  if (times) times->clear();
  if (perFrame) perFrame->clear();
  const bool ground = rec.info().groundEnabled;
  for (std::size_t k = first; k < rec.numFrames() && k <= last; ++k) {
    rec.readFrame(k, f);
    if (times) times->push_back(f.time);
    particleSpheres(table, f.px.data(), f.py.data(), f.pz.data(), f.qw.data(), f.qx.data(), f.qy.data(), f.qz.data(), s,
                    rec.header().particlesOf(f.numBodies()));
    if (visit) visit(f, s);
    Bounds fb = robustBounds(s);
    if (!fb.empty) {
      b.add(fb.lo, 0.0f);
      b.add(fb.hi, 0.0f);
      if (ground) fb.lo.z = std::min(std::max(fb.lo.z, rec.info().groundHeight), fb.hi.z);
    }
    if (perFrame) perFrame->push_back(fb);
  }
  if (ground && !b.empty) b.lo.z = std::min(std::max(b.lo.z, rec.info().groundHeight), b.hi.z);
  return framedWithWalls(b, rec.header().walls);
}

Rgb wallColor(WallKind kind) {
  switch (kind) {
    case WallKind::Plane: return {0.62f, 0.70f, 0.82f};
    case WallKind::Cylinder: return {0.70f, 0.74f, 0.80f};
    case WallKind::Cone: return {0.74f, 0.72f, 0.80f};
    case WallKind::Disk: return {0.66f, 0.76f, 0.78f};
    case WallKind::Mesh: return {0.78f, 0.74f, 0.66f};
  }
  return {0.7f, 0.7f, 0.7f};
}

std::vector<WallMesh> wallMeshes(const std::vector<WallSurface>& walls) {
  // Corners are welded by their exact bits: the geometry computes a shared corner once, so
  // neighbours agree to the bit (wall_geometry.cpp).
  using Key = std::array<std::uint32_t, 3>;
  const auto key = [](const float* p) {
    return Key{std::bit_cast<std::uint32_t>(p[0]), std::bit_cast<std::uint32_t>(p[1]), std::bit_cast<std::uint32_t>(p[2])};
  };
  const float kCrease = 0.866f;  // cos 30°
  std::vector<WallMesh> out;
  out.reserve(walls.size());
  for (const WallSurface& w : walls) {
    WallMesh m;
    m.color = wallColor(w.kind);
    m.motion = w.motion;
    const std::size_t nt = w.numTriangles();
    const float* t = w.triangles.data();
    std::vector<Vec3f> face(nt);
    std::map<Key, std::vector<std::size_t>> at;  // corner position -> triangles there
    std::map<std::pair<Key, Key>, std::vector<std::size_t>> edges;  // (lower, higher) -> triangles
    for (std::size_t i = 0; i < nt; ++i) {
      const float* c = t + 9 * i;
      const Vec3f n = cross(Vec3f{c[3] - c[0], c[4] - c[1], c[5] - c[2]}, Vec3f{c[6] - c[0], c[7] - c[1], c[8] - c[2]});
      const float len = norm(n);
      face[i] = len > 0.0f ? (1.0f / len) * n : Vec3f{0.0f, 0.0f, 0.0f};
      for (int k = 0; k < 3; ++k) {
        at[key(c + 3 * k)].push_back(i);
        m.bounds.add(Vec3f{c[3 * k], c[3 * k + 1], c[3 * k + 2]}, 0.0f);
        const Key a = key(c + 3 * k), b = key(c + 3 * ((k + 1) % 3));
        edges[std::minmax(a, b)].push_back(i);
      }
    }
    m.vertices.reserve(18 * nt);
    for (std::size_t i = 0; i < nt; ++i)
      for (int k = 0; k < 3; ++k) {
        const float* c = t + 9 * i + 3 * k;
        Vec3f n{0.0f, 0.0f, 0.0f};
        for (const std::size_t j : at[key(c)])
          if (dot(face[i], face[j]) >= kCrease) n += face[j];
        const float len = norm(n);
        if (len > 0.0f) n = (1.0f / len) * n;
        m.vertices.insert(m.vertices.end(), {c[0], c[1], c[2], n.x, n.y, n.z});
      }
    for (const auto& [e, tris] : edges) {
      const bool fold = tris.size() == 2 && dot(face[tris[0]], face[tris[1]]) < kCrease;
      if (tris.size() != 1 && !fold) continue;
      for (const Key& k : {e.first, e.second})
        for (const std::uint32_t v : k) m.outline.push_back(std::bit_cast<float>(v));
    }
    out.push_back(std::move(m));
  }
  return out;
}

Bounds framedWithWalls(const Bounds& bodies, const std::vector<WallSurface>& walls) {
  if (bodies.empty) return bodies;
  Bounds b = bodies;
  const float limit = 4.0f * norm(bodies.hi - bodies.lo);
  // A plane that meets another (a corner of one within a millionth of the walls' size of a corner
  // of the other) is a container's face: a box's, open or closed. A lone plane meets none.
  const auto corners = [](const WallSurface& w) {
    std::vector<Vec3f> c;
    for (std::size_t i = 0; i + 2 < w.triangles.size(); i += 3) c.push_back({w.triangles[i], w.triangles[i + 1], w.triangles[i + 2]});
    return c;
  };
  Bounds all = bodies;
  for (const WallSurface& w : walls)
    for (const Vec3f& c : corners(w)) all.add(c, 0.0f);
  const float tol = 1e-6f * norm(all.hi - all.lo);
  const auto meetsAnotherPlane = [&](std::size_t k) {
    const std::vector<Vec3f> mine = corners(walls[k]);
    for (std::size_t j = 0; j < walls.size(); ++j) {
      if (j == k || walls[j].kind != WallKind::Plane) continue;
      for (const Vec3f& p : corners(walls[j]))
        for (const Vec3f& q : mine)
          if (norm(p - q) <= tol) return true;
    }
    return false;
  };
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const WallSurface& w = walls[k];
    if (w.triangles.empty() || (w.kind == WallKind::Plane && !meetsAnotherPlane(k))) continue;
    Bounds wb;
    for (std::size_t i = 0; i + 2 < w.triangles.size(); i += 3)
      wb.add(Vec3f{w.triangles[i], w.triangles[i + 1], w.triangles[i + 2]}, 0.0f);
    if (norm(wb.hi - wb.lo) > limit) continue;
    b.add(wb.lo, 0.0f);
    b.add(wb.hi, 0.0f);
  }
  return b;
}

}  // namespace tumble::viewer
