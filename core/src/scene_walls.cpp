// SPDX-License-Identifier: MIT
// The TOML scene reader's [[wall]] tables: planes, boxes, cylinders, cones, disks and meshes,
// and their motion: SceneParser members (scene_reader.hpp).
#include "scene_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "binary_io.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/mesh.hpp"
#include "tumble/world.hpp"

namespace tumble::scene_reader {

namespace {

// "triangle 7 PROBLEM" at the triangle's line in its mesh file (its byte in a binary STL).
InputError triangleError(const TriangleMesh& mesh, std::size_t t, const std::string& problem) {
  const std::string what = "triangle " + std::to_string(t + 1) + " " + problem;
  return mesh.binary ? InputError(mesh.file, 0, "byte " + std::to_string(mesh.source[t]) + ": " + what)
                     : InputError(mesh.file, static_cast<long>(mesh.source[t]), what);
}

}  // namespace

/// [[wall]]: a plane (point, normal) or an axis-aligned box (min, max, open faces) of planes,
/// each with the ground's contact keys.
void SceneParser::readWalls(Scene& scene) {
  const toml::node* n = m_root.get("wall");
  if (n == nullptr) return;
  const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'wall'", "[[wall]]");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const std::size_t first = scene.walls.size();  // this table's walls (a box: up to six)
    m_wallOfTable.push_back(first);
    const std::string name = "[[wall]] #" + std::to_string(k + 1);
    const TableReader r(m_file, *tables[k], name,
                        {"type", "point", "normal", "min", "max", "open", "axis", "radius", "inner_radius",
                         "velocity", "angular_velocity", "pivot", "start", "stop", "file", "scale", "position",
                         "orientation", "stiffness", "friction", "tangential_stiffness", "rolling_friction",
                         "material", "cohesion_energy_density", "surface_energy"});
    const std::string where =
        name + " (" + printable(m_file) + ":" + std::to_string(static_cast<long>(r.header().begin.line)) + ")";
    WallDef wall;
    wall.where = where;
    readPlaneContact(scene, r, "wall", &wall.contact);
    wall.contact.enabled = true;
    const toml::node& typeNode =
        r.require("type", "type = \"plane\", \"box\", \"cylinder\", \"cone\", \"disk\" or \"mesh\"");
    const std::string type = r.string(typeNode, "type");
    // Every key but the contact's belongs to some types only.
    static const std::pair<const char*, const char*> kKeysOf[] = {
        {"plane", "point normal velocity start stop"},
        {"box", "min max open velocity start stop"},
        {"cylinder", "point axis radius velocity angular_velocity start stop"},
        {"cone", "point axis radius velocity angular_velocity start stop"},
        {"disk", "point normal radius inner_radius velocity angular_velocity start stop"},
        {"mesh", "file scale position orientation velocity angular_velocity pivot start stop"}};
    const auto* entry = std::find_if(std::begin(kKeysOf), std::end(kKeysOf),
                                     [&](const auto& e) { return type == e.first; });
    if (entry == std::end(kKeysOf))
      r.fail(sourceOf(typeNode), "unknown wall type \"" + type + "\" (\"plane\", \"box\", \"cylinder\", \"cone\", "
                                 "\"disk\" or \"mesh\")");
    for (const char* key : {"point", "normal", "min", "max", "open", "axis", "radius", "inner_radius", "velocity",
                            "angular_velocity", "pivot", "start", "stop", "file", "scale", "position", "orientation"}) {
      const std::string keys = std::string(" ") + entry->second + " ";
      if (const toml::node* e = r.find(key); e != nullptr && keys.find(std::string(" ") + key + " ") == std::string::npos)
        r.fail(sourceOf(*e), std::string(key) + " is not a key of type = \"" + type + "\" (its keys: " +
                                 entry->second + ")");
    }
    if (type == "cylinder" || type == "cone" || type == "disk") {
      readRevolvedWall(r, type, &wall);
      scene.walls.push_back(wall);
    } else if (type == "mesh") {
      readMeshWall(r, &wall);
      scene.walls.push_back(wall);
    } else if (type == "plane") {
      wall.point = r.vec3(r.require("point", "a point of the plane in m, e.g. point = [0, 0, 0]"), "point", Rule::Coordinate);
      const toml::node& nn = r.require("normal", "the normal towards the spheres, e.g. normal = [0, 0, 1]");
      wall.normal = r.vec3(nn, "normal", Rule::Any);  // normalised in double where the planes are built
      const Vec3f& v = wall.normal;
      const double len = std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
      if (!(len > 0.0) || !std::isfinite(len)) r.fail(sourceOf(nn), "normal must be a non-zero, finite vector");
      readWallMotionWindow(r, &wall);
      scene.walls.push_back(wall);
    } else {  // a box
      const Vec3f lo = r.vec3(r.require("min", "the lowest corner in m, e.g. min = [-1, -1, 0]"), "min", Rule::Coordinate);
      const toml::node& hiNode = r.require("max", "the highest corner in m, e.g. max = [1, 1, 2]");
      const Vec3f hi = r.vec3(hiNode, "max", Rule::Coordinate);
      if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "max must exceed min on every axis (as single-precision numbers: min [%.9g, %.9g, "
                      "%.9g], max [%.9g, %.9g, %.9g])", double(lo.x), double(lo.y), double(lo.z), double(hi.x),
                      double(hi.y), double(hi.z));
        r.fail(sourceOf(hiNode), buf);
      }
      static const char* const kFaces[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
      bool open[6] = {false, false, false, false, false, false};
      if (const toml::node* o = r.find("open")) {
        const toml::array& a = r.array(*o, "open", "of face names, e.g. open = [\"+z\"]");
        for (const toml::node& el : a) {
          const std::string face = r.string(el, "each entry of open");
          const auto* f = std::find_if(kFaces, kFaces + 6, [&](const char* x) { return face == x; });
          if (f == kFaces + 6) r.fail(sourceOf(el), "unknown face \"" + face + "\" (one of -x, +x, -y, +y, -z, +z)");
          if (open[f - kFaces]) r.fail(sourceOf(el), "face \"" + face + "\" is listed twice");
          open[f - kFaces] = true;
        }
        if (std::all_of(open, open + 6, [](bool b) { return b; }))
          r.fail(sourceOf(*o), "every face is open: the box has no walls");
      }
      readWallMotionWindow(r, &wall);  // the box translates: each face with the velocity
      // Six inward planes: the face at min of axis a has normal +e_a, the one at max −e_a.
      const float l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
      for (int f = 0; f < 6; ++f) {
        if (open[f]) continue;
        const int a = f / 2;
        const bool atMax = (f % 2) == 1;
        float p[3] = {0.0f, 0.0f, 0.0f}, nv[3] = {0.0f, 0.0f, 0.0f};
        p[a] = atMax ? h[a] : l[a];
        nv[a] = atMax ? -1.0f : 1.0f;
        WallDef face = wall;
        face.boxFace = true;
        face.point = Vec3f{p[0], p[1], p[2]};
        face.normal = Vec3f{nv[0], nv[1], nv[2]};
        face.where = where + " face " + kFaces[f];
        scene.walls.push_back(face);
      }
    }
    for (std::size_t q = first; q < scene.walls.size(); ++q)  // [periodic] is read before the walls
      if (const std::string why = periodicWallProblem(scene.walls[q], scene.periodic); !why.empty()) {
        const std::string& w = scene.walls[q].where;  // a box's face: where + " face -x"
        r.fail(r.header(), (w.size() > where.size() ? w.substr(where.size() + 1) + ": " : std::string()) + why);
      }
  }
}

