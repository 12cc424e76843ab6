// SPDX-License-Identifier: MIT
// Triangle-mesh walls on the host: the STL and OBJ reader, the kernels' mesh data and its
// hierarchy, and the queries built on them (mesh.hpp).
//
// Design notes
// - Our own reader. Debian has no small, maintained STL reader, and assimp is heavy and reports
//   no positions. Every refusal names the file and the line (text) or the byte offset (binary
//   STL), what is wrong and what to do; the input is untrusted (fuzz_mesh): every size is
//   checked before it is used, and nothing is allocated beyond what the bytes imply.
// - Welding. STL repeats each corner in every facet; the adjacency that the counting rule
//   needs (kernels/mesh.hpp) comes from welding corners whose coordinates are bit-identical
//   (−0 and +0 alike), in the file's coordinates, numbered in order of first appearance.
// - Determinism. Everything here is computed once at load, in double, and rounded once; the
//   hierarchy's shape changes only speed: the triangles a query returns are those whose own box
//   passes the test (forTrianglesNear()), and every caller sorts them by triangle.
#include "tumble/mesh.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"

namespace tumble {
namespace {

constexpr double kFloatMax = std::numeric_limits<float>::max();
constexpr double kUnit = 0x1p-24;  // u, the unit roundoff of float

std::string point(Vec3f v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
  return buf;
}

std::string extensionOf(const std::string& name) {
  const std::size_t dot = name.find_last_of('.');
  const std::size_t slash = name.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string e = name.substr(dot + 1);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

/// Welds corners into vertices and checks each triangle as it comes.
class MeshBuilder {
 public:
  explicit MeshBuilder(TriangleMesh& m) : m_mesh(m) {}

  std::uint32_t vertex(Vec3f v) {
    // +0.0f turns −0 into +0: the same point, the same key.
    const Vec3f k{v.x + 0.0f, v.y + 0.0f, v.z + 0.0f};
    std::array<std::uint32_t, 3> key;
    std::memcpy(key.data(), &k, sizeof key);
    const auto [it, added] = m_index.try_emplace(key, static_cast<std::uint32_t>(m_mesh.vertices.size()));
    if (added) m_mesh.vertices.push_back(k);
    return it->second;
  }

  /// Adds a triangle of welded vertices, refused when it is degenerate; `fail` reports at its
  /// source.
  template <class Fail>
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint64_t source, Fail&& fail) {
    const std::size_t t = m_mesh.numTriangles();
    if (t >= (std::size_t{1} << 31)) fail(source, "more than 2^31 triangles; split the mesh into several [[wall]]s");
    if (const std::string why = degenerateTriangle(m_mesh.vertices[a], m_mesh.vertices[b], m_mesh.vertices[c]);
        !why.empty())
      fail(source, "triangle " + std::to_string(t + 1) + " is degenerate: " + why + "; remove it from the mesh");
    m_mesh.triangles.insert(m_mesh.triangles.end(), {a, b, c});
    m_mesh.source.push_back(source);
  }

 private:
  struct KeyHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (std::uint32_t w : k) h = (h ^ w) * 1099511628211ull;
      return static_cast<std::size_t>(h);
    }
  };
  TriangleMesh& m_mesh;
  std::unordered_map<std::array<std::uint32_t, 3>, std::uint32_t, KeyHash> m_index;
};

/// A coordinate of a text mesh: a number (a leading '+' allowed), finite and within single
/// precision; `fail` reports why not.
template <class Fail>
float coordinate(std::string_view tok, const std::string& what, Fail&& fail) {
  std::string_view s = tok;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || res.ec == std::errc::invalid_argument || res.ptr != s.data() + s.size())
    fail(what + " must be a number (got '" + std::string(tok.substr(0, 40)) + "')");
  if (res.ec == std::errc::result_out_of_range) {  // from_chars: overflow or underflow
    if (std::abs(std::strtod(std::string(s).c_str(), nullptr)) > 1.0) fail(what + " " + std::string(tok.substr(0, 40)) +
                                                                              " is beyond single precision; scale the mesh in its file");
    return 0.0f;  // below the smallest double: 0
  }
  if (!std::isfinite(v)) fail(what + " must be a finite number (got " + std::string(tok.substr(0, 40)) + ")");
  if (std::abs(v) > kFloatMax)
    fail(what + " " + std::string(tok.substr(0, 40)) + " is beyond single precision (at most 3.4e38); scale the mesh in its file");
  return static_cast<float>(v);
}

/// Whitespace-separated tokens of a text, with their lines.
class Tokens {
 public:
  explicit Tokens(std::string_view text) : m_text(text) {}
  /// The next token (empty at the end); *line its line.
  std::string_view next(std::uint64_t* line) {
    skipSpace();
    *line = m_line;
    const std::size_t begin = m_pos;
    while (m_pos < m_text.size() && !isSpace(m_text[m_pos])) ++m_pos;
    return m_text.substr(begin, m_pos - begin);
  }
  /// Skips to the start of the next line.
  void skipLine() {
    while (m_pos < m_text.size() && m_text[m_pos] != '\n') ++m_pos;
  }
  std::uint64_t line() const { return m_line; }

