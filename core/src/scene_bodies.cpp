// SPDX-License-Identifier: MIT
// The TOML scene reader's [[shape]], [[body]] and [[group]] tables (a group's lattice drawn
// from tumble::Rng) and the particle and memory budget: SceneParser members (scene_reader.hpp).
#include "scene_reader.hpp"

#include "tumble/clump.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tumble/memory.hpp"
#include "tumble/random.hpp"
#include "tumble/run_memory.hpp"
#include "tumble/world.hpp"

namespace tumble::scene_reader {

void SceneParser::readShapes(Scene& scene) {
  const toml::node* n = m_root.get("shape");
  if (n == nullptr) return;
  const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'shape'", "[[shape]]");
  for (std::size_t s = 0; s < tables.size(); ++s) {
    const TableReader r(m_file, *tables[s], "[[shape]] #" + std::to_string(s + 1),
                        {"name", "sphere", "mass", "centre_of_mass", "inertia", "mesh", "spheres", "tolerance", "fill",
                         "resolution", "scale", "orientation", "density", "material", "elasticity"});
    ShapeDef shape;
    const toml::node& nameNode = r.require("name", "the name that bodies and groups use, e.g. name = \"dimer\"");
    shape.name = r.string(nameNode, "name");
    if (shape.name.empty()) r.fail(sourceOf(nameNode), "name must not be empty");
    if (m_shapeIndex.count(shape.name) != 0) {
      r.fail(sourceOf(nameNode), "shape name \"" + shape.name +
                                     "\" is already used by another [[shape]]; give each shape its own name");
    }
    const std::string where = "shape \"" + shape.name + "\"";
    // A shape made from a mesh, or of the spheres written out: each has keys the other has not.
    const bool fromMesh = r.has("mesh");
    static const std::vector<const char*> kSpheresOnly{"sphere", "mass", "centre_of_mass", "inertia"};
    static const std::vector<const char*> kMeshOnly{"spheres", "tolerance", "fill", "resolution", "scale", "orientation",
                                                    "density",  "material",  "elasticity"};
    for (const char* key : fromMesh ? kSpheresOnly : kMeshOnly)
      if (const toml::node* k = r.find(key))
        r.fail(sourceOf(*k), fromMesh ? std::string(key) + " is not a key of a shape made from a mesh (its spheres and "
                                                           "mass properties come from the mesh)"
                                      : std::string(key) + " is a key of a shape made from a mesh: give mesh = "
                                                           "\"FILE.stl\" too, or write the spheres as [[shape.sphere]]");
    if (fromMesh) {
      shape = readMeshShape(scene, r, shape.name);
    } else {
      const toml::node* spheres = r.find("sphere");
      const std::vector<const toml::table*> sphereTables =
          spheres != nullptr ? tablesOf(m_file, *spheres, where + ": 'sphere'", "[[shape.sphere]]")
                             : std::vector<const toml::table*>{};
      if (sphereTables.empty()) {
        r.fail(spheres != nullptr ? sourceOf(*spheres) : r.header(),
               where + " has no spheres; add at least one [[shape.sphere]] with offset, radius and mass");
      }
      shape.solid = readSolid(r);
      for (std::size_t i = 0; i < sphereTables.size(); ++i) {
        const TableReader sr(m_file, *sphereTables[i],
                             where + ", [[shape.sphere]] #" + std::to_string(i + 1),
                             {"offset", "radius", "mass", "density", "elasticity", "material"});
        SphereDef sd;
        sd.offset = sr.vec3("offset", Vec3f{0.0f, 0.0f, 0.0f}, Rule::Coordinate);
        sd.radius = sr.single(sr.require("radius", "sphere radius in m, e.g. radius = 0.5"), "radius",
                              Rule::Radius);
        readSphereMaterial(scene, sr, &sd, shape.solid.has_value());
        for (const WallDef& plane : shape.solid ? std::vector<WallDef>{} : scene.planes())  // (a solid's: below)
          if (const std::string why = groundDampingOutOfRange(sd, plane.contact, plane.where); !why.empty())
            sr.fail(sr.header(), why);  // sr names the shape and the sphere
        shape.spheres.push_back(sd);
      }
    }
    if (shape.solid) {  // each sphere its share of the solid's mass, by volume (r³)
      shareMassByVolume(shape);
      for (std::size_t i = 0; i < shape.spheres.size(); ++i) {
        const SphereDef& sd = shape.spheres[i];
        if (!(sd.mass >= std::numeric_limits<float>::min() && sd.mass <= std::numeric_limits<float>::max()))
          r.fail(r.header(), where + ": sphere " + std::to_string(i + 1) + "'s share of the mass (" +
                                 fmt(double(sd.mass)) + " kg) is beyond single precision");
        for (const WallDef& plane : scene.planes())
          if (const std::string why = groundDampingOutOfRange(sd, plane.contact, plane.where); !why.empty())
            r.fail(r.header(), where + ", sphere " + std::to_string(i + 1) + ": " + why);
      }
    }
    if (const std::string why = shapeOutOfRange(shape, scene.contact.rotatesSpheres(), scene.gravity); !why.empty()) r.fail(r.header(), where + ": " + why);
    m_shapeIndex.emplace(shape.name, static_cast<std::uint32_t>(scene.shapes.size()));
    scene.shapes.push_back(std::move(shape));
  }
}

/// A [[shape]] made from a closed mesh (`mesh`, docs/scenes.md): the clump of clumpFromMesh()
/// (`spheres`, `tolerance`, `resolution`) of the mesh times `scale`, its mass properties the
/// solid's at `density` (or its material's), its spheres' elasticity and material the shape's.
ShapeDef SceneParser::readMeshShape(const Scene& scene, const TableReader& r, const std::string& name) const {
  const toml::node& mn = *r.find("mesh");
  std::string bytes;
  const std::string resolved = readMeshFileOf(r, mn, "mesh", &bytes);
  ClumpOptions o;
  const toml::node* sn = r.find("spheres");
  const toml::node* tn = r.find("tolerance");
  if (sn == nullptr && tn == nullptr)
    r.fail(r.header(), "a shape made from a mesh needs spheres = N (the most spheres) or tolerance = D (m: how deep the "
                       "solid may stay uncovered), or both");
  if (sn != nullptr) {
    const std::int64_t n = r.integer(*sn, "spheres", 1);
    if (n > 100000) r.fail(sourceOf(*sn), "spheres must be at most 100000 (got " + std::to_string(n) + ")");
    o.spheres = std::uint32_t(n);
  }
  if (tn != nullptr) o.tolerance = r.number(*tn, "tolerance", Rule::Positive);
  if (const toml::node* fn = r.find("fill")) {
    const std::string fill = r.string(*fn, "fill");
    if (fill == "surface") o.fill = ClumpFill::Surface;
    else if (fill != "inside")
      r.fail(sourceOf(*fn), "unknown fill \"" + fill + "\"; use \"inside\" (spheres filling the solid, the largest "
                            "first) or \"surface\" (a layer of spheres of one radius under its surface)");
  }
  if (const toml::node* rn = r.find("resolution")) {
    const std::int64_t n = r.integer(*rn, "resolution", 8);
    if (n > 512) r.fail(sourceOf(*rn), "resolution must be from 8 to 512 voxels along the longest side (got " +
                                           std::to_string(n) + ")");
    o.resolution = std::uint32_t(n);
  }
  const Vec3f scale = readMeshScale(r);
  SphereDef sphere;  // the spheres' elasticity and material
  const MaterialDef* md = readMaterialAndElasticity(scene, r, &sphere);
  const toml::node* dn = r.find("density");
  const double density = dn != nullptr ? r.number(*dn, "density", Rule::Positive) : md != nullptr ? md->density : 0.0;
  if (!(density > 0.0))
    r.fail(r.header(), "a shape made from a mesh needs its density (density = 2500, in kg/m³, here or in its "
                       "[[material]]): its mass is the mesh's volume times it");
  const toml::node* qn = r.find("orientation");
  const std::optional<Quatf> turn = qn != nullptr ? std::optional<Quatf>(r.orientation(*qn)) : std::nullopt;
  Clump clump;
  try {
    TriangleMesh mesh = parseMesh(bytes, resolved);
    std::array<double, 3> clumpScale{double(scale.x), double(scale.y), double(scale.z)};
    if (turn && !(turn->w == 1.0f && turn->x == 0.0f && turn->y == 0.0f && turn->z == 0.0f)) {
      // turned after the scale, as a mesh wall (rounded to float once; the identity turns nothing)
      WallDef placed;
      placed.where = r.where();
      placed.mesh = std::make_shared<const TriangleMesh>(mesh);
      placed.scale = scale;
      placed.orientation = *turn;
      mesh.vertices = meshWallVertices(placed);
      clumpScale = {1.0, 1.0, 1.0};
    }
    clump = clumpFromMesh(mesh, o, clumpScale);
  } catch (const InputError& e) {
    throw InputError(e.file(), e.line(), e.problem() + " (the mesh of " + r.where() + ")");
  } catch (const Error& e) {
    r.fail(sourceOf(mn), e.what());
  }
  ShapeDef shape = clumpShape(clump, name, density);
  for (SphereDef& sd : shape.spheres) sd.elasticity = sphere.elasticity, sd.material = sphere.material;
  shape.meshFile = resolved;
  return shape;
}

/// A shape's own mass properties (`mass`, `centre_of_mass`, `inertia`: all three or none), as
/// `tumble clump` writes them for a shape made from a mesh; nothing when the shape has none.
std::optional<ShapeSolid> SceneParser::readSolid(const TableReader& r) const {
  const toml::node* mass = r.find("mass");
  const toml::node* centre = r.find("centre_of_mass");
  const toml::node* inertia = r.find("inertia");
  if (mass == nullptr && centre == nullptr && inertia == nullptr) return std::nullopt;
  if (mass == nullptr || centre == nullptr || inertia == nullptr)
    r.fail(r.header(), "give the shape's mass, centre_of_mass and inertia together (a solid's mass properties, as "
                       "tumble clump writes them), or none (the spheres' own)");
  ShapeSolid s;
  s.mass = r.number(*mass, "mass", Rule::Positive);  // (its range: shapeOutOfRange())
  const auto c = r.numbers<3>(*centre, "centre_of_mass", Rule::Coordinate);
  s.centre = {c[0], c[1], c[2]};
  const auto i = r.numbers<6>(*inertia, "inertia", Rule::Any);
  for (int k = 0; k < 6; ++k) s.inertia[k] = i[k];
  return s;
}

/// A sphere's material, mass and elasticity (after its radius): `material` names a
/// [[material]] (default: the only one, if the scene has exactly one); the mass is `mass`, or
/// the volume 4/3 π r³ times `density` or the material's density. Under hertz-mindlin the
/// elasticity is the material's restitution.
void SceneParser::readSphereMaterial(const Scene& scene, const TableReader& sr, SphereDef* sd, bool shapeMass) const {
  const MaterialDef* md = readMaterialAndElasticity(scene, sr, sd);
  const toml::node* mass = sr.find("mass");
  const toml::node* density = sr.find("density");
  if (mass != nullptr && density != nullptr)
    sr.fail(sourceOf(*density), "give mass or density, not both");
  if (shapeMass) {  // the shape's mass, shared out by volume later
    if (mass != nullptr || density != nullptr)
      sr.fail(sourceOf(mass != nullptr ? *mass : *density),
              "the shape gives the mass (its mass, centre_of_mass and inertia): a sphere's share is its volume's; "
              "remove this sphere's " + std::string(mass != nullptr ? "mass" : "density"));
  } else if (mass != nullptr) {
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
}

/// A sphere's (or a mesh shape's) material and elasticity: `material` names a [[material]]
/// (default: the only one, if the scene has exactly one); the elasticity is `elasticity`, or
/// under hertz-mindlin the material's restitution. Returns the material (null: none).
const MaterialDef* SceneParser::readMaterialAndElasticity(const Scene& scene, const TableReader& sr,
                                                          SphereDef* sd) const {
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
  if (hertz) {
    if (const toml::node* e = sr.find("elasticity"))
      sr.fail(sourceOf(*e), "elasticity is not read under law = \"hertz-mindlin\": the restitution is the "
                            "material's (restitution = … in its [[material]])");
    sd->elasticity = md->restitution;
  } else {
    sd->elasticity = sr.single("elasticity", 0.5f, Rule::Elasticity);
  }
  return md;
}

/// Index of a named shape, or an error at the node that names it.
std::uint32_t SceneParser::shapeNamed(const TableReader& r, const toml::node& n, const std::string& what,
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

void SceneParser::addParticles(const TableReader& r, const toml::source_region& at, std::uint64_t count) {
  m_numParticles += count;
  if (m_numParticles > kMaxParticles) {
    r.fail(at, "the scene has more than 2^31 particles (" + std::to_string(m_numParticles) +
                   " so far); use fewer or smaller groups");
  }
}

void SceneParser::readBodies(Scene& scene) {
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
std::vector<std::uint32_t> SceneParser::shapesOf(const TableReader& r, const Scene& scene) const {
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

/// Refuses `bodies` more bodies of at least `minSpheres` spheres each (`pour`: bodies a [[pour]]
/// adds during the run) when the scene would pass 2^31 particles, or when the run's peak memory
/// (runMemoryEstimate(), with the bodies of the tables before) would not fit in the memory
/// available: here, at the table that makes it too big, instead of bad_alloc later.
void SceneParser::checkBodyBudget(const TableReader& r, const toml::node& at, const Scene& scene, std::uint64_t bodies,
                                  std::size_t minSpheres, bool pour) const {
  if (m_numParticles + bodies * minSpheres > kMaxParticles) {
    r.fail(sourceOf(at), "the scene would have more than 2^31 particles (" +
                             std::to_string(m_numParticles + bodies * minSpheres) + " at least); use a smaller count");
  }
  // m_numParticles counts the particles of earlier pours too, which scene.bodies does not hold.
  const std::uint64_t placed = scene.bodies.size() + (pour ? 0 : bodies);
  const std::uint64_t poured = scene.pourBodies.size() + (pour ? bodies : 0);
  const std::uint64_t particles = m_numParticles + bodies * minSpheres;
  const std::uint64_t need = runMemoryEstimate(runSizeOf(scene, placed, poured, particles));
  if (!memoryShortfall(need).empty()) {
    r.fail(sourceOf(at), "a run of " + std::to_string(placed + poured) + " bodies and " + std::to_string(particles) +
                             " particles needs about " + bytesText(need) + " at its peak (docs/scenes.md#memory), more than " +
                             availableMemoryText() + "; use a smaller count");
  }
}

void SceneParser::readBody(Scene& scene, const toml::table& t, std::size_t index) {
  const TableReader r(m_file, t, "[[body]] #" + std::to_string(index + 1),
                      {"shape", "position", "velocity", "orientation", "angular_velocity"});
  BodyDef b;
  b.shape = shapeNamed(r, r.require("shape", "the name of a [[shape]], e.g. shape = \"dimer\""),
                       "shape", scene);
  const toml::node& positionNode = r.require("position", "centre of mass in m, e.g. position = [0, 0, 1]");
  b.position = r.vec3(positionNode, "position", Rule::Coordinate);
  if (const std::string why = outsidePeriodicBox(scene.periodic, b.position); !why.empty())
    r.fail(sourceOf(positionNode), why);
  const double reach = shapeExtent(scene.shapes[b.shape]);
  for (float x : {b.position.x, b.position.y, b.position.z}) {
    if (!(std::fabs(double(x)) + reach <= kMaxCoordinate))
      r.fail(r.header(), "the body's spheres reach beyond +-2^60 m (1.15e18) from this position, the range whose "
                         "contacts single precision decides right");
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

void SceneParser::readGroup(Scene& scene, const toml::table& t, std::size_t index) {
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
  if (const toml::node* o = r.find("origin")) origin = r.numbers<3>(*o, "origin", Rule::Coordinate);
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
    if (!(extent <= kMaxCoordinate)) {
      r.fail(r.header(), "the lattice reaches beyond +-2^60 m (1.15e18) along " + std::string(kAxes[c]) +
                             " (origin, spacing, jitter and the shapes' size), the range whose contacts single "
                             "precision decides right");
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

}  // namespace tumble::scene_reader
