// SPDX-License-Identifier: MIT
// The TOML scene reader's internals, shared by its files (internal to tumble_core): the checked
// reading of one table (TableReader), the top-level table names, and the SceneParser class whose
// members are defined by table in scene_io.cpp (entry points, overrides, run), scene_settings.cpp,
// scene_walls.cpp, scene_bodies.cpp and scene_fills.cpp. Design notes: scene_io.cpp.
#pragma once
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/fill.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"

namespace tumble::scene_reader {

/// The most particles a scene may have (particle indices and counts are 32-bit, with the top
/// bit kept free for sentinels).
inline constexpr std::uint64_t kMaxParticles = std::uint64_t{1} << 31;

/// Draws per lattice body (shape pick 1, jitter 3, velocity jitter 3, orientation 3, spin
/// direction 2), taken whether or not the option is used.
inline constexpr int kDrawsPerBody = 12;

/// The top-level tables: the single ones (--set SECTION.KEY) and the arrays of tables (--set
/// ARRAY[INDEX].KEY, ARRAY.NAME.KEY).
inline constexpr std::array<std::string_view, 8> kSingleTables = {
    "scene", "contact", "ground", "pulls", "broadphase", "integrator", "output", "periodic"};
inline constexpr std::array<std::string_view, 7> kArrayTables = {"material", "wall",  "shape", "body",
                                                                  "group",    "fill", "pour"};

/// "[scene], [contact], …" (and ", [[material]], [[wall]], …" with `arrays`).
std::string tableNames(bool arrays);

/// "[[material]], [[wall]], …".
std::string arrayTableNames();

template <std::size_t N>
bool isOneOf(const std::array<std::string_view, N>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// Where a node or key was written: in the scene file (its path and line), or in a --set
/// override, whose source path is its origin ("command line, --set ground.friction=-1").
inline const toml::source_region& sourceOf(const toml::node& n) { return n.source(); }
inline const toml::source_region& sourceOf(const toml::key& k) { return k.source(); }

/// The error for a problem at `at`: the file and its line, or the override's origin without a
/// line (the override is one line of its own, not a line of the file).
InputError errorAt(const std::string& file, const toml::source_region& at, const std::string& problem);

/// Shortest round-trip text of a double, %g style ("-1", "0.0001", "1e-50", "nan").
std::string fmt(double v);

std::string typeName(const toml::node& n);

std::string joinNames(std::initializer_list<std::string_view> names);

/// Range rule for a number.
/// What a number may be. Coordinate: a position within ±2^60 m; Radius: a sphere radius in
/// [2^-60, 2^60] m (the range whose contacts single precision decides right, exact_range.hpp).
enum class Rule { Any, Positive, NonNegative, Elasticity, Poisson, Coordinate, Radius };

/// Reads one TOML table: rejects unknown keys up front, then hands out typed, checked values.
class TableReader {
 public:
  TableReader(const std::string& file, const toml::table& table, std::string where,
              std::initializer_list<std::string_view> allowed)
      : m_file(file), m_table(table), m_where(std::move(where)) {
    for (auto&& [key, value] : table) {
      (void)value;
      const bool known = std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end();
      if (!known) {
        fail(sourceOf(key), "unknown key '" + std::string(key.str()) + "'; allowed keys: " +
                                joinNames(allowed));
      }
    }
  }

  const std::string& where() const { return m_where; }
  /// Where the table starts (its header), for problems of the table as a whole.
  const toml::source_region& header() const { return sourceOf(m_table); }
  const toml::node* find(std::string_view key) const { return m_table.get(key); }
  bool has(std::string_view key) const { return find(key) != nullptr; }

  [[noreturn]] void fail(const toml::source_region& at, const std::string& problem) const {
    throw errorAt(m_file, at, m_where + ": " + problem);
  }

  /// The node of a required key, or an error at the table's line.
  const toml::node& require(std::string_view key, std::string_view hint) const {
    const toml::node* n = find(key);
    if (n == nullptr) {
      fail(header(), "missing required key '" + std::string(key) + "' (" + std::string(hint) + ")");
    }
    return *n;
  }

  /// A finite number (integer or float) checked against `rule`; `what` names it in messages.
  double number(const toml::node& n, const std::string& what, Rule rule) const {
    double v = 0.0;
    if (const auto* i = n.as_integer()) {
      v = static_cast<double>(i->get());
    } else if (const auto* f = n.as_floating_point()) {
      v = f->get();
    } else {
      fail(sourceOf(n), what + " must be a number (got " + typeName(n) + ")");
    }
    if (!std::isfinite(v)) fail(sourceOf(n), what + " must be a finite number (got " + fmt(v) + ")");
    check(n, what, v, rule);
    return v;
  }

  /// As number(), converted to float: values beyond float range are errors, and the rule is
  /// checked again after rounding (1e-50 becomes 0 and is not > 0).
  float single(const toml::node& n, const std::string& what, Rule rule) const {
    const double v = number(n, what, rule);
    if (std::fabs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
      fail(sourceOf(n), what + " is out of single-precision range (got " + fmt(v) + ")");
    }
    const float f = static_cast<float>(v);
    check(n, what, static_cast<double>(f), rule, v);
    return f;
  }

  float single(std::string_view key, float fallback, Rule rule) const {
    const toml::node* n = find(key);
    return n != nullptr ? single(*n, std::string(key), rule) : fallback;
  }

  double number(std::string_view key, double fallback, Rule rule) const {
    const toml::node* n = find(key);
    return n != nullptr ? number(*n, std::string(key), rule) : fallback;
  }

  std::int64_t integer(const toml::node& n, const std::string& what, std::int64_t min) const {
    const auto* i = n.as_integer();
    if (i == nullptr) {
      std::string got = typeName(n);
      if (const auto* f = n.as_floating_point()) got = fmt(f->get());
      fail(sourceOf(n), what + " must be an integer (got " + got + ")");
    }
    const std::int64_t v = i->get();
    if (v < min) {
      fail(sourceOf(n), what + " must be >= " + std::to_string(min) + " (got " + std::to_string(v) + ")");
    }
    return v;
  }

  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t min) const {
    const toml::node* n = find(key);
    return n != nullptr ? integer(*n, std::string(key), min) : fallback;
  }

  bool boolean(std::string_view key, bool fallback) const {
    const toml::node* n = find(key);
    if (n == nullptr) return fallback;
    const auto* b = n->as_boolean();
    if (b == nullptr) {
      fail(sourceOf(*n), std::string(key) + " must be true or false (got " + typeName(*n) + ")");
    }
    return b->get();
  }

  std::string string(const toml::node& n, const std::string& what) const {
    const auto* s = n.as_string();
    if (s == nullptr) fail(sourceOf(n), what + " must be a string (got " + typeName(n) + ")");
    return s->get();
  }

  std::string string(std::string_view key, const std::string& fallback) const {
    const toml::node* n = find(key);
    return n != nullptr ? string(*n, std::string(key)) : fallback;
  }

  const toml::array& array(const toml::node& n, const std::string& what, std::string_view form) const {
    const auto* a = n.as_array();
    if (a == nullptr) {
      fail(sourceOf(n), what + " must be an array " + std::string(form) + " (got " + typeName(n) + ")");
    }
    return *a;
  }

  /// An array of exactly N elements (N = 3: [x, y, z]; N = 4: [w, x, y, z]; N = 6: a symmetric
  /// tensor [xx, yy, zz, xy, xz, yz]).
  template <std::size_t N>
  const toml::array& fixedArray(const toml::node& n, const std::string& what) const {
    static_assert(N == 3 || N == 4 || N == 6);
    const std::string_view form = N == 3   ? "of 3 numbers [x, y, z]"
                                  : N == 4 ? "of 4 numbers [w, x, y, z]"
                                           : "of 6 numbers [xx, yy, zz, xy, xz, yz]";
    const toml::array& a = array(n, what, form);
    if (a.size() != N) {
      fail(sourceOf(n), what + " must be an array " + std::string(form) + " (got " +
                            std::to_string(a.size()) + " elements)");
    }
    return a;
  }

  static std::string component(std::size_t n, std::size_t c, const std::string& what) {
    static constexpr std::string_view kNames3[] = {"x", "y", "z"};
    static constexpr std::string_view kNames4[] = {"w", "x", "y", "z"};
    static constexpr std::string_view kNames6[] = {"xx", "yy", "zz", "xy", "xz", "yz"};
    return "component " + std::string(n == 3 ? kNames3[c] : n == 4 ? kNames4[c] : kNames6[c]) + " of " + what;
  }

  /// An array of exactly N finite numbers, each checked against `rule`, in double precision.
  template <std::size_t N>
  std::array<double, N> numbers(const toml::node& n, const std::string& what, Rule rule) const {
    const toml::array& a = fixedArray<N>(n, what);
    std::array<double, N> out{};
    for (std::size_t c = 0; c < N; ++c) out[c] = number(*a.get(c), component(N, c, what), rule);
    return out;
  }

  Vec3f vec3(const toml::node& n, const std::string& what, Rule rule) const {
    const toml::array& a = fixedArray<3>(n, what);
    std::array<float, 3> f{};
    for (std::size_t c = 0; c < 3; ++c) f[c] = single(*a.get(c), component(3, c, what), rule);
    return {f[0], f[1], f[2]};
  }

  /// A quaternion [w, x, y, z], not zero, normalised in double.
  Quatf orientation(const toml::node& q) const {
    const std::array<double, 4> d = numbers<4>(q, "orientation", Rule::Any);
    const double n2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[3] * d[3];
    if (!(n2 > 0.0)) fail(sourceOf(q), "orientation must not be the zero quaternion; use [1, 0, 0, 0] for no rotation");
    if (!std::isfinite(n2)) fail(sourceOf(q), "orientation is too large to normalise");
    const double inv = 1.0 / std::sqrt(n2);
    return Quatf{static_cast<float>(d[0] * inv), static_cast<float>(d[1] * inv), static_cast<float>(d[2] * inv),
                 static_cast<float>(d[3] * inv)};
  }

  Vec3f vec3(std::string_view key, Vec3f fallback, Rule rule) const {
    const toml::node* n = find(key);
    return n != nullptr ? vec3(*n, std::string(key), rule) : fallback;
  }

 private:
  void check(const toml::node& n, const std::string& what, double v, Rule rule,
             double shown = std::numeric_limits<double>::quiet_NaN()) const {
    if (std::isnan(shown)) shown = v;
    switch (rule) {
      case Rule::Any: return;
      case Rule::Positive:
        if (!(v > 0.0)) fail(sourceOf(n), what + " must be > 0 (got " + fmt(shown) + ")");
        return;
      case Rule::NonNegative:
        if (!(v >= 0.0)) fail(sourceOf(n), what + " must be >= 0 (got " + fmt(shown) + ")");
        return;
      case Rule::Elasticity:
        if (!(v > 0.0 && v <= 1.0)) {
          fail(sourceOf(n), what + " must be in (0, 1] (coefficient of restitution: 1 = perfectly "
                                   "elastic, small = very inelastic; got " + fmt(shown) + ")");
        }
        return;
      case Rule::Poisson:
        if (!(v >= 0.0 && v < 0.5)) fail(sourceOf(n), what + " must be in [0, 0.5) (got " + fmt(shown) + ")");
        return;
      case Rule::Coordinate:
        if (!withinExactRange(v))
          fail(sourceOf(n), what + " must be within +-2^60 m (1.15e18), the range whose contacts single precision "
                                   "decides right (got " + fmt(shown) + ")");
        return;
      case Rule::Radius:
        if (!(v > 0.0)) fail(sourceOf(n), what + " must be > 0 (got " + fmt(shown) + ")");
        if (!(v >= kMinRadius && v <= kMaxCoordinate))
          fail(sourceOf(n), what + " must be in [2^-60, 2^60] m (8.7e-19 to 1.15e18), the range whose contacts single "
                                   "precision decides right (got " + fmt(shown) + ")");
        return;
    }
  }

  const std::string& m_file;
  const toml::table& m_table;
  std::string m_where;
};

/// The tables of an array-of-tables key (e.g. every [[shape]]), or an error if the key holds
/// something else.
std::vector<const toml::table*> tablesOf(const std::string& file, const toml::node& n,
                                         const std::string& where, std::string_view header);

/// A table-valued key such as [scene]; nullptr if absent.
/// (Inline: out of line, GCC 12 at -O3 warns falsely about its chain of + (-Wrestrict).)
inline const toml::table* sectionOf(const std::string& file, const toml::table& root, std::string_view key) {
  const toml::node* n = root.get(key);
  if (n == nullptr) return nullptr;
  const auto* t = n->as_table();
  if (t == nullptr) {
    throw errorAt(file, sourceOf(*n), "'" + std::string(key) + "' must be a table, written as [" +
                                          std::string(key) + "] (got " + typeName(*n) + ")");
  }
  return t;
}

std::string stemOf(const std::string& path);

class SceneParser {
 public:
  /// `base`: the folder a relative mesh file is found from; empty: the scene file's folder.
  SceneParser(const toml::table& root, const std::string& file, std::string base = {})
      : m_root(root), m_file(file), m_base(std::move(base)) {}

