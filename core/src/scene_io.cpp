// SPDX-License-Identifier: MIT
/// @file scene_io.cpp
/// TOML scene reader (schema: docs/scenes.md).
///
/// Design notes
/// - Every problem is reported as tumble::InputError(file, line, problem), where line is the
///   1-based line of the offending TOML node (toml++ keeps a source region for every key and
///   value), or 0 when the problem concerns the file as a whole (no [scene], no bodies).
///   Messages name the table, the key, the rule and the offending value, so that the user
///   knows what to change.
/// - Unknown keys are errors, not warnings: a misspelt key ("stifness") silently falling back
///   to a default is the commonest way to get a scene that runs but is not the one intended.
/// - Lattice groups are generated from tumble::Rng (SplitMix64), never <random>, and the
///   orientation uses tumble::sinCos (our own polynomial) rather than std::sin/std::cos, so a
///   scene file gives bit-identical bodies on every platform and standard library. Each group
///   has its own generator seeded from (scene seed, group index), and every body draws a fixed
///   number of values whatever its options, so editing one group never changes another.
/// - [[body]] and [[group]] are separate TOML arrays; bodies are emitted in file order by
///   sorting their tables by source position.
#include "tumble/scene_io.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/fill.hpp"
#include "tumble/math.hpp"
#include "tumble/memory.hpp"
#include "tumble/mesh.hpp"
#include "tumble/random.hpp"
#include "tumble/world.hpp"
#include "placement.hpp"

