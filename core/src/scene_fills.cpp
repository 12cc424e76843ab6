// SPDX-License-Identifier: MIT
// The TOML scene reader's [[fill]] and [[pour]] tables and what they share (shapes, count,
// region, scale, motion, seed): SceneParser members (scene_reader.hpp).
#include "scene_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "placement.hpp"
#include "tumble/fill.hpp"
#include "tumble/random.hpp"
#include "tumble/world.hpp"

namespace tumble::scene_reader {

/// What [[fill]] and [[pour]] share: the shapes and their odds, the count, the region, the
/// scale, the motion, the seed and the attempts (`kind` "fill" or "pour", `k` its index).
FillDef SceneParser::readPlacement(const TableReader& r, Scene& scene, const std::string& kind, std::size_t k) {
  FillDef f;
  f.where = r.where() + " (" + printable(m_file) + ":" + std::to_string(static_cast<long>(r.header().begin.line)) + ")";
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
  checkBodyBudget(r, countNode, scene, f.count, minSpheres, kind == "pour");
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
    g.min = r.vec3(r.require("min", "the lowest corner in m, e.g. min = [-1, -1, 0]"), "min", Rule::Coordinate);
    const toml::node& hiNode = r.require("max", "the highest corner in m, e.g. max = [1, 1, 2]");
    g.max = r.vec3(hiNode, "max", Rule::Coordinate);
    if (!(g.min.x < g.max.x && g.min.y < g.max.y && g.min.z < g.max.z))
      r.fail(sourceOf(hiNode), "max must exceed min on every axis");
  } else {
    g.kind = FillRegion::Kind::Cylinder;
    g.point = r.vec3(r.require("point", "the axis's start in m, e.g. point = [0, 0, 0]"), "point", Rule::Coordinate);
    const toml::node& an = r.require("axis", "from point to the far end in m, e.g. axis = [0, 0, 1]");
    g.axis = r.vec3(an, "axis", Rule::Coordinate);
    const double len =
        std::sqrt(double(g.axis.x) * g.axis.x + double(g.axis.y) * g.axis.y + double(g.axis.z) * g.axis.z);
    if (!(len > 0.0) || !std::isfinite(len)) r.fail(sourceOf(an), "axis must be a non-zero, finite vector");
    const toml::node& rn = r.require("radius", "the radius in m, e.g. radius = 0.5");
    g.radius = r.single(rn, "radius", Rule::Positive);
    // Every point of it within the range whose contacts single precision decides right.
    for (const auto& [p, a] : {std::pair{g.point.x, g.axis.x}, {g.point.y, g.axis.y}, {g.point.z, g.axis.z}})
      if (!(std::fabs(double(p)) + std::fabs(double(a)) + double(g.radius) <= kMaxCoordinate))
        r.fail(sourceOf(rn), "the cylinder (point, axis and radius) reaches beyond +-2^60 m (1.15e18), the range "
                             "whose contacts single precision decides right");
  }
  const toml::node* sn = r.find("scale");
  if (const toml::node* zn = r.find("size")) {
    if (sn != nullptr)
      r.fail(sourceOf(*zn), "give either scale (a uniform factor) or size (a distribution), not both");
    sn = zn;
    f.size = readSize(r, *zn);
  } else if (sn != nullptr) {
    if (sn->is_array()) {
      const toml::array& sa = r.array(*sn, "scale", "of 2 numbers [min, max]");
      if (sa.size() != 2)
        r.fail(sourceOf(*sn), "scale must be a number or an array of 2 numbers [min, max] (got " +
                                  std::to_string(sa.size()) + " elements)");
      const float lo = r.single(*sa.get(0), "scale[0]", Rule::Positive);
      const float hi = r.single(*sa.get(1), "scale[1]", Rule::Positive);
      if (!(lo <= hi)) r.fail(sourceOf(*sn), "scale = [min, max] needs min <= max");
      f.size = SizeDistribution::uniform(lo, hi, SizeDistribution::Weight::Number);
    } else {
      f.size = SizeDistribution::fixed(r.single(*sn, "scale", Rule::Positive));
    }
  }
  if (sn != nullptr) {
    // Every scaled radius within the range whose contacts single precision decides right.
    for (std::uint32_t s : f.shapes)
      for (const SphereDef& sp : scene.shapes[s].spheres)
        if (!(double(sp.radius) * f.size.min() >= kMinRadius && double(sp.radius) * f.size.max() <= kMaxCoordinate))
          r.fail(sourceOf(*sn), std::string(sn == r.find("size") ? "size" : "scale") + " makes a sphere of shape '" +
                                    printable(scene.shapes[s].name) +
                                    "' leave [2^-60, 2^60] m (8.7e-19 to 1.15e18), the range whose contacts single "
                                    "precision decides right");
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
    for (SphereDef& sp : big.spheres) sp.offset = f.size.max() * sp.offset, sp.radius *= f.size.max();
    if (const std::string why = angularVelocityOutOfRange(big, f.spin); !why.empty())
      r.fail(sourceOf(*r.find("spin")), "spin: " + why + " (shape '" + scene.shapes[s].name + "')");
  }
  // Each fill and each pour its own generator: the scene's seed (or its own) and its index.
  const std::uint64_t stream = (kind == "fill" ? std::uint64_t{1} : std::uint64_t{2}) << 32;
  f.seed = groupSeed(static_cast<std::uint64_t>(r.integer("seed", static_cast<std::int64_t>(m_seed & INT64_MAX), 0)),
                     stream + k);
  f.attempts = static_cast<std::uint64_t>(r.integer("attempts", kind == "fill" ? 1000 : 100, 1));
  // Each draw tests the body against its neighbours: a bound keeps a full region from holding
  // the load (a [[fill]]) or every batch (a [[pour]]) for hours.
  if (f.attempts > kMaxPlacementAttempts)
    r.fail(sourceOf(*r.find("attempts")), "attempts must be <= " + std::to_string(kMaxPlacementAttempts) + " (got " +
                                              std::to_string(f.attempts) +
                                              "): draws per body; a region that needs more is too full (docs/scenes.md)");
  return f;
}

