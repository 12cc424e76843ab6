// SPDX-License-Identifier: MIT
// Periodic boundaries (issue 12; docs/model.md#periodic-boundaries): bodies that cross the box
// and contacts across it are exactly the periodic brute-force oracle's at every step; the bits
// do not depend on the threads, the skin, the cell size or the numbering; a run shifted by a
// period is the same run; a checkpoint resumes it exactly; momentum along a periodic axis is
// conserved through collisions across the boundary; the energy guard follows bodies across it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <iterator>
#include <string>
#include <unistd.h>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

/// A box [0, lx) × [0, ly) (an axis with length 0 is not periodic), no gravity and no ground,
/// the report's law (k = 1e3, soft: deep overlaps, many contacts).
Scene emptyBox(float lx, float ly) {
  Scene s;
  s.name = "periodic";
  s.gravity = {0, 0, 0};
  s.dt = 1e-3f;
  s.contact = {1e3f, 0.5f, 0.2f};
  for (int a = 0; a < 2; ++a) {
    const float l = a == 0 ? lx : ly;
    if (l <= 0.0f) continue;
    s.periodic.on[a] = true;
    s.periodic.lo[a] = 0.0f;
    s.periodic.hi[a] = l;
  }
  return s;
}

std::uint32_t addShape(Scene& s, const std::string& name, std::vector<SphereDef> spheres) {
  s.shapes.push_back(ShapeDef{name, std::move(spheres)});
  return static_cast<std::uint32_t>(s.shapes.size() - 1);
}

void addBody(Scene& s, std::uint32_t shape, Vec3f x, Vec3f v = {0, 0, 0}, Quatf q = {1, 0, 0, 0},
             Vec3f omega = {0, 0, 0}) {
  BodyDef b;
  b.shape = shape;
  b.position = x;
  b.velocity = v;
  b.orientation = q;
  b.angularVelocity = omega;
  s.bodies.push_back(b);
}

/// Random bodies in the box: single spheres (radius 0.3–0.5) and, with `clumps`, three-sphere
/// rods of extent 0.9 in random orientations; velocities up to `speed` box lengths per 100 steps
/// (they cross the box), some of them straddling the boundaries from the start.
Scene randomBox(std::uint64_t seed, float lx, float ly, int count, float speed, bool clumps) {
  Scene s = emptyBox(lx, ly);
  Rng rng(seed);
  const std::uint32_t ball = addShape(s, "ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}});
  const std::uint32_t small = addShape(s, "small", {SphereDef{{0, 0, 0}, 0.3f, 0.5f, 0.5f}});
  const std::uint32_t rod = addShape(s, "rod", {SphereDef{{-0.5f, 0, 0}, 0.4f, 1.0f, 0.5f},
                                                SphereDef{{0, 0, 0}, 0.3f, 1.0f, 0.5f},
                                                SphereDef{{0.5f, 0, 0}, 0.4f, 1.0f, 0.5f}});
  const float v = speed * std::max(lx, ly) / (100.0f * s.dt);
  const float ex = lx > 0.0f ? lx : 8.0f, ey = ly > 0.0f ? ly : 8.0f;
  for (int k = 0; k < count; ++k) {
    const std::uint32_t shape = clumps && k % 3 == 0 ? rod : (k % 2 ? ball : small);
    Vec3f x{rng.uniform(0.0f, ex), rng.uniform(0.0f, ey), rng.uniform(0.0f, 4.0f)};
    if (k % 7 == 0 && lx > 0.0f) x.x = k % 2 ? 0.05f : lx - 0.05f;  // straddling x
    if (k % 11 == 0 && ly > 0.0f) x.y = k % 2 ? 0.02f : ly - 0.02f;  // straddling y (both: a corner)
    const Vec3f vel{rng.uniform(-v, v), rng.uniform(-v, v), rng.uniform(-0.1f * v, 0.1f * v)};
    float u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
    const Quatf q = normalized(Quatf{b * std::cos(6.2831853f * u3), a * std::sin(6.2831853f * u2),
                                     a * std::cos(6.2831853f * u2), b * std::sin(6.2831853f * u3)});
    addBody(s, shape, x, vel, q, Vec3f{rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3)});
  }
  return s;
}

