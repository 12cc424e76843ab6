// SPDX-License-Identifier: MIT
// [[pour]]: bodies entering a run (tumble/pour.hpp).
#include "tumble/pour.hpp"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>

#include "placement.hpp"
#include "tumble/error.hpp"
#include "tumble/mesh.hpp"
#include "tumble/random.hpp"

namespace tumble {
namespace {

/// The centre of a region: where a pour body is held in a world before its state is known (a
/// mesh region: the centre of its vertices' box where the mesh was given).
Vec3f centreOf(const FillRegion& g, const Scene& scene) {
  if (g.kind == FillRegion::Kind::Mesh) {
    Vec3f lo{FLT_MAX, FLT_MAX, FLT_MAX}, hi{-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (const Vec3f& v : meshWallVertices(scene.walls[g.wall])) {
      lo = Vec3f{std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = Vec3f{std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    FillRegion box = g;
    box.kind = FillRegion::Kind::Box;
    box.min = lo;
    box.max = hi;
    return centreOf(box, scene);
  }
  if (g.kind == FillRegion::Kind::Box)
    return Vec3f{float(0.5 * (double(g.min.x) + g.max.x)), float(0.5 * (double(g.min.y) + g.max.y)),
                 float(0.5 * (double(g.min.z) + g.max.z))};
  return Vec3f{float(g.point.x + 0.5 * g.axis.x), float(g.point.y + 0.5 * g.axis.y), float(g.point.z + 0.5 * g.axis.z)};
}

/// The region moved into frame f (its points minus the frame's origin).
FillRegion shifted(FillRegion g, const LocalFrame& f) {
  const auto sub = [&](Vec3f p) {
    return Vec3f{float(double(p.x) - f.x), float(double(p.y) - f.y), float(double(p.z) - f.z)};
  };
  g.min = sub(g.min), g.max = sub(g.max), g.point = sub(g.point);
  return g;
}

}  // namespace

Pouring::Pouring(const Scene& scene) : m_scene(scene) {
  if (m_scene.pourBodies.empty()) return;
  double start = std::numeric_limits<double>::infinity(), interval = std::numeric_limits<double>::infinity();
  for (const PourDef& p : m_scene.pours) start = std::min(start, p.start), interval = std::min(interval, p.interval);
  const double dt = m_scene.dt;
  const double first = std::ceil(start / dt - 1e-9);  // (a start beyond any step: never)
  m_firstStep = first < 1.8e19 ? static_cast<std::uint64_t>(first) : std::numeric_limits<std::uint64_t>::max();
  m_everySteps = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(interval / dt)));
}

std::uint64_t Pouring::nextBatch(std::uint64_t step, std::size_t bodies) const {
  if (bodies >= finalBodies()) return std::numeric_limits<std::uint64_t>::max();
  if (step <= m_firstStep) return m_firstStep;
  return m_firstStep + (step - m_firstStep + m_everySteps - 1) / m_everySteps * m_everySteps;
}

World Pouring::worldWith(std::size_t bodies) const {
  if (bodies == 0 && m_scene.bodies.empty()) {  // the run starts with the bodies due at t = 0
    const std::vector<Wall> walls = kernelWalls(m_scene, LocalFrame{});
    const std::vector<Vec3f> placed = place(0, dueBy(0, 0.0), {}, {}, 0.0f, LocalFrame{}, walls, {}, 0);
    if (placed.empty())
      throw Error(m_scene.pours.empty() ? "the scene has no bodies"
                                        : m_scene.pours[0].where + ": the scene's bodies all come from [[pour]] and none "
                                          "could enter at t = 0; give the first pour start = 0 (and room), or add a "
                                          "[[body]], [[group]] or [[fill]]");
    return withBodies(0, placed, LocalFrame{}, true);
  }
  // The scene's own bodies are checked as any scene's (behind a wall, outside a periodic box);
  // a world with poured bodies holds them where the run has them.
  return withBodies(bodies - std::min(bodies, m_scene.bodies.size()), {}, LocalFrame{}, bodies <= m_scene.bodies.size());
}

std::vector<Vec3f> Pouring::place(std::size_t first, std::size_t due, const std::vector<float>& x,
                                  const std::vector<float>& radius, float maxRadius, const LocalFrame& frame,
                                  const std::vector<Wall>& walls, const std::vector<MeshPose>& meshPoses,
                                  std::uint64_t step) const {
  using namespace detail;
  float largest = 0.0f;
  std::vector<std::vector<Ball>> balls;
  for (std::size_t b = first; b < due; ++b) {
    balls.push_back(ballsOf(m_scene.shapes[m_scene.pourBodies[b].body.shape]));
    for (const Ball& s : balls.back()) largest = std::max(largest, s.r);
  }
  // The pours' regions in the frame, and the particles near one (its bounding box, grown by the
  // largest reach).
  const MeshObstacles meshes = meshesIn(frame).posed(meshPoses);
  std::vector<RegionFrame> regions;
  for (const PourDef& p : m_scene.pours) regions.emplace_back(shifted(p.region, frame), m_scene, frame, meshes);
  const double reach = 2.0 * (double(largest) + maxRadius);
  std::vector<std::array<double, 6>> boxes;
  for (const RegionFrame& rf : regions) {
    const FillRegion& g = rf.region;
    if (g.kind == FillRegion::Kind::Box) {
      boxes.push_back({g.min.x - reach, g.min.y - reach, g.min.z - reach, g.max.x + reach, g.max.y + reach,
                       g.max.z + reach});
    } else if (g.kind == FillRegion::Kind::Mesh) {  // the box of its vertices' box where the mesh is now
      std::array<double, 6> b{DBL_MAX, DBL_MAX, DBL_MAX, -DBL_MAX, -DBL_MAX, -DBL_MAX};
      for (int c = 0; c < 8; ++c) {
        const Vec3f y = meshes.placed(g.wall, Vec3f{c & 1 ? g.max.x : g.min.x, c & 2 ? g.max.y : g.min.y,
                                                    c & 4 ? g.max.z : g.min.z});
        const double v[3] = {y.x, y.y, y.z};
        for (int a = 0; a < 3; ++a) {
          b[a] = std::min(b[a], v[a] - reach);
          b[a + 3] = std::max(b[a + 3], v[a] + reach);
        }
      }
      boxes.push_back(b);
    } else {
      const double a[3] = {g.axis.x, g.axis.y, g.axis.z}, p0[3] = {g.point.x, g.point.y, g.point.z};
      const double r = std::sqrt(0.25 * (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) + double(g.radius) * g.radius) + reach;
      boxes.push_back({p0[0] + 0.5 * a[0] - r, p0[1] + 0.5 * a[1] - r, p0[2] + 0.5 * a[2] - r, p0[0] + 0.5 * a[0] + r,
                       p0[1] + 0.5 * a[1] + r, p0[2] + 0.5 * a[2] + r});
    }
  }
  SphereHash hash(2.0 * double(largest));
  hash.setPeriodic(m_scene.periodic, frame);
  for (std::size_t i = 0; i < radius.size(); ++i) {
    const Vec3f xi{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    // (With periodic sides every particle: an image of one far away may be near.)
    const bool near = m_scene.periodic.any() || std::any_of(boxes.begin(), boxes.end(), [&](const std::array<double, 6>& b) {
      return xi.x >= b[0] && xi.y >= b[1] && xi.z >= b[2] && xi.x <= b[3] && xi.y <= b[4] && xi.z <= b[5];
    });
    if (near) hash.add(xi, radius[i]);
  }
  // The bodies due, in order, until one finds no place.
  std::vector<Vec3f> placed;
  for (std::size_t b = first; b < due; ++b) {
    const PourBody& pb = m_scene.pourBodies[b];
    const PourDef& p = m_scene.pours[pb.pour];
    Rng rng(groupSeed(p.seed ^ (0x9E3779B97F4A7C15ull * (step + 1)), pb.index));
    Vec3f at;
    Quatf q = pb.body.orientation;
    if (!placeBody(rng, regions[pb.pour], balls[b - first], hash, walls, meshes, p.attempts, false, false, &at, &q))
      break;
    placed.push_back(at);
  }
  return placed;
}

const detail::MeshObstacles& Pouring::meshesIn(const LocalFrame& frame) const {
  if (!m_meshes || m_meshesFrame.x != frame.x || m_meshesFrame.y != frame.y || m_meshesFrame.z != frame.z) {
    m_meshes = std::make_shared<const detail::MeshObstacles>(m_scene, frame);
    m_meshesFrame = frame;
  }
  return *m_meshes;
}

std::size_t Pouring::dueBy(std::size_t first, double t) const {
  std::size_t due = first;
  while (due < m_scene.pourBodies.size() && m_scene.pourBodies[due].time <= t) ++due;
  return due;
}

std::optional<World> Pouring::pour(const World& world, const Pipeline& pipeline) const {
  const std::size_t nb = world.numBodies(), first = nb - m_scene.bodies.size();
  const double t = pipeline.time();
  const std::uint64_t step = pipeline.stepCount();
  const std::size_t due = dueBy(first, t);
  if (due == first) return std::nullopt;
  // What the bodies must keep clear of: the particles where the pipeline has them (its frame),
  // the ground and the walls where they are now.
  const LocalFrame frame = pipeline.frame();
  std::vector<float> x;
  pipeline.readLocalPositions(x);
  std::vector<Wall> walls = kernelWalls(world.params, frame);
  std::vector<MeshPose> meshPoses(meshWallsMove(world.params) ? walls.size() : 0, MeshPose{});
  setWallMotion(walls, world.params, t, meshPoses.empty() ? nullptr : meshPoses.data());
  const std::vector<Vec3f> placed = place(first, due, x, world.radius, world.maxRadius, frame, walls, meshPoses, step);
  if (placed.empty()) return std::nullopt;

  // The world with them: the pipeline's state (as it integrates it, in its frame) and theirs.
  World out = withBodies(first, placed, frame, false);
  BodyState now;
  pipeline.readLocalState(now);
  BodyState& st = out.state;
  for (auto [to, from] : {std::pair{&st.px, &now.px}, {&st.py, &now.py}, {&st.pz, &now.pz}, {&st.vx, &now.vx},
                          {&st.vy, &now.vy}, {&st.vz, &now.vz}, {&st.qw, &now.qw}, {&st.qx, &now.qx},
                          {&st.qy, &now.qy}, {&st.qz, &now.qz}, {&st.lx, &now.lx}, {&st.ly, &now.ly}, {&st.lz, &now.lz}})
    std::copy(from->begin(), from->end(), to->begin());
  // The wall springs, plane-major: each plane's column of the old particles, then zeros.
  const std::size_t np = world.numParticles(), npOut = out.numParticles();
  const std::size_t planes = np > 0 ? now.groundSpringX.size() / np : 0;
  st.groundSpringX.assign(planes * npOut, 0.0f);
  st.groundSpringY.assign(planes * npOut, 0.0f);
  for (std::size_t k = 0; k < planes; ++k) {
    std::copy_n(now.groundSpringX.begin() + std::ptrdiff_t(k * np), np, st.groundSpringX.begin() + std::ptrdiff_t(k * npOut));
    std::copy_n(now.groundSpringY.begin() + std::ptrdiff_t(k * np), np, st.groundSpringY.begin() + std::ptrdiff_t(k * npOut));
  }
  st.contacts = std::move(now.contacts);  // the old particles keep their indices
  st.meshContacts = std::move(now.meshContacts);  // (particle, triangle): likewise
  // The periods the old bodies have crossed; the new ones have crossed none.
  for (auto [to, from] : {std::pair{&st.imageX, &now.imageX}, {&st.imageY, &now.imageY}})
    if (!from->empty()) {
      to->assign(out.numBodies(), 0);
      std::copy(from->begin(), from->end(), to->begin());
    }
  out.frame = frame;
  out.step = step;
  out.time = t;
  return out;
}

World Pouring::withBodies(std::size_t first, const std::vector<Vec3f>& placed, const LocalFrame& frame,
                          bool checkPlacement) const {
  Scene s = m_scene;
  s.pourBodies.clear();
  for (std::size_t b = 0; b < first + placed.size(); ++b) {
    BodyDef d = m_scene.pourBodies[b].body;
    d.position = b < first ? centreOf(m_scene.pours[m_scene.pourBodies[b].pour].region, m_scene)
                           : Vec3f{float(double(placed[b - first].x) + frame.x), float(double(placed[b - first].y) + frame.y),
                                   float(double(placed[b - first].z) + frame.z)};
    s.bodies.push_back(d);
  }
  World out = World::fromScene(s, checkPlacement);
  for (std::size_t b = 0; b < placed.size(); ++b) {  // as placed, in the frame
    const std::size_t k = s.bodies.size() - placed.size() + b;
    out.state.px[k] = placed[b].x;
    out.state.py[k] = placed[b].y;
    out.state.pz[k] = placed[b].z;
  }
  return out;
}

bool Pouring::enter(Pipeline& pipeline, World& world, StepStats* stats) const {
  if (nextBatch(pipeline.stepCount(), world.numBodies()) != pipeline.stepCount()) return false;
  std::optional<World> grown = pour(world, pipeline);
  if (!grown) return false;
  if (stats) stats->add(pipeline.stats());  // load() starts the pipeline's counters afresh
  const std::uint32_t pulls = pipeline.pulls();      // and the pulls from the scene's
  world = std::move(*grown);
  pipeline.load(world);
  pipeline.setPulls(pulls);
  return true;
}

bool Pouring::step(Pipeline& pipeline, World& world, std::uint64_t n, StepStats* stats) const {
  bool grew = false;
  const std::uint64_t end = pipeline.stepCount() + n;
  while (pipeline.stepCount() < end) {
    grew = enter(pipeline, world, stats) || grew;
    pipeline.step(std::min(end, nextBatch(pipeline.stepCount() + 1, world.numBodies())) - pipeline.stepCount());
  }
  return grew;
}

}  // namespace tumble