/// The `size` table of a [[fill]] or a [[pour]]: a distribution of the scale factor
/// (docs/scenes.md#size-distributions).
SizeDistribution SceneParser::readSize(const TableReader& placement, const toml::node& n) const {
  const toml::table* t = n.as_table();
  if (t == nullptr)
    placement.fail(sourceOf(n), "size must be a table, e.g. size = { distribution = \"lognormal\", median = 1, "
                                "sigma = 0.25 } (got " + typeName(n) + ")");
  const TableReader r(m_file, *t, placement.where() + " size",
                      {"distribution", "by", "min", "max", "mean", "sd", "median", "sigma", "sizes", "cumulative"});
  const toml::node& kindNode =
      r.require("distribution", "\"uniform\", \"normal\", \"lognormal\" or \"table\"");
  const std::string kind = r.string(kindNode, "distribution");
  static const std::pair<const char*, const char*> kKeysOf[] = {{"uniform", "min max by"},
                                                                {"normal", "mean sd min max by"},
                                                                {"lognormal", "median sigma min max by"},
                                                                {"table", "sizes cumulative by"}};
  const auto* entry =
      std::find_if(std::begin(kKeysOf), std::end(kKeysOf), [&](const auto& e) { return kind == e.first; });
  if (entry == std::end(kKeysOf))
    r.fail(sourceOf(kindNode), "unknown distribution \"" + printable(kind) +
                                   "\" (\"uniform\", \"normal\", \"lognormal\" or \"table\")");
  for (auto&& [key, value] : *t) {
    const std::string keys = std::string(" distribution ") + entry->second + " ";
    std::string word(1, ' ');  // (" " + key + " ": GCC 12 warns falsely, -Wrestrict)
    word.append(key.str()).push_back(' ');
    if (keys.find(word) == std::string::npos)
      r.fail(sourceOf(value), std::string(key.str()) + " is not a key of distribution = \"" + kind +
                                  "\" (its keys: " + entry->second + ")");
  }
  SizeDistribution::Weight by = SizeDistribution::Weight::Number;
  if (const toml::node* bn = r.find("by")) {
    const std::string w = r.string(*bn, "by");
    if (w == "volume" || w == "mass")
      by = SizeDistribution::Weight::Volume;
    else if (w != "number")
      r.fail(sourceOf(*bn), "by must be \"number\" (the fraction of the bodies) or \"volume\" (of their volume; "
                            "\"mass\" is the same), got \"" + printable(w) + "\"");
  }
  try {
    if (kind == "table") {
      const toml::node& sn = r.require("sizes", "the sizes (scale factors), increasing, e.g. sizes = [0.5, 1, 2]");
      const toml::node& cn =
          r.require("cumulative", "the fraction at or below each size, from 0 to 1, e.g. cumulative = [0, 0.7, 1]");
      const toml::array& sa = r.array(sn, "sizes", "of sizes > 0, increasing");
      const toml::array& ca = r.array(cn, "cumulative", "of fractions from 0 to 1, one per size");
      if (sa.size() < 2) r.fail(sourceOf(sn), "sizes needs at least 2 entries (the smallest and the largest size)");
      if (ca.size() != sa.size())
        r.fail(sourceOf(cn), "cumulative has " + std::to_string(ca.size()) + " entries for " +
                                 std::to_string(sa.size()) + " sizes; give one per size");
      std::vector<double> sizes, cumulative;
      for (std::size_t i = 0; i < sa.size(); ++i) {
        sizes.push_back(double(r.single(*sa.get(i), "each size", Rule::Positive)));
        cumulative.push_back(r.number(*ca.get(i), "each cumulative fraction", Rule::NonNegative));
        if (i > 0 && !(sizes[i] > sizes[i - 1]))
          r.fail(sourceOf(*sa.get(i)), "sizes must increase (entry " + std::to_string(i + 1) +
                                           " is not above the one before in single precision)");
        if (i > 0 && !(cumulative[i] >= cumulative[i - 1]))
          r.fail(sourceOf(*ca.get(i)), "cumulative must not decrease (entry " + std::to_string(i + 1) + " is below the one before)");
      }
      if (cumulative.front() != 0.0 || cumulative.back() != 1.0)
        r.fail(sourceOf(cn), "cumulative must start at 0 and end at 1 (the fractions at or below the smallest and "
                             "the largest size)");
      return SizeDistribution::table(std::move(sizes), std::move(cumulative), by);
    }
    if (kind == "uniform") {
      const float lo = r.single(r.require("min", "the smallest size, e.g. min = 0.8"), "min", Rule::Positive);
      const toml::node& hn = r.require("max", "the largest size, e.g. max = 1.2");
      const float hi = r.single(hn, "max", Rule::Positive);
      if (!(lo <= hi)) r.fail(sourceOf(hn), "max must be at least min");
      return SizeDistribution::uniform(lo, hi, by);
    }
    // A normal or a log-normal: its two parameters, and bounds 3 of its σ out where not given.
    const bool normal = kind == "normal";
    const toml::node& cn = normal ? r.require("mean", "the mean size, e.g. mean = 1")
                                  : r.require("median", "the median size (e^mu), e.g. median = 1");
    const double centre = r.number(cn, normal ? "mean" : "median", Rule::Positive);
    const toml::node& wn = normal ? r.require("sd", "the standard deviation, e.g. sd = 0.1")
                                  : r.require("sigma", "the standard deviation of ln(size), e.g. sigma = 0.25");
    const double width = r.number(wn, normal ? "sd" : "sigma", Rule::Positive);
    const auto [lo0, hi0] = SizeDistribution::defaultBounds(
        normal ? SizeDistribution::Kind::Normal : SizeDistribution::Kind::LogNormal, centre, width);
    const toml::node* ln = r.find("min");
    const toml::node* hn = r.find("max");
    if (ln == nullptr && !(lo0 > 0.0))
      r.fail(sourceOf(wn), normal ? "the default lower bound, mean - 3 sd, is not above 0: give min (> 0)"
                                  : "the default lower bound, median e^(-3 sigma), is not above 0 in double "
                                    "precision: give min and max (> 0)");
    const float lo = ln != nullptr ? r.single(*ln, "min", Rule::Positive) : float(lo0);
    const float hi = hn != nullptr ? r.single(*hn, "max", Rule::Positive) : float(hi0);
    if (!(lo < hi) || !std::isfinite(hi) || !(lo > 0.0f))
      r.fail(hn != nullptr ? sourceOf(*hn) : sourceOf(wn),
             "the bounds must satisfy 0 < min < max (finite; by default 3 standard deviations either side)");
    return normal ? SizeDistribution::normal(centre, width, lo, hi, by)
                  : SizeDistribution::logNormal(centre, width, lo, hi, by);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    r.fail(r.header(), e.what());
  }
}