/// pairs() after each step against the periodic oracle on the state the step started from (in
/// the frame the pipeline integrates in, so that the positions are the ones it used). Returns
/// the most contacts across a boundary seen in one step (a pair whose plain difference exceeds
/// half a period on some axis).
std::size_t expectExactAtEveryStep(Pipeline& p, const World& w, int steps, const std::string& what) {
  p.load(w);
  const World local = toLocal(w, p.frame());
  const PeriodicBox box = kernelPeriodic(w.params, p.frame());
  std::size_t across = 0;
  for (int s = 0; s < steps; ++s) {
    BodyState st;
    p.readLocalState(st);
    p.step(1);
    ParticleCloud cloud = cloudOf(local, st);
    cloud.periodic = box;
    const auto want = bruteForcePairs(cloud);
    const auto got = p.pairs();
    if (got != want) {
      std::vector<Pair> missing;
      std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
      char first[240] = "";
      if (!missing.empty()) {
        const Pair q = missing[0];
        std::snprintf(first, sizeof first, "; first missing (%u, %u) at (%.9g, %.9g, %.9g) and (%.9g, %.9g, %.9g)", q.i,
                      q.j, cloud.x[q.i], cloud.y[q.i], cloud.z[q.i], cloud.x[q.j], cloud.y[q.j], cloud.z[q.j]);
      }
      ADD_FAILURE() << what << ": step " << s << ": " << got.size() << " pairs, the oracle has " << want.size() << first;
      return across;
    }
    std::size_t n = 0;
    for (const Pair& q : want)
      n += (box.on(0) && std::abs(cloud.x[q.i] - cloud.x[q.j]) > box.half[0]) ||
           (box.on(1) && std::abs(cloud.y[q.i] - cloud.y[q.j]) > box.half[1]);
    across = std::max(across, n);
  }
  return across;
}

/// A pipeline (`threads` threads) that has run `steps` steps of `w` with the given skin, its
/// contacts checked against the oracle at every step; *across receives expectExactAtEveryStep's.
std::unique_ptr<Pipeline> checkedRun(const World& w, float skin, int threads, int steps, const std::string& what,
                                     std::size_t* across = nullptr, Backend backend = Backend::Cpu) {
  World ws = w;
  ws.params.broadphase.skin = skin;
  PipelineOptions o;
  o.threads = threads;
  auto p = makePipeline(backend, o);
  const std::size_t n = expectExactAtEveryStep(*p, ws, steps, what + ", skin " + std::to_string(skin) + ", " +
                                                                 std::to_string(threads) + " thread(s), " +
                                                                 toString(backend));
  if (across) *across = n;
  return p;
}

/// The crossings of the periodic boundaries, Σ |n| over the bodies' image counters.
int crossingsOf(const BodyState& s) {
  int n = 0;
  for (const auto* c : {&s.imageX, &s.imageY})
    for (std::int32_t k : *c) n += std::abs(k);
  return n;
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "tumble_" + std::to_string(::getpid()) + "_" + name;
}

}  // namespace

namespace {

// The contacts of random periodic boxes (x, y, both; spheres and clumps) against the oracle at
// every step, for the skins given and 1 and 2 threads.
void expectContactsAreTheOracle(Backend backend, std::initializer_list<float> skins) {
  const std::uint64_t seed = 20261212;
  std::printf("random periodic boxes, seed %llu\n", static_cast<unsigned long long>(seed));
  struct Box {
    const char* name;
    float lx, ly;
  };
  std::size_t acrossMost = 0;
  for (const Box& b : {Box{"x", 9.0f, 0.0f}, Box{"y", 0.0f, 7.5f}, Box{"x and y", 8.0f, 6.5f}}) {
    for (bool clumps : {false, true}) {
      const World w = World::fromScene(randomBox(seed, b.lx, b.ly, 60, 1.5f, clumps));
      for (float skin : skins) {
        for (int threads : {1, 2}) {
          const std::string what = std::string("periodic ") + b.name + (clumps ? ", clumps" : ", spheres");
          std::size_t across = 0;
          const auto p = checkedRun(w, skin, threads, 120, what, &across, backend);
          acrossMost = std::max(acrossMost, across);
          EXPECT_GT(across, 0u) << what << ": no contact across a boundary";
          BodyState st;
          p->readState(st);
          EXPECT_GT(crossingsOf(st), 10) << what << ": the bodies must cross the boundaries";
        }
      }
    }
  }
  std::printf("at most %zu contacts across a boundary in one step\n", acrossMost);
}

}  // namespace

TEST(PeriodicTest, ContactsAreTheOracleAtEveryStep) {
  expectContactsAreTheOracle(Backend::Cpu, {0.0f, -1.0f, 1.5f});  // every step, automatic, large (3 radii)
}

