// SPDX-License-Identifier: MIT
// Contacts as state (SPEC §4, kernels/contact_list.hpp): the trajectory does not depend on how
// the contacts were found — cell size, PCA interval, thread count, skin, reordering — and with a
// skin the contacts are still exactly the brute-force set at every step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/soa.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

class ContactListTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

/// One way of finding the contacts: the knobs that must not change a bit.
struct Knobs {
  std::string name;
  float cellFactor = 0.0f;  ///< × the automatic cell size; 0 = automatic
  int pcaEvery = 10;
  float skinFactor = 1.0f;  ///< × the automatic skin (0 = detect every step)
  int threads = 2;
  bool reorder = true;
  bool debug = false;  ///< the debug capture: the CPU's forces particle by particle (bodyForces())
};

/// The states of a run every `every` steps (and at the end), plus its last-step statistics.
struct Run {
  std::vector<BodyState> states;
  StepStats stats;
};

Run run(Backend b, World w, const Knobs& k, std::uint64_t steps, std::uint64_t every, float autoCell) {
  w.params.broadphase.cellSize = k.cellFactor > 0.0f ? k.cellFactor * autoCell : 0.0f;
  w.params.broadphase.pcaEvery = k.pcaEvery;
  w.params.broadphase.skin = k.skinFactor * kAutoSkinPerRadius * w.maxRadius;
  PipelineOptions o;
  o.threads = k.threads;
  o.reorder = k.reorder;
  auto p = makePipeline(b, o);
  p->setDebugCapture(k.debug);
  p->load(w);
  Run r;
  for (std::uint64_t done = 0; done < steps;) {
    const std::uint64_t n = std::min(every, steps - done);
    p->step(n);
    done += n;
    r.states.emplace_back();
    p->readState(r.states.back());
  }
  r.stats = p->stats();
  return r;
}

void expectInvariant(Backend b, const std::string& scene, std::uint64_t steps, ContactLaw law = ContactLaw::Report) {
  Scene sc = readSceneFile(sourcePath(scene));
  if (law == ContactLaw::HookeHistory) sc = withHookeHistory(sc);
  if (law == ContactLaw::HertzMindlin) sc = withHertzMindlin(sc, 1.0e6f, true);
  const bool hookeHistory = law != ContactLaw::Report;
  const World w = World::fromScene(sc);
  const std::uint64_t every = steps / 10;
  const Run ref = run(b, w, Knobs{"reference"}, steps, every, 0.0f);
  const float autoCell = ref.stats.cellSize;
  std::printf("%s: %llu steps, %llu contacts at the end, %llu rebuilds, cell %g, hash %016llx\n", scene.c_str(),
              static_cast<unsigned long long>(steps), static_cast<unsigned long long>(ref.stats.numPairs),
              static_cast<unsigned long long>(ref.stats.numRebuilds), autoCell,
              static_cast<unsigned long long>(stateHash(ref.states.back())));
  ASSERT_GT(ref.stats.numPairs, 20u) << "the run needs contacts for the test to mean something";
  if (hookeHistory) {
    std::printf("  %s: %zu contacts carry a tangential history at the end\n", toString(law), ref.states.back().contacts.size());
    EXPECT_GT(ref.states.back().contacts.size(), 20u) << "the histories are what this variant tests";
  }
  const Knobs variants[] = {
      {"cell x0.5", 0.5f},  {"cell x2", 2.0f},          {"cell x10", 10.0f},
      {"pca_every 1", 0.0f, 1},    {"pca_every 1000", 0.0f, 1000},
      {"1 thread", 0.0f, 10, 1.0f, 1},  {"4 threads", 0.0f, 10, 1.0f, 4},
      {"skin 0 (detect every step)", 0.0f, 10, 0.0f}, {"skin x0.5", 0.0f, 10, 0.5f}, {"skin x3", 0.0f, 10, 3.0f},
      {"no reordering", 0.0f, 10, 1.0f, 2, false},
      {"debug capture (particle by particle)", 0.0f, 10, 1.0f, 2, true, true},
  };
  for (const Knobs& k : variants) {
    const Run got = run(b, w, k, steps, every, autoCell);
    for (std::size_t c = 0; c < ref.states.size(); ++c) {
      const auto d = firstDifference(ref.states[c], got.states[c]);
      if (d) {
        ADD_FAILURE() << scene << ", " << k.name << ": first difference by step " << std::min(steps, (c + 1) * every)
                      << ": " << d->describe();
        break;
      }
    }
  }
}

}  // namespace

