// SPDX-License-Identifier: MIT
#include "tumble/validation/scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/mesh.hpp"
#include "tumble/pour.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/compare.hpp"

namespace tumble::validation {

Scene withHookeHistory(Scene s, float gammaN, float friction) {
  s.contact.law = ContactLaw::HookeHistory;
  s.contact.gammaN = gammaN;
  s.contact.friction = friction;
  return s;
}

Scene withHertzMindlin(Scene s, float youngsModulus, bool twoMaterials) {
  s.contact.law = ContactLaw::HertzMindlin;
  // (Aggregates: GCC 12 warns falsely, -Wrestrict, on assigning a short literal to the name.)
  s.materials = {MaterialDef{"a", 0.0f, youngsModulus, 0.3f, 0.5f, 0.5f, 0.0f}};
  if (twoMaterials) {
    const MaterialDef b{"b", 0.0f, 2.0f * youngsModulus, 0.25f, 0.7f, 0.3f, 0.05f};
    s.materials.push_back(b);
    for (ShapeDef& sh : s.shapes)
      for (std::size_t k = 0; k < sh.spheres.size(); ++k) sh.spheres[k].material = std::uint32_t(k % 2);
  }
  for (ShapeDef& sh : s.shapes)
    for (SphereDef& sp : sh.spheres) sp.elasticity = s.materials[sp.material].restitution;
  return s;
}

Scene modelProbe(ContactLaw law, bool wall) {
  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = true;
  s.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
  BodyDef b;
  b.position = {0.0f, 0.0f, 0.1f};
  s.bodies = {b};
  if (wall) {
    WallDef w;
    w.point = {1.0f, 0.0f, 0.0f};
    w.normal = {-1.0f, 0.0f, 0.0f};
    w.contact = wallContact(1.0e4f, 0.5f);
    s.walls = {w};
  }
  if (law == ContactLaw::HookeHistory) return withHookeHistory(s);
  if (law == ContactLaw::HertzMindlin) return withHertzMindlin(s);
  return s;
}

Scene thrownAtWalls(const char* file) {
  Scene s = readSceneFile(sourcePath(file));
  for (WallDef& wall : s.walls) wall.start = 0.0;
  for (BodyDef& b : s.bodies) b.velocity.z -= 3.0f;
  return s;
}

std::string sourcePath(const std::string& relative) {
  // The source tree while it is there (a build), else the installed data (share/tumble: the
  // scenes that `tumble validate` and `tumble bench` read).
  static const std::string base = [] {
    std::error_code ec;
    const std::string src = TUMBLE_SOURCE_DIR;
    return std::filesystem::exists(src + "/scenes/molecules.toml", ec) ? src : std::string(TUMBLE_INSTALL_DATADIR);
  }();
  return base + "/" + relative;
}

Scene benchScene(std::uint32_t numParticles, std::uint64_t seed) {
  if (numParticles == 16000 || numParticles == 128000 || numParticles == 960000) {
    const std::string file = numParticles == 16000 ? "16k" : numParticles == 128000 ? "128k" : "960k";
    if (seed == 12345) return readSceneFile(sourcePath("scenes/bench-" + file + ".toml"));
  }
  if (numParticles == 0 || numParticles % 8 != 0) throw Error("bench scene needs a positive multiple of 8 particles");
  // Same physics as the 16k file, on a 4:4:1 lattice of numParticles / 8 clumps.
  Scene s = readSceneFile(sourcePath("scenes/bench-16k.toml"));
  s.bodies.clear();
  const std::uint32_t nb = numParticles / 8;
  std::uint32_t nz = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::cbrt(nb / 16.0)));
  std::uint32_t nx = static_cast<std::uint32_t>(std::ceil(std::sqrt(double(nb) / nz)));
  Rng rng(seed);
  const float a = 1.65f;
  for (std::uint32_t k = 0; k < nb; ++k) {
    const std::uint32_t i = k % nx, j = (k / nx) % nx, l = k / (nx * nx);
    BodyDef b;
    b.shape = 0;
    b.position = {(i + 0.5f) * a + rng.uniform(-0.025f, 0.025f), (j + 0.5f) * a + rng.uniform(-0.025f, 0.025f),
                  0.8f + l * a + rng.uniform(-0.025f, 0.025f)};
    b.velocity = {rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f)};
    s.bodies.push_back(b);
  }
  s.name = "bench-" + std::to_string(numParticles);
  return s;
}

