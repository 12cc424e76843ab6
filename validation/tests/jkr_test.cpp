// SPDX-License-Identifier: MIT
// JKR cohesion with its hysteresis (issue 37, item 1; docs/model.md#cohesion), on every backend.
//
// Oracles, written out here in double from JKR's parametric curve (Johnson, Kendall & Roberts
// 1971): δ(a) = a²/R* − √(2πγa/Y*), F(a) = 4Y*a³/(3R*) − √(8πγY*a³).
// - the force of the kernel along the curve; its minimum, the pull-off force 3/2 π γ R*; the
//   neck's end δ_c = −¾ (π²γ²R*/Y*²)^{1/3}, where the contact lets go;
// - a sphere under a steady pull from the ground (gravity turned upwards, held by its neck)
//   stays below the pull-off force and leaves above it;
// - a sphere dropped on the ground settles where F(a) carries its weight;
// - Thornton & Ning's (1998) criterion for elastic adhesive spheres: a head-on impact sticks when
//   the kinetic energy ½ m* v² is below the work W = ∫_{δ_c}^0 |F| dδ that breaks the neck (the
//   hysteresis of the loop: 7.09 (γ⁵R*⁴/Y*²)^{1/3}), so V_s = √(2W/m*); above it the pair
//   rebounds at √(v² − V_s²), and the energy tally's dissipated_cohesion is that W.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/cohesion.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/validation/jkr.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;