TEST_P(ContactListTest, MoleculesDoNotDependOnHowContactsAreFound) {
  expectInvariant(GetParam(), "scenes/molecules.toml", 1500);
}
TEST_P(ContactListTest, SpheresDoNotDependOnHowContactsAreFound) {
  expectInvariant(GetParam(), "scenes/spheres.toml", 1500);
}
TEST_P(ContactListTest, Bench16kDoesNotDependOnHowContactsAreFound) {
  expectInvariant(GetParam(), "scenes/bench-16k.toml", 600);
}
// With a tangential history per contact (hooke-history): it follows the contacts across every
// rebuild and renumbering, so it does not depend on how they were found either.
TEST_P(ContactListTest, HookeHistoryDoesNotDependOnHowContactsAreFound) {
  TUMBLE_SKIP_IF_NOT_SUPPORTED(GetParam(), modelProbe(ContactLaw::HookeHistory));
  expectInvariant(GetParam(), "scenes/molecules.toml", 1500, ContactLaw::HookeHistory);
  expectInvariant(GetParam(), "scenes/spheres.toml", 1500, ContactLaw::HookeHistory);
}
// hertz-mindlin with two materials (a per-pair table, rolling resistance between some pairs).
TEST_P(ContactListTest, HertzMindlinDoesNotDependOnHowContactsAreFound) {
  TUMBLE_SKIP_IF_NOT_SUPPORTED(GetParam(), modelProbe(ContactLaw::HertzMindlin));
  expectInvariant(GetParam(), "scenes/molecules.toml", 1500, ContactLaw::HertzMindlin);
  expectInvariant(GetParam(), "scenes/spheres.toml", 1500, ContactLaw::HertzMindlin);
}

namespace {

/// A hard case of SPEC §3 set in motion: every particle a single-sphere body with a random
/// velocity of about `speed` smallest radii per step, no gravity, no ground; particle 0
/// optionally fast enough to force a rebuild every step (two largest radii per step, more than
/// half of any skin below 4 largest radii).
World movingCloud(const ParticleCloud& c, std::uint64_t seed, float speed, bool fast,
                  ContactLaw law = ContactLaw::Report, float gammaN = 100.0f) {
  Scene s;
  s.gravity = {0, 0, 0};
  s.dt = 1e-3f;
  s.contact = {1e3f, 0.5f, 0.2f};
  Rng rng(seed);
  float rmin = 1e30f, rmax = 0.0f;
  for (float r : c.r) {
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
  }
  for (std::size_t i = 0; i < c.size(); ++i) {
    s.shapes.push_back(ShapeDef{std::to_string(i), {SphereDef{{0, 0, 0}, c.r[i], 1.0f, 0.5f}}});
    BodyDef b;
    b.shape = static_cast<std::uint32_t>(i);
    b.position = {c.x[i], c.y[i], c.z[i]};
    const float v = speed * rmin / s.dt;
    b.velocity = {rng.uniform(-v, v), rng.uniform(-v, v), rng.uniform(-v, v)};
    s.bodies.push_back(b);
  }
  if (fast && !s.bodies.empty()) s.bodies[0].velocity = {2.0f * rmax / s.dt, 0.0f, 0.0f};
  return World::fromScene(law == ContactLaw::HookeHistory ? withHookeHistory(s, gammaN) : s);
}

/// pairs() after each step against the oracle on the state the step started from (in the frame
/// the pipeline integrates in, so that the positions are the ones it used).
void expectExactAtEveryStep(Pipeline& p, const World& w, int steps, const std::string& what) {
  p.load(w);
  const World local = toLocal(w, p.frame());
  for (int s = 0; s < steps; ++s) {
    BodyState st;
    p.readLocalState(st);
    p.step(1);
    const auto want = bruteForcePairs(cloudOf(local, st));
    const auto got = p.pairs();
    if (got != want) {
      ADD_FAILURE() << what << ": step " << s << ": " << got.size() << " pairs, the oracle has " << want.size();
      return;
    }
  }
}

}  // namespace

