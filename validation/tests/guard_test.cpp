// SPDX-License-Identifier: MIT
// Run-time guards (core/include/tumble/guard.hpp): quiet on stable runs (with and without the
// swirl pull, which feeds energy in), and tripping with a useful message on a run whose dt is
// beyond the stability limit, on a particle driven through the ground, and on a non-finite state.
#include <gtest/gtest.h>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/kernels/integrate.hpp"

#include <cmath>
#include <cstdio>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/world.hpp"

using namespace tumble;
using tumble::validation::modelProbe;

namespace {

class GuardTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

// A 4 × 4 × 3 block of unit spheres dropped on the ground; k = 2e4, m = 1: t_c ≈ 22 ms (ground).
Scene pile(float dt) {
  Scene s;
  s.dt = dt;
  s.ground.enabled = true;
  s.ground.stiffness = 2e4f;
  s.contact.stiffness = 2e4f;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}}};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) {
        BodyDef b;
        b.position = {1.05f * float(i) - 1.5f, 1.05f * float(j) - 1.5f, 0.6f + 1.05f * float(k)};
        b.velocity = {0.1f * float(j - i), 0.05f * float(k), 0.0f};
        s.bodies.push_back(b);
      }
  return s;
}

// Steps in chunks of `every`, checking after each; returns the first trip.
std::optional<GuardTrip> runGuarded(Pipeline& p, const World& w, std::uint64_t steps, std::uint64_t every,
                                    double* maxGain = nullptr) {
  RunGuard guard(w, p);
  const double e0 = guard.energy();
  for (std::uint64_t done = 0; done < steps; done += every) {
    try {
      p.step(every);
    } catch (const SimulationError& e) {
      ADD_FAILURE() << "the pipeline diverged before the guard saw it: " << e.what();
      return std::nullopt;
    }
    if (auto t = guard.check(p)) return t;
    if (maxGain) *maxGain = std::max(*maxGain, guard.energy() - e0 - guard.pullWork());
  }
  return std::nullopt;
}

// A ball (r = 0.05 m, 1 kg, e = 1) dropped from 10 m onto a frictionless ground of stiffness k,
// dt = 1e-4 s.
Scene ballDrop(float k) {
  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = true;
  s.ground.stiffness = k;
  s.ground.friction = 0.0f;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.05f, 1.0f, 1.0f}}}};
  BodyDef b;
  b.position = {0, 0, 10.0f};
  s.bodies = {b};
  return s;
}

struct GuardedRun {
  std::optional<GuardTrip> trip;
  BodyState state;          ///< at the end (or at the trip)
  bool localFrame = false;  ///< the pipeline integrated in a local frame
};

// Loads a scene into a fresh pipeline and runs it under the guard.
GuardedRun runScene(const Scene& s, Backend backend, std::uint64_t steps, std::uint64_t every) {
  const World w = World::fromScene(s);
  auto p = makePipeline(backend);
  p->load(w);
  GuardedRun r;
  r.localFrame = p->frame().active();
  r.trip = runGuarded(*p, w, steps, every);
  p->readState(r.state);
  return r;
}

}  // namespace

TEST_P(GuardTest, QuietOnAStableRun) {
  const World w = World::fromScene(pile(1e-3f));  // t_c / 22
  auto p = makePipeline(GetParam());
  p->load(w);
  double gain = -1e30;
  const auto t = runGuarded(*p, w, 3000, 10, &gain);
  EXPECT_FALSE(t.has_value()) << t->message;
  std::printf("stable pile, 3 s: largest energy gain %.3g J\n", gain);
}

TEST_P(GuardTest, QuietWhenTheSwirlFeedsEnergyIn) {
  Scene s = pile(1e-3f);
  s.pulls.active = kPullSwirl | kPullX;
  s.pulls.swirl = 4.0f;
  const World w = World::fromScene(s);
  auto p = makePipeline(GetParam());
  p->load(w);
  RunGuard guard(w, *p);
  const double e0 = guard.energy();
  for (int c = 0; c < 300; ++c) {
    p->step(10);
    const auto t = guard.check(*p);
    ASSERT_FALSE(t.has_value()) << t->message;
  }
  std::printf("swirl + x pull, 3 s: energy %.4g -> %.4g J, swirl work %.4g J\n", e0, guard.energy(), guard.pullWork());
  EXPECT_GT(guard.pullWork(), 10.0) << "the swirl must actually have done work for this test to mean anything";
  // Switching a pull off mid-run rebases the budget instead of tripping.
  p->setPulls(0);
  p->step(10);
  EXPECT_FALSE(guard.check(*p).has_value());
}