namespace {

void expectHardCasesAtTheBoundaries(Backend backend) {
  // A box [0, 4) × [0, 4): a sphere exactly at x0 and one at x1 − ulp (touching across x), two
  // spheres exactly touching across y (not a contact: the predicate is strict), four at the
  // corners overlapping across both, a clump straddling x, a fast sphere crossing the box every
  // six steps.
  Scene s = emptyBox(4.0f, 4.0f);
  const std::uint32_t ball = addShape(s, "ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}});
  const std::uint32_t rod = addShape(s, "rod", {SphereDef{{-0.4f, 0, 0}, 0.3f, 1.0f, 0.5f},
                                                SphereDef{{0.4f, 0, 0}, 0.3f, 1.0f, 0.5f}});
  const float below = std::nextafter(4.0f, 0.0f);
  addBody(s, ball, {0.0f, 2.0f, 0.0f});
  addBody(s, ball, {below, 2.0f, 0.1f});
  addBody(s, ball, {2.0f, 0.5f, 3.0f});
  addBody(s, ball, {2.0f, 3.5f, 3.0f});  // 1.0 apart across y: exactly touching
  addBody(s, ball, {0.2f, 0.2f, 6.0f});
  addBody(s, ball, {3.8f, 0.2f, 6.0f});
  addBody(s, ball, {0.2f, 3.8f, 6.0f});
  addBody(s, ball, {3.8f, 3.8f, 6.0f});
  addBody(s, rod, {0.1f, 1.0f, 9.0f});  // its spheres at x = −0.3 and 0.5
  addBody(s, ball, {3.7f, 1.0f, 9.0f});
  addBody(s, ball, {2.0f, 2.0f, 12.0f}, {700.0f, 300.0f, 0.0f});  // 0.7 box lengths per step in x
  const World w = World::fromScene(s);
  {
    const World local = toLocal(w, LocalFrame::of(w));
    ParticleCloud c = cloudOf(local, local.state);
    c.periodic = kernelPeriodic(w.params, LocalFrame::of(w));
    const auto pairs = bruteForcePairs(c);
    std::printf("hard cases: %zu contacts at the start\n", pairs.size());
    const auto has = [&](std::uint32_t i, std::uint32_t j) {
      return std::find(pairs.begin(), pairs.end(), Pair{i, j}) != pairs.end();
    };
    EXPECT_TRUE(has(0, 1)) << "x0 and x1 − ulp touch across the boundary";
    EXPECT_FALSE(has(2, 3)) << "exactly touching across y is no contact";
    EXPECT_TRUE(has(4, 7)) << "opposite corners touch across both boundaries";
    EXPECT_TRUE(has(5, 6));
    EXPECT_TRUE(has(4, 5) && has(4, 6) && has(5, 7) && has(6, 7));
    EXPECT_TRUE(has(8, 10)) << "the clump straddling x touches the sphere at 3.7";
    auto p = makePipeline(backend);
    EXPECT_EQ(p->findPairs(c, BroadphaseParams{}), pairs) << "findPairs() in a periodic box is the oracle";
  }
  for (float skin : {0.0f, -1.0f, 0.6f})
    for (int threads : {1, 2}) {
      const auto p = checkedRun(w, skin, threads, 60, "hard cases", nullptr, backend);
      BodyState st;
      p->readLocalState(st);
      EXPECT_GT(std::abs(st.imageX[10]), 5) << "the fast sphere crosses the box every few steps";
      const PeriodicBox box = kernelPeriodic(w.params, p->frame());
      for (std::size_t k = 0; k < st.size(); ++k) {
        EXPECT_TRUE(st.px[k] >= -box.half[0] && st.px[k] < box.half[0]) << "body " << k << " x " << st.px[k];
        EXPECT_TRUE(st.py[k] >= -box.half[1] && st.py[k] < box.half[1]) << "body " << k << " y " << st.py[k];
      }
    }
}

void expectFindPairsIsTheOracleOnRandomClouds(Backend backend) {
  const std::uint64_t seed = 20261213;
  std::printf("random periodic clouds, seed %llu\n", static_cast<unsigned long long>(seed));
  Rng rng(seed);
  auto p = makePipeline(backend);
  for (int k = 0; k < 12; ++k) {
    const float l = rng.uniform(3.0f, 20.0f);
    ParticleCloud c = randomCloud(200 + rng.below(2000), seed + k, l, 0.1f, 0.5f, 1 + rng.below(3));
    // randomCloud fills [0, l)³: the periodic frame's box is [−l/2, l/2)
    for (std::size_t i = 0; i < c.size(); ++i) {
      c.x[i] -= 0.5f * l;
      c.y[i] -= 0.5f * l;
    }
    c.periodic.axes = 1u + rng.below(3);  // x, y or both
    for (int a = 0; a < 2; ++a) {
      c.periodic.half[a] = 0.5f * l;
      c.periodic.length[a] = l;
    }
    const auto want = bruteForcePairs(c);
    EXPECT_EQ(p->findPairs(c, BroadphaseParams{}), want) << "cloud " << k << ", axes " << c.periodic.axes;
  }
}

}  // namespace

TEST(PeriodicTest, HardCasesAtTheBoundaries) { expectHardCasesAtTheBoundaries(Backend::Cpu); }

TEST(PeriodicTest, FindPairsIsTheOracleOnRandomClouds) { expectFindPairsIsTheOracleOnRandomClouds(Backend::Cpu); }

namespace {

/// The knobs that must not change a bit (as contact_list_test.cpp's).
struct Knobs {
  std::string name;
  float cellFactor = 0.0f;  ///< × the automatic cell size; 0 = automatic
  float skin = -1.0f;       ///< negative: automatic
  int threads = 2;
  bool reorder = true;
};

void expectKnobInvariance(const World& w, std::uint64_t steps, const std::string& what) {
  auto ref = makePipeline(Backend::Cpu);
  ref->load(w);
  const std::uint64_t every = steps / 4;
  std::vector<BodyState> want;
  for (std::uint64_t s = 0; s < steps; s += every) {
    ref->step(every);
    want.emplace_back();
    ref->readState(want.back());
  }
  const float autoCell = ref->stats().cellSize;
  const int crossings = crossingsOf(want.back());
  std::printf("%s: %llu steps, %llu contacts at the end, %d crossings, hash %016llx\n", what.c_str(),
              static_cast<unsigned long long>(steps), static_cast<unsigned long long>(ref->stats().numPairs), crossings,
              static_cast<unsigned long long>(stateHash(want.back())));
  EXPECT_GT(crossings, 10) << what;
  const Knobs variants[] = {{"1 thread", 0.0f, -1.0f, 1},   {"cell x0.5", 0.5f},  {"cell x3", 3.0f},
                            {"skin 0 (detect every step)", 0.0f, 0.0f},
                            {"large skin", 0.0f, 2.5f * w.maxRadius},
                            {"no reordering", 0.0f, -1.0f, 2, false}};
  for (const Knobs& k : variants) {
    World wk = w;
    wk.params.broadphase.cellSize = k.cellFactor * autoCell;
    wk.params.broadphase.skin = k.skin;
    PipelineOptions o;
    o.threads = k.threads;
    o.reorder = k.reorder;
    auto p = makePipeline(Backend::Cpu, o);
    p->load(wk);
    for (std::size_t c = 0; c < want.size(); ++c) {
      p->step(every);
      BodyState got;
      p->readState(got);
      if (const auto d = firstDifference(want[c], got)) {
        ADD_FAILURE() << what << ", " << k.name << ": first difference by step " << (c + 1) * every << ": "
                      << d->describe();
        break;
      }
    }
  }
}

Scene chute() { return readSceneFile(sourcePath("scenes/chute.toml")); }

}  // namespace

TEST(PeriodicTest, BitsDoNotDependOnHowContactsAreFound) {
  // Clumps crossing x, y and the corner under the report's law, and the chute (hooke-history:
  // contact histories across the boundary, plates, ground, tilted gravity).
  expectKnobInvariance(World::fromScene(randomBox(20261214, 8.0f, 6.5f, 60, 1.5f, true)), 400, "random box x and y");
  expectKnobInvariance(World::fromScene(randomBox(20261215, 9.0f, 0.0f, 50, 1.5f, true)), 400, "random box x");
  Scene c = chute();
  c.bodies.erase(c.bodies.begin() + 300, c.bodies.end());  // the bed and a layer and a half of the flow
  expectKnobInvariance(World::fromScene(c), 2000, "chute, 292 spheres");
}

TEST(PeriodicTest, AShiftByOnePeriodIsTheSameRun) {
  // Positions on a grid of 1/64 (exact in float wherever they go below 2^17), in [0, 8) × [0, 6.5)
  // and in the same box shifted by a period in x, in y: the same bits in the frame each run
  // integrates in (centred on its box), and in the world the positions shifted by the period
  // wherever the shifted value is a float.
  Scene a = randomBox(20261216, 8.0f, 6.5f, 50, 1.5f, true);
  a.gravity = {1.0f, 0.5f, -9.81f};
  a.ground.enabled = true;
  a.ground.height = -1.0f;
  for (BodyDef& b : a.bodies) {
    b.position.x = std::floor(b.position.x * 64.0f) / 64.0f;
    b.position.y = std::floor(b.position.y * 64.0f) / 64.0f;
    b.position.z = std::floor(b.position.z * 64.0f) / 64.0f;
  }
  const World wa = World::fromScene(a);
  auto pa = makePipeline(Backend::Cpu);
  pa->load(wa);
  pa->step(300);
  BodyState la, ga;
  pa->readLocalState(la);
  pa->readState(ga);
  for (int axis = 0; axis < 2; ++axis) {
    const float period = a.periodic.hi[axis] - a.periodic.lo[axis];
    Scene b = a;
    b.periodic.lo[axis] += period;
    b.periodic.hi[axis] += period;
    for (BodyDef& body : b.bodies) (axis == 0 ? body.position.x : body.position.y) += period;
    auto pb = makePipeline(Backend::Cpu);
    pb->load(World::fromScene(b));
    pb->step(300);
    BodyState lb, gb;
    pb->readLocalState(lb);
    pb->readState(gb);
    if (const auto d = firstDifference(la, lb)) ADD_FAILURE() << "shifted in " << "xy"[axis] << ": " << d->describe();
    const std::vector<float>& ca = axis == 0 ? ga.px : ga.py;
    const std::vector<float>& cb = axis == 0 ? gb.px : gb.py;
    std::size_t exact = 0;
    for (std::size_t k = 0; k < ca.size(); ++k) {
      const double shifted = double(ca[k]) + period;
      if (double(static_cast<float>(shifted)) != shifted) continue;
      ++exact;
      EXPECT_EQ(double(cb[k]), shifted) << "body " << k;
    }
    EXPECT_GT(exact, ca.size() / 4) << "few shifted positions are floats";
    EXPECT_EQ(ga.imageX, gb.imageX);
    EXPECT_EQ(ga.imageY, gb.imageY);
  }
}

TEST(PeriodicTest, ResumeEqualsTheUninterruptedRun) {
  Scene c = chute();
  c.bodies.erase(c.bodies.begin() + 300, c.bodies.end());
  for (RotationScheme scheme : {RotationScheme::Report, RotationScheme::Splitting}) {
    SCOPED_TRACE(toString(scheme));
    c.integrator.rotation = scheme;
    const World w = World::fromScene(c);
    const BodyState want = stateAfter(Backend::Cpu, w, 3000);
    const std::string path = tempPath("periodic.ck");
    {
      auto p = makePipeline(Backend::Cpu);
      p->load(w);
      p->step(1500);
      Checkpoint::of(w, *p).write(path);
    }
    const Checkpoint ck = Checkpoint::read(path);
    std::remove(path.c_str());
    EXPECT_GT(crossingsOf(ck.state), 0) << "the checkpoint must carry image counters that are not all zero";
    EXPECT_FALSE(ck.state.contacts.empty());
    std::string warning;
    auto p = makePipeline(Backend::Cpu);
    p->load(ck.resume(w, &warning));
    EXPECT_TRUE(warning.empty()) << warning;
    p->step(1500);
    BodyState got;
    p->readState(got);
    if (const auto d = firstDifference(want, got)) ADD_FAILURE() << d->describe();
    EXPECT_EQ(stateHash(want), stateHash(got));
  }
  // A checkpoint of a scene without periodic boundaries does not resume one with them.
  Scene flat = chute();
  flat.bodies.erase(flat.bodies.begin() + 300, flat.bodies.end());
  const World wp = World::fromScene(flat);
  flat.periodic = PeriodicParams{};
  const World wf = World::fromScene(flat);
  auto p = makePipeline(Backend::Cpu);
  p->load(wf);
  p->step(10);
  std::string warning;
  try {
    (void)Checkpoint::of(wf, *p).resume(wp, &warning);
    ADD_FAILURE() << "expected a refusal";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("image counters"), std::string::npos) << e.what();
  }
}