 private:
  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  void skipSpace() {
    while (m_pos < m_text.size() && isSpace(m_text[m_pos])) {
      if (m_text[m_pos] == '\n') ++m_line;
      ++m_pos;
    }
  }
  std::string_view m_text;
  std::size_t m_pos = 0;
  std::uint64_t m_line = 1;
};

constexpr const char* kFacetForm =
    "an ASCII STL facet is 'facet normal nx ny nz', 'outer loop', three 'vertex x y z', 'endloop', 'endfacet'";

void parseAsciiStl(std::string_view text, TriangleMesh& m) {
  Tokens tok(text);
  MeshBuilder b(m);
  std::uint64_t line = 1;
  const auto failAt = [&](std::uint64_t at, const std::string& problem) -> void {
    throw InputError(m.file, static_cast<long>(at), problem);
  };
  const auto expect = [&](const char* word, const char* after) {
    const std::string_view t = tok.next(&line);
    if (t != word)
      failAt(line, std::string("expected '") + word + "' after " + after + " (got '" +
                       (t.empty() ? std::string("the end of the file") : std::string(t.substr(0, 40))) +
                       "'); " + kFacetForm + (t.empty() ? " (the file may be truncated)" : ""));
  };
  std::string_view t = tok.next(&line);
  if (t != "solid") failAt(line, "an ASCII STL starts with 'solid' (got '" + std::string(t.substr(0, 40)) + "')");
  tok.skipLine();  // the solid's name
  for (;;) {
    t = tok.next(&line);
    if (t.empty()) failAt(line, "missing 'endsolid' at the end: the file is truncated; export it again");
    if (t == "endsolid") {
      tok.skipLine();
      t = tok.next(&line);
      if (t.empty()) break;
      if (t != "solid")
        failAt(line, "expected the end of the file or another 'solid' after 'endsolid' (got '" +
                         std::string(t.substr(0, 40)) + "')");
      tok.skipLine();
      continue;
    }
    if (t != "facet")
      failAt(line, "expected 'facet' or 'endsolid' (got '" + std::string(t.substr(0, 40)) + "'); " + kFacetForm);
    const std::uint64_t facetLine = line;
    expect("normal", "'facet'");
    for (int k = 0; k < 3; ++k) {  // the normal is not read (the kernels compute theirs), but must be there
      const std::string_view n = tok.next(&line);
      if (n.empty()) failAt(line, "the facet's normal is cut short: the file is truncated; export it again");
    }
    expect("outer", "the facet's normal");
    expect("loop", "'outer'");
    std::uint32_t corner[3];
    for (int c = 0; c < 3; ++c) {
      expect("vertex", c == 0 ? "'outer loop'" : "a vertex");
      float v[3];
      for (int a = 0; a < 3; ++a) {
        const std::string_view n = tok.next(&line);
        if (n.empty()) failAt(line, "a vertex is cut short: the file is truncated; export it again");
        v[a] = coordinate(n, std::string("coordinate ") + "xyz"[a] + " of vertex " + std::to_string(c + 1) + " of facet " +
                                 std::to_string(m.numTriangles() + 1),
                          [&](const std::string& why) { failAt(line, why); });
      }
      corner[c] = b.vertex(Vec3f{v[0], v[1], v[2]});
    }
    expect("endloop", "the third vertex (a facet has exactly three)");
    expect("endfacet", "'endloop'");
    b.triangle(corner[0], corner[1], corner[2], facetLine, failAt);
  }
}

void parseBinaryStl(std::string_view bytes, TriangleMesh& m) {
  const auto failAt = [&](std::uint64_t at, const std::string& problem) -> void {
    throw InputError(m.file, 0, "byte " + std::to_string(at) + ": " + problem);
  };
  m.binary = true;
  if (bytes.size() < 84)
    failAt(bytes.size(), "too short for a binary STL (an 80-byte header and a triangle count, 84 bytes; the file has " +
                             std::to_string(bytes.size()) + ") and not an ASCII STL (which starts with 'solid')");
  std::uint32_t count;
  std::memcpy(&count, bytes.data() + 80, 4);  // little-endian on the hosts tumble builds on
  const std::uint64_t need = 84 + 50 * std::uint64_t(count);
  if (need != bytes.size())
    failAt(80, "the header gives " + std::to_string(count) + " triangles, which need " + std::to_string(need) +
                   " bytes, and the file has " + std::to_string(bytes.size()) +
                   (need > bytes.size() ? ": it is truncated; export it again" : ": bytes follow its last triangle; export it again"));
  MeshBuilder b(m);
  m.triangles.reserve(3 * std::size_t(count));
  m.source.reserve(count);
  for (std::uint64_t t = 0; t < count; ++t) {
    const std::uint64_t at = 84 + 50 * t;
    std::uint32_t corner[3];
    for (int c = 0; c < 3; ++c) {
      float v[3];
      std::memcpy(v, bytes.data() + at + 12 + 12 * c, 12);
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite(v[a]))
          failAt(at + 12 + 12 * c + 4 * a, std::string("coordinate ") + "xyz"[a] + " of vertex " + std::to_string(c + 1) +
                                               " of triangle " + std::to_string(t + 1) + " is not finite; fix the mesh");
      corner[c] = b.vertex(Vec3f{v[0], v[1], v[2]});
    }
    b.triangle(corner[0], corner[1], corner[2], at, [&](std::uint64_t a, const std::string& why) { failAt(a, why); });
  }
}