// Leapfrog on a linear spring is unstable for ω dt > 2; ω = √(k/m) = 141 rad/s on the ground,
// so dt = 2e-2 (ω dt = 2.8) diverges. The guard must stop it before any value turns non-finite.
TEST_P(GuardTest, TripsOnAnUnstableTimeStep) {
  const World w = World::fromScene(pile(2e-2f));
  auto p = makePipeline(GetParam());
  p->load(w);
  const auto t = runGuarded(*p, w, 2000, 1);
  ASSERT_TRUE(t.has_value()) << "dt = 2e-2 s must be caught";
  std::printf("%s\n", t->message.c_str());
  EXPECT_NE(t->kind, GuardTrip::Kind::NonFinite) << "caught only when already non-finite";
  EXPECT_NE(t->message.find("step " + std::to_string(t->step)), std::string::npos);
  EXPECT_NE(t->message.find("use dt <= "), std::string::npos);
  EXPECT_NEAR(t->suggestedDt, shortestContactTime(w) / 20.0, 1e-12);
  EXPECT_LT(t->body, w.numBodies());
}

// A wall that moved once does not switch the energy guard off for the rest of the run: the
// unstable pile with a belt far from it, moving during the first step only, trips on the
// energy as the pile alone does (moving walls do work the guard does not measure, so it skips
// the energy test only while one moves).
TEST_P(GuardTest, AWallThatStoppedMovingLeavesTheEnergyGuardOn) {
  TUMBLE_SKIP_IF_NOT_SUPPORTED(GetParam(), modelProbe(ContactLaw::Report, /*wall=*/true));
  Scene s = pile(2e-2f);
  WallDef belt;
  belt.point = {50.0f, 0.0f, 0.0f};
  belt.normal = {-1.0f, 0.0f, 0.0f};
  belt.contact = s.ground;
  belt.velocity = {0.0f, 1.0f, 0.0f};
  belt.stop = 0.5 * double(s.dt);
  s.walls = {belt};
  for (const bool withBelt : {false, true}) {
    Scene t = s;
    if (!withBelt) t.walls.clear();
    const World w = World::fromScene(t);
    auto p = makePipeline(GetParam());
    p->load(w);
    const auto trip = runGuarded(*p, w, 2000, 1);
    ASSERT_TRUE(trip.has_value()) << (withBelt ? "with" : "without") << " the belt";
    std::printf("%s the belt: %s\n", withBelt ? "with" : "without", trip->message.c_str());
    EXPECT_EQ(trip->kind, GuardTrip::Kind::Energy) << (withBelt ? "with" : "without") << " the belt";
  }
}

// One sphere thrown down at 60 m/s with dt = 1e-3: it moves 6 cm per step and the ground spring
// (k = 2e4, m = 1) cannot stop it within the radius (it would need v ≤ ω r ≈ 71 m/s for r = 0.5,
// the sphere here has r = 0.2: v ≤ 28 m/s). The overlap guard names it.
TEST_P(GuardTest, TripsWhenABodyIsDrivenThroughTheGround) {
  Scene s;
  s.dt = 1e-3f;
  s.gravity = {0, 0, 0};
  s.ground.enabled = true;
  s.ground.stiffness = 2e4f;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.2f, 1.0f, 1.0f}}}};
  BodyDef still, fast;
  still.position = {3, 0, 0.2f};
  fast.position = {0, 0, 0.5f};
  fast.velocity = {0, 0, -60.0f};
  s.bodies = {still, fast};
  const auto t = runScene(s, GetParam(), 100, 1).trip;
  ASSERT_TRUE(t.has_value());
  std::printf("%s\n", t->message.c_str());
  EXPECT_EQ(t->kind, GuardTrip::Kind::Overlap);
  EXPECT_EQ(t->body, 1u);
  EXPECT_NE(t->message.find("body 1 sinks into the ground"), std::string::npos);
}