// A cylinder (point, axis, radius), a cone (point, axis, radius = [r0, r1]) or a disk or ring
// (point, normal, radius, inner_radius) as the revolved segment of WallDef, with its spin.
void SceneParser::readRevolvedWall(const TableReader& r, const std::string& type, WallDef* wall) {
  wall->shape = WallDef::Shape::Revolved;
  const bool disk = type == "disk";
  wall->point = r.vec3(r.require("point", disk ? "the disk's centre in m, e.g. point = [0, 0, 0]"
                                               : "the axis's start in m, e.g. point = [0, 0, 0]"),
                       "point", Rule::Coordinate);
  const char* dirKey = disk ? "normal" : "axis";
  const toml::node& dn = r.require(dirKey, disk ? "the disk's normal (either way), e.g. normal = [0, 0, 1]"
                                                : "the axis from point to the far end in m, e.g. axis = [0, 0, 2]");
  wall->normal = r.vec3(dn, dirKey, Rule::Any);
  const Vec3f& a = wall->normal;
  const double len = std::sqrt(double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z);
  if (!(len > 0.0) || !std::isfinite(len) || (!disk && !(static_cast<float>(len) > 0.0f)))
    r.fail(sourceOf(dn), std::string(dirKey) + " must be a non-zero, finite vector");
  wall->length = disk ? 0.0f : static_cast<float>(len);
  const toml::node& rn = r.require("radius", type == "cone" ? "the radii at point and at point + axis in m, e.g. "
                                                              "radius = [0.1, 0.5]"
                                                            : "the radius in m, e.g. radius = 0.5");
  if (type == "cone") {
    const toml::array& ra = r.array(rn, "radius", "of 2 numbers [at point, at point + axis]");
    if (ra.size() != 2)
      r.fail(sourceOf(rn), "radius must be an array of 2 numbers [at point, at point + axis] (got " +
                               std::to_string(ra.size()) + " elements)");
    wall->radius0 = r.single(*ra.get(0), "radius[0]", Rule::NonNegative);
    wall->radius1 = r.single(*ra.get(1), "radius[1]", Rule::NonNegative);
    if (wall->radius0 == wall->radius1)
      r.fail(sourceOf(rn), "a cone's two radii must differ (equal radii: type = \"cylinder\")");
  } else if (disk) {
    wall->radius1 = r.single(rn, "radius", Rule::Positive);
    if (const toml::node* in = r.find("inner_radius")) {
      wall->radius0 = r.single(*in, "inner_radius", Rule::NonNegative);
      if (!(wall->radius0 < wall->radius1))
        r.fail(sourceOf(*in), "inner_radius (the hole) must be below radius (got " + fmt(wall->radius0) + " and " +
                                  fmt(wall->radius1) + ")");
    }
  } else {
    wall->radius0 = wall->radius1 = r.single(rn, "radius", Rule::Positive);
  }
  wall->angularVelocity = r.single("angular_velocity", 0.0f, Rule::Any);
  readWallMotionWindow(r, wall);
}