void parseObj(std::string_view text, TriangleMesh& m) {
  MeshBuilder b(m);
  std::vector<std::uint32_t> welded;  // the OBJ's vertices (1-based in the file) as welded vertices
  std::size_t pos = 0;
  std::uint64_t line = 0;
  const auto failAt = [&](std::uint64_t at, const std::string& problem) -> void {
    throw InputError(m.file, static_cast<long>(at), problem);
  };
  // Faces are resolved when read: OBJ indices refer to the vertices defined before them.
  std::vector<std::string_view> words;
  while (pos < text.size()) {
    ++line;
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(pos, end - pos);
    pos = end + 1;
    if (const std::size_t hash = l.find('#'); hash != std::string_view::npos) l = l.substr(0, hash);
    words.clear();
    for (std::size_t i = 0; i < l.size();) {
      while (i < l.size() && (l[i] == ' ' || l[i] == '\t' || l[i] == '\r')) ++i;
      const std::size_t s = i;
      while (i < l.size() && l[i] != ' ' && l[i] != '\t' && l[i] != '\r') ++i;
      if (i > s) words.push_back(l.substr(s, i - s));
    }
    if (words.empty()) continue;
    const auto fail = [&](const std::string& why) { failAt(line, why); };
    if (words[0] == "v") {
      if (words.size() < 4) fail("a vertex needs three coordinates, 'v x y z' (got " + std::to_string(words.size() - 1) + ")");
      float v[3];
      for (int a = 0; a < 3; ++a)
        v[a] = coordinate(words[1 + a], std::string("coordinate ") + "xyz"[a] + " of vertex " +
                                            std::to_string(welded.size() + 1), fail);
      welded.push_back(b.vertex(Vec3f{v[0], v[1], v[2]}));
    } else if (words[0] == "f") {
      if (words.size() < 4)
        fail("a face needs at least three vertices, 'f i j k' (got " + std::to_string(words.size() - 1) + ")");
      std::vector<std::uint32_t> ref(words.size() - 1);
      for (std::size_t k = 1; k < words.size(); ++k) {
        const std::string_view w = words[k].substr(0, words[k].find('/'));  // v, v/vt, v//vn, v/vt/vn
        long long idx = 0;
        const auto res = std::from_chars(w.data(), w.data() + w.size(), idx);
        if (w.empty() || res.ec != std::errc() || res.ptr != w.data() + w.size())
          fail("vertex " + std::to_string(k) + " of the face must be an index, 'i', 'i/t', 'i//n' or 'i/t/n' (got '" +
               std::string(words[k].substr(0, 40)) + "')");
        const long long n = static_cast<long long>(welded.size());
        if (idx == 0) fail("vertex " + std::to_string(k) + " of the face: OBJ indices start at 1 (or count back from -1); 0 names no vertex");
        const long long at = idx > 0 ? idx - 1 : n + idx;  // negative: relative to the vertices so far
        if (at < 0 || at >= n)
          fail("vertex " + std::to_string(k) + " of the face is index " + std::to_string(idx) + ", and " +
               std::to_string(n) + " vertices are defined before this line; an index names a 'v' line above it");
        ref[k - 1] = welded[static_cast<std::size_t>(at)];
      }
      for (std::size_t k = 1; k + 1 < ref.size(); ++k)  // a fan: (0, k, k + 1)
        b.triangle(ref[0], ref[k], ref[k + 1], line, failAt);
    }
    // Anything else (vt, vn, o, g, s, usemtl, mtllib, l, p, …) says nothing about the surface.
  }
}