// Two bodies placed on top of each other start with a full overlap; that is the scene's choice,
// not a divergence: the guard measures overlaps beyond the initial one.
TEST_P(GuardTest, InitialOverlapIsNotATrip) {
  Scene s;
  s.dt = 1e-4f;
  s.gravity = {0, 0, 0};
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}}};
  BodyDef a, b;
  b.position = {1e-3f, 0, 0};
  s.bodies = {a, b};
  const auto t = runScene(s, GetParam(), 2000, 10).trip;
  EXPECT_FALSE(t.has_value()) << t->message;
}

// Far from the origin the positions a pipeline hands out are rounded to ulp(|X|) (7.8 mm at
// 10⁵ m); on a stiff ground (k = 10⁶ N/m) that is joules of apparent spring energy. The guard
// must count it as rounding, not growth, and still catch a real divergence there.
TEST_P(GuardTest, FarFromTheOriginRoundingIsNotGrowth) {
  for (const float dt : {2e-5f, 2e-3f}) {
    Scene s;
    s.dt = dt;
    s.ground.enabled = true;
    s.ground.height = 1.0e5f;
    s.ground.stiffness = 1.0e6f;
    s.contact.stiffness = 1.0e6f;
    s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.2f, 1.0f, 0.5f}}}};
    for (int i = 0; i < 3; ++i) {
      BodyDef b;
      b.position = {0.5f * float(i), 0.0f, 1.0e5f + 0.2f + 0.40625f * float(i)};
      s.bodies.push_back(b);
    }
    const auto t = runScene(s, GetParam(), dt < 1e-4f ? 20000 : 2000, 10).trip;
    if (dt < 1e-4f) {
      EXPECT_FALSE(t.has_value()) << "stable run (dt = t_c/110) at 1e5 m: " << t->message;
    } else {
      ASSERT_TRUE(t.has_value()) << "dt = 2e-3 s (ω dt = 2.8) must be caught at 1e5 m too";
      EXPECT_NE(t->kind, GuardTrip::Kind::NonFinite);
    }
  }
}

// One sphere dropped from 10 m onto a stiff ground (k = 10⁶ N/m, e = 1, dt = t_c/31): a clean,
// well-resolved bounce. Its energy comes from the fall to the ground, which the budget must count
// (not only the fall to the lowest body, which here is itself).
TEST_P(GuardTest, QuietForAWellResolvedDropOntoTheGround) {
  const Scene s = ballDrop(1.0e6f);
  const auto t = runScene(s, GetParam(), 40000, 10).trip;
  EXPECT_FALSE(t.has_value()) << t->message;
}

// Two small spheres colliding head-on 10⁵ m from the origin: the pipeline integrates them in a
// local frame; the guard must judge them there too, not from world positions rounded to 7.8 mm
// (coarser than their 5 mm radius).
TEST_P(GuardTest, QuietForACollisionFarFromTheOrigin) {
  Scene s;
  s.dt = 1e-5f;
  s.gravity = {0, 0, 0};
  s.contact = {1.0e3f, 0.0f, 0.0f};
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.005f, 0.001f, 1.0f}}}};
  BodyDef a, b;
  a.position = {100000.0f, 0, 0};
  a.velocity = {0.5f, 0, 0};
  b.position = {100000.03125f, 0, 0};
  s.bodies = {a, b};
  const GuardedRun r = runScene(s, GetParam(), 20000, 10);
  ASSERT_TRUE(r.localFrame);
  EXPECT_FALSE(r.trip.has_value()) << r.trip->message;
  EXPECT_NEAR(r.state.vx[1], 0.5f, 1e-4f) << "the collision happened and passed the momentum on";
}