/// [[fill]]: bodies packed at random in a box or a cylinder, after every [[body]] and
/// [[group]], in file order (tumble/fill.hpp).
void SceneParser::readFills(Scene& scene) {
  const toml::node* n = m_root.get("fill");
  if (n == nullptr) return;
  const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'fill'", "[[fill]]");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const TableReader r(m_file, *tables[k], "[[fill]] #" + std::to_string(k + 1),
                        {"shape", "shapes", "weights", "count", "region", "min", "max", "point", "axis", "radius",
                         "wall", "scale", "size", "velocity", "velocity_jitter", "random_orientation", "spin", "seed",
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
void SceneParser::readPours(Scene& scene) {
  const toml::node* n = m_root.get("pour");
  if (n == nullptr) return;
  const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'pour'", "[[pour]]");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const TableReader r(m_file, *tables[k], "[[pour]] #" + std::to_string(k + 1),
                        {"shape", "shapes", "weights", "count", "region", "min", "max", "point", "axis", "radius",
                         "wall", "scale", "size", "velocity", "velocity_jitter", "random_orientation", "spin", "seed",
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
        b.body.shape = detail::drawShape(scene, rng, f.shapes, f.weights, f.size, scaled, f.where);
      } catch (const Error& e) {
        r.fail(r.header(), std::string(e.what()).substr(f.where.size() + 2));
      }
      const float o1 = rng.uniform(), o2 = rng.uniform(), o3 = rng.uniform();
      if (f.randomOrientation) b.body.orientation = randomRotation(o1, o2, o3);
      detail::drawMotion(rng, f.velocity, f.velocityJitter, f.spin, &b.body);
      particles += scene.shapes[b.body.shape].spheres.size();
      scene.pourBodies.push_back(b);
    }
    // A region no sphere of the pour fits in takes no body, ever: said here, not by a pour that
    // waits for the whole run (issue 34, item 11). (A mesh region is left to the placement.)
    const FillRegion& g = p.region;
    const double room = g.kind == FillRegion::Kind::Box
                            ? 0.5 * std::min({double(g.max.x) - g.min.x, double(g.max.y) - g.min.y, double(g.max.z) - g.min.z})
                        : g.kind == FillRegion::Kind::Cylinder
                            ? std::min(double(g.radius), 0.5 * std::sqrt(double(g.axis.x) * g.axis.x +
                                                                         double(g.axis.y) * g.axis.y + double(g.axis.z) * g.axis.z))
                            : std::numeric_limits<double>::infinity();
    for (std::size_t b = scene.pourBodies.size() - f.count; b < scene.pourBodies.size(); ++b)
      for (const SphereDef& s : scene.shapes[scene.pourBodies[b].body.shape].spheres)
        if (double(s.radius) > room) {
          char sizes[96];
          std::snprintf(sizes, sizeof sizes, "radius %.6g m, the region's half-width %.6g m", double(s.radius), room);
          r.fail(r.header(), "its region is narrower than a sphere of shape '" +
                                 scene.shapes[scene.pourBodies[b].body.shape].name + "' (" + sizes +
                                 "): no body could ever enter; use a larger region or smaller bodies");
        }
    addParticles(r, r.header(), particles);
  }
  // The order they enter: by the time each is due, then by pour, then by index.
  std::stable_sort(scene.pourBodies.begin(), scene.pourBodies.end(), [](const PourBody& a, const PourBody& b) {
    return a.time != b.time ? a.time < b.time : a.pour < b.pour;
  });
}

}  // namespace tumble::scene_reader