TEST_P(ContactListTest, PairsAreExactAtEveryStepWithASkin) {
  const std::uint64_t seed = 20261201;
  std::printf("moving hard cases, seed %llu\n", static_cast<unsigned long long>(seed));
  std::size_t withContacts = 0;
  std::uint64_t refreshes = 0;
  for (const auto& hc : hardCases(seed)) {
    if (hc.cloud.size() < 2 || hc.cloud.size() > 2500) continue;
    for (bool fast : {false, true}) {
      const World w = movingCloud(hc.cloud, seed, 0.02f, fast);
      for (float skin : {0.0f, 0.1f, 1.0f}) {  // × the largest radius
        World ws = w;
        ws.params.broadphase.skin = skin * w.maxRadius;
        auto p = makePipeline(GetParam());
        std::string what = hc.name;
        if (fast) what += " (fast particle)";
        what += ", skin ";
        what += std::to_string(skin);
        expectExactAtEveryStep(*p, ws, 30, what);
        refreshes += p->stats().numNearRefreshes;
        if (fast && skin > 0.0f) {
          EXPECT_EQ(p->stats().numRebuilds, p->stats().steps)
              << hc.name << ": a particle moving 2 radii per step must force a rebuild every step";
        }
      }
    }
    if (!bruteForcePairs(hc.cloud).empty()) ++withContacts;
  }
  EXPECT_GE(withContacts, 6u) << "the hard cases must contain contacts";
  std::printf("near-list refreshes over all runs: %llu\n", static_cast<unsigned long long>(refreshes));
  if (GetParam() == Backend::Cpu) {
    EXPECT_GT(refreshes, 0u) << "the near list must be refreshed between rebuilds";
  }
}

// Under a law with history the near list's entries find their ξ beside the candidate list
// (StepView::historySlot), and a contact left out of the near list at a refresh forgets its ξ
// there (fillNear()), as the pass over the candidate list would at that step: else a contact that
// opened by more than the near skin in one step kept a stale ξ for its next touch (and across
// rebuilds). A cloud moving about a fifth of a radius per step (seed printed) under undamped
// hooke-history: the same bits with the near list (skins of 0.5 and 1 radius) as with none (skin
// 0: every step detected, the candidate list itself), and particle by particle (debug capture).
TEST_P(ContactListTest, HistoriesLeavingTheNearListAreForgotten) {
  TUMBLE_SKIP_IF_NOT_SUPPORTED(GetParam(), modelProbe(ContactLaw::HookeHistory));
  const std::uint64_t seed = 20261207;
  std::printf("cloud seed %llu\n", static_cast<unsigned long long>(seed));
  const ParticleCloud c = randomCloud(1500, seed, 1.2f, 0.05f, 0.05f, 1);
  // Undamped (γ_n = 0): a contact's normal force stays positive to its last step, so that its ξ
  // is not zero when it opens (damping would clamp the force, and ξ with it, to zero).
  const World w = movingCloud(c, seed, 0.1f, false, ContactLaw::HookeHistory, 0.0f);
  const ::Run ref = run(GetParam(), w, Knobs{"skin 0", 0.0f, 10, 0.0f}, 400, 40, 0.0f);
  std::printf("skin 0: %llu contacts at the end, %zu with a history\n",
              static_cast<unsigned long long>(ref.stats.numPairs), ref.states.back().contacts.size());
  ASSERT_GT(ref.states.back().contacts.size(), 20u) << "the histories are what this test is about";
  const Knobs variants[] = {{"skin 0.5 r", 0.0f, 10, 0.5f / kAutoSkinPerRadius},
                            {"skin 1 r", 0.0f, 10, 1.0f / kAutoSkinPerRadius},
                            {"skin 1 r, particle by particle", 0.0f, 10, 1.0f / kAutoSkinPerRadius, 2, true, true}};
  for (const Knobs& k : variants) {
    const ::Run got = run(GetParam(), w, k, 400, 40, 0.0f);
    std::printf("%s: %llu rebuilds, %llu near-list refreshes\n", k.name.c_str(), static_cast<unsigned long long>(got.stats.numRebuilds),
                static_cast<unsigned long long>(got.stats.numNearRefreshes));
    for (std::size_t s = 0; s < ref.states.size(); ++s)
      if (const auto d = firstDifference(ref.states[s], got.states[s])) {
        ADD_FAILURE() << k.name << ": first difference by step " << 40 * (s + 1) << ": " << d->describe();
        break;
      }
  }
}