// A deep overlap at a dt that resolves the contact is physics, not numerics: the message must
// not send the user halving dt.
TEST_P(GuardTest, DeepOverlapAtAGoodTimeStepBlamesTheStiffness) {
  Scene s = ballDrop(1.0e4f);  // t_c = 31 ms: 314 steps per contact
  BodyDef spectator;
  // A second body far away: the scene's shortest contact is now a (never happening) pair
  // contact with the default k_s, much shorter than the ground contact that trips. The advice
  // must be about the contact that tripped.
  spectator.position = {30.0f, 0, 0.05f};
  s.bodies.push_back(spectator);
  const auto t = runScene(s, GetParam(), 40000, 10).trip;
  ASSERT_TRUE(t.has_value()) << "v = 14 m/s on k = 1e4: sinks v sqrt(m/k) = 0.14 m, radius 0.05 m";
  EXPECT_EQ(t->kind, GuardTrip::Kind::Overlap);
  EXPECT_NE(t->message.find("the depth is physical"), std::string::npos) << t->message;
  EXPECT_EQ(t->message.find("use dt"), std::string::npos) << t->message;
}

// An outward pull (κ < 0) has a negative potential; the budget must use its size, not clamp the
// scale to nothing (which tripped a clean bounce at the first check).
TEST_P(GuardTest, QuietWithAnOutwardPull) {
  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = true;
  s.ground.stiffness = 1.0e5f;
  s.ground.friction = 0.0f;
  s.pulls.x = -2.0f;
  s.pulls.active = kPullX;
  s.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.1f, 1.0f, 1.0f}}}};
  BodyDef b;
  b.position = {3.0f, 0, 0.0995f};
  b.velocity = {0, 0, -1.0f};
  s.bodies = {b};
  const auto t = runScene(s, GetParam(), 2000, 10).trip;
  EXPECT_FALSE(t.has_value()) << t->message;
}

// With no contacts at all, a trip cannot be about resolving one: the message must say so, and
// point a clump on the report's rotation scheme to the splitting scheme.
TEST_P(GuardTest, NoContactsMessagePointsToTheRotationScheme) {
  Scene s;
  s.dt = 1e-3f;
  s.gravity = {0, 0, 0};
  s.shapes = {ShapeDef{"tri",
                       {SphereDef{{0.3f, 0, 0}, 0.05f, 0.2f, 0.5f}, SphereDef{{0, 0.15f, 0}, 0.05f, 0.3f, 0.5f},
                        SphereDef{{0, 0, 0.05f}, 0.05f, 0.4f, 0.5f}}}};
  BodyDef b;
  b.position = {0, 0, 1};
  b.angularVelocity = {0.3f, 20.0f, 0.2f};
  s.bodies = {b};
  for (const RotationScheme scheme : {RotationScheme::Report, RotationScheme::Splitting}) {
    s.integrator.rotation = scheme;
    const auto t = runScene(s, GetParam(), 20000, 10).trip;
    if (scheme == RotationScheme::Report) {
      ASSERT_TRUE(t.has_value()) << "the report's scheme more than doubles this spin's energy";
      EXPECT_NE(t->message.find("no contacts"), std::string::npos) << t->message;
      EXPECT_NE(t->message.find("splitting"), std::string::npos) << t->message;
      EXPECT_EQ(t->message.find("inf"), std::string::npos) << t->message;
    } else {
      EXPECT_FALSE(t.has_value()) << t->message;
    }
  }
}

namespace {

// A pipeline whose state is whatever the test puts in it.
class FakePipeline : public Pipeline {
 public:
  explicit FakePipeline(const World& w) : m_world(w), m_state(w.state) {}
  Backend backend() const override { return Backend::Cpu; }
  void load(const World&) override {}
  void step(std::uint64_t n) override { m_stats.steps += n; }
  void readState(BodyState& out) const override { out = m_state; }
  void readLocalPositions(std::vector<float>& out) const override {
    out.clear();
    for (std::uint32_t i = 0; i < m_world.numParticles(); ++i) {
      const std::uint32_t k = m_world.body[i];
      const Vec3f x = particlePosition(Vec3f{m_state.px[k], m_state.py[k], m_state.pz[k]},
                                       rotationMatrix(Quatf{m_state.qw[k], m_state.qx[k], m_state.qy[k], m_state.qz[k]}),
                                       Vec3f{m_world.ux[i], m_world.uy[i], m_world.uz[i]});
      out.insert(out.end(), {x.x, x.y, x.z});
    }
  }
  std::vector<Pair> pairs() const override { return {}; }
  std::vector<Pair> findPairs(const ParticleCloud&, const BroadphaseParams&) override { return {}; }
  void readDebug(ParticleDebug&) const override {}
  void setDebugCapture(bool) override {}
  void setEnergyTally(bool) override {}
  void setPulls(std::uint32_t) override {}
  std::uint32_t pulls() const override { return 0; }
  const StepStats& stats() const override { return m_stats; }
  void resetStats() override {}
  double time() const override { return 0.0; }
  std::uint64_t stepCount() const override { return m_stats.steps; }
  const World& m_world;
  BodyState m_state;
  StepStats m_stats;
};

}  // namespace