/// A triangle listed twice (the same three welded corners, in any order) would double the wall's
/// spring where a sphere touches it: refused at the later copy, naming the first.
void refuseRepeatedTriangles(const TriangleMesh& m) {
  struct Key {
    std::array<std::uint32_t, 3> corners;
    std::uint32_t triangle;
  };
  const std::size_t n = m.numTriangles();
  std::vector<Key> keys(n);
  for (std::size_t t = 0; t < n; ++t) {
    std::array<std::uint32_t, 3> c{m.triangles[3 * t], m.triangles[3 * t + 1], m.triangles[3 * t + 2]};
    std::sort(c.begin(), c.end());
    keys[t] = Key{c, static_cast<std::uint32_t>(t)};
  }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return a.corners != b.corners ? a.corners < b.corners : a.triangle < b.triangle;
  });
  std::size_t later = n, first = n;  // the earliest copy in the file, and what it repeats
  for (std::size_t k = 1; k < n; ++k)
    if (keys[k].corners == keys[k - 1].corners && keys[k].triangle < later) {
      std::size_t f = k - 1;
      while (f > 0 && keys[f - 1].corners == keys[k].corners) --f;
      later = keys[k].triangle;
      first = keys[f].triangle;
    }
  if (later == n) return;
  throw InputError(m.file, m.binary ? 0L : static_cast<long>(m.source[later]),
                   (m.binary ? "byte " + std::to_string(m.source[later]) + ": " : std::string()) + "triangle " +
                       std::to_string(later + 1) + " repeats triangle " + std::to_string(first + 1) + " (" +
                       m.where(first) + "): the same three corners; a triangle listed twice doubles the wall's "
                       "spring where a sphere touches it: remove the copy");
}

}  // namespace

std::string TriangleMesh::where(std::size_t t) const {
  if (t >= source.size()) return file;
  return binary ? file + ": byte " + std::to_string(source[t]) : file + ":" + std::to_string(source[t]);
}

TriangleMesh parseMesh(std::string_view bytes, const std::string& name) {
  TriangleMesh m;
  m.file = name;
  const std::string ext = extensionOf(name);
  if (ext == "obj") {
    parseObj(bytes, m);
  } else if (ext == "stl") {
    bool binary = true;
    if (bytes.size() >= 84) {
      std::uint32_t count;
      std::memcpy(&count, bytes.data() + 80, 4);
      binary = 84 + 50 * std::uint64_t(count) == bytes.size();
    }
    std::size_t s = 0;
    while (s < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[s]))) ++s;
    if (!binary || bytes.size() < 84) binary = !(bytes.substr(s, 5) == "solid");
    binary ? parseBinaryStl(bytes, m) : parseAsciiStl(bytes, m);
  } else {
    throw InputError(name, 0, "unknown mesh format '." + ext + "': give an STL (.stl, binary or ASCII) or an OBJ (.obj) file");
  }
  if (m.numTriangles() == 0)
    throw InputError(name, 0, "the mesh has no triangles (an empty solid, or vertices without faces); a mesh wall needs at least one");
  refuseRepeatedTriangles(m);
  return m;
}

TriangleMesh readMeshFile(const std::string& path) {
  return parseMesh(detail::readWholeFile(path, "the mesh file", detail::kMeshFileLimit), path);
}