TEST(PeriodicTest, MomentumIsConservedThroughCollisionsAcrossTheBoundary) {
  // 60 bodies (spheres and rods) in a box periodic in x and y, no gravity, no ground, no walls:
  // the contacts are exact negations through the minimum image, so Σ M V stays where it was to
  // the rounding of the velocities, over 10^4 steps of collisions across the boundaries.
  const World w = World::fromScene(randomBox(20261217, 8.0f, 6.5f, 60, 0.5f, true));
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  const auto momentum = [&](const BodyState& s, double* scale) {
    double m[3] = {0, 0, 0};
    *scale = 0.0;
    for (std::size_t k = 0; k < s.size(); ++k) {
      const double M = w.bodyMass[k];
      m[0] += M * s.vx[k], m[1] += M * s.vy[k], m[2] += M * s.vz[k];
      *scale += M * std::sqrt(double(s.vx[k]) * s.vx[k] + double(s.vy[k]) * s.vy[k] + double(s.vz[k]) * s.vz[k]);
    }
    return std::array<double, 3>{m[0], m[1], m[2]};
  };
  BodyState s;
  p->readState(s);
  double scale0;
  const std::array<double, 3> p0 = momentum(s, &scale0);
  double worst = 0.0;
  std::size_t across = 0, contacts = 0;
  const PeriodicBox box = kernelPeriodic(w.params, p->frame());
  std::vector<float> x;
  for (int c = 0; c < 100; ++c) {
    p->readLocalPositions(x);
    p->step(100);
    for (const Pair& q : p->pairs()) {  // at the start of the last step
      ++contacts;
      across += std::abs(x[3 * q.i] - x[3 * q.j]) > box.half[0] || std::abs(x[3 * q.i + 1] - x[3 * q.j + 1]) > box.half[1];
    }
    p->readState(s);
    double scale;
    const std::array<double, 3> pc = momentum(s, &scale);
    for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(pc[a] - p0[a]) / scale0);
  }
  const int crossings = crossingsOf(s);
  std::printf("10^4 steps: %d crossings, %zu of %zu sampled contacts across a boundary; largest |dP| / sum M|V| = %.3g\n",
              crossings, across, contacts, worst);
  EXPECT_GT(crossings, 100);
  EXPECT_GT(across, 0u);
  EXPECT_LT(worst, 1e-5);
}