TEST(Guard, NamesTheBodyWithANonFiniteState) {
  Scene s = pile(1e-3f);
  const World w = World::fromScene(s);
  FakePipeline p(w);
  RunGuard guard(w, p);
  p.step(7);
  p.m_state.vy[5] = std::nanf("");
  const auto t = guard.check(p);
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->kind, GuardTrip::Kind::NonFinite);
  EXPECT_EQ(t->body, 5u);
  EXPECT_EQ(t->step, 7u);
  EXPECT_NE(t->message.find("step 7"), std::string::npos) << t->message;
  EXPECT_NE(t->message.find("body 5"), std::string::npos) << t->message;
}

// The CPU pipeline sums the guard's contact terms on its own contact list, in its internal
// (Morton) numbering; the sums must be the bits of the reference computed from pairs() in scene
// order, at every check, with contacts and a deepest pair to find.
TEST(Guard, PipelineContactSumsEqualThoseOfItsPairs) {
  for (bool hertz : {false, true}) {
  SCOPED_TRACE(hertz ? "hertz-mindlin, two materials" : "report");
  const Scene sc = validation::benchScene(16000);
  const World w = World::fromScene(hertz ? validation::withHertzMindlin(sc, 1.0e6f, true) : sc);
  for (int threads : {1, 2}) {
    PipelineOptions o;
    o.threads = threads;
    auto p = makePipeline(Backend::Cpu, o);
    p->load(w);
    const SpringLaw k = springLawOf(w);
    std::vector<ContactSums> own, ref;
    std::vector<float> x;
    std::vector<double> err(w.numBodies());
    BodyState s;
    ASSERT_TRUE(p->contactSumsPerBody(k, own));
    for (const ContactSums& c : own) ASSERT_EQ(c.springs, 0.0) << "no contacts before the first step";
    std::size_t checks = 0;
    for (int c = 0; c < 8; ++c) {
      p->step(60);
      ASSERT_TRUE(p->contactSumsPerBody(k, own));
      p->readLocalPositions(x);
      p->readLocalState(s);
      for (std::size_t b = 0; b < err.size(); ++b) err[b] = bodyRounding(s.px[b], s.py[b], s.pz[b]);
      contactSumsOfPairs(w, p->pairs(), x, err, k, ref);
      ASSERT_EQ(own.size(), ref.size());
      std::size_t touching = 0, deepest = 0;
      for (std::size_t b = 0; b < ref.size(); ++b) {
        ASSERT_EQ(own[b].springs, ref[b].springs) << "body " << b << ", step " << p->stepCount();
        ASSERT_EQ(own[b].slack, ref[b].slack) << "body " << b;
        ASSERT_EQ(own[b].maxOverlap, ref[b].maxOverlap) << "body " << b;
        ASSERT_EQ(own[b].deepestI, ref[b].deepestI) << "body " << b;
        ASSERT_EQ(own[b].deepestJ, ref[b].deepestJ) << "body " << b;
        touching += ref[b].springs > 0.0;
        deepest += ref[b].maxOverlap > 0.0 && w.body[ref[b].deepestI] == b;
      }
      if (touching > 0) ++checks;
      EXPECT_EQ(deepest, touching) << "every body with contacts names its own deepest pair";
    }
    EXPECT_GE(checks, 4u) << "the pile must touch for the comparison to mean anything";
  }
  }
}

TEST(Guard, DivergenceMessageNamesParticleBodyAndDt) {
  const World w = World::fromScene(pile(5e-3f));
  const std::string m = divergenceMessage(w, 42, 13);
  EXPECT_NE(m.find("step 42: particle 13 (body 13)"), std::string::npos) << m;
  EXPECT_NE(m.find("use dt <= "), std::string::npos) << m;
}

INSTANTIATE_TEST_SUITE_P(Backends, GuardTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);