std::vector<Vec3f> meshWallVertices(const WallDef& wall, const LocalFrame& f) {
  if (!wall.mesh) throw Error(wall.where + ": not a mesh wall");
  const Quatf& q = wall.orientation;
  const double qn = std::sqrt(double(q.w) * q.w + double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z);
  if (!(qn > 0.0) || !std::isfinite(qn)) throw Error(wall.where + ": the orientation must be a non-zero, finite quaternion");
  const double w = q.w / qn, x = q.x / qn, y = q.y / qn, z = q.z / qn;
  // R(q) of the unit quaternion, in double.
  const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  const double s[3] = {wall.scale.x, wall.scale.y, wall.scale.z};
  const double t[3] = {double(wall.point.x) - f.x, double(wall.point.y) - f.y, double(wall.point.z) - f.z};
  std::vector<Vec3f> out(wall.mesh->vertices.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const Vec3f& v = wall.mesh->vertices[k];
    const double a[3] = {s[0] * v.x, s[1] * v.y, s[2] * v.z};
    double p[3];
    for (int r = 0; r < 3; ++r) {
      p[r] = t[r] + R[r][0] * a[0] + R[r][1] * a[1] + R[r][2] * a[2];
      if (!withinExactRange(p[r]))
        throw Error(wall.where + ": vertex " + point(v) + " of " + wall.mesh->file +
                    " lies beyond +-2^60 m (1.15e18) once scaled, turned and placed, the range whose contacts single "
                    "precision decides right; use a smaller scale or position");
    }
    out[k] = Vec3f{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
  }
  return out;
}

std::vector<Vec3f> meshWallTriangles(const WallDef& wall) {
  const std::vector<Vec3f> v = meshWallVertices(wall);
  std::vector<Vec3f> out;
  out.reserve(wall.mesh->triangles.size());
  for (std::uint32_t i : wall.mesh->triangles) out.push_back(v[i]);
  return out;
}

std::uint32_t meshTriangleCount(const Scene& scene) {
  std::size_t n = 0;
  for (const WallDef& w : scene.walls)
    if (w.shape == WallDef::Shape::Mesh && w.mesh) n += w.mesh->numTriangles();
  return static_cast<std::uint32_t>(n);
}

std::string meshTriangleWhere(const Scene& scene, std::uint32_t t) {
  for (const WallDef& w : scene.walls) {
    if (w.shape != WallDef::Shape::Mesh || !w.mesh) continue;
    if (t < w.mesh->numTriangles())
      return (w.where.empty() ? std::string("a mesh wall") : w.where) + ", triangle " + std::to_string(t + 1) + " of " +
             w.mesh->file + " (" + w.mesh->where(t) + ")";
    t -= static_cast<std::uint32_t>(w.mesh->numTriangles());
  }
  return "mesh triangle " + std::to_string(t);
}

MeshView KernelMesh::view() const { return meshViewOf(*this); }

MeshView KernelMesh::view(const std::vector<MeshPose>& poses) const {
  MeshView v = view();
  if (!poses.empty() && !tri.empty()) {
    v.poses = poses.data();
    v.numPoses = static_cast<std::uint32_t>(poses.size());
  }
  return v;
}

namespace {

using Vec3d = std::array<double, 3>;
Vec3d toD(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d crossD(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dotD(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d unit(const Vec3d& a) {
  const double l = std::sqrt(dotD(a, a));
  return {a[0] / l, a[1] / l, a[2] / l};
}
Vec3f toF(const Vec3d& a) { return Vec3f{static_cast<float>(a[0]), static_cast<float>(a[1]), static_cast<float>(a[2])}; }

/// A float at most v (rounding towards −∞) or at least v.
float floatBelow(double v) {
  const float f = static_cast<float>(v);
  return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float floatAbove(double v) {
  const float f = static_cast<float>(v);
  return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

/// The outward normal of the plane through edge (a, b) of a triangle with normal n and third
/// corner c: perpendicular to the face, away from c.
Vec3d edgePlane(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& n) {
  Vec3d m = unit(crossD(sub(b, a), n));
  if (dotD(m, sub(c, a)) > 0.0) m = {-m[0], -m[1], -m[2]};
  return m;
}

/// Median splits of the triangles' centres along the longest axis of their bounds, 4 triangles
/// per leaf; the children of a node are adjacent (kernels/mesh.hpp).
class BvhBuilder {
 public:
  BvhBuilder(const std::vector<MeshTriangle>& tri, std::vector<MeshBvhNode>& nodes, std::vector<std::uint32_t>& prims)
      : m_tri(tri), m_nodes(nodes), m_prims(prims) {
    m_centre.resize(tri.size());
    for (std::size_t t = 0; t < tri.size(); ++t)
      for (int a = 0; a < 3; ++a) m_centre[t][a] = 0.5 * (double((&tri[t].lo.x)[a]) + (&tri[t].hi.x)[a]);
    m_prims.resize(tri.size());
    for (std::size_t t = 0; t < tri.size(); ++t) m_prims[t] = static_cast<std::uint32_t>(t);
    m_nodes.assign(1, MeshBvhNode{});
    build(0, 0, static_cast<std::uint32_t>(tri.size()), 0);
  }

 private:
  void build(std::uint32_t node, std::uint32_t begin, std::uint32_t end, int depth) {
    Vec3f lo = m_tri[m_prims[begin]].lo, hi = m_tri[m_prims[begin]].hi;
    double clo[3] = {1e300, 1e300, 1e300}, chi[3] = {-1e300, -1e300, -1e300};
    for (std::uint32_t k = begin; k < end; ++k) {
      const MeshTriangle& t = m_tri[m_prims[k]];
      lo = Vec3f{std::min(lo.x, t.lo.x), std::min(lo.y, t.lo.y), std::min(lo.z, t.lo.z)};
      hi = Vec3f{std::max(hi.x, t.hi.x), std::max(hi.y, t.hi.y), std::max(hi.z, t.hi.z)};
      for (int a = 0; a < 3; ++a) {
        clo[a] = std::min(clo[a], m_centre[m_prims[k]][a]);
        chi[a] = std::max(chi[a], m_centre[m_prims[k]][a]);
      }
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
    if (end - begin <= 4 || depth >= kMeshBvhMaxDepth - 1 || !(chi[axis] > clo[axis])) {
      m_nodes[node] = MeshBvhNode{lo, hi, begin, end - begin};
      return;
    }
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(m_prims.begin() + begin, m_prims.begin() + mid, m_prims.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return m_centre[a][axis] != m_centre[b][axis] ? m_centre[a][axis] < m_centre[b][axis] : a < b;
                     });
    const std::uint32_t child = static_cast<std::uint32_t>(m_nodes.size());
    m_nodes.resize(m_nodes.size() + 2);
    m_nodes[node] = MeshBvhNode{lo, hi, child, 0};
    build(child, begin, mid, depth + 1);
    build(child + 1, mid, end, depth + 1);
  }

  const std::vector<MeshTriangle>& m_tri;
  std::vector<MeshBvhNode>& m_nodes;
  std::vector<std::uint32_t>& m_prims;
  std::vector<std::array<double, 3>> m_centre;
};

/// CSR of the triangles incident to each of `count` keys, triangles ascending: keys[3t + j]
/// is the key of corner or edge j of triangle t.
void incidence(const std::vector<std::uint32_t>& keys, std::size_t count, std::vector<std::uint32_t>& offsets,
               std::vector<std::uint32_t>& tris) {
  offsets.assign(count + 1, 0u);
  for (std::uint32_t k : keys) ++offsets[k + 1];
  for (std::size_t k = 0; k < count; ++k) offsets[k + 1] += offsets[k];
  tris.resize(keys.size());
  std::vector<std::uint32_t> at(offsets.begin(), offsets.end() - 1);
  for (std::size_t e = 0; e < keys.size(); ++e) tris[at[keys[e]]++] = static_cast<std::uint32_t>(e / 3);
}

}  // namespace

std::string degenerateTriangle(Vec3f p, Vec3f q, Vec3f r) {
  const Vec3f c[3] = {p, q, r};
  double longest2 = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      const Vec3f e = c[j] - c[i];
      if (c[i].x == c[j].x && c[i].y == c[j].y && c[i].z == c[j].z)
        return "its corners " + std::to_string(i + 1) + " and " + std::to_string(j + 1) + " are the same point " + point(c[i]);
      if (!(dot(e, e) > 0.0f))
        return "its corners " + std::to_string(i + 1) + " and " + std::to_string(j + 1) + " (" + point(c[i]) + ", " +
               point(c[j]) + ") are too close for single precision (their squared distance is 0 there)";
      const Vec3d ed = sub(toD(c[j]), toD(c[i]));
      longest2 = std::max(longest2, dotD(ed, ed));
    }
  const Vec3d n = crossD(sub(toD(q), toD(p)), sub(toD(r), toD(p)));
  const double twiceArea = std::sqrt(dotD(n, n));
  if (!(twiceArea > 0.0)) return "its corners " + point(p) + ", " + point(q) + ", " + point(r) + " lie on one line (zero area)";
  const double thin = twiceArea / longest2;  // its smallest height over its longest edge
  if (!(thin >= kThinnestTriangle)) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "it is too thin for single precision: its smallest height is %.3g times its longest "
                  "edge (at least %.3g), at ", thin, kThinnestTriangle);
    return buf + point(p) + ", " + point(q) + ", " + point(r);
  }
  return {};
}

KernelMesh kernelMesh(const Scene& scene, const LocalFrame& f) {
  KernelMesh km;
  const std::uint32_t firstWall = scene.ground.enabled ? 1u : 0u;  // plane index of walls[0]
  std::vector<std::pair<std::uint32_t, std::uint32_t>> wallOf;      // per triangle: (wall, triangle in its file)
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const WallDef& w = scene.walls[k];
    if (w.shape != WallDef::Shape::Mesh) continue;
    const std::vector<Vec3f> v = meshWallVertices(w, f);
    const std::uint32_t base = static_cast<std::uint32_t>(km.vertices.size());
    km.vertices.insert(km.vertices.end(), v.begin(), v.end());
    for (std::size_t t = 0; t < w.mesh->numTriangles(); ++t) {
      for (int c = 0; c < 3; ++c) km.triangles.push_back(base + w.mesh->triangles[3 * t + c]);
      wallOf.emplace_back(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(t));
    }
  }
  const std::size_t nt = wallOf.size();
  if (nt == 0) return km;
  if (km.vertices.size() > 0xFFFFFFF0u || nt > (std::size_t{1} << 31)) throw Error("the mesh walls have too many triangles (limit 2^31)");
  km.tri.resize(nt);
  // Normals and boxes (double from the float corners, rounded once); a triangle that is
  // degenerate in single precision is refused here, naming it.
  std::vector<Vec3d> normal(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t* c = &km.triangles[3 * t];
    const Vec3f p = km.vertices[c[0]], q = km.vertices[c[1]], r = km.vertices[c[2]];
    const WallDef& w = scene.walls[wallOf[t].first];
    if (const std::string why = degenerateTriangle(p, q, r); !why.empty())
      throw Error(w.where + ": triangle " + std::to_string(wallOf[t].second + 1) + " (" +
                  w.mesh->where(wallOf[t].second) + ") is degenerate once scaled and placed: " + why +
                  "; use a larger scale, or remove it from the mesh");
    normal[t] = unit(crossD(sub(toD(q), toD(p)), sub(toD(r), toD(p))));
    MeshTriangle& tr = km.tri[t];
    tr.n = toF(normal[t]);
    tr.wall = firstWall + wallOf[t].first;
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min({double((&p.x)[a]), double((&q.x)[a]), double((&r.x)[a])});
      hi[a] = std::max({double((&p.x)[a]), double((&q.x)[a]), double((&r.x)[a])});
    }
    // The kernels' rounding of a distance to this triangle is a few u times its size (and the
    // sphere's reach, which the candidate list's margin covers): the box grows by 64 u × its
    // diagonal.
    const double pad = 64.0 * kUnit * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                                 (hi[2] - lo[2]) * (hi[2] - lo[2]));
    tr.lo = Vec3f{floatBelow(lo[0] - pad), floatBelow(lo[1] - pad), floatBelow(lo[2] - pad)};
    tr.hi = Vec3f{floatAbove(hi[0] + pad), floatAbove(hi[1] + pad), floatAbove(hi[2] + pad)};
  }
  // Edges: the corner pairs (lower index first), numbered in order of (lower, higher).
  struct EdgeKey {
    std::uint32_t a, b, entry;  // entry = 3 t + j
  };
  std::vector<EdgeKey> ek(3 * nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t p = km.triangles[3 * t + j], q = km.triangles[3 * t + (j + 1) % 3];
      ek[3 * t + j] = EdgeKey{std::min(p, q), std::max(p, q), static_cast<std::uint32_t>(3 * t + j)};
    }
  std::sort(ek.begin(), ek.end(), [](const EdgeKey& x, const EdgeKey& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.entry < y.entry;
  });
  km.triEdges.resize(3 * nt);
  std::uint32_t numEdges = 0;
  for (std::size_t k = 0; k < ek.size(); ++k) {
    if (k > 0 && (ek[k].a != ek[k - 1].a || ek[k].b != ek[k - 1].b)) ++numEdges;
    km.triEdges[ek[k].entry] = numEdges;
  }
  ++numEdges;
  incidence(km.triEdges, numEdges, km.edgeTriOffsets, km.edgeTris);
  incidence(km.triangles, km.vertices.size(), km.vertexTriOffsets, km.vertexTris);
  // Edge planes: a flat edge's one plane shared by its two triangles (m and exactly −m), every
  // other edge's the triangle's own.
  const double cosFlat = std::cos(kFlatEdgeAngle);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) {
      const std::uint32_t* c = &km.triangles[3 * t];
      const std::uint32_t p = c[j], q = c[(j + 1) % 3];
      const Vec3d a = toD(km.vertices[std::min(p, q)]), b = toD(km.vertices[std::max(p, q)]);
      const auto own = [&](std::size_t u) {
        const std::uint32_t* cu = &km.triangles[3 * u];
        std::uint32_t third = cu[0];
        for (int k = 0; k < 3; ++k)
          if (cu[k] != p && cu[k] != q) third = cu[k];
        return edgePlane(a, b, toD(km.vertices[third]), normal[u]);
      };
      const Vec3d mine = own(t);
      km.tri[t].m[j] = toF(mine);
      const std::uint32_t e = km.triEdges[3 * t + j];
      if (km.edgeTriOffsets[e + 1] - km.edgeTriOffsets[e] != 2) continue;
      const std::uint32_t t1 = km.edgeTris[km.edgeTriOffsets[e]], t2 = km.edgeTris[km.edgeTriOffsets[e] + 1];
      const Vec3d m1 = own(t1), m2 = own(t2);
      if (-dotD(m1, m2) < cosFlat) continue;  // a crease: each triangle's own plane
      const Vec3f s = toF(unit(sub(m1, m2)));  // the bisector, outward for t1
      km.tri[t].m[j] = t == t1 ? s : -s;
    }
  BvhBuilder(km.tri, km.nodes, km.prims);
  return km;
}