TEST(PeriodicTest, TheEnergyGuardFollowsBodiesAcrossTheBoundary) {
  // The chute's flow leaves through x1 and comes back at x0 hundreds of times; its height down
  // the slope is counted with the image counters, so the guard sees the energy fall, not jump.
  const World w = World::fromScene(chute());
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  RunGuard guard(w, *p);
  const double e0 = guard.sample().kineticTranslation + guard.sample().gravity;
  for (int c = 0; c < 80; ++c) {
    p->step(50);
    const auto trip = guard.check(*p);
    ASSERT_FALSE(trip) << trip->message;
  }
  BodyState s;
  p->readState(s);
  const int crossings = crossingsOf(s);
  const double e = guard.sample().kineticTranslation + guard.sample().gravity;
  std::printf("chute, 4000 steps: %d crossings, kinetic + gravity %.4g J -> %.4g J\n", crossings, e0, e);
  EXPECT_GT(crossings, 50);
  EXPECT_LT(e, e0) << "friction and collisions only take energy out";
}

namespace {

void expectContactSumsEqualThoseOfThePairs(Backend backend) {
  const World w = World::fromScene(randomBox(20261218, 8.0f, 6.5f, 60, 1.5f, true));
  auto p = makePipeline(backend);
  p->load(w);
  const SpringLaw law = springLawOf(w);
  const PeriodicBox box = kernelPeriodic(w.params, p->frame());
  std::vector<ContactSums> own, ref;
  std::vector<float> x;
  std::vector<double> err(w.numBodies());
  BodyState s;
  std::size_t across = 0;
  for (int c = 0; c < 20; ++c) {
    p->step(10);
    ASSERT_TRUE(p->contactSumsPerBody(law, own));
    p->readLocalPositions(x);
    p->readLocalState(s);
    for (std::size_t b = 0; b < err.size(); ++b) err[b] = bodyRounding(s.px[b], s.py[b], s.pz[b]);
    const std::vector<Pair> pairs = p->pairs();
    contactSumsOfPairs(w, pairs, x, err, law, ref, box);
    for (std::size_t b = 0; b < ref.size(); ++b) {
      ASSERT_EQ(own[b].springs, ref[b].springs) << "body " << b << ", step " << p->stepCount();
      ASSERT_EQ(own[b].maxOverlap, ref[b].maxOverlap) << "body " << b;
    }
    for (const Pair& q : pairs)
      across += (std::abs(x[3 * q.i] - x[3 * q.j]) > box.half[0] || std::abs(x[3 * q.i + 1] - x[3 * q.j + 1]) > box.half[1]) &&
                ref[w.body[q.i]].springs > 0.0;
  }
  EXPECT_GT(across, 0u) << "contacts across the boundary must be among those summed";
}

}  // namespace