TEST_P(ContactListTest, PairsAreExactAtEveryStepOfAClumpRun) {
  // The bench lattice falling and landing: skin reuse across many steps, clumps, ground.
  const World w = World::fromScene(benchScene(4000));
  auto p = makePipeline(GetParam());
  p->load(w);
  p->step(350);  // near landing: contacts form and break at every step
  BodyState st;
  p->readState(st);
  World w2 = w;
  w2.state = st;
  expectExactAtEveryStep(*p, w2, 80, "bench-4k from step 350");
  std::printf("bench-4k from step 350: %llu contacts, %llu rebuilds and %llu near-list refreshes in 80 steps\n",
              static_cast<unsigned long long>(p->stats().numPairs),
              static_cast<unsigned long long>(p->stats().numRebuilds),
              static_cast<unsigned long long>(p->stats().numNearRefreshes));
  EXPECT_GT(p->stats().numPairs, 100u);
  EXPECT_LT(p->stats().numRebuilds, p->stats().steps) << "the skin must actually be reused";
  if (GetParam() == Backend::Cpu) {  // the CPU's forces read the near list, refreshed between rebuilds
    EXPECT_GT(p->stats().numNearRefreshes, 0u) << "the near list must actually be refreshed";
  }
}

TEST_P(ContactListTest, AParticleMovingToAndFroDoesNotForceRebuilds) {
  // A row of resting spheres, one of which swings in x (the x-pull, amplitude 0.075 = 0.3 skin,
  // 5 periods). Two particles never close in by the skin, so the list of the first step lasts:
  // the near list's refreshes must not add up the swings.
  Scene s;
  s.gravity = {0, 0, 0};
  s.dt = 1e-3f;
  s.broadphase.skin = 0.25f;
  s.pulls.x = 100.0f;
  s.pulls.active = kPullX;
  s.shapes.push_back(ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}});
  for (int k = 0; k < 100; ++k) {
    BodyDef b;
    b.shape = 0;
    b.position = {k == 0 ? 0.075f : 0.0f, 2.0f * float(k), 0.0f};
    s.bodies.push_back(b);
  }
  auto p = makePipeline(GetParam());
  p->load(World::fromScene(s));
  p->step(3000);
  std::printf("swinging sphere, 3000 steps: %llu rebuilds, %llu near-list refreshes\n",
              static_cast<unsigned long long>(p->stats().numRebuilds),
              static_cast<unsigned long long>(p->stats().numNearRefreshes));
  EXPECT_EQ(p->stats().numRebuilds, 1u);
  if (GetParam() == Backend::Cpu) {
    EXPECT_GE(p->stats().numNearRefreshes, 5u) << "the near list must follow the swings";
  }
}

TEST_P(ContactListTest, PairsAreExactForAParticleWithThousandsOfContacts) {
  // 2500 small spheres on a big one (radius 19.6, overlap 0.1 each, none touching another small
  // one): more contacts than the per-particle count the step keeps (255), and more than the
  // other particles of a chunk of pairs() can make room for, so pairs() must size the big
  // sphere's room from its row. Checked at every step, and through readDebug().
  Scene s;
  s.gravity = {0, 0, 0};
  s.dt = 1e-4f;
  s.contact = {1e3f, 0.5f, 0.2f};
  s.shapes.push_back(ShapeDef{"big", {SphereDef{{0, 0, 0}, 19.6f, 100.0f, 0.5f}}});
  s.shapes.push_back(ShapeDef{"small", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}});
  BodyDef big;
  big.shape = 0;
  s.bodies.push_back(big);
  const int m = 2500;
  for (int k = 0; k < m; ++k) {  // a Fibonacci sphere of radius 20
    const float z = 1.0f - 2.0f * (float(k) + 0.5f) / float(m), rho = std::sqrt(1.0f - z * z);
    const float phi = 2.39996323f * float(k);
    BodyDef b;
    b.shape = 1;
    b.position = {20.0f * rho * std::cos(phi), 20.0f * rho * std::sin(phi), 20.0f * z};
    s.bodies.push_back(b);
  }
  const World w = World::fromScene(s);
  ASSERT_EQ(bruteForcePairs(cloudOf(w, w.state)).size(), std::size_t(m));
  auto p = makePipeline(GetParam());
  expectExactAtEveryStep(*p, w, 10, "big sphere with 2500 contacts");
  p->setDebugCapture(true);
  p->step(1);
  ParticleDebug dbg;
  p->readDebug(dbg);
  EXPECT_EQ(dbg.contacts, p->pairs());
  EXPECT_EQ(dbg.contacts.size(), std::size_t(m));
}