ParticleCloud randomCloud(std::uint32_t n, std::uint64_t seed, float box, float rMin, float rMax,
                          std::uint32_t bodySize) {
  Rng rng(seed);
  ParticleCloud c;
  for (std::uint32_t i = 0; i < n; ++i) {
    c.x.push_back(rng.uniform(0.0f, box));
    c.y.push_back(rng.uniform(0.0f, box));
    c.z.push_back(rng.uniform(0.0f, box));
    c.r.push_back(rng.uniform(rMin, rMax));
    c.body.push_back(i / std::max<std::uint32_t>(1, bodySize));
  }
  return c;
}

namespace {

void push(ParticleCloud& c, float x, float y, float z, float r, std::uint32_t body) {
  c.x.push_back(x);
  c.y.push_back(y);
  c.z.push_back(z);
  c.r.push_back(r);
  c.body.push_back(body);
}

}  // namespace

std::vector<NamedCloud> hardCases(std::uint64_t seed) {
  std::vector<NamedCloud> out;
  Rng rng(seed);
  {  // every particle at one z
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 3000; ++i) push(c, rng.uniform(0, 30), rng.uniform(0, 30), 1.5f, 0.3f, i);
    out.push_back({"same_z", c});
  }
  {  // every particle at one x and y: a column along z
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 2000; ++i) push(c, -2.0f, 3.0f, rng.uniform(-50, 50), 0.1f, i);
    out.push_back({"one_column", c});
  }
  {  // isotropic cloud: degenerate PCA
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 4000;) {
      const float x = rng.uniform(-1, 1), y = rng.uniform(-1, 1), z = rng.uniform(-1, 1);
      if (x * x + y * y + z * z > 1.0f) continue;
      push(c, 10 * x, 10 * y, 10 * z, 0.4f, i / 2);
      ++i;
    }
    out.push_back({"isotropic_ball", c});
  }
  {  // offset 1e6, radii 1e-3 (float spacing at 1e6 is 0.0625: many coincident or far apart)
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 3000; ++i)
      push(c, 1.0e6f + rng.uniform(0, 2), 1.0e6f + rng.uniform(0, 2), -1.0e6f + rng.uniform(0, 2), 1.0e-3f, i);
    out.push_back({"offset_1e6_radius_1e-3", c});
  }
  {  // radii 1:100
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 3000; ++i)
      push(c, rng.uniform(0, 40), rng.uniform(0, 40), rng.uniform(0, 40), i % 50 == 0 ? 5.0f : 0.05f, i);
    out.push_back({"radii_1_to_100", c});
  }
  {  // exactly touching lattice: spacing = 2 r with exactly representable values
    ParticleCloud c;
    std::uint32_t id = 0;
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j)
        for (int k = 0; k < 8; ++k, ++id) push(c, i * 1.0f, j * 1.0f, k * 1.0f, 0.5f, id);
    out.push_back({"touching_lattice", c});
  }
  {  // touching lattice with a tiny overlap on every other row
    ParticleCloud c;
    std::uint32_t id = 0;
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j, ++id) push(c, i * 0.25f, j * 0.25f, 0.0f, (i % 2) ? 0.125f : 0.1250001f, id);
    out.push_back({"near_touching", c});
  }
  {  // particles spanning many cells: a few huge spheres among small ones
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 2000; ++i)
      push(c, rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20), i < 5 ? 12.0f : 0.2f, i);
    out.push_back({"spanning_many_cells", c});
  }
  {  // negative coordinates
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 3000; ++i)
      push(c, rng.uniform(-30, -10), rng.uniform(-25, -5), rng.uniform(-1000, -990), rng.uniform(0.2f, 0.6f), i / 3);
    out.push_back({"negative_coordinates", c});
  }
  {  // coincident particles (pairs and triples at identical centres)
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 500; ++i) {
      const float x = rng.uniform(0, 10), y = rng.uniform(0, 10), z = rng.uniform(0, 10);
      for (std::uint32_t k = 0; k < 1 + i % 3; ++k) push(c, x, y, z, 0.1f, static_cast<std::uint32_t>(c.size()));
    }
    out.push_back({"coincident", c});
  }
  {  // all particles in one cell, one body per particle pair
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 600; ++i)
      push(c, rng.uniform(0, 0.5f), rng.uniform(0, 0.5f), rng.uniform(0, 0.5f), 0.3f, i / 2);
    out.push_back({"one_cell", c});
  }
  {  // every particle in one body: no pairs at all
    ParticleCloud c;
    for (std::uint32_t i = 0; i < 500; ++i) push(c, rng.uniform(0, 3), rng.uniform(0, 3), rng.uniform(0, 3), 0.3f, 7);
    out.push_back({"one_body", c});
  }
  out.push_back({"empty", ParticleCloud{}});
  {
    ParticleCloud c;
    push(c, 1, 2, 3, 0.5f, 0);
    out.push_back({"single", c});
  }
  {
    ParticleCloud c;
    push(c, 0, 0, 0, 0.5f, 0);
    push(c, 0.5f, 0, 0, 0.5f, 1);
    out.push_back({"two", c});
  }
  return out;
}