namespace tumble {
namespace {

/// The most particles a scene may have (particle indices and counts are 32-bit, with the top
/// bit kept free for sentinels).
constexpr std::uint64_t kMaxParticles = std::uint64_t{1} << 31;

/// Draws per lattice body (shape pick 1, jitter 3, velocity jitter 3, orientation 3, spin
/// direction 2), taken whether or not the option is used.
constexpr int kDrawsPerBody = 12;

/// The top-level tables: the single ones (which --set can address) and the arrays of tables.
constexpr std::array<std::string_view, 8> kSingleTables = {
    "scene", "contact", "ground", "pulls", "broadphase", "integrator", "output", "periodic"};
constexpr std::array<std::string_view, 7> kArrayTables = {"material", "wall",  "shape", "body",
                                                           "group",    "fill", "pour"};

/// "[scene], [contact], …" (and ", [[shape]], [[body]], [[group]]" with `arrays`).
std::string tableNames(bool arrays) {
  std::string out;
  for (std::string_view t : kSingleTables) out += (out.empty() ? "[" : ", [") + std::string(t) + "]";
  if (arrays)
    for (std::string_view t : kArrayTables) out += ", [[" + std::string(t) + "]]";
  return out;
}

template <std::size_t N>
bool isOneOf(const std::array<std::string_view, N>& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// Where a node or key was written: in the scene file (its path and line), or in a --set
/// override, whose source path is its origin ("command line, --set ground.friction=-1").
const toml::source_region& sourceOf(const toml::node& n) { return n.source(); }
const toml::source_region& sourceOf(const toml::key& k) { return k.source(); }

/// The error for a problem at `at`: the file and its line, or the override's origin without a
/// line (the override is one line of its own, not a line of the file).
InputError errorAt(const std::string& file, const toml::source_region& at, const std::string& problem) {
  if (at.path != nullptr && *at.path != file) return InputError(*at.path, 0, problem);
  return InputError(file, static_cast<long>(at.begin.line), problem);
}

/// Shortest round-trip text of a double, %g style ("-1", "0.0001", "1e-50", "nan").
std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::array<char, 64> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general);
  return std::string(buf.data(), res.ptr);
}

std::string typeName(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a floating-point number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

std::string joinNames(std::initializer_list<std::string_view> names) {
  std::string out;
  for (std::string_view n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

/// Range rule for a number.
enum class Rule { Any, Positive, NonNegative, Elasticity, Poisson };

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

  /// An array of exactly N elements (N = 3: [x, y, z]; N = 4: [w, x, y, z]).
  template <std::size_t N>
  const toml::array& fixedArray(const toml::node& n, const std::string& what) const {
    static_assert(N == 3 || N == 4);
    const std::string_view form = N == 3 ? "of 3 numbers [x, y, z]" : "of 4 numbers [w, x, y, z]";
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
    return "component " + std::string(n == 3 ? kNames3[c] : kNames4[c]) + " of " + what;
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
    }
  }

  const std::string& m_file;
  const toml::table& m_table;
  std::string m_where;
};

/// The tables of an array-of-tables key (e.g. every [[shape]]), or an error if the key holds
/// something else.
std::vector<const toml::table*> tablesOf(const std::string& file, const toml::node& n,
                                         const std::string& where, std::string_view header) {
  const auto* arr = n.as_array();
  if (arr == nullptr) {
    throw errorAt(file, sourceOf(n), where + " must be an array of tables: write each entry as " +
                                         std::string(header) + " (got " + typeName(n) + ")");
  }
  std::vector<const toml::table*> out;
  for (const toml::node& el : *arr) {
    const auto* t = el.as_table();
    if (t == nullptr) {
      throw errorAt(file, sourceOf(el), where + " entries must be tables, written as " +
                                            std::string(header) + " (got " + typeName(el) + ")");
    }
    out.push_back(t);
  }
  return out;
}

/// A table-valued key such as [scene]; nullptr if absent.
const toml::table* sectionOf(const std::string& file, const toml::table& root, std::string_view key) {
  const toml::node* n = root.get(key);
  if (n == nullptr) return nullptr;
  const auto* t = n->as_table();
  if (t == nullptr) {
    throw errorAt(file, sourceOf(*n), "'" + std::string(key) + "' must be a table, written as [" +
                                          std::string(key) + "] (got " + typeName(*n) + ")");
  }
  return t;
}

std::string stemOf(const std::string& path) {
  const std::string stem = std::filesystem::path(path).stem().string();
  return stem.empty() ? std::string("scene") : stem;
}

class SceneParser {
 public:
  SceneParser(const toml::table& root, const std::string& file) : m_root(root), m_file(file) {}

  Scene run() {
    Scene scene;
    scene.sourceFile = m_file;
    scene.name = stemOf(m_file);

    for (auto&& [key, value] : m_root) {
      (void)value;
      if (!isOneOf(kSingleTables, key.str()) && !isOneOf(kArrayTables, key.str())) {
        throw errorAt(m_file, sourceOf(key), "unknown top-level key '" + std::string(key.str()) +
                                                 "'; allowed tables: " + tableNames(true));
      }
    }

    readScene(scene);
    readContact(scene);
    readMaterials(scene);
    readGround(scene);
    readPeriodic(scene);
    readWalls(scene);
    readPulls(scene);
    readBroadphase(scene);
    readIntegrator(scene);
    readOutput(scene);
    readShapes(scene);
    readBodies(scene);
    readFills(scene);
    readPours(scene);
    if (scene.bodies.empty() && scene.pourBodies.empty()) {
      throw InputError(m_file, 0, "the scene has no bodies; add a [[body]], a [[group]] or a [[fill]] "
                                  "(and the [[shape]] it uses)");
    }
    checkPeriod(scene);
    return scene;
  }

 private:
  void readScene(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "scene");
    if (t == nullptr) {
      throw InputError(m_file, 0, "missing the [scene] table; it needs at least dt (time step in s) "
                                  "and steps (number of steps to run)");
    }
    const TableReader r(m_file, *t, "[scene]", {"name", "dt", "steps", "gravity", "seed"});
    scene.name = r.string("name", scene.name);
    scene.dt = r.single(r.require("dt", "time step in seconds, e.g. dt = 1e-4"), "dt", Rule::Positive);
    scene.steps = static_cast<std::uint64_t>(
        r.integer(r.require("steps", "number of steps to run, e.g. steps = 1000"), "steps", 1));
    scene.gravity = r.vec3("gravity", scene.gravity, Rule::Any);
    m_seed = static_cast<std::uint64_t>(r.integer("seed", 1, 0));
  }

  void readContact(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "contact");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[contact]",
                        {"law", "stiffness", "damping", "shear", "tangential_stiffness", "gamma_n", "gamma_t",
                         "friction", "rolling_friction"});
    ContactParams& c = scene.contact;
    if (const toml::node* law = r.find("law")) {
      const std::string name = r.string(*law, "law");
      if (name == "report") c.law = ContactLaw::Report;
      else if (name == "hooke-history") c.law = ContactLaw::HookeHistory;
      else if (name == "hertz-mindlin") c.law = ContactLaw::HertzMindlin;
      else r.fail(sourceOf(*law), "unknown law \"" + name + "\"; use \"report\", \"hooke-history\" or \"hertz-mindlin\"");
    }
    // Each law reads its own keys; another law's key is a mistake worth naming.
    static const std::vector<std::string> kReportKeys = {"stiffness", "damping", "shear"};
    static const std::vector<std::string> kHookeKeys = {"stiffness", "tangential_stiffness", "gamma_n", "gamma_t",
                                                        "friction", "rolling_friction"};
    const std::vector<std::string> none;
    const std::vector<std::string>& mine = c.law == ContactLaw::Report         ? kReportKeys
                                           : c.law == ContactLaw::HookeHistory ? kHookeKeys
                                                                                : none;
    for (auto&& [key, value] : *t) {
      (void)value;
      const std::string k(key.str());
      if (k == "law" || std::find(mine.begin(), mine.end(), k) != mine.end()) continue;
      const bool inReport = std::find(kReportKeys.begin(), kReportKeys.end(), k) != kReportKeys.end();
      const bool inHooke = std::find(kHookeKeys.begin(), kHookeKeys.end(), k) != kHookeKeys.end();
      std::string why = inHooke && inReport ? "it belongs to the report's law and to hooke-history"
                        : inHooke            ? "it belongs to law = \"hooke-history\""
                        : inReport           ? "it belongs to the report's law"
                                             : "";
      if (c.law == ContactLaw::HookeHistory && inReport) why += "; hooke-history damps with gamma_n, gamma_t";
      if (c.law == ContactLaw::HertzMindlin)
        why += "; under hertz-mindlin every pair's parameters come from its spheres' [[material]] tables";
      r.fail(sourceOf(key), k + " is not a parameter of law = \"" + toString(c.law) + "\" (" + why + "; docs/scenes.md)");
    }
    c.stiffness = r.single("stiffness", c.stiffness, Rule::Positive);
    c.damping = r.single("damping", c.damping, Rule::NonNegative);
    c.shear = r.single("shear", c.shear, Rule::NonNegative);
    c.tangentialStiffness = r.single("tangential_stiffness", c.tangentialStiffness, Rule::NonNegative);
    c.gammaN = r.single("gamma_n", c.gammaN, Rule::NonNegative);
    if (r.has("gamma_t")) c.gammaT = r.single("gamma_t", 0.0f, Rule::NonNegative);
    c.friction = r.single("friction", c.friction, Rule::NonNegative);
    c.rollingFriction = r.single("rolling_friction", c.rollingFriction, Rule::NonNegative);
  }

  void readGround(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "ground");
    GroundParams& g = scene.ground;
    if (t == nullptr) {
      g.enabled = false;
      return;
    }
    const TableReader r(m_file, *t, "[ground]",
                        {"enabled", "height", "stiffness", "friction", "tangential_stiffness", "rolling_friction",
                         "material"});
    g.enabled = r.boolean("enabled", true);
    g.height = r.single("height", 0.0f, Rule::Any);
    readPlaneContact(scene, r, "ground", &g);
  }

  /// The contact keys of a plane (the ground or a wall) under the scene's law.
  void readPlaneContact(const Scene& scene, const TableReader& r, const std::string& what, GroundParams* out) const {
    GroundParams& g = *out;
    const bool materials = scene.contact.usesMaterials();
    for (const char* key : {"stiffness", "tangential_stiffness", "material"})
      if (const toml::node* n = r.find(key); n != nullptr && (std::string(key) == "material") != materials)
        r.fail(sourceOf(*n), materials ? std::string(key) + " is not read under law = \"hertz-mindlin\": the " + what +
                                             "'s contact comes from its material (material = \"name\" of a [[material]]; "
                                             "none: rigid, with each sphere's own restitution and friction)"
                                       : std::string("material is read under law = \"hertz-mindlin\" only; this "
                                                     "law's " + what + " uses stiffness and friction"));
    if (const toml::node* n = r.find("material")) g.material = static_cast<int>(materialNamed(r, *n, "material"));
    if (materials) {  // friction and rolling_friction replace the mixed values of every sphere–plane pair
      if (r.has("friction")) g.frictionOverride = r.single("friction", 0.0f, Rule::NonNegative);
      if (r.has("rolling_friction")) g.rollingFriction = r.single("rolling_friction", 0.0f, Rule::NonNegative);
      return;
    }
    g.stiffness = r.single("stiffness", scene.contact.stiffness, Rule::Positive);
    g.friction = r.single("friction", g.friction, Rule::NonNegative);
    g.tangentialStiffness = r.single("tangential_stiffness", 0.0f, Rule::NonNegative);
    if (const toml::node* n = r.find("rolling_friction")) {
      if (!scene.contact.rotatesSpheres())
        r.fail(sourceOf(*n), "rolling_friction needs a contact law that turns spheres ([contact] law = "
                             "\"hooke-history\"); under the report's law single spheres do not rotate");
      g.rollingFriction = r.single("rolling_friction", 0.0f, Rule::NonNegative);
    }
  }

  /// [[wall]]: a plane (point, normal) or an axis-aligned box (min, max, open faces) of planes,
  /// each with the ground's contact keys.
  void readWalls(Scene& scene) {
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
                           "material"});
      const std::string where =
          name + " (" + m_file + ":" + std::to_string(static_cast<long>(r.header().begin.line)) + ")";
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
        wall.point = r.vec3(r.require("point", "a point of the plane in m, e.g. point = [0, 0, 0]"), "point", Rule::Any);
        const toml::node& nn = r.require("normal", "the normal towards the spheres, e.g. normal = [0, 0, 1]");
        wall.normal = r.vec3(nn, "normal", Rule::Any);  // normalised in double where the planes are built
        const Vec3f& v = wall.normal;
        const double len = std::sqrt(double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z);
        if (!(len > 0.0) || !std::isfinite(len)) r.fail(sourceOf(nn), "normal must be a non-zero, finite vector");
        readWallMotionWindow(r, &wall);
        scene.walls.push_back(wall);
      } else {  // a box
        const Vec3f lo = r.vec3(r.require("min", "the lowest corner in m, e.g. min = [-1, -1, 0]"), "min", Rule::Any);
        const toml::node& hiNode = r.require("max", "the highest corner in m, e.g. max = [1, 1, 2]");
        const Vec3f hi = r.vec3(hiNode, "max", Rule::Any);
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
  void readRevolvedWall(const TableReader& r, const std::string& type, WallDef* wall) {
    wall->shape = WallDef::Shape::Revolved;
    const bool disk = type == "disk";
    wall->point = r.vec3(r.require("point", disk ? "the disk's centre in m, e.g. point = [0, 0, 0]"
                                                 : "the axis's start in m, e.g. point = [0, 0, 0]"),
                         "point", Rule::Any);
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
  // the scene file's folder; its problems are reported at its own lines, naming the wall.
  void readMeshWall(const TableReader& r, WallDef* wall) {
    wall->shape = WallDef::Shape::Mesh;
    const toml::node& fn = r.require("file", "the mesh's STL or OBJ file, relative to the scene file's folder, e.g. "
                                             "file = \"hopper.stl\"");
    const std::string file = r.string(fn, "file");
    if (file.empty()) r.fail(sourceOf(fn), "file must name an STL or OBJ file (got \"\")");
    std::filesystem::path path(file);
    if (path.is_relative()) path = std::filesystem::path(m_file).parent_path() / path;
    const std::string resolved = path.lexically_normal().string();
    std::string bytes;
    try {
      bytes = detail::readWholeFile(resolved, "the mesh file");
    } catch (const InputError& e) {
      r.fail(sourceOf(fn), e.problem() + " (file = \"" + file + "\", looked for at " + resolved +
                               "); a relative file is found from the scene file's folder");
    }
    if (const toml::node* sn = r.find("scale")) {
      if (sn->is_array()) {
        wall->scale = r.vec3(*sn, "scale", Rule::Positive);
      } else {
        const float k = r.single(*sn, "scale", Rule::Positive);
        wall->scale = Vec3f{k, k, k};
      }
    }
    wall->point = r.vec3("position", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
    if (const toml::node* q = r.find("orientation")) wall->orientation = r.orientation(*q);
    try {
      const auto mesh = std::make_shared<const TriangleMesh>(parseMesh(bytes, resolved));
      wall->mesh = mesh;
      // Every vertex placed within single precision, and every triangle still a triangle there.
      const std::vector<Vec3f> v = meshWallVertices(*wall);
      for (std::size_t t = 0; t < mesh->numTriangles(); ++t) {
        const std::uint32_t* c = &mesh->triangles[3 * t];
        if (const std::string why = degenerateTriangle(v[c[0]], v[c[1]], v[c[2]]); !why.empty())
          throw mesh->binary ? InputError(mesh->file, 0, "byte " + std::to_string(mesh->source[t]) + ": triangle " +
                                                             std::to_string(t + 1) + " is degenerate once scaled and placed: " +
                                                             why + "; use a larger scale, or remove it from the mesh")
                             : InputError(mesh->file, static_cast<long>(mesh->source[t]),
                                          "triangle " + std::to_string(t + 1) + " is degenerate once scaled and placed: " +
                                              why + "; use a larger scale, or remove it from the mesh");
      }
    } catch (const InputError& e) {
      throw InputError(e.file(), e.line(), e.problem() + " (the mesh of " + wall->where + ")");
    } catch (const Error& e) {  // a vertex beyond single precision once placed (its message names the wall)
      throw errorAt(m_file, r.header().begin.line ? r.header() : sourceOf(fn), e.what());
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
      wall->pivot = r.vec3(*pn, "pivot", Rule::Any);
    }
    readWallMotionWindow(r, wall);
  }

  // velocity [m/s] and start and stop of a wall's motion [s] (start and stop only with a
  // velocity or a spin).
  void readWallMotionWindow(const TableReader& r, WallDef* wall) {
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

  // [periodic]: x = [x0, x1] and/or y = [y0, y1].
  void readPeriodic(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "periodic");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[periodic]", {"x", "y"});
    PeriodicParams& p = scene.periodic;
    for (int a = 0; a < 2; ++a) {
      const char* key = a == 0 ? "x" : "y";
      const toml::node* n = r.find(key);
      if (n == nullptr) continue;
      const std::string form = std::string("of 2 numbers [") + key + "0, " + key + "1] (the box's ends)";
      const toml::array& v = r.array(*n, key, form);
      if (v.size() != 2)
        r.fail(sourceOf(*n), std::string(key) + " must be an array " + form + " (got " + std::to_string(v.size()) +
                                 " elements)");
      p.lo[a] = r.single(*v.get(0), std::string(key) + "[0]", Rule::Any);
      p.hi[a] = r.single(*v.get(1), std::string(key) + "[1]", Rule::Any);
      if (!(p.lo[a] < p.hi[a]))
        r.fail(sourceOf(*n), std::string(key) + " = [" + key + "0, " + key + "1] needs " + key + "1 > " + key + "0 (got [" +
                                 fmt(p.lo[a]) + ", " + fmt(p.hi[a]) + "])");
      p.on[a] = true;
      m_periodicAt[a] = sourceOf(*n);
    }
    if (!p.any()) r.fail(r.header(), "give x = [x0, x1] and/or y = [y0, y1], the box of the periodic axes");
  }

  // The periods against the bodies and the skin (after the bodies are read).
  void checkPeriod(const Scene& scene) {
    if (!scene.periodic.any()) return;
    const PeriodReach reach = periodReach(scene);
    for (int a = 0; a < 2; ++a)
      if (const std::string why = periodTooShort(scene.periodic, a, reach); !why.empty())
        throw errorAt(m_file, m_periodicAt[a], why);
  }

  void readPulls(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "pulls");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[pulls]", {"x", "y", "swirl", "on"});
    PullParams& p = scene.pulls;
    p.x = r.single("x", p.x, Rule::Any);
    p.y = r.single("y", p.y, Rule::Any);
    p.swirl = r.single("swirl", p.swirl, Rule::Any);
    p.active = 0;
    if (const toml::node* on = r.find("on")) {
      const toml::array& a = r.array(*on, "on", "of pull names, e.g. on = [\"x\", \"swirl\"]");
      for (const toml::node& el : a) {
        const std::string name = r.string(el, "each entry of on");
        std::uint32_t bit = 0;
        if (name == "x") {
          bit = kPullX;
        } else if (name == "y") {
          bit = kPullY;
        } else if (name == "swirl") {
          bit = kPullSwirl;
        } else {
          r.fail(sourceOf(el), "unknown pull \"" + name + "\" in on; use \"x\", \"y\" or \"swirl\"");
        }
        if (const std::string why = periodicPullProblem(scene.periodic, bit); !why.empty()) r.fail(sourceOf(el), why);
        p.active |= bit;
      }
    }
  }

  void readBroadphase(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "broadphase");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[broadphase]", {"cell_size", "pca_every", "skin"});
    BroadphaseParams& b = scene.broadphase;
    b.cellSize = r.single("cell_size", b.cellSize, Rule::NonNegative);
    b.skin = r.single("skin", b.skin, Rule::NonNegative);  // absent: automatic (negative)
    const std::int64_t every = r.integer("pca_every", b.pcaEvery, 1);
    if (every > std::numeric_limits<int>::max()) {
      r.fail(sourceOf(*r.find("pca_every")), "pca_every is too large (got " + std::to_string(every) + ")");
    }
    b.pcaEvery = static_cast<int>(every);
  }

  void readIntegrator(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "integrator");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[integrator]", {"rotation"});
    if (const toml::node* n = r.find("rotation")) {
      const std::string name = r.string(*n, "rotation");
      if (name == "report") {
        scene.integrator.rotation = RotationScheme::Report;
      } else if (name == "splitting") {
        scene.integrator.rotation = RotationScheme::Splitting;
      } else {
        r.fail(sourceOf(*n), "unknown rotation scheme \"" + name + "\"; use \"report\" or \"splitting\"");
      }
    }
  }

  void readOutput(Scene& scene) {
    const toml::table* t = sectionOf(m_file, m_root, "output");
    if (t == nullptr) return;
    const TableReader r(m_file, *t, "[output]",
                        {"record", "record_steps", "debug", "steps_per_frame", "thermo", "thermo_every"});
    scene.recordFile = r.string("record", "");
    scene.recordSteps = static_cast<std::uint64_t>(r.integer("record_steps", 0, 0));
    scene.recordDebug = r.boolean("debug", false);
    const std::int64_t spf = r.integer("steps_per_frame", 10, 1);
    if (spf > std::numeric_limits<int>::max()) {
      r.fail(sourceOf(*r.find("steps_per_frame")),
             "steps_per_frame is too large (got " + std::to_string(spf) + ")");
    }
    scene.stepsPerFrame = static_cast<int>(spf);
    scene.thermoFile = r.string("thermo", "");
    scene.thermoEvery = static_cast<std::uint64_t>(r.integer("thermo_every", 100, 1));
  }

  void readMaterials(Scene& scene) {
    const toml::node* n = m_root.get("material");
    const bool hertz = scene.contact.usesMaterials();
    if (n == nullptr) return;
    const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'material'", "[[material]]");
    for (std::size_t k = 0; k < tables.size(); ++k) {
      const TableReader r(m_file, *tables[k], "[[material]] #" + std::to_string(k + 1),
                          {"name", "density", "youngs_modulus", "poisson_ratio", "restitution", "friction",
                           "rolling_friction"});
      MaterialDef md;
      const toml::node& nameNode = r.require("name", "the name that spheres use, e.g. name = \"glass\"");
      md.name = r.string(nameNode, "name");
      if (md.name.empty()) r.fail(sourceOf(nameNode), "name must not be empty");
      if (m_materialIndex.count(md.name) != 0)
        r.fail(sourceOf(nameNode), "material name \"" + md.name + "\" is already used by another [[material]]");
      md.density = r.single("density", 0.0f, Rule::Positive);
      if (!hertz) {
        for (const char* key : {"youngs_modulus", "poisson_ratio", "restitution", "friction", "rolling_friction"})
          if (const toml::node* e = r.find(key))
            r.fail(sourceOf(*e), std::string(key) + " is read under [contact] law = \"hertz-mindlin\" only; under law = \"" +
                                     toString(scene.contact.law) + "\" a material gives its density");
      } else {
        md.youngsModulus = r.single(r.require("youngs_modulus", "Young's modulus in Pa, e.g. youngs_modulus = 6.3e10"),
                                    "youngs_modulus", Rule::Positive);
        md.poissonRatio = r.single(r.require("poisson_ratio", "Poisson's ratio, e.g. poisson_ratio = 0.23"),
                                   "poisson_ratio", Rule::Poisson);
        md.restitution = r.single(r.require("restitution", "coefficient of restitution, e.g. restitution = 0.9"),
                                  "restitution", Rule::Elasticity);
        md.friction = r.single("friction", md.friction, Rule::NonNegative);
        md.rollingFriction = r.single("rolling_friction", md.rollingFriction, Rule::NonNegative);
        if (const std::string why = materialOutOfRange(md); !why.empty()) r.fail(r.header(), why);
      }
      m_materialIndex.emplace(md.name, static_cast<std::uint32_t>(scene.materials.size()));
      m_materialNames.push_back(md.name);
      scene.materials.push_back(std::move(md));
    }
  }

  /// Index of a named material, or an error at the node that names it.
  std::uint32_t materialNamed(const TableReader& r, const toml::node& n, const std::string& what) const {
    const std::string name = r.string(n, what);
    const auto it = m_materialIndex.find(name);
    if (it == m_materialIndex.end()) {
      std::string known;
      for (const std::string& k : m_materialNames) known += (known.empty() ? "" : ", ") + ("\"" + k + "\"");
      r.fail(sourceOf(n), "unknown material \"" + name + "\"" +
                              (known.empty() ? std::string("; the scene has no [[material]] tables")
                                             : "; the scene's materials: " + known));
    }
    return it->second;
  }

  void readShapes(Scene& scene) {
    const toml::node* n = m_root.get("shape");
    if (n == nullptr) return;
    const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'shape'", "[[shape]]");
    for (std::size_t s = 0; s < tables.size(); ++s) {
      const TableReader r(m_file, *tables[s], "[[shape]] #" + std::to_string(s + 1), {"name", "sphere"});
      ShapeDef shape;
      const toml::node& nameNode = r.require("name", "the name that bodies and groups use, e.g. name = \"dimer\"");
      shape.name = r.string(nameNode, "name");
      if (shape.name.empty()) r.fail(sourceOf(nameNode), "name must not be empty");
      if (m_shapeIndex.count(shape.name) != 0) {
        r.fail(sourceOf(nameNode), "shape name \"" + shape.name +
                                       "\" is already used by another [[shape]]; give each shape its own name");
      }
      const std::string where = "shape \"" + shape.name + "\"";
      const toml::node* spheres = r.find("sphere");
      const std::vector<const toml::table*> sphereTables =
          spheres != nullptr ? tablesOf(m_file, *spheres, where + ": 'sphere'", "[[shape.sphere]]")
                             : std::vector<const toml::table*>{};
      if (sphereTables.empty()) {
        r.fail(spheres != nullptr ? sourceOf(*spheres) : r.header(),
               where + " has no spheres; add at least one [[shape.sphere]] with offset, radius and mass");
      }
      for (std::size_t i = 0; i < sphereTables.size(); ++i) {
        const TableReader sr(m_file, *sphereTables[i],
                             where + ", [[shape.sphere]] #" + std::to_string(i + 1),
                             {"offset", "radius", "mass", "density", "elasticity", "material"});
        SphereDef sd;
        sd.offset = sr.vec3("offset", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
        sd.radius = sr.single(sr.require("radius", "sphere radius in m, e.g. radius = 0.5"), "radius",
                              Rule::Positive);
        readSphereMaterial(scene, sr, &sd);
        for (const WallDef& plane : scene.planes())
          if (const std::string why = groundDampingOutOfRange(sd, plane.contact, plane.where); !why.empty())
            sr.fail(sr.header(), why);  // sr names the shape and the sphere
        shape.spheres.push_back(sd);
      }
      if (const std::string why = shapeOutOfRange(shape, scene.contact.rotatesSpheres()); !why.empty()) r.fail(r.header(), where + ": " + why);
      m_shapeIndex.emplace(shape.name, static_cast<std::uint32_t>(scene.shapes.size()));
      scene.shapes.push_back(std::move(shape));
    }
  }

  /// A sphere's material, mass and elasticity (after its radius): `material` names a
  /// [[material]] (default: the only one, if the scene has exactly one); the mass is `mass`, or
  /// the volume 4/3 π r³ times `density` or the material's density. Under hertz-mindlin the
  /// elasticity is the material's restitution.
  void readSphereMaterial(const Scene& scene, const TableReader& sr, SphereDef* sd) const {
    const bool hertz = scene.contact.usesMaterials();
    const MaterialDef* md = nullptr;
    if (const toml::node* n = sr.find("material")) {
      sd->material = materialNamed(sr, *n, "material");
      md = &scene.materials[sd->material];
    } else if (scene.materials.size() == 1) {
      md = &scene.materials[0];
    } else if (hertz) {
      sr.fail(sr.header(), scene.materials.empty()
                               ? "law = \"hertz-mindlin\" needs a [[material]] (name, youngs_modulus, poisson_ratio, "
                                 "restitution) for the spheres"
                               : "the scene has several [[material]] tables: say which this sphere is made of, e.g. "
                                 "material = \"" + scene.materials[0].name + "\"");
    }
    const toml::node* mass = sr.find("mass");
    const toml::node* density = sr.find("density");
    if (mass != nullptr && density != nullptr)
      sr.fail(sourceOf(*density), "give mass or density, not both");
    if (mass != nullptr) {
      sd->mass = sr.single(*mass, "mass", Rule::Positive);
    } else {
      const float rho = density != nullptr ? sr.single(*density, "density", Rule::Positive)
                                           : md != nullptr ? md->density : 0.0f;
      if (!(rho > 0.0f))
        sr.fail(sr.header(), "the sphere needs its mass (mass = 1.0, in kg) or a density (density = 2500, in kg/m³, "
                             "here or in its [[material]])");
      const double m = double(rho) * (4.0 / 3.0) * 3.14159265358979323846 * double(sd->radius) * sd->radius * sd->radius;
      if (!(m >= double(std::numeric_limits<float>::min()) && m <= double(std::numeric_limits<float>::max())))
        sr.fail(density != nullptr ? sourceOf(*density) : sr.header(),
                "density × volume gives a mass beyond single precision (" + fmt(m) + " kg)");
      sd->mass = static_cast<float>(m);
    }
    if (hertz) {
      if (const toml::node* e = sr.find("elasticity"))
        sr.fail(sourceOf(*e), "elasticity is not read under law = \"hertz-mindlin\": the restitution is the "
                              "material's (restitution = … in its [[material]])");
      sd->elasticity = md->restitution;
    } else {
      sd->elasticity = sr.single("elasticity", 0.5f, Rule::Elasticity);
    }
  }

  /// Index of a named shape, or an error at the node that names it.
  std::uint32_t shapeNamed(const TableReader& r, const toml::node& n, const std::string& what,
                           const Scene& scene) const {
    const std::string name = r.string(n, what);
    const auto it = m_shapeIndex.find(name);
    if (it == m_shapeIndex.end()) {
      std::string known;
      for (const ShapeDef& s : scene.shapes) known += (known.empty() ? "\"" : ", \"") + s.name + "\"";
      r.fail(sourceOf(n), "unknown shape \"" + name + "\"; " +
                              (known.empty() ? std::string("no [[shape]] is defined in this file")
                                             : "defined shapes: " + known));
    }
    return it->second;
  }

  void addParticles(const TableReader& r, const toml::source_region& at, std::uint64_t count) {
    m_numParticles += count;
    if (m_numParticles > kMaxParticles) {
      r.fail(at, "the scene has more than 2^31 particles (" + std::to_string(m_numParticles) +
                     " so far); use fewer or smaller groups");
    }
  }

  void readBodies(Scene& scene) {
    struct Entry {
      const toml::table* table;
      bool isGroup;
      std::size_t index;  // among its kind, 0-based
    };
    std::vector<Entry> entries;
    if (const toml::node* n = m_root.get("body")) {
      const auto tables = tablesOf(m_file, *n, "'body'", "[[body]]");
      for (std::size_t i = 0; i < tables.size(); ++i) entries.push_back({tables[i], false, i});
    }
    if (const toml::node* n = m_root.get("group")) {
      const auto tables = tablesOf(m_file, *n, "'group'", "[[group]]");
      for (std::size_t i = 0; i < tables.size(); ++i) entries.push_back({tables[i], true, i});
    }
    // File order: by the position of each table's header (inline tables on one line keep
    // their order within their kind through the stable sort).
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
      const auto& pa = a.table->source().begin;
      const auto& pb = b.table->source().begin;
      return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
    });
    for (const Entry& e : entries) {
      if (e.isGroup) {
        readGroup(scene, *e.table, e.index);
      } else {
        readBody(scene, *e.table, e.index);
      }
    }
  }

  /// One shape (`shape = "name"`) or several (`shapes = ["a", "b"]`) of a [[group]] or [[fill]].
  std::vector<std::uint32_t> shapesOf(const TableReader& r, const Scene& scene) const {
    std::vector<std::uint32_t> shapes;
    const toml::node* one = r.find("shape");
    const toml::node* many = r.find("shapes");
    if (one != nullptr && many != nullptr) {
      r.fail(sourceOf(*many), "give either shape = \"name\" or shapes = [\"a\", \"b\"], not both");
    }
    if (one != nullptr) {
      shapes.push_back(shapeNamed(r, *one, "shape", scene));
    } else if (many != nullptr) {
      const toml::array& a = r.array(*many, "shapes", "of shape names, e.g. shapes = [\"a\", \"b\"]");
      if (a.empty()) r.fail(sourceOf(*many), "shapes must name at least one [[shape]]");
      for (const toml::node& el : a) shapes.push_back(shapeNamed(r, el, "each entry of shapes", scene));
    } else {
      r.fail(r.header(), "missing the shape: give shape = \"name\" or shapes = [\"a\", \"b\", ...]");
    }
    return shapes;
  }

  /// Refuses `bodies` more bodies of at least `minSpheres` spheres each when the scene would
  /// pass 2^31 particles, or the run could not be held in memory (instead of bad_alloc later).
  /// `pouredBefore`: the bodies of earlier pours, whose particles m_numParticles already counts
  /// but scene.bodies does not hold.
  void checkBodyBudget(const TableReader& r, const toml::node& at, const Scene& scene, std::uint64_t bodies,
                       std::size_t minSpheres, std::uint64_t pouredBefore = 0) const {
    if (m_numParticles + bodies * minSpheres > kMaxParticles) {
      r.fail(sourceOf(at), "the scene would have more than 2^31 particles (" +
                               std::to_string(m_numParticles + bodies * minSpheres) + " at least); use a smaller count");
    }
    const std::uint64_t allBodies = scene.bodies.size() + pouredBefore + bodies, allParticles = m_numParticles + bodies * minSpheres;
    if (const std::string shortfall = memoryShortfall(allBodies * (kRunBytesPerBody + sizeof(BodyDef)) +
                                                      allParticles * kRunBytesPerParticle);
        !shortfall.empty()) {
      r.fail(sourceOf(at), "a run of " + std::to_string(allBodies) + " bodies and " + std::to_string(allParticles) +
                               " particles needs at least " + shortfall.substr(6) + "; use a smaller count");
    }
  }

  /// What [[fill]] and [[pour]] share: the shapes and their odds, the count, the region, the
  /// scale, the motion, the seed and the attempts (`kind` "fill" or "pour", `k` its index).
  FillDef readPlacement(const TableReader& r, Scene& scene, const std::string& kind, std::size_t k) {
    FillDef f;
    f.where = r.where() + " (" + m_file + ":" + std::to_string(static_cast<long>(r.header().begin.line)) + ")";
    f.shapes = shapesOf(r, scene);
    if (const toml::node* w = r.find("weights")) {
      const toml::array& a = r.array(*w, "weights", "of one number > 0 per shape, e.g. weights = [3, 1]");
      if (a.size() != f.shapes.size())
        r.fail(sourceOf(*w), "weights has " + std::to_string(a.size()) + " entries for " +
                                 std::to_string(f.shapes.size()) + " shapes; give one per shape");
      for (const toml::node& el : a) f.weights.push_back(r.number(el, "each weight", Rule::Positive));
    } else {
      f.weights.assign(f.shapes.size(), 1.0);
    }
    const toml::node& countNode = r.require("count", "the number of bodies, e.g. count = 500");
    f.count = static_cast<std::uint64_t>(r.integer(countNode, "count", 1));
    std::size_t minSpheres = std::numeric_limits<std::size_t>::max();
    for (std::uint32_t s : f.shapes) minSpheres = std::min(minSpheres, scene.shapes[s].spheres.size());
    if (f.count > kMaxParticles) r.fail(sourceOf(countNode), "count asks for more than 2^31 bodies");
    checkBodyBudget(r, countNode, scene, f.count, minSpheres, scene.pourBodies.size());
    const toml::node& regionNode =
        r.require("region", "where to put them: region = \"box\", \"cylinder\" or \"mesh\"");
    const std::string region = r.string(regionNode, "region");
    static const std::pair<const char*, const char*> kKeysOf[] = {
        {"box", "min max"}, {"cylinder", "point axis radius"}, {"mesh", "wall"}};
    const auto* entry = std::find_if(std::begin(kKeysOf), std::end(kKeysOf),
                                     [&](const auto& e) { return region == e.first; });
    if (entry == std::end(kKeysOf))
      r.fail(sourceOf(regionNode), "unknown region \"" + region + "\" (\"box\", \"cylinder\" or \"mesh\")");
    for (const char* key : {"min", "max", "point", "axis", "radius", "wall"}) {
      const std::string keys = std::string(" ") + entry->second + " ";
      if (const toml::node* e = r.find(key); e != nullptr && keys.find(std::string(" ") + key + " ") == std::string::npos)
        r.fail(sourceOf(*e), std::string(key) + " is not a key of region = \"" + region + "\" (its keys: " +
                                 entry->second + ")");
    }
    FillRegion& g = f.region;
    if (region == "mesh") {  // the inside of a closed mesh wall: [[wall]] #k
      g.kind = FillRegion::Kind::Mesh;
      const toml::node& wn = r.require("wall", "the number of the [[wall]] table of a closed mesh, e.g. wall = 1");
      const std::int64_t k = r.integer(wn, "wall", 1);
      if (std::size_t(k) > m_wallOfTable.size() || scene.walls[m_wallOfTable[std::size_t(k) - 1]].shape != WallDef::Shape::Mesh)
        r.fail(sourceOf(wn), "wall = " + std::to_string(k) + " names no [[wall]] of type = \"mesh\" (the scene has " +
                                 std::to_string(m_wallOfTable.size()) + " [[wall]] tables; count them from 1)");
      g.wall = m_wallOfTable[std::size_t(k) - 1];
    } else if (region == "box") {
      g.kind = FillRegion::Kind::Box;
      g.min = r.vec3(r.require("min", "the lowest corner in m, e.g. min = [-1, -1, 0]"), "min", Rule::Any);
      const toml::node& hiNode = r.require("max", "the highest corner in m, e.g. max = [1, 1, 2]");
      g.max = r.vec3(hiNode, "max", Rule::Any);
      if (!(g.min.x < g.max.x && g.min.y < g.max.y && g.min.z < g.max.z))
        r.fail(sourceOf(hiNode), "max must exceed min on every axis");
    } else {
      g.kind = FillRegion::Kind::Cylinder;
      g.point = r.vec3(r.require("point", "the axis's start in m, e.g. point = [0, 0, 0]"), "point", Rule::Any);
      const toml::node& an = r.require("axis", "from point to the far end in m, e.g. axis = [0, 0, 1]");
      g.axis = r.vec3(an, "axis", Rule::Any);
      const double len =
          std::sqrt(double(g.axis.x) * g.axis.x + double(g.axis.y) * g.axis.y + double(g.axis.z) * g.axis.z);
      if (!(len > 0.0) || !std::isfinite(len)) r.fail(sourceOf(an), "axis must be a non-zero, finite vector");
      g.radius = r.single(r.require("radius", "the radius in m, e.g. radius = 0.5"), "radius", Rule::Positive);
    }
    if (const toml::node* sn = r.find("scale")) {
      if (sn->is_array()) {
        const toml::array& sa = r.array(*sn, "scale", "of 2 numbers [min, max]");
        if (sa.size() != 2)
          r.fail(sourceOf(*sn), "scale must be a number or an array of 2 numbers [min, max] (got " +
                                    std::to_string(sa.size()) + " elements)");
        f.scaleMin = r.single(*sa.get(0), "scale[0]", Rule::Positive);
        f.scaleMax = r.single(*sa.get(1), "scale[1]", Rule::Positive);
        if (!(f.scaleMin <= f.scaleMax)) r.fail(sourceOf(*sn), "scale = [min, max] needs min <= max");
      } else {
        f.scaleMin = f.scaleMax = r.single(*sn, "scale", Rule::Positive);
      }
    }
    f.velocity = r.vec3("velocity", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
    f.velocityJitter = r.single("velocity_jitter", 0.0f, Rule::NonNegative);
    for (float v : {f.velocity.x, f.velocity.y, f.velocity.z})
      if (!(std::fabs(double(v)) + double(f.velocityJitter) <= double(std::numeric_limits<float>::max())))
        r.fail(r.header(), "velocity with velocity_jitter reaches beyond single-precision range");
    f.randomOrientation = r.boolean("random_orientation", true);
    f.spin = r.single("spin", 0.0f, Rule::NonNegative);
    for (std::uint32_t s : f.shapes) {
      ShapeDef big = scene.shapes[s];
      for (SphereDef& sp : big.spheres) sp.offset = f.scaleMax * sp.offset, sp.radius *= f.scaleMax;
      if (const std::string why = angularVelocityOutOfRange(big, f.spin); !why.empty())
        r.fail(sourceOf(*r.find("spin")), "spin: " + why + " (shape '" + scene.shapes[s].name + "')");
    }
    // Each fill and each pour its own generator: the scene's seed (or its own) and its index.
    const std::uint64_t stream = (kind == "fill" ? std::uint64_t{1} : std::uint64_t{2}) << 32;
    f.seed = groupSeed(static_cast<std::uint64_t>(r.integer("seed", static_cast<std::int64_t>(m_seed & INT64_MAX), 0)),
                       stream + k);
    f.attempts = static_cast<std::uint64_t>(r.integer("attempts", kind == "fill" ? 1000 : 100, 1));
    return f;
  }

  /// [[fill]]: bodies packed at random in a box or a cylinder, after every [[body]] and
  /// [[group]], in file order (tumble/fill.hpp).
  void readFills(Scene& scene) {
    const toml::node* n = m_root.get("fill");
    if (n == nullptr) return;
    const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'fill'", "[[fill]]");
    for (std::size_t k = 0; k < tables.size(); ++k) {
      const TableReader r(m_file, *tables[k], "[[fill]] #" + std::to_string(k + 1),
                          {"shape", "shapes", "weights", "count", "region", "min", "max", "point", "axis", "radius",
                           "wall", "scale", "velocity", "velocity_jitter", "random_orientation", "spin", "seed",
                           "attempts"});
      const FillDef f = readPlacement(r, scene, "fill", k);
      const std::size_t before = scene.bodies.size();
      try {
        fillScene(scene, f);
      } catch (const Error& e) {
        r.fail(r.header(), std::string(e.what()).substr(f.where.size() + 2));
      }
      std::uint64_t particles = 0;
      for (std::size_t b = before; b < scene.bodies.size(); ++b) particles += scene.shapes[scene.bodies[b].shape].spheres.size();
      addParticles(r, r.header(), particles);
    }
  }

  /// [[pour]]: bodies that enter during the run (tumble/pour.hpp); their shapes, orientations
  /// and velocities drawn now, in the order they are due.
  void readPours(Scene& scene) {
    const toml::node* n = m_root.get("pour");
    if (n == nullptr) return;
    const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'pour'", "[[pour]]");
    for (std::size_t k = 0; k < tables.size(); ++k) {
      const TableReader r(m_file, *tables[k], "[[pour]] #" + std::to_string(k + 1),
                          {"shape", "shapes", "weights", "count", "region", "min", "max", "point", "axis", "radius",
                           "wall", "scale", "velocity", "velocity_jitter", "random_orientation", "spin", "seed",
                           "attempts", "rate", "start", "interval"});
      const FillDef f = readPlacement(r, scene, "pour", k);
      PourDef p;
      p.region = f.region;
      p.count = f.count;
      p.seed = f.seed;
      p.attempts = f.attempts;
      p.where = f.where;
      p.rate = r.number(r.require("rate", "bodies per second, e.g. rate = 200"), "rate", Rule::Positive);
      p.start = r.number("start", 0.0, Rule::NonNegative);
      p.interval = r.number("interval", 100.0 * double(scene.dt), Rule::Positive);
      const std::uint32_t pour = static_cast<std::uint32_t>(scene.pours.size());
      scene.pours.push_back(p);
      std::map<std::pair<std::uint32_t, float>, std::uint32_t> scaled;
      Rng rng(f.seed);
      std::uint64_t particles = 0;
      for (std::uint64_t i = 0; i < f.count; ++i) {
        PourBody b;
        b.pour = pour;
        b.index = i;
        b.time = p.start + double(i) / p.rate;
        try {
          b.body.shape = detail::drawShape(scene, rng, f.shapes, f.weights, f.scaleMin, f.scaleMax, scaled, f.where);
        } catch (const Error& e) {
          r.fail(r.header(), std::string(e.what()).substr(f.where.size() + 2));
        }
        const float o1 = rng.uniform(), o2 = rng.uniform(), o3 = rng.uniform();
        if (f.randomOrientation) b.body.orientation = randomRotation(o1, o2, o3);
        detail::drawMotion(rng, f.velocity, f.velocityJitter, f.spin, &b.body);
        particles += scene.shapes[b.body.shape].spheres.size();
        scene.pourBodies.push_back(b);
      }
      addParticles(r, r.header(), particles);
    }
    // The order they enter: by the time each is due, then by pour, then by index.
    std::stable_sort(scene.pourBodies.begin(), scene.pourBodies.end(), [](const PourBody& a, const PourBody& b) {
      return a.time != b.time ? a.time < b.time : a.pour < b.pour;
    });
  }

  void readBody(Scene& scene, const toml::table& t, std::size_t index) {
    const TableReader r(m_file, t, "[[body]] #" + std::to_string(index + 1),
                        {"shape", "position", "velocity", "orientation", "angular_velocity"});
    BodyDef b;
    b.shape = shapeNamed(r, r.require("shape", "the name of a [[shape]], e.g. shape = \"dimer\""),
                         "shape", scene);
    const toml::node& positionNode = r.require("position", "centre of mass in m, e.g. position = [0, 0, 1]");
    b.position = r.vec3(positionNode, "position", Rule::Any);
    if (const std::string why = outsidePeriodicBox(scene.periodic, b.position); !why.empty())
      r.fail(sourceOf(positionNode), why);
    const double reach = shapeExtent(scene.shapes[b.shape]);
    for (float x : {b.position.x, b.position.y, b.position.z}) {
      if (!(std::fabs(double(x)) + reach <= double(std::numeric_limits<float>::max())))
        r.fail(r.header(), "the body's spheres reach beyond single-precision range from this position");
    }
    b.velocity = r.vec3("velocity", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
    if (const toml::node* q = r.find("orientation")) b.orientation = r.orientation(*q);
    b.angularVelocity = r.vec3("angular_velocity", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
    {
      const Vec3f& om = b.angularVelocity;
      if (const std::string why = angularVelocityOutOfRange(
              scene.shapes[b.shape], std::sqrt(double(om.x) * om.x + double(om.y) * om.y + double(om.z) * om.z));
          !why.empty())
        r.fail(sourceOf(*r.find("angular_velocity")), "angular_velocity: " + why);
    }
    addParticles(r, r.header(), scene.shapes[b.shape].spheres.size());
    scene.bodies.push_back(b);
  }

  void readGroup(Scene& scene, const toml::table& t, std::size_t index) {
    const TableReader r(m_file, t, "[[group]] #" + std::to_string(index + 1),
                        {"shape", "shapes", "count", "spacing", "origin", "jitter", "velocity",
                         "velocity_jitter", "random_orientation", "spin"});
    // Shapes: one name, or a list picked from per body.
    const std::vector<std::uint32_t> shapes = shapesOf(r, scene);

    // Lattice size.
    const toml::node& countNode =
        r.require("count", "lattice sites along x, y and z, e.g. count = [10, 10, 4]");
    const toml::array& ca = r.array(countNode, "count", "of 3 integers [nx, ny, nz]");
    if (ca.size() != 3) {
      r.fail(sourceOf(countNode), "count must be an array of 3 integers [nx, ny, nz] (got " +
                                      std::to_string(ca.size()) + " elements)");
    }
    static constexpr std::string_view kAxes[] = {"x", "y", "z"};
    std::array<std::uint64_t, 3> count{};
    std::uint64_t sites = 1;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::int64_t v = r.integer(*ca.get(c), "component " + std::string(kAxes[c]) + " of count", 1);
      count[c] = static_cast<std::uint64_t>(v);
      // Each factor ≤ 2^31 before multiplying keeps the product below 2^62.
      if (count[c] > kMaxParticles || sites * count[c] > kMaxParticles) {
        r.fail(sourceOf(countNode), "count asks for more than 2^31 bodies; use a smaller lattice");
      }
      sites *= count[c];
    }
    std::size_t minSpheres = std::numeric_limits<std::size_t>::max();
    for (std::uint32_t s : shapes) minSpheres = std::min(minSpheres, scene.shapes[s].spheres.size());
    checkBodyBudget(r, countNode, scene, sites, minSpheres);

    // Spacing: a scalar or one value per axis; required once a lattice has two sites.
    std::array<double, 3> spacing{0.0, 0.0, 0.0};
    if (const toml::node* sp = r.find("spacing")) {
      if (sp->is_array()) {
        spacing = r.numbers<3>(*sp, "spacing", Rule::Positive);
      } else {
        const double s = r.number(*sp, "spacing", Rule::Positive);
        spacing = {s, s, s};
      }
    } else if (sites > 1) {
      r.fail(r.header(), "missing required key 'spacing' (distance between lattice sites in m, a number "
                         "or [sx, sy, sz])");
    }
    std::array<double, 3> origin{0.0, 0.0, 0.0};
    if (const toml::node* o = r.find("origin")) origin = r.numbers<3>(*o, "origin", Rule::Any);
    const float jitter = r.single("jitter", 0.0f, Rule::NonNegative);
    const Vec3f velocity = r.vec3("velocity", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Any);
    const float velocityJitter = r.single("velocity_jitter", 0.0f, Rule::NonNegative);
    const bool randomOrientation = r.boolean("random_orientation", false);
    const float spin = r.single("spin", 0.0f, Rule::NonNegative);
    // Lattice positions must be representable: origin + (n−1) spacing, the jitter and the
    // shapes' reach within float range; so must the velocities with their jitter.
    double reach = 0.0;
    for (std::uint32_t s : shapes) reach = std::max(reach, shapeExtent(scene.shapes[s]));
    constexpr double kFloatMax = std::numeric_limits<float>::max();
    for (std::size_t c = 0; c < 3; ++c) {
      const double far = origin[c] + static_cast<double>(count[c] - 1) * spacing[c];
      const double extent = std::max(std::fabs(origin[c]), std::fabs(far)) + double(jitter) + reach;
      if (!(extent <= kFloatMax)) {
        r.fail(r.header(), "the lattice reaches beyond single-precision range along " + std::string(kAxes[c]) +
                               " (origin, spacing, jitter and the shapes' size)");
      }
    }
    for (float v : {velocity.x, velocity.y, velocity.z}) {
      if (!(std::fabs(double(v)) + double(velocityJitter) <= kFloatMax))
        r.fail(r.header(), "velocity with velocity_jitter reaches beyond single-precision range");
    }
    for (std::uint32_t s : shapes) {
      if (const std::string why = angularVelocityOutOfRange(scene.shapes[s], spin); !why.empty())
        r.fail(sourceOf(*r.find("spin")), "spin: " + why + " (shape '" + scene.shapes[s].name + "')");
    }

    Rng rng(groupSeed(m_seed, index));
    const std::size_t first = scene.bodies.size();
    scene.bodies.reserve(first + static_cast<std::size_t>(sites));
    std::uint64_t particles = 0;
    // Lattice order as peers/gen_init.py: x fastest, then y, then z.
    for (std::uint64_t k = 0; k < count[2]; ++k) {
      for (std::uint64_t j = 0; j < count[1]; ++j) {
        for (std::uint64_t i = 0; i < count[0]; ++i) {
          BodyDef b;
          const std::uint32_t pick = rng.below(static_cast<std::uint32_t>(shapes.size()));
          b.shape = shapes[pick];
          const float jx = rng.uniform(-jitter, jitter);
          const float jy = rng.uniform(-jitter, jitter);
          const float jz = rng.uniform(-jitter, jitter);
          b.position = Vec3f{
              static_cast<float>(origin[0] + static_cast<double>(i) * spacing[0] + static_cast<double>(jx)),
              static_cast<float>(origin[1] + static_cast<double>(j) * spacing[1] + static_cast<double>(jy)),
              static_cast<float>(origin[2] + static_cast<double>(k) * spacing[2] + static_cast<double>(jz))};
          const float vx = rng.uniform(-velocityJitter, velocityJitter);
          const float vy = rng.uniform(-velocityJitter, velocityJitter);
          const float vz = rng.uniform(-velocityJitter, velocityJitter);
          b.velocity = Vec3f{velocity.x + vx, velocity.y + vy, velocity.z + vz};
          const float u1 = rng.uniform();
          const float u2 = rng.uniform();
          const float u3 = rng.uniform();
          if (randomOrientation) b.orientation = randomRotation(u1, u2, u3);
          const float w1 = rng.uniform();
          const float w2 = rng.uniform();
          if (spin > 0.0f) b.angularVelocity = randomDirection(w1, w2, spin);
          static_assert(kDrawsPerBody == 12, "update docs/scenes.md when the draws change");
          if (const std::string why = outsidePeriodicBox(scene.periodic, b.position); !why.empty())
            r.fail(r.header(), "the body at site (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                                   std::to_string(k) + ") (0-based): " + why);
          particles += scene.shapes[b.shape].spheres.size();
          scene.bodies.push_back(b);
        }
      }
    }
    addParticles(r, sourceOf(countNode), particles);
  }

  const toml::table& m_root;
  const std::string& m_file;
  std::uint64_t m_seed = 1;
  std::uint64_t m_numParticles = 0;
  std::unordered_map<std::string, std::uint32_t> m_shapeIndex;
  toml::source_region m_periodicAt[2];  ///< [periodic] x and y, for the period check
  std::unordered_map<std::string, std::uint32_t> m_materialIndex;
  std::vector<std::string> m_materialNames;  ///< in file order, for messages
  std::vector<std::size_t> m_wallOfTable;     ///< per [[wall]] table, the index of its first wall
};

// The most parts a dotted key or table header may have: tumble's deepest have two
// ("[[shape.sphere]]"); toml++ 3.3.0 parses a dotted key by recursion, one frame per part, and
// overflows the stack at some tens of thousands (an 80 KB file).
inline constexpr int kMaxKeyParts = 64;

// What toml++ must not see, refused before it parses, with the line: non-ASCII bytes outside
// strings and comments (its 3.3.0 reaches an "unreachable" branch, undefined behaviour, for some
// code points where it expects whitespace: U+00A1–U+0499, e.g. "Ñ"), and dotted keys of more
// than kMaxKeyParts parts (the dots outside strings and comments since the last newline, '=',
// ',', bracket or brace: a key's or a header's separators; a value such as 1.5 has one).
// Strings: "…" and '…', and their multi-line forms.
void checkBeforeToml(std::string_view t, const std::string& file) {
  long line = 1;
  int dots = 0;
  std::size_t i = t.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte-order mark (toml++ skips it)
  const auto starts = [&](std::string_view s) { return t.substr(i, s.size()) == s; };
  while (i < t.size()) {
    const char c = t[i];
    if (c == '\n' || c == '=' || c == ',' || c == '[' || c == ']' || c == '{' || c == '}') {
      dots = 0;
      if (c == '\n') ++line;
      ++i;
    } else if (c == '.') {
      if (++dots >= kMaxKeyParts)
        throw InputError(file, line,
                         "a dotted key or table header of more than " + std::to_string(kMaxKeyParts) +
                             " parts; tumble's keys have at most two (docs/scenes.md)");
      ++i;
    } else if (c == '#') {  // comment: to the end of the line
      while (i < t.size() && t[i] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool multi = starts(c == '"' ? "\"\"\"" : "'''");
      const std::size_t open = multi ? 3 : 1;
      i += open;
      for (;;) {
        if (i >= t.size()) return;  // unterminated: toml++ reports it
        if (t[i] == '\n') {
          if (!multi) break;  // toml++ reports the unterminated string
          ++line;
        }
        if (c == '"' && t[i] == '\\') {  // an escape in a basic string (a line-ending one too)
          if (i + 1 < t.size() && t[i + 1] == '\n') ++line;
          i += 2;
          continue;
        }
        if (t[i] == c && !multi) {
          ++i;
          break;
        }
        if (t[i] == c) {  // a run of quotes: three or more end the string, after the whole run
          std::size_t k = 0;
          while (i + k < t.size() && t[i + k] == c) ++k;
          i += k;
          if (k >= 3) break;
          continue;
        }
        ++i;
      }
    } else if (static_cast<unsigned char>(c) >= 0x80) {
      throw InputError(file, line,
                       "a non-ASCII character outside a string or comment; TOML allows them only in "
                       "\"strings\" and # comments");
    } else {
      ++i;
    }
  }
}

/// The TOML document of `text`, refused (InputError at `name` and the line) for a syntax error
/// or a non-ASCII character outside strings and comments.
toml::table parseToml(std::string_view text, const std::string& name) {
  checkBeforeToml(text, name);
#if TOML_EXCEPTIONS
  try {
    return toml::parse(text, std::string_view(name));
  } catch (const toml::parse_error& e) {
    throw InputError(name, static_cast<long>(e.source().begin.line),
                     "TOML syntax error: " + std::string(e.description()));
  }
#else
  toml::parse_result result = toml::parse(text, std::string_view(name));
  if (!result) {
    const toml::parse_error& e = result.error();
    throw InputError(name, static_cast<long>(e.source().begin.line),
                     "TOML syntax error: " + std::string(e.description()));
  }
  return std::move(result).table();
#endif
}

/// A --set override, parsed: the document "[SECTION]\nKEY = VALUE" whose nodes have the
/// override's origin as their source path, so that the reader's messages name it.
struct Override {
  std::string origin;  // "command line, --set SPEC"
  std::string section, key;
  toml::table doc;
};

/// A TOML bare key: letters, digits, '_' and '-'.
bool isBareKey(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string_view trimmed(std::string_view s) {
  const std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

Override parseOverride(const std::string& spec) {
  Override o;
  o.origin = "command line, --set " + spec;
  const std::string_view text = spec;
  const std::size_t eq = text.find('=');
  const std::string_view name = trimmed(text.substr(0, eq));
  const std::size_t dot = name.find('.');
  if (eq == std::string_view::npos || dot == std::string_view::npos || !isBareKey(name.substr(0, dot)) ||
      !isBareKey(name.substr(dot + 1))) {
    throw InputError(o.origin, 0,
                     "expected SECTION.KEY=VALUE, one table and one of its keys (letters, digits, _ and -) and "
                     "a TOML value, e.g. --set ground.friction=0.3");
  }
  o.section = std::string(name.substr(0, dot));
  o.key = std::string(name.substr(dot + 1));
  if (!isOneOf(kSingleTables, o.section)) {
    throw InputError(o.origin, 0,
                     (isOneOf(kArrayTables, o.section)
                          ? "[[" + o.section + "]] entries cannot be set from the command line (a scene may have "
                                                "several: edit the file)"
                          : "unknown section '" + o.section + "'") +
                         "; --set can change the keys of " + tableNames(false));
  }
  const std::string_view value = text.substr(eq + 1);
  try {
    o.doc = parseToml("[" + o.section + "]\n" + o.key + " = " + std::string(value) + "\n", o.origin);
  } catch (const InputError& e) {
    const std::string_view v = trimmed(value);
    const bool bare = v.empty() || std::string_view("\"'[{").find(v.front()) == std::string_view::npos;
    throw InputError(o.origin, 0,
                     e.problem() + (bare ? "; VALUE is TOML: a string needs quotes, e.g. --set "
                                           "output.record='\"run.bin\"'"
                                         : ""));
  }
  const toml::table* t = o.doc.get_as<toml::table>(o.section);
  if (o.doc.size() != 1 || t == nullptr || t->size() != 1) {
    throw InputError(o.origin, 0, "VALUE must be one TOML value, not more keys or tables");
  }
  return o;
}

std::vector<Override> parseOverrides(const std::vector<std::string>& specs) {
  std::vector<Override> out;
  out.reserve(specs.size());
  for (const std::string& spec : specs) out.push_back(parseOverride(spec));
  return out;
}

/// Puts the override's key into the file's table (creating the table when the file lacks it),
/// replacing the file's value: moved, not copied, so that the nodes keep their source.
void applyOverride(toml::table& root, Override& o, const std::string& file) {
  toml::table& from = *o.doc.get_as<toml::table>(o.section);
  toml::node* existing = root.get(o.section);
  if (existing == nullptr) {
    root.insert(o.section, std::move(from));
    return;
  }
  (void)sectionOf(file, root, o.section);  // the file's own error when it is not a table there
  toml::table& to = *existing->as_table();
  auto [key, node] = *from.begin();
  to.erase(o.key);
  to.insert(key, std::move(node));
}

Scene parseWith(std::string_view text, const std::string& sourceName, std::vector<Override>& overrides) {
  toml::table root = parseToml(text, sourceName);
  for (Override& o : overrides) applyOverride(root, o, sourceName);
  return SceneParser(root, sourceName).run();
}

}  // namespace

Scene parseScene(std::string_view text, const std::string& sourceName, const std::vector<std::string>& overrides) {
  std::vector<Override> parsed = parseOverrides(overrides);
  return parseWith(text, sourceName, parsed);
}

Scene readSceneFile(const std::string& path, const std::vector<std::string>& overrides) {
  std::vector<Override> parsed = parseOverrides(overrides);  // mistakes on the command line first
  return parseWith(detail::readWholeFile(path), path, parsed);
}

}  // namespace tumble