// The CPU sums a body's contacts in one batch (kernels/step.hpp bodyForces()) and goes particle
// by particle (particleForce()) for a body of more than kBodyBatchParticles particles or more
// than kBodyBatch entries in its rows, and with the debug capture on: the same bits every way.
// Rods of 20 spheres (past the particle limit), plates of 16 (at it), clumps of 8 (batched), a
// big sphere touching dozens (past the entry limit) and loose balls, packed to overlap, falling
// on the ground.
TEST_P(ContactListTest, TheBodyBatchEqualsParticleByParticle) {
  Scene s;
  s.dt = 2e-4f;
  s.contact = {2e3f, 2.0f, 1.0f};  // soft: the packs stay in contact over the run
  s.ground.enabled = true;
  ShapeDef rod{"rod", {}}, clump{"clump", {}}, plate{"plate", {}};
  for (int k = 0; k < 20; ++k) rod.spheres.push_back(SphereDef{{0.8f * float(k) - 7.6f, 0, 0}, 0.5f, 1.0f, 0.5f});
  for (int k = 0; k < 16; ++k)
    plate.spheres.push_back(SphereDef{{0.9f * float(k % 4) - 1.35f, 0.9f * float(k / 4) - 1.35f, 0}, 0.5f, 1.0f, 0.5f});
  for (int k = 0; k < 8; ++k)
    clump.spheres.push_back(SphereDef{{k & 1 ? 0.3f : -0.3f, k & 2 ? 0.3f : -0.3f, k & 4 ? 0.3f : -0.3f}, 0.5f, 1.0f, 0.5f});
  s.shapes = {rod, clump, ShapeDef{"big", {SphereDef{{0, 0, 0}, 4.0f, 50.0f, 0.5f}}},
              ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}}, plate};
  auto add = [&](std::uint32_t shape, Vec3f x, Quatf q = Quatf{1, 0, 0, 0}) {
    BodyDef b;
    b.shape = shape;
    b.position = x;
    b.orientation = q;
    s.bodies.push_back(b);
  };
  for (int y = 0; y < 4; ++y)
    for (int z = 0; z < 3; ++z) add(0, {0.0f, 0.9f * float(y) - 12.0f, 0.9f * float(z) + 0.6f}, Quatf{0.9950f, 0, 0, 0.0998f});
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 6; ++y) add(1, {1.4f * float(x) - 3.5f, 1.4f * float(y) + 6.0f, 1.0f});
  add(4, {-1.5f, 8.0f, 2.2f});  // plates pressed 0.1 onto the clumps' top spheres
  add(4, {2.0f, 11.0f, 2.2f});
  add(2, {0.0f, 0.0f, 5.0f});
  for (int k = 0; k < 120; ++k) {  // a shell of balls on the big sphere, each pressed 0.05 into it
    const float zc = 1.0f - 2.0f * (float(k) + 0.5f) / 120.0f, rho = std::sqrt(1.0f - zc * zc), phi = 2.39996323f * float(k);
    add(3, {4.45f * rho * std::cos(phi), 4.45f * rho * std::sin(phi), 5.0f + 4.45f * zc});
  }
  const World w = World::fromScene(s);
  const ::Run ref = run(GetParam(), w, Knobs{"reference"}, 400, 40, 0.0f);
  std::printf("batch test: %u bodies, %u particles, %llu contacts after 400 steps, hash %016llx\n", w.numBodies(),
              w.numParticles(), static_cast<unsigned long long>(ref.stats.numPairs),
              static_cast<unsigned long long>(stateHash(ref.states.back())));
  EXPECT_GT(ref.stats.numPairs, 150u) << "the shell and the packs must touch for the test to mean something";
  for (const Knobs& k : {Knobs{"debug capture", 0.0f, 10, 1.0f, 2, true, true},
                         Knobs{"debug capture, skin 0", 0.0f, 10, 0.0f, 2, true, true}, Knobs{"skin 0", 0.0f, 10, 0.0f}}) {
    const ::Run got = run(GetParam(), w, k, 400, 40, 0.0f);
    for (std::size_t c = 0; c < ref.states.size(); ++c)
      if (const auto d = firstDifference(ref.states[c], got.states[c])) {
        ADD_FAILURE() << k.name << ": first difference by step " << (c + 1) * 40 << ": " << d->describe();
        break;
      }
  }
}