// A triangle mesh (file, scale, position, orientation): the file is read here, relative to
// the scene file's folder (or the base folder given to parseScene); its problems are reported
// at its own lines, naming the wall.
/// The mesh file a key names (`fn`, a path relative to the scene file's folder or the base
/// folder), read into *bytes (within the mesh files' limit); returns its resolved path. Refused
/// at the key's line with where it was looked for.
std::string SceneParser::readMeshFileOf(const TableReader& r, const toml::node& fn, const std::string& key,
                                        std::string* bytes) const {
  const std::string file = r.string(fn, key);
  if (file.empty()) r.fail(sourceOf(fn), key + " must name an STL or OBJ file (got \"\")");
  const std::filesystem::path folder =
      m_base.empty() ? std::filesystem::path(m_file).parent_path() : std::filesystem::path(m_base);
  std::filesystem::path path(file);
  if (path.is_relative()) path = folder / path;
  const std::string resolved = path.lexically_normal().string();
  try {
    *bytes = detail::readWholeFile(resolved, "the mesh file", detail::kMeshFileLimit);
  } catch (const InputError& e) {
    const std::string from = m_base.empty() ? std::string("the scene file's folder") : "the base folder " + m_base;
    r.fail(sourceOf(fn), e.problem() + (std::filesystem::path(file).is_relative()
                                            ? " (" + key + " = \"" + file + "\", looked for at " + resolved +
                                                  "); a relative file is found from " + from
                                            : " (" + key + " = \"" + file + "\")"));
  }
  return resolved;
}