TEST(PeriodicTest, PipelineContactSumsEqualThoseOfItsPairs) { expectContactSumsEqualThoseOfThePairs(Backend::Cpu); }

TEST(PeriodicTest, ABallTrainInAPeriodicPipe) {
  // A pipe along the periodic x (a cylinder of radius 1.5 reaching half a period beyond the box),
  // gravity tilted down it: balls and rods slide and tumble along the pipe, through the boundary
  // and against each other across it, and stay inside. The contacts are the oracle's.
  Scene s = emptyBox(8.0f, 0.0f);
  s.gravity = {3.0f, 0.0f, -9.0f};
  s.contact = {1e4f, 20.0f, 5.0f};
  s.dt = 5e-4f;
  WallDef pipe;
  pipe.shape = WallDef::Shape::Revolved;
  pipe.point = {-4.0f, 0.0f, 0.0f};
  pipe.normal = {1.0f, 0.0f, 0.0f};
  pipe.length = 16.0f;
  pipe.radius0 = pipe.radius1 = 1.5f;
  pipe.contact.stiffness = 1e4f;
  pipe.where = "the pipe";
  s.walls.push_back(pipe);
  const std::uint32_t ball = addShape(s, "ball", {SphereDef{{0, 0, 0}, 0.4f, 1.0f, 0.5f}});
  const std::uint32_t rod = addShape(s, "rod", {SphereDef{{-0.3f, 0, 0}, 0.3f, 1.0f, 0.5f},
                                                SphereDef{{0.3f, 0, 0}, 0.3f, 1.0f, 0.5f}});
  for (int k = 0; k < 16; ++k)
    addBody(s, k % 2 ? ball : rod, {0.25f + 0.5f * float(k), 0.4f * float(k % 3) - 0.4f, -0.6f + 0.3f * float(k % 2)},
            {8.0f + 2.0f * float(k % 5), 0.0f, 0.0f});
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  const std::size_t across = expectExactAtEveryStep(*p, w, 3000, "balls in a periodic pipe");
  BodyState st;
  p->readLocalState(st);
  const int crossings = crossingsOf(st);
  std::printf("pipe: %d crossings, at most %zu contacts across the boundary in a step\n", crossings, across);
  EXPECT_GT(crossings, 10);
  EXPECT_GT(across, 0u);
  for (std::size_t k = 0; k < st.size(); ++k)
    EXPECT_LT(std::sqrt(st.py[k] * st.py[k] + st.pz[k] * st.pz[k]), 1.5f) << "body " << k << " left the pipe";
}