TEST_P(ContactListTest, SkinIsReusedAndCounted) {
  World w = World::fromScene(benchScene(16000));
  auto p = makePipeline(GetParam());
  p->load(w);
  p->step(200);
  const StepStats& st = p->stats();
  std::printf("bench-16k, 200 steps: skin %g, %llu rebuilds, %llu candidate pairs\n", st.skin,
              static_cast<unsigned long long>(st.numRebuilds), static_cast<unsigned long long>(st.numCandidates));
  EXPECT_FLOAT_EQ(st.skin, kAutoSkinPerRadius * 0.5f);
  EXPECT_GE(st.numRebuilds, 1u);
  EXPECT_LT(st.numRebuilds, 50u);
  EXPECT_NEAR(st.rebuildsPer1000(), 1000.0 * double(st.numRebuilds) / 200.0, 1e-9);
  w.params.broadphase.skin = 0.0f;
  p->load(w);
  p->step(20);
  EXPECT_EQ(p->stats().numRebuilds, 20u) << "skin 0 detects every step";
}

INSTANTIATE_TEST_SUITE_P(Backends, ContactListTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);

// The bytes of a step (Pipeline::stepTraffic(), the memory floor of `tumble bench`; issue 32,
// item 3) against the arrays of two single spheres that touch each other and the ground, counted
// here from the rows' sizes: each array the pass reads once at its size, once more if it writes
// it. Under hooke-history the bodies rotate (their particles' bodies are read) and each near
// entry reads its candidate entry and its ξ, the contacts write theirs.
TEST(StepTraffic, CountsTheArraysOfThePass) {
  Scene s;
  s.dt = 1e-4f;
  s.contact = {1e3f, 0.5f, 0.2f};
  s.ground.enabled = true;
  s.shapes.push_back(ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.5f, 1.0f, 0.5f}}});
  for (float x : {0.0f, 0.9f}) {
    BodyDef b;
    b.position = {x, 0.0f, 0.45f};
    s.bodies.push_back(b);
  }
  for (const bool history : {false, true}) {
    SCOPED_TRACE(history ? "hooke-history" : "report");
    const World w = World::fromScene(history ? withHookeHistory(s) : s);
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    p->step(1);
    ASSERT_EQ(p->stats().numPairs, 1u);
    const double n = 2, nb = 2, entries = 2, contacts = 2;  // the pair, from both sides
    double want = 2 * n * sizeof(PosRow) + n * sizeof(OwnRow) + n * 4 /* radii */ + n * 1 /* contacts */ +
                  (n + 1) * 4 /* offsets */ + entries * 4 /* near entries */ + entries * 4 /* their particles */ +
                  2 * nb * sizeof(BodyRow) + nb * sizeof(BodyStatic) + n * sizeof(PosRow) /* skin reference */ +
                  2 * 2 * n * 4 /* the ground's springs, read and written */;
    if (history) want += n * 4 /* bodies of the particles */ + entries * 4 /* candidate entries */ +
                         (entries + contacts) * sizeof(Vec3f);
    double got = 0.0;
    for (const TrafficLine& l : p->stepTraffic()) {
      std::printf("  %-90s %6.0f B\n", l.what.c_str(), l.bytes);
      got += l.bytes;
    }
    EXPECT_EQ(got, want);
  }
}