/// A mesh's `scale`: a number, or [sx, sy, sz], each > 0 (default 1).
Vec3f SceneParser::readMeshScale(const TableReader& r) const {
  const toml::node* sn = r.find("scale");
  if (sn == nullptr) return Vec3f{1.0f, 1.0f, 1.0f};
  if (sn->is_array()) return r.vec3(*sn, "scale", Rule::Positive);
  const float k = r.single(*sn, "scale", Rule::Positive);
  return Vec3f{k, k, k};
}

void SceneParser::readMeshWall(const TableReader& r, WallDef* wall) {
  wall->shape = WallDef::Shape::Mesh;
  const toml::node& fn = r.require("file", "the mesh's STL or OBJ file, relative to the scene file's folder, e.g. "
                                           "file = \"hopper.stl\"");
  std::string bytes;
  const std::string resolved = readMeshFileOf(r, fn, "file", &bytes);
  wall->meshFile = resolved;
  wall->scale = readMeshScale(r);
  wall->point = r.vec3("position", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Coordinate);
  if (const toml::node* q = r.find("orientation")) wall->orientation = r.orientation(*q);
  try {
    const auto mesh = std::make_shared<const TriangleMesh>(parseMesh(bytes, resolved));
    wall->mesh = mesh;
    // Every vertex placed within single precision, and every triangle still a triangle there.
    const std::vector<Vec3f> v = meshWallVertices(*wall);
    for (std::size_t t = 0; t < mesh->numTriangles(); ++t) {
      const std::uint32_t* c = &mesh->triangles[3 * t];
      if (const std::string why = degenerateTriangle(v[c[0]], v[c[1]], v[c[2]]); !why.empty())
        throw triangleError(*mesh, t, "is degenerate once scaled and placed: " + why +
                                          "; use a larger scale, or remove it from the mesh");
    }
  } catch (const InputError& e) {
    throw InputError(e.file(), e.line(), e.problem() + " (the mesh of " + wall->where + ")");
  } catch (const Error& e) {  // a vertex beyond ±2^60 m once placed (named with the wall's place: once here)
    std::string m = e.what();
    if (m.rfind(wall->where, 0) == 0) m = r.where() + m.substr(wall->where.size());
    throw errorAt(m_file, r.header().begin.line ? r.header() : sourceOf(fn), m);
  }
  // Its motion: a rigid one, turning about the pivot at ω and translating (WallDef).
  if (const toml::node* an = r.find("angular_velocity")) {
    if (an->is_number())
      r.fail(sourceOf(*an), "a mesh turns about a vector: angular_velocity = [x, y, z] in rad/s (the axis, "
                            "right-handed, and the rate), about pivot; a number is a cylinder's, cone's or disk's");
    wall->meshAngularVelocity = r.vec3(*an, "angular_velocity", Rule::Any);
  }
  if (const toml::node* pn = r.find("pivot")) {
    const Vec3f& w = wall->meshAngularVelocity;
    if (w.x == 0.0f && w.y == 0.0f && w.z == 0.0f)
      r.fail(sourceOf(*pn), "pivot is the point the mesh turns about, and it does not turn; give it an "
                            "angular_velocity = [x, y, z] (rad/s), or leave pivot out");
    wall->pivot = r.vec3(*pn, "pivot", Rule::Coordinate);
  }
  readWallMotionWindow(r, wall);
}