std::vector<MeshContact> findMeshContacts(const KernelMesh& mesh, const std::vector<float>& x,
                                          const std::vector<float>& radius, const std::vector<MeshPose>& poses) {
  const std::size_t n = radius.size();
  std::vector<std::vector<std::uint32_t>> rows(n);
  const MeshView v = mesh.view(poses);
  if (v.numTriangles > 0) {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      const Vec3f xi{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
      const float r = radius[i];
      const auto hit = [&](std::uint32_t t) {
        if (meshHit(v, t, meshPoint(v, v.tri[t].wall, xi), r).counts) rows[i].push_back(t);
      };
      // A contact is within r of the triangle, less its rounding, which its box's growth covers.
      if (v.poses != nullptr)
        forPosedTrianglesNear(v, xi, r + r * 0x1p-20f, hit);
      else
        forTrianglesNear(v, xi, r + r * 0x1p-20f, hit);
      std::sort(rows[i].begin(), rows[i].end());
    });
  }
  std::vector<MeshContact> out;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t t : rows[i]) out.push_back(MeshContact{static_cast<std::uint32_t>(i), t});
  return out;
}

MeshMotionBound::MeshMotionBound(const Scene& scene, const KernelMesh& mesh, const std::vector<Wall>& planes,
                                 float maxRadius, float skin) {
  const std::size_t first = planes.size() - scene.walls.size();  // after the ground
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const WallDef& d = scene.walls[k];
    if (d.shape != WallDef::Shape::Mesh || !d.moves()) continue;
    const std::uint32_t plane = static_cast<std::uint32_t>(first + k);
    const Vec3d pivot = toD(planes[plane].restCentre);
    double far = 0.0;  // D: the largest distance of a vertex from the pivot
    for (std::uint32_t t = 0; t < mesh.numTriangles(); ++t) {
      if (mesh.tri[t].wall != plane) continue;
      for (int c = 0; c < 3; ++c) {
        const Vec3d e = sub(toD(mesh.vertices[mesh.triangles[3 * std::size_t(t) + c]]), pivot);
        far = std::max(far, std::sqrt(dotD(e, e)));
      }
    }
    const Vec3d v = toD(d.velocity), w = toD(d.meshAngularVelocity);
    const double r = maxRadius;
    m_walls.push_back(Moving{d, std::sqrt(dotD(v, v)), std::sqrt(dotD(w, w)), far + r,
                             16.0 * kUnit * (far + 2.0 * (r + double(skin)) + std::sqrt(dotD(pivot, pivot)))});
  }
}