  Scene run();

 private:
  // The single tables and [[material]] (scene_settings.cpp).
  void readScene(Scene& scene);
  void readContact(Scene& scene);
  void readGround(Scene& scene);
  void readPlaneContact(const Scene& scene, const TableReader& r, const std::string& what, GroundParams* out) const;
  float readCohesion(const Scene& scene, const TableReader& r, float fallback) const;
  void readPeriodic(Scene& scene);
  void checkPeriod(const Scene& scene);
  void checkWallResolution(const Scene& scene) const;
  void readPulls(Scene& scene);
  void readBroadphase(Scene& scene);
  void readIntegrator(Scene& scene);
  void readOutput(Scene& scene);
  void readMaterials(Scene& scene);
  std::uint32_t materialNamed(const TableReader& r, const toml::node& n, const std::string& what) const;

  // [[wall]] (scene_walls.cpp).
  void readWalls(Scene& scene);
  void readRevolvedWall(const TableReader& r, const std::string& type, WallDef* wall);
  void readMeshWall(const TableReader& r, WallDef* wall);
  void readWallMotionWindow(const TableReader& r, WallDef* wall);

  // [[shape]], [[body]] and [[group]] (scene_bodies.cpp).
  void readShapes(Scene& scene);
  std::optional<ShapeSolid> readSolid(const TableReader& r) const;
  void readSphereMaterial(const Scene& scene, const TableReader& sr, SphereDef* sd, bool shapeMass) const;
  const MaterialDef* readMaterialAndElasticity(const Scene& scene, const TableReader& sr, SphereDef* sd) const;
  ShapeDef readMeshShape(const Scene& scene, const TableReader& r, const std::string& name) const;
  std::string readMeshFileOf(const TableReader& r, const toml::node& fileNode, const std::string& key,
                             std::string* bytes) const;
  Vec3f readMeshScale(const TableReader& r) const;
  std::uint32_t shapeNamed(const TableReader& r, const toml::node& n, const std::string& what,
                           const Scene& scene) const;
  void addParticles(const TableReader& r, const toml::source_region& at, std::uint64_t count);
  void readBodies(Scene& scene);
  std::vector<std::uint32_t> shapesOf(const TableReader& r, const Scene& scene) const;
  void checkBodyBudget(const TableReader& r, const toml::node& at, const Scene& scene, std::uint64_t bodies,
                       std::size_t minSpheres, bool pour = false) const;
  void readBody(Scene& scene, const toml::table& t, std::size_t index);
  void readGroup(Scene& scene, const toml::table& t, std::size_t index);

  // [[fill]] and [[pour]] (scene_fills.cpp).
  FillDef readPlacement(const TableReader& r, Scene& scene, const std::string& kind, std::size_t k);
  SizeDistribution readSize(const TableReader& placement, const toml::node& n) const;
  void readFills(Scene& scene);
  void readPours(Scene& scene);

  const toml::table& m_root;
  const std::string& m_file;
  std::string m_base;
  std::uint64_t m_seed = 1;
  std::uint64_t m_numParticles = 0;
  std::unordered_map<std::string, std::uint32_t> m_shapeIndex;
  toml::source_region m_periodicAt[2];  ///< [periodic] x and y, for the period check
  std::unordered_map<std::string, std::uint32_t> m_materialIndex;
  std::vector<std::string> m_materialNames;  ///< in file order, for messages
  std::vector<std::size_t> m_wallOfTable;     ///< per [[wall]] table, the index of its first wall
  bool m_cohesionOff = false;  ///< [contact] cohesion = "none" given: the coefficients are checked, not read
};

}  // namespace tumble::scene_reader