ShapeDef sphereShape(float r, float m, float e) { return ShapeDef{"sphere", {SphereDef{{0, 0, 0}, r, m, e}}}; }

GroundParams wallContact(float k, float mu) {
  GroundParams c;
  c.enabled = true;
  c.stiffness = k;
  c.friction = mu;
  return c;
}

WallDef meshWall(std::vector<Vec3f> vertices, std::vector<std::uint32_t> triangles, const GroundParams& c) {
  auto m = std::make_shared<TriangleMesh>();
  m->file = "test mesh";
  m->vertices = std::move(vertices);
  m->triangles = std::move(triangles);
  for (std::size_t t = 0; t < m->numTriangles(); ++t) m->source.push_back(t + 1);
  WallDef w;
  w.shape = WallDef::Shape::Mesh;
  w.mesh = m;
  w.contact = c;
  return w;
}

WallDef gridMesh(int nx, int ny, float h, float x0, float y0, const std::function<float(float, float)>& height,
                 const GroundParams& c) {
  std::vector<Vec3f> v;
  std::vector<std::uint32_t> t;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const float x = x0 + float(i) * h, y = y0 + float(j) * h;
      v.push_back(Vec3f{x, y, height(x, y)});
    }
  const auto at = [&](int i, int j) { return std::uint32_t(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), cc = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2 == 0)
        t.insert(t.end(), {a, b, cc, a, cc, d});
      else
        t.insert(t.end(), {a, b, d, b, cc, d});
    }
  return meshWall(std::move(v), std::move(t), c);
}

WallDef flatGrid(int nx, int ny, float h, float x0, float y0, const GroundParams& c) {
  return gridMesh(nx, ny, h, x0, y0, [](float, float) { return 0.0f; }, c);
}

Scene spheresOn(const WallDef& wall, float r, const std::vector<Vec3f>& at, bool ground) {
  Scene s;
  s.dt = 1e-4f;
  s.contact.law = ContactLaw::HookeHistory;
  s.contact.stiffness = 1e5f;
  s.contact.gammaN = 100.0f;
  s.ground.enabled = ground;
  s.ground.stiffness = 1e5f;
  s.walls = {wall};
  s.shapes = {sphereShape(r, 0.1f, 0.5f)};
  for (const Vec3f& p : at) {
    BodyDef b;
    b.position = p;
    s.bodies.push_back(b);
  }
  return s;
}

DrumStop drumDragAndStop(const Scene& s) {
  DrumStop out;
  out.earlyVx = runCpu(World::fromScene(s), 200).vx[0];
  Scene stopping = s;
  stopping.walls[0].stop = 0.05;
  const World turning = World::fromScene(s), stops = World::fromScene(stopping);
  const auto before = firstDifference(runCpu(turning, 450), runCpu(stops, 450));
  out.sameBeforeTheStop = !before.has_value();
  if (before) out.before = before->describe();
  const BodyState a = runCpu(turning, 1500), b = runCpu(stops, 1500);
  out.differentAfter = firstDifference(a, b).has_value();
  out.turningVx = a.vx[0];
  out.stoppedVx = b.vx[0];
  return out;
}

BodyState runCpu(const World& w, std::uint64_t steps, const PipelineOptions& o) {
  return stateAfter(Backend::Cpu, w, steps, o);
}

PourRun pourRun(const Scene& s, std::uint64_t steps, const PipelineOptions& o, const PourBatchCheck& atBatch,
                const Checkpoint* from) {
  const Pouring pouring(s);
  World world = pouring.worldWith(pouring.initialBodies());
  if (from) world = from->resume(pouring.worldWith(from->state.size()), nullptr);
  auto p = makePipeline(Backend::Cpu, o);
  p->load(world);
  while (p->stepCount() < steps) {
    const std::size_t before = world.numBodies();
    const double t = p->time();
    pouring.step(*p, world, 1, nullptr);
    if (atBatch && world.numBodies() != before) atBatch(world, *p, before, t);
  }
  PourRun r{world, {}};
  p->readState(r.state);
  return r;
}

}  // namespace tumble::validation