double MeshMotionBound::closure(double t0, double t1) const {
  double most = 0.0;
  for (const Moving& m : m_walls) {
    const double a = wallMotionTime(m.def, t0), b = wallMotionTime(m.def, t1);
    if (!(a > 0.0) && !(b > 0.0)) continue;  // where it was given at both: its points are not transformed
    const double dt = std::abs(b - a);
    const double rounding = m.rounding + 16.0 * kUnit * m.speed * std::max(a, b);
    most = std::max(most, m.speed * dt + m.rate * dt * m.reach + 2.0 * rounding);
  }
  return 2.0 * most;
}

bool pointInsideMesh(const KernelMesh& mesh, const Scene& scene, std::size_t wall, Vec3f p) {
  if (wall >= scene.walls.size() || scene.walls[wall].shape != WallDef::Shape::Mesh)
    throw Error("pointInsideMesh: wall " + std::to_string(wall) + " is not a mesh wall");
  const std::uint32_t plane = (scene.ground.enabled ? 1u : 0u) + static_cast<std::uint32_t>(wall);
  // Directions of no particular alignment with a mesh's axes, tried in turn.
  static const double kDirs[4][3] = {
      {0.5773502691896258, 0.5773502691896258 * 1.0009765625, 0.5772094}, {0.2672612, -0.5345225, 0.8017837},
      {-0.7071068, 0.1, 0.6998542}, {0.3, 0.9, -0.3162278}};
  const Vec3d o = toD(p);
  for (const auto& dir : kDirs) {
    const Vec3d d = unit({dir[0], dir[1], dir[2]});
    bool ambiguous = false;
    std::uint64_t crossings = 0;
    // The hierarchy's boxes met by the ray (slab test), then each triangle (Möller–Trumbore), in
    // double; a hit within 1e-9 of an edge, or at the origin, is ambiguous.
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty() && !ambiguous) {
      const MeshBvhNode& node = mesh.nodes[stack.back()];
      stack.pop_back();
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3 && t0 <= t1; ++a) {
        const double lo = (&node.lo.x)[a], hi = (&node.hi.x)[a];
        if (d[a] == 0.0) {
          if (o[a] < lo || o[a] > hi) t0 = 1.0, t1 = 0.0;
          continue;
        }
        double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 > t1) continue;
      if (node.count == 0) {
        stack.push_back(node.first);
        stack.push_back(node.first + 1);
        continue;
      }
      for (std::uint32_t k = node.first; k < node.first + node.count && !ambiguous; ++k) {
        const std::uint32_t t = mesh.prims[k];
        if (mesh.tri[t].wall != plane) continue;
        const std::uint32_t* c = &mesh.triangles[3 * std::size_t(t)];
        const Vec3d a = toD(mesh.vertices[c[0]]), e1 = sub(toD(mesh.vertices[c[1]]), a), e2 = sub(toD(mesh.vertices[c[2]]), a);
        const Vec3d h = crossD(d, e2);
        const double det = dotD(e1, h);
        const double scale = std::sqrt(dotD(e1, e1) * dotD(e2, e2));
        if (std::abs(det) <= 1e-12 * scale) continue;  // parallel to the ray (an edge-on triangle: its neighbours decide)
        const Vec3d s = sub(o, a);
        const double u = dotD(s, h) / det;
        const Vec3d qv = crossD(s, e1);
        const double v = dotD(d, qv) / det, tt = dotD(e2, qv) / det;
        const double eps = 1e-9;
        if (u < -eps || v < -eps || u + v > 1.0 + eps) continue;
        const double len = std::sqrt(scale);
        if (std::abs(tt) <= eps * len) {
          ambiguous = true;  // p on the surface
          break;
        }
        if (tt < 0.0) continue;
        if (u <= eps || v <= eps || u + v >= 1.0 - eps) {
          ambiguous = true;  // through an edge or a vertex: try another direction
          break;
        }
        ++crossings;
      }
    }
    if (!ambiguous) return (crossings & 1u) != 0;
  }
  return false;  // on the surface, or every ray grazed an edge: not inside
}

}  // namespace tumble