TEST(PeriodicTest, ScenesBuiltInCodeAreCheckedToo) {
  const auto expectRefused = [](const Scene& s, const char* needle) {
    try {
      (void)World::fromScene(s);
      ADD_FAILURE() << "no error; expected " << needle;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const Scene ok = randomBox(1, 8.0f, 0.0f, 10, 0.1f, true);
  EXPECT_NO_THROW((void)World::fromScene(ok));
  Scene s = ok;
  s.periodic.hi[0] = 0.0f;
  expectRefused(s, "needs finite lo < hi");
  s = ok;
  s.bodies[3].position.x = 8.0f;
  expectRefused(s, "body 3: its centre x = 8 lies outside the periodic box [0, 8)");
  s = ok;
  s.pulls.active = kPullSwirl;
  expectRefused(s, "the pulls \"swirl\" pull along a periodic axis");
  s = ok;
  s.walls.push_back(planeWall(Vec3f{0, 0, 0}, Vec3f{1, 0, 0}));
  s.walls.back().where = "the plane";
  expectRefused(s, "the plane: a plane across the periodic x axis");
  s = ok;
  s.periodic.hi[0] = 2.0f;
  s.bodies.resize(1);
  s.bodies[0].position.x = 1.0f;
  expectRefused(s, "[periodic] x spans 2 m, not more than the shortest period this scene allows");
  // A skin given after the scene (--skin, or a test) is checked when a pipeline loads the world.
  // Every pipeline: the host backend everywhere, the device where CUDA is there at all (a broken
  // driver fails here, in makePipeline). The refused load follows a run of another world, which
  // it must leave as it was: the same contacts, and the run goes on as if nothing happened.
  World w = World::fromScene(ok);
  w.params.broadphase.skin = 3.0f;
  const World before = World::fromScene(randomBox(20261219, 9.0f, 0.0f, 60, 1.5f, true));
  const BodyState want = stateAfter(Backend::Cpu, before, 60);
  for (const Backend b : compiledBackends()) {
    if (b == Backend::Cuda && cudaStatus().state == CudaState::NoDevice) continue;
    auto p = makePipeline(b);
    p->load(before);
    p->step(50);
    const std::vector<Pair> pairs = p->pairs();
    ASSERT_FALSE(pairs.empty()) << toString(b);
    try {
      p->load(w);
      ADD_FAILURE() << toString(b) << ": a skin of 3 leaves a period of 8 too short";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the skin 3 m"), std::string::npos) << toString(b) << ": " << e.what();
    }
    EXPECT_EQ(p->pairs(), pairs) << toString(b) << ": pairs() after a refused load";
    p->step(10);
    BodyState got;
    p->readState(got);
    const auto d = firstDifference(want, got);
    EXPECT_FALSE(d) << toString(b) << ": the run after a refused load: " << d->describe();
  }
}

TEST(PeriodicTest, PairsWithinRoundingOfTouchingAcrossTheBoundary) {
  // 600 pairs of spheres across x's boundary (box [0, 3), radii 0.3-0.5), each pair within a few
  // ulp of touching through the nearest images, in random directions. A ghost's shifted
  // coordinate and the nearest image's difference are rounded differently (at the size of the
  // box), so the sweep sees some of these pairs on the other side of touching than the exact
  // predicate does: the detection must grow the radii by that rounding even without a skin (skin
  // 0 detects every step), or it misses contacts the oracle has.
  const std::uint64_t seed = 20261219;
  std::printf("pairs within rounding of touching, seed %llu\n", static_cast<unsigned long long>(seed));
  Rng rng(seed);
  Scene s = emptyBox(3.0f, 0.0f);
  s.contact = {1e-6f, 0.0f, 0.0f};  // barely any force: the positions stay where they are
  const std::uint32_t big = addShape(s, "big", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}});
  const std::uint32_t small = addShape(s, "small", {SphereDef{{0, 0, 0}, 0.3f, 1.0f, 0.5f}});
  for (int k = 0; k < 600; ++k) {
    const bool b1 = rng.below(2) != 0, b2 = rng.below(2) != 0;
    const double reach = (b1 ? 0.5 : 0.3) + (b2 ? 0.5 : 0.3);
    const double dist = reach * (1.0 + 4e-7 * (2.0 * rng.uniform() - 1.0));
    const double dy = 0.3 * (2.0 * rng.uniform() - 1.0) * reach, dz = 0.3 * (2.0 * rng.uniform() - 1.0) * reach;
    const double dx = std::sqrt(dist * dist - dy * dy - dz * dz);  // i near x0, j across x1
    const double xi = 0.05 + 0.2 * rng.uniform(), y = 3.0 * k;
    addBody(s, b1 ? big : small, {float(xi), float(y), 0.0f});
    addBody(s, b2 ? big : small, {float(xi - dx + 3.0), float(y + dy), float(dz)});
  }
  const World w = World::fromScene(s);
  for (float skin : {0.0f, -1.0f}) (void)checkedRun(w, skin, 2, 2, "pairs within rounding of touching across x");
}