namespace {

constexpr double kPi = 3.14159265358979323846, kR = validation::kJkrRadius, kGamma = validation::kJkrGamma;
using validation::JkrCurve;
using validation::jkrSceneText;
using validation::jkrYstar;

TEST(Jkr, ForceIsJohnsonKendallRobertsAlongTheBranch) {
  for (const double reff : {0.5 * kR, kR, 0.0012}) {
    const JkrCurve c{reff, jkrYstar(reff == kR), kGamma};
    const double dc = -0.75 * std::cbrt(kPi * kPi * kGamma * kGamma * reff / (c.ystar * c.ystar));
    EXPECT_NEAR(c.delta(c.aEnd()), dc, 1e-9 * std::fabs(dc));
    double worst = 0.0, least = 0.0, worstEnergy = 0.0;
    // From near the neck's end (at 1 % of its a the overlap is 3e-4 of |δ_c| from it: closer,
    // the float δ no longer resolves a, whose δ is flat there) to 5 times the radius at touching.
    for (int k = 0; k <= 4000; ++k) {
      const double a = c.aEnd() * (1.0 + 1e-2) + (5.0 * c.aTouch() - c.aEnd()) * k / 4000.0;
      const JkrContact j = jkrContact(float(c.delta(a)), float(reff), float(c.ystar), float(kGamma));
      ASSERT_TRUE(j.held) << "a = " << a;
      worst = std::max(worst, std::fabs(j.elastic - c.force(a)) / (c.pullOff() + std::fabs(c.force(a))));
      least = std::min(least, double(j.elastic));
      if (k % 100 == 0) {
        const double u = jkrEnergy(c.delta(a), reff, c.ystar, kGamma), want = c.work(c.aTouch(), a);
        worstEnergy = std::max(worstEnergy, std::fabs(u - want) / c.neckWork());
      }
    }
    const JkrContact touch = jkrContact(0.0f, float(reff), float(c.ystar), float(kGamma));
    std::printf("R* %g m: force within %.2g of JKR's (relative to the pull-off force and itself), least %.6g N against "
                "-3/2 pi gamma R* = %.6g N; at delta = 0 %.6g N (-8/9 of it: %.6g); energy within %.2g of the neck's "
                "%.4g J; delta_c %.5g m\n",
                reff, worst, least, -c.pullOff(), double(touch.elastic), -8.0 / 9.0 * c.pullOff(), worstEnergy,
                c.neckWork(), dc);
    EXPECT_LT(worst, 2e-5);
    EXPECT_NEAR(least, -c.pullOff(), 1e-4 * c.pullOff());
    EXPECT_NEAR(touch.elastic, -8.0 / 9.0 * c.pullOff(), 1e-5 * c.pullOff());
    EXPECT_LT(worstEnergy, 1e-6);
    EXPECT_FALSE(jkrContact(float(dc * (1.0 + 1e-4)), float(reff), float(c.ystar), float(kGamma)).held);
    EXPECT_TRUE(jkrContact(float(dc * (1.0 - 1e-4)), float(reff), float(c.ystar), float(kGamma)).held);
    // The neck's work against the closed form of the literature, 7.09 (γ⁵ R*⁴ / Y*²)^{1/3}.
    EXPECT_NEAR(c.neckWork(), 7.09 * std::cbrt(std::pow(kGamma, 5) * std::pow(reff, 4) / (c.ystar * c.ystar)),
                2e-3 * c.neckWork());
  }
}

// What a JKR scene refuses: a mesh wall (its contacts keep no neck), named with the wall.
TEST(Jkr, MeshWallsAreRefused) {
  const std::string wall = "[[wall]]\ntype = \"mesh\"\nfile = \"" + validation::sourcePath("scenes/rock.obj") + "\"\n";
  const Scene scene = parseScene(jkrSceneText(0.5, -9.81, 1e-6, wall + "[[body]]\nshape = \"s\"\nposition = [0, 0, 1]\n"),
                                 "jkr-mesh.toml");
  try {
    (void)World::fromScene(scene);
    ADD_FAILURE() << "a mesh wall under jkr: no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("jkr-mesh.toml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not reach mesh walls"), std::string::npos) << e.what();
  }
}

class JkrTest : public ::testing::TestWithParam<Backend> {};

// A sphere held to the ground by its neck at the equilibrium of a steady upward pull (gravity
// +z) of 0.97 of the pull-off force stays; at 1.03 from the same start it leaves. The ground's
// spring starts marked as held (heldPlaneSpring(): as a checkpoint of a neck carries it), so the
// stretched contact (δ < 0 there) exists from the first step.
TEST_P(JkrTest, PullOffForceIsThreeHalvesPiGammaR) {
  TUMBLE_NEED_BACKEND(GetParam());
  const JkrCurve c{kR, jkrYstar(true), kGamma};
  const double m = validation::kJkrDensity * 4.0 / 3.0 * kPi * kR * kR * kR;
  const double a = c.radiusAt(-0.97 * c.pullOff()), delta = c.delta(a);
  ASSERT_LT(delta, 0.0);
  char body[160];
  std::snprintf(body, sizeof body, "[[body]]\nshape = \"s\"\nposition = [0, 0, %.17g]\n", -delta);  // ground at −r
  for (const double load : {0.97, 1.03}) {
    const Scene scene = parseScene(jkrSceneText(0.5, load * c.pullOff() / m, 2e-6, body), "jkr pull-off");
    World w = World::fromScene(scene);
    w.state.groundSpringX.assign(1, 0.0f);
    w.state.groundSpringY.assign(1, -0.0f);  // held
    auto p = makePipeline(GetParam());
    p->load(w);
    p->step(20000);
    BodyState s;
    p->readState(s);
    const double z = s.pz[0];
    std::printf("pulled at %.2f of 3/2 pi gamma R = %.5g N: the centre at %.6g m after 0.04 s (started at %.6g, the "
                "neck's end at %.6g)\n",
                load, c.pullOff(), z, -delta, -c.delta(c.aEnd()));
    if (load < 1.0) {
      EXPECT_NEAR(z, -delta, 1e-3 * std::fabs(delta)) << "held below the pull-off force";
    } else {
      EXPECT_GT(z, 10.0 * std::fabs(c.delta(c.aEnd()))) << "pulled off above it";
    }
  }
}

// A sphere dropped onto the ground comes to rest where F(a) carries its weight (the ground at
// −r, as cohesion_test's, for the float resolution of the centre).
TEST_P(JkrTest, SettlesAtTheEquilibriumOverlap) {
  TUMBLE_NEED_BACKEND(GetParam());
  const JkrCurve c{kR, jkrYstar(true), kGamma};
  const Scene scene = parseScene(jkrSceneText(0.2, -9.81, 2e-6, "[[body]]\nshape = \"s\"\nposition = [0, 0, 0.00001]\n"),
                                 "jkr resting");
  const World w = World::fromScene(scene);
  const double m = w.bodyMass[0];
  const double want = c.delta(c.radiusAt(m * 9.81));
  auto p = makePipeline(GetParam());
  p->load(w);
  p->step(60000);
  BodyState s;
  p->readState(s);
  const double overlap = -double(s.pz[0]);
  std::printf("resting overlap %.6g m, JKR's equilibrium %.6g m (at zero load %.6g, Hertz's %.3g)\n", overlap, want,
              c.delta(c.radiusAt(0.0)), std::pow(3.0 * m * 9.81 / (4.0 * c.ystar * std::sqrt(kR)), 2.0 / 3.0));
  EXPECT_NEAR(overlap, want, 2e-3 * want);
}

// Head-on impacts without damping (restitution 1): two equal spheres (m* = m/2, R* = r/2) and a
// sphere on the ground (m, r). Below V_s = √(2W/m*) they stay bound; above, the relative speed
// after is √(v² − V_s²) and the tally's dissipated_cohesion is W (each within 1 %).
TEST_P(JkrTest, StickingVelocityIsThorntonNings) {
  TUMBLE_NEED_BACKEND(GetParam());
  const double m = validation::kJkrDensity * 4.0 / 3.0 * kPi * kR * kR * kR;
  for (const bool plane : {false, true}) {
    const JkrCurve c{plane ? kR : 0.5 * kR, jkrYstar(plane), kGamma};
    const double mstar = plane ? m : 0.5 * m, w = c.neckWork(), vs = std::sqrt(2.0 * w / mstar);
    for (const double f : {0.9, 1.5}) {
      const double v = f * vs;
      const validation::JkrImpact r = validation::jkrImpact(GetParam(), plane, v);
      const double after = r.after, gap = r.gap, lost = r.neckEnergy;
      std::printf("%s at %.2f V_s (V_s %.5g m/s): relative speed after %.6g m/s (expected %.6g), gap %.4g m; "
                  "dissipated_cohesion %.6g J, the neck's work W %.6g J\n",
                  plane ? "on the ground" : "two spheres", f, vs, after, f > 1.0 ? std::sqrt(v * v - vs * vs) : 0.0, gap,
                  lost, w);
      if (f < 1.0) {  // bound, ringing: within the neck's reach, the neck never broken
        EXPECT_LT(gap, -c.delta(c.aEnd())) << "stuck";
        EXPECT_LT(lost, w) << "what the neck holds now, never more than W";
      } else {
        EXPECT_NEAR(after, std::sqrt(v * v - vs * vs), 1e-2 * std::sqrt(v * v - vs * vs));
        EXPECT_NEAR(lost, w, 1e-2 * w);
      }
    }
  }
}

// A bound pair (0.9 V_s, no damping) rings through its neck. While the neck holds beyond
// touching it is a contact of the step (pairs(), the debug capture's forces, the contact count),
// and its energy is the guard's: a run resumed with the neck stretched (a checkpoint's state, the
// guard's reference taken there) does not trip when the neck gives that energy back.
TEST_P(JkrTest, NecksAreContactsAndTheGuardCountsTheirEnergy) {
  TUMBLE_NEED_BACKEND(GetParam());
  const double m = validation::kJkrDensity * 4.0 / 3.0 * kPi * kR * kR * kR;
  const JkrCurve c{0.5 * kR, jkrYstar(false), kGamma};
  const double v = 0.9 * std::sqrt(2.0 * c.neckWork() / (0.5 * m));
  const World w =
      World::fromScene(parseScene(jkrSceneText(1.0, 0.0, 1e-6, validation::jkrHeadOnBodies(false, v)), "jkr neck"));
  auto p = makePipeline(GetParam());
  p->load(w);
  p->setDebugCapture(true);
  BodyState s;
  double gap = 0.0;
  bool touched = false;
  std::uint64_t steps = 0;
  // After the impact, until the neck is half stretched.
  for (; steps < 20000 && !(touched && gap > 0.5 * -c.delta(c.aEnd())); steps += 10) {
    p->step(10);
    p->readState(s);
    gap = double(s.px[1]) - double(s.px[0]) - 2.0 * kR;
    touched = touched || gap < 0.0;
  }
  ASSERT_GT(gap, 0.0) << "no neck within 20000 steps";
  const std::vector<Pair> pairs = p->pairs();
  ParticleDebug dbg;
  p->readDebug(dbg);
  std::printf("step %llu: the surfaces %.4g m apart (the neck's end at %.4g m); %zu pair(s), %zu contact force(s), "
              "%llu contact(s) counted\n",
              static_cast<unsigned long long>(steps), gap, -c.delta(c.aEnd()), pairs.size(), dbg.contactForces.size(),
              static_cast<unsigned long long>(p->stats().numPairs));
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].i, 0u);
  EXPECT_EQ(pairs[0].j, 1u);
  ASSERT_EQ(dbg.contactForces.size(), 1u);
  EXPECT_LT(dbg.contactForces[0].fn, 0.0f) << "the neck pulls";
  EXPECT_EQ(p->stats().numPairs, 1u);
  World resumed = w;
  resumed.state = s;
  resumed.time = p->time();
  resumed.step = p->stepCount();
  auto q = makePipeline(GetParam());
  q->load(resumed);
  RunGuard guard(resumed, *q);
  for (int k = 0; k < 200; ++k) {
    q->step(100);
    const auto trip = guard.check(*q);
    ASSERT_FALSE(trip) << trip->message;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, JkrTest, ::testing::ValuesIn(compiledBackends()), tumble_test::backendName);

}  // namespace