// velocity [m/s] and start and stop of a wall's motion [s] (start and stop only with a
// velocity or a spin).
void SceneParser::readWallMotionWindow(const TableReader& r, WallDef* wall) {
  wall->velocity = r.vec3("velocity", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
  const toml::node* on = r.find("start");
  const toml::node* off = r.find("stop");
  if ((on || off) && !wall->moves())
    r.fail(sourceOf(on ? *on : *off), std::string(on ? "start" : "stop") + " times a wall's motion, and this wall "
                                      "does not move (give it a velocity, or a cylinder, cone, disk or mesh an "
                                      "angular_velocity)");
  wall->start = r.number("start", 0.0, Rule::NonNegative);
  wall->stop = r.number("stop", wall->stop, Rule::Positive);
  if (!(wall->stop > wall->start))
    r.fail(sourceOf(*off), "stop must be after start (got start = " + fmt(wall->start) + ", stop = " +
                               fmt(wall->stop) + ")");
}

/// The walls against the smallest sphere of the scene's bodies (after they are read): a mesh
/// triangle's nearest point, and a cylinder's, cone's, disk's or ring's distance, are computed
/// to within a few 2^-24 of its size, so each is at most kMaxTriangleToRadius (2^15) times that
/// radius long (exact_range.hpp).
void SceneParser::checkWallResolution(const Scene& scene) const {
  double radius = INFINITY;
  const auto smallest = [&](std::uint32_t shape) {
    for (const SphereDef& sp : scene.shapes[shape].spheres) radius = std::min(radius, double(sp.radius));
  };
  for (const BodyDef& b : scene.bodies) smallest(b.shape);
  for (const PourBody& p : scene.pourBodies) smallest(p.body.shape);
  const double longest = kMaxTriangleToRadius * radius;
  for (std::size_t k = 0; k < scene.walls.size(); ++k) {
    const WallDef& w = scene.walls[k];
    if (w.shape == WallDef::Shape::Revolved) {
      const double size = std::max({double(w.radius0), double(w.radius1), double(w.length)});
      if (size > longest) {
        // The [[wall]] table of wall k: the last whose first wall is at or before k.
        const std::size_t table =
            std::size_t(std::upper_bound(m_wallOfTable.begin(), m_wallOfTable.end(), k) - m_wallOfTable.begin()) - 1;
        const std::vector<const toml::table*> tables = tablesOf(m_file, *m_root.get("wall"), "'wall'", "[[wall]]");
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "[[wall]] #%zu: its radius or length, %.4g m, is more than 2^15 = 32768 times the smallest "
                      "sphere's radius (%.4g m): single precision finds its contacts to within a few 2^-24 of that "
                      "size; at most %.4g m",
                      table + 1, size, radius, longest);
        throw errorAt(m_file, sourceOf(*tables[table]), buf);
      }
    }
    if (!w.mesh) continue;
    const std::vector<Vec3f> v = meshWallVertices(w);
    for (std::size_t t = 0; t < w.mesh->numTriangles(); ++t) {
      const std::uint32_t* c = &w.mesh->triangles[3 * t];
      double edge = 0.0;
      for (int j = 0; j < 3; ++j) {
        const Vec3f a = v[c[j]], b = v[c[j == 2 ? 0 : j + 1]];
        const double dx = double(b.x) - a.x, dy = double(b.y) - a.y, dz = double(b.z) - a.z;
        edge = std::max(edge, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
      if (edge > longest) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "is %.4g m long once scaled and placed, more than 2^15 = 32768 times the smallest sphere's "
                      "radius (%.4g m): single precision finds its contacts to within a few 2^-24 of its size; "
                      "split it into triangles at most %.4g m long, or use a smaller scale (the mesh of %s)",
                      edge, radius, longest, w.where.c_str());
        throw triangleError(*w.mesh, t, buf);
      }
    }
  }
}

}  // namespace tumble::scene_reader