// The CUDA pipeline's periodic detection (gpu/src/periodic_images.hpp, the per-element steps of
// kernels/periodic_images.hpp): the same oracles on the host backend in every build, on the
// device where there is one. Its trajectories are the CPU's bit for bit: cuda_equals_cpu_test.cpp.
class PeriodicCudaPipeline : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { TUMBLE_NEED_BACKEND(GetParam()); }
};

TEST_P(PeriodicCudaPipeline, ContactsAreTheOracleAtEveryStep) {
  expectContactsAreTheOracle(GetParam(), {0.0f, -1.0f, 1.5f});  // every step, automatic, large (3 radii)
}

TEST_P(PeriodicCudaPipeline, HardCasesAtTheBoundaries) { expectHardCasesAtTheBoundaries(GetParam()); }

TEST_P(PeriodicCudaPipeline, FindPairsIsTheOracleOnRandomClouds) {
  expectFindPairsIsTheOracleOnRandomClouds(GetParam());
}

TEST_P(PeriodicCudaPipeline, PipelineContactSumsEqualThoseOfItsPairs) {
  expectContactSumsEqualThoseOfThePairs(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Backends, PeriodicCudaPipeline, ::testing::ValuesIn(tumble_test::cudaPipelineBackends()),
                         tumble_test::backendName);
