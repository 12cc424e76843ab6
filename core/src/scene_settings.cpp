// SPDX-License-Identifier: MIT
// The TOML scene reader's single tables ([scene], [contact], [ground], [periodic], [pulls],
// [broadphase], [integrator], [output]) and [[material]]: SceneParser members (scene_reader.hpp).
#include "scene_reader.hpp"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tumble/world.hpp"

namespace tumble::scene_reader {

void SceneParser::readScene(Scene& scene) {
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

void SceneParser::readContact(Scene& scene) {
  const toml::table* t = sectionOf(m_file, m_root, "contact");
  if (t == nullptr) return;
  // Each law reads its own keys; another law's key is a mistake worth naming, and an unknown key is
  // told the keys of the law the table chose (checked before the reader, whose message lists all).
  static const std::vector<std::string> kReportKeys = {"stiffness", "damping", "shear"};
  static const std::vector<std::string> kHookeKeys = {"stiffness", "tangential_stiffness", "gamma_n", "gamma_t",
                                                      "friction", "rolling_friction", "cohesion",
                                                      "cohesion_energy_density", "surface_energy"};
  static const std::vector<std::string> kHertzKeys = {"cohesion"};
  ContactParams& c = scene.contact;
  if (const toml::node* law = t->get("law")) {
    const auto* name = law->as_string();
    if (name == nullptr) throw errorAt(m_file, sourceOf(*law), "[contact]: law must be a string (got " + typeName(*law) + ")");
    if (name->get() == "report") c.law = ContactLaw::Report;
    else if (name->get() == "hooke-history") c.law = ContactLaw::HookeHistory;
    else if (name->get() == "hertz-mindlin") c.law = ContactLaw::HertzMindlin;
    else
      throw errorAt(m_file, sourceOf(*law),
                    "[contact]: unknown law \"" + name->get() + "\"; use \"report\", \"hooke-history\" or \"hertz-mindlin\"");
  }
  const std::vector<std::string>& mine = c.law == ContactLaw::Report         ? kReportKeys
                                         : c.law == ContactLaw::HookeHistory ? kHookeKeys
                                                                              : kHertzKeys;
  for (auto&& [key, value] : *t) {
    (void)value;
    const std::string k(key.str());
    if (k == "law" || std::find(mine.begin(), mine.end(), k) != mine.end()) continue;
    const bool inReport = std::find(kReportKeys.begin(), kReportKeys.end(), k) != kReportKeys.end();
    const bool inHooke = std::find(kHookeKeys.begin(), kHookeKeys.end(), k) != kHookeKeys.end();
    if (k == "cohesion")
      throw errorAt(m_file, sourceOf(key), "[contact]: cohesion needs a law with history (law = \"hooke-history\" or "
                                           "\"hertz-mindlin\"); the report's law has none (docs/model.md#cohesion)");
    const std::string law = "law = \"" + std::string(toString(c.law)) + "\"";
    if (!inReport && !inHooke) {
      std::string allowed = "law";
      for (const std::string& m : mine) allowed += ", " + m;
      throw errorAt(m_file, sourceOf(key), "[contact]: unknown key '" + k + "'; allowed keys under " + law + ": " + allowed);
    }
    std::string why = inHooke && inReport ? "it belongs to the report's law and to hooke-history"
                      : inHooke            ? "it belongs to law = \"hooke-history\""
                                           : "it belongs to the report's law";
    if (c.law == ContactLaw::HookeHistory && inReport) why += "; hooke-history damps with gamma_n, gamma_t";
    if (c.law == ContactLaw::HertzMindlin)
      why += "; under hertz-mindlin every pair's parameters come from its spheres' [[material]] tables";
    throw errorAt(m_file, sourceOf(key), "[contact]: " + k + " is not a parameter of " + law + " (" + why + "; docs/scenes.md)");
  }
  const TableReader r(m_file, *t, "[contact]",
                      {"law", "stiffness", "damping", "shear", "tangential_stiffness", "gamma_n", "gamma_t",
                       "friction", "rolling_friction", "cohesion", "cohesion_energy_density", "surface_energy"});
  if (const toml::node* n = r.find("cohesion")) {
    const std::string model = r.string(*n, "cohesion");
    if (model == "sjkr") c.cohesion = Cohesion::Sjkr;
    else if (model == "dmt") c.cohesion = Cohesion::Dmt;
    else if (model == "jkr") {
      if (c.law != ContactLaw::HertzMindlin)
        r.fail(sourceOf(*n), "cohesion = \"jkr\" needs law = \"hertz-mindlin\": JKR's contact radius comes from "
                             "Hertz's elasticity (Y*); under hooke-history use \"dmt\" or \"sjkr\" "
                             "(docs/model.md#cohesion)");
      c.cohesion = Cohesion::Jkr;
    } else if (model == "none")
      m_cohesionOff = true;  // its coefficients may stay in the file (--set contact.cohesion='"none"')
    else
      r.fail(sourceOf(*n), "unknown cohesion \"" + model + "\"; use \"sjkr\" (k_c, cohesion_energy_density), \"dmt\" "
                           "or \"jkr\" (the work of adhesion, surface_energy) or \"none\" (docs/model.md#cohesion)");
  }
  c.cohesionValue = readCohesion(scene, r, 0.0f);
  c.stiffness = r.single("stiffness", c.stiffness, Rule::Positive);
  c.damping = r.single("damping", c.damping, Rule::NonNegative);
  c.shear = r.single("shear", c.shear, Rule::NonNegative);
  c.tangentialStiffness = r.single("tangential_stiffness", c.tangentialStiffness, Rule::NonNegative);
  c.gammaN = r.single("gamma_n", c.gammaN, Rule::NonNegative);
  if (r.has("gamma_t")) c.gammaT = r.single("gamma_t", 0.0f, Rule::NonNegative);
  c.friction = r.single("friction", c.friction, Rule::NonNegative);
  c.rollingFriction = r.single("rolling_friction", c.rollingFriction, Rule::NonNegative);
}

void SceneParser::readGround(Scene& scene) {
  const toml::table* t = sectionOf(m_file, m_root, "ground");
  GroundParams& g = scene.ground;
  if (t == nullptr) {
    g.enabled = false;
    return;
  }
  const TableReader r(m_file, *t, "[ground]",
                      {"enabled", "height", "stiffness", "friction", "tangential_stiffness", "rolling_friction",
                       "material", "cohesion_energy_density", "surface_energy"});
  g.enabled = r.boolean("enabled", true);
  g.height = r.single("height", 0.0f, Rule::Coordinate);
  readPlaneContact(scene, r, "ground", &g);
}

/// The coefficient of the scene's cohesion model in table r (k_c: cohesion_energy_density under
/// sjkr, γ: surface_energy under dmt), or `fallback` when it is not given; the other model's key,
/// or either without a model, is an error at that key.
float SceneParser::readCohesion(const Scene& scene, const TableReader& r, float fallback) const {
  const Cohesion model = scene.contact.cohesion;
  float value = fallback;
  for (const char* key : {"cohesion_energy_density", "surface_energy"}) {
    const toml::node* n = r.find(key);
    if (n == nullptr) continue;
    const bool sjkrKey = key[0] == 'c';
    if (model == Cohesion::None && !m_cohesionOff)
      r.fail(sourceOf(*n), std::string(key) + " needs a cohesion model: [contact] cohesion = \"" +
                               (sjkrKey ? "sjkr" : "dmt\" or \"jkr") + "\" (docs/model.md#cohesion)");
    if (model != Cohesion::None && sjkrKey != (model == Cohesion::Sjkr))
      r.fail(sourceOf(*n), std::string(key) + " is not read under cohesion = \"" + toString(model) + "\"; give " +
                               (sjkrKey ? "surface_energy (the work of adhesion, J/m^2)"
                                        : "cohesion_energy_density (k_c, J/m^3)"));
    const float v = r.single(*n, key, Rule::NonNegative);
    if (model != Cohesion::None) value = v;  // cohesion = "none": checked, and not read
  }
  return value;
}

/// The contact keys of a plane (the ground or a wall) under the scene's law.
void SceneParser::readPlaneContact(const Scene& scene, const TableReader& r, const std::string& what, GroundParams* out) const {
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
  g.cohesion = readCohesion(scene, r, g.cohesion);
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

// [periodic]: x = [x0, x1] and/or y = [y0, y1].
void SceneParser::readPeriodic(Scene& scene) {
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
    p.lo[a] = r.single(*v.get(0), std::string(key) + "[0]", Rule::Coordinate);
    p.hi[a] = r.single(*v.get(1), std::string(key) + "[1]", Rule::Coordinate);
    if (!(p.lo[a] < p.hi[a]))
      r.fail(sourceOf(*n), std::string(key) + " = [" + key + "0, " + key + "1] needs " + key + "1 > " + key + "0 (got [" +
                               fmt(p.lo[a]) + ", " + fmt(p.hi[a]) + "])");
    // The integration wraps by the length and works about the centre (world.cpp): both must be
    // single-precision numbers, which [-3.4e38, 3.4e38] is not (its length overflows).
    if (const std::string why = periodicBoxRange(p.lo[a], p.hi[a]); !why.empty())
      r.fail(sourceOf(*n), std::string(key) + ": " + why);
    p.on[a] = true;
    m_periodicAt[a] = sourceOf(*n);
  }
  if (!p.any()) r.fail(r.header(), "give x = [x0, x1] and/or y = [y0, y1], the box of the periodic axes");
}

// The periods against the bodies and the skin (after the bodies are read).
void SceneParser::checkPeriod(const Scene& scene) {
  if (!scene.periodic.any()) return;
  const PeriodReach reach = periodReach(scene);
  for (int a = 0; a < 2; ++a)
    if (const std::string why = periodTooShort(scene.periodic, a, reach); !why.empty())
      throw errorAt(m_file, m_periodicAt[a], why);
}

void SceneParser::readPulls(Scene& scene) {
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

void SceneParser::readBroadphase(Scene& scene) {
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

void SceneParser::readIntegrator(Scene& scene) {
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

void SceneParser::readOutput(Scene& scene) {
  const toml::table* t = sectionOf(m_file, m_root, "output");
  if (t == nullptr) return;
  const TableReader r(m_file, *t, "[output]",
                      {"record", "record_steps", "debug", "contacts", "steps_per_frame", "thermo", "thermo_every",
                       "energy_balance"});
  scene.recordFile = r.string("record", "");
  scene.recordSteps = static_cast<std::uint64_t>(r.integer("record_steps", 0, 0));
  scene.recordDebug = r.boolean("debug", false);
  scene.recordContacts = r.boolean("contacts", false);
  const std::int64_t spf = r.integer("steps_per_frame", 10, 1);
  if (spf > std::numeric_limits<int>::max()) {
    r.fail(sourceOf(*r.find("steps_per_frame")),
           "steps_per_frame is too large (got " + std::to_string(spf) + ")");
  }
  scene.stepsPerFrame = static_cast<int>(spf);
  scene.thermoFile = r.string("thermo", "");
  scene.thermoEvery = static_cast<std::uint64_t>(r.integer("thermo_every", 100, 1));
  scene.energyBalance = r.boolean("energy_balance", false);
}

void SceneParser::readMaterials(Scene& scene) {
  const toml::node* n = m_root.get("material");
  const bool hertz = scene.contact.usesMaterials();
  if (n == nullptr) return;
  const std::vector<const toml::table*> tables = tablesOf(m_file, *n, "'material'", "[[material]]");
  for (std::size_t k = 0; k < tables.size(); ++k) {
    const TableReader r(m_file, *tables[k], "[[material]] #" + std::to_string(k + 1),
                        {"name", "density", "youngs_modulus", "poisson_ratio", "restitution", "friction",
                         "rolling_friction", "cohesion_energy_density", "surface_energy"});
    MaterialDef md;
    const toml::node& nameNode = r.require("name", "the name that spheres use, e.g. name = \"glass\"");
    md.name = r.string(nameNode, "name");
    if (md.name.empty()) r.fail(sourceOf(nameNode), "name must not be empty");
    if (m_materialIndex.count(md.name) != 0)
      r.fail(sourceOf(nameNode), "material name \"" + md.name + "\" is already used by another [[material]]");
    md.density = r.single("density", 0.0f, Rule::Positive);
    if (!hertz) {
      for (const char* key : {"youngs_modulus", "poisson_ratio", "restitution", "friction", "rolling_friction",
                              "cohesion_energy_density", "surface_energy"})
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
      md.cohesion = readCohesion(scene, r, md.cohesion);
      if (const std::string why = materialOutOfRange(md); !why.empty()) r.fail(r.header(), why);
    }
    m_materialIndex.emplace(md.name, static_cast<std::uint32_t>(scene.materials.size()));
    m_materialNames.push_back(md.name);
    scene.materials.push_back(std::move(md));
  }
}

/// Index of a named material, or an error at the node that names it.
std::uint32_t SceneParser::materialNamed(const TableReader& r, const toml::node& n, const std::string& what) const {
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

}  // namespace tumble::scene_reader
