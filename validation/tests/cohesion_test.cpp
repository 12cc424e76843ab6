// SPDX-License-Identifier: MIT
// Cohesion (issue 37, item 1; docs/model.md#cohesion): sjkr and dmt on top of hooke-history and
// hertz-mindlin, on every backend.
//
// Oracles: the normal force of a contact at rest against the law written out here in double from
// the positions (Hertz or Hooke minus k_c π a² or 2 π γ R*, the pair's coefficients mixed by the
// geometric mean, a plane's override), for two spheres, a sphere on the ground and one on a wall;
// the tension at vanishing overlap is the pull-off force 2 π γ R* (DMT); a sphere settled on the
// ground rests at the overlap where the spring carries its weight and the attraction (solved here
// by bisection); in elastic collisions the energy with the cohesive potential (the guard's, the
// time series') is conserved while the attraction does work, and the pair rebounds at its speed
// (sjkr and dmt attract only while the surfaces overlap: the work in and out cancels). LIGGGHTS's
// sjkr on the same collisions: validation/liggghts/sjkr_collisions.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tumble/factory.hpp"
#include "tumble/kernels/cohesion.hpp"
#include "tumble/guard.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/thermo.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;

namespace {

constexpr double kPi = 3.14159265358979323846;

void replaceAll(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t at; (at = s.find(from)) != std::string::npos;) s.replace(at, from.size(), to);
}

struct Case {
  bool hertz;
  Cohesion model;
  std::string name() const {
    return std::string(hertz ? "hertz-mindlin" : "hooke-history") + " + " + toString(model);
  }
  std::string key() const { return model == Cohesion::Sjkr ? "cohesion_energy_density" : "surface_energy"; }
  // The coefficients: the spheres' material (or [contact]), the wall's material (or [[wall]]), the
  // ground's override. sjkr: k_c [J/m^3]; dmt: γ [J/m^2]. Under hooke-history sjkr's attraction
  // grows as fast as the spring (2 π k_c r δ on a plane) and must stay below it.
  double sphere() const { return model == Cohesion::Sjkr ? (hertz ? 2.0e5 : 1.0e5) : 0.08; }
  double wall() const { return model == Cohesion::Sjkr ? (hertz ? 8.0e5 : 4.0e4) : 0.02; }
  double ground() const { return model == Cohesion::Sjkr ? (hertz ? 5.0e5 : 1.0e5) : 0.3; }
};
const Case kCases[] = {{true, Cohesion::Sjkr}, {true, Cohesion::Dmt}, {false, Cohesion::Sjkr}, {false, Cohesion::Dmt}};

// The parameters of both laws.
constexpr double kE1 = 1.0e7, kNu1 = 0.3, kE2 = 4.0e7, kNu2 = 0.2;  // materials m and w
constexpr double kKn = 2000.0, kKwall = 1500.0, kKground = 3000.0;  // hooke-history stiffnesses
constexpr double kDensity = 2500.0;

// The law's section, the materials and the planes; the wall is the plane x = 0.1 facing -x.
std::string lawText(const Case& c) {
  std::string t = "[contact]\nlaw = \"" + std::string(c.hertz ? "hertz-mindlin" : "hooke-history") +
                  "\"\ncohesion = \"" + toString(c.model) + "\"\n";
  char buf[512];
  if (c.hertz) {
    std::snprintf(buf, sizeof buf,
                  "[[material]]\nname = \"m\"\ndensity = %g\nyoungs_modulus = %g\npoisson_ratio = %g\nrestitution = 0.5\n"
                  "%s = %.17g\n[[material]]\nname = \"w\"\ndensity = %g\nyoungs_modulus = %g\npoisson_ratio = %g\n"
                  "restitution = 0.5\n%s = %.17g\n[ground]\nheight = 0.0\n%s = %.17g\n[[wall]]\ntype = \"plane\"\n"
                  "point = [0.1, 0, 0]\nnormal = [-1, 0, 0]\nmaterial = \"w\"\n",
                  kDensity, kE1, kNu1, c.key().c_str(), c.sphere(), kDensity, kE2, kNu2, c.key().c_str(), c.wall(),
                  c.key().c_str(), c.ground());
  } else {
    std::snprintf(buf, sizeof buf,
                  "stiffness = %g\ngamma_n = 0\n%s = %.17g\n[[material]]\nname = \"m\"\ndensity = %g\n[[material]]\n"
                  "name = \"w\"\ndensity = %g\n[ground]\nheight = 0.0\nstiffness = %g\n%s = %.17g\n[[wall]]\n"
                  "type = \"plane\"\npoint = [0.1, 0, 0]\nnormal = [-1, 0, 0]\nstiffness = %g\n%s = %.17g\n",
                  kKn, c.key().c_str(), c.sphere(), kDensity, kDensity, kKground, c.key().c_str(), c.ground(), kKwall,
                  c.key().c_str(), c.wall());
  }
  return t + buf;
}

double ystar(double e1, double nu1, double e2, double nu2) {
  return 1.0 / ((1.0 - nu1 * nu1) / e1 + (e2 > 0.0 ? (1.0 - nu2 * nu2) / e2 : 0.0));
}

// The attraction in double: sjkr k_c π a² (a² of two spheres at centre distance d, or on a plane
// at depth delta: rj = 0), dmt 2 π γ R*.
double pullOf(const Case& c, double value, double delta, double ri, double rj) {
  if (c.model == Cohesion::Dmt) return 2.0 * kPi * value * (rj > 0.0 ? ri * rj / (ri + rj) : ri);
  if (rj == 0.0) return kPi * value * delta * (2.0 * ri - delta);
  const double d = ri + rj - delta;
  return kPi * value * (d * d - (ri - rj) * (ri - rj)) * ((ri + rj) * (ri + rj) - d * d) / (4.0 * d * d);
}

// Four spheres at rest: a (material m, r 4 mm) against b (material w, r 2.5 mm) overlapping by
// frac of b's radius, c (m, 3 mm) pressed into the ground and d (m, 3.5 mm) into the wall by frac
// of their radii.
std::string restingScene(const Case& c, double frac) {
  char bodies[1024];
  const double ra = 0.004, rb = 0.0025, rc = 0.003, rd = 0.0035;
  std::snprintf(bodies, sizeof bodies,
                "[[shape]]\nname = \"a\"\n[[shape.sphere]]\nradius = %g\nmaterial = \"m\"\n"
                "[[shape]]\nname = \"b\"\n[[shape.sphere]]\nradius = %g\nmaterial = \"w\"\n"
                "[[shape]]\nname = \"c\"\n[[shape.sphere]]\nradius = %g\nmaterial = \"m\"\n"
                "[[shape]]\nname = \"d\"\n[[shape.sphere]]\nradius = %g\nmaterial = \"m\"\n"
                "[[body]]\nshape = \"a\"\nposition = [-0.01, 0, 0.05]\n"
                "[[body]]\nshape = \"b\"\nposition = [%.9g, 0, 0.05]\n"
                "[[body]]\nshape = \"c\"\nposition = [0, 0.02, %.9g]\n"
                "[[body]]\nshape = \"d\"\nposition = [%.9g, 0, 0.03]\n",
                ra, rb, rc, rd, -0.01 + ra + rb - frac * rb, rc - frac * rc, 0.1 - rd + frac * rd);
  return "[scene]\nname = \"cohesion-at-rest\"\ndt = 1e-6\nsteps = 1\ngravity = [0, 0, 0]\n" + lawText(c) + bodies;
}

// The crossing circle against the geometry in double: two spheres' surfaces cross where
// x = (d² + ri² − rj²) / (2d) from i's centre, a² = ri² − x²; bit-identical from either side;
// nothing (0, finite) once a sphere is inside the other, at coincident centres or through a plane.
TEST(Cohesion, CrossingCircleIsTheLensGeometry) {
  for (const float ri : {0.01f, 0.003f})
    for (const float rj : {0.01f, 0.007f, 0.0005f})
      for (const float frac : {1e-4f, 1e-2f, 0.3f}) {
        const float delta = frac * std::min(ri, rj);
        const double d = double(ri) + rj - delta, x = (d * d + double(ri) * ri - double(rj) * rj) / (2.0 * d);
        const double want = double(ri) * ri - x * x;
        const float got = crossingRadius2(delta, ri, rj);
        EXPECT_NEAR(got, want, 1e-5 * want) << ri << " " << rj << " " << delta;
        EXPECT_EQ(got, crossingRadius2(delta, rj, ri)) << "antisymmetry";
      }
  EXPECT_EQ(crossingRadius2(0.01f + 0.002f, 0.01f, 0.002f), 0.0f) << "the small sphere inside the large one";
  EXPECT_EQ(crossingRadius2(0.02f, 0.01f, 0.01f), 0.0f) << "coincident centres";
  EXPECT_EQ(planeCrossingRadius2(0.025f, 0.01f), 0.0f) << "through the plane";
  EXPECT_NEAR(planeCrossingRadius2(0.001f, 0.01f), 0.001 * 0.019, 1e-12);
}

class CohesionTest : public ::testing::TestWithParam<Backend> {};

// The normal force of each contact at rest against the law in double; at vanishing overlap dmt's
// tension is the pull-off force 2 π γ R*. The pair's overlap is the one the step computed (the
// capture's), the ground's r − z is exact; the wall's depth carries the rounding of x − 0.1 in
// float, allowed for through the law's slope.
TEST_P(CohesionTest, NormalForceIsTheLawsOnSpheresGroundAndWalls) {
  TUMBLE_NEED_BACKEND(GetParam());
  for (const Case& c : kCases)
    for (const double frac : {2e-3, 2e-2, 1e-6}) {
      const std::string at = c.name() + ", overlap " + std::to_string(frac) + " r";
      const Scene scene = parseScene(restingScene(c, frac), at);
      const World w = World::fromScene(scene);
      auto p = makePipeline(GetParam());
      p->load(w);
      p->setDebugCapture(true);
      std::vector<float> x;
      p->readLocalPositions(x);
      ASSERT_FALSE(p->frame().active());
      p->step(1);
      ParticleDebug d;
      p->readDebug(d);
      const auto pos = [&](int i, int a) { return double(x[3 * i + a]); };
      const auto rad = [&](int i) { return double(w.radius[i]); };
      // Two spheres, materials m and w.
      ASSERT_EQ(d.contactForces.size(), 1u) << at;
      const double ra = rad(0), rb = rad(1), dab = d.contactForces[0].overlap, reff = ra * rb / (ra + rb);
      const double elastic = c.hertz ? 4.0 / 3.0 * ystar(kE1, kNu1, kE2, kNu2) * std::sqrt(reff) * std::pow(dab, 1.5)
                                     : kKn * dab;
      const double mixed = c.hertz ? std::sqrt(c.sphere() * c.wall()) : c.sphere();
      const double pull = pullOf(c, mixed, dab, ra, rb);
      const double fn = d.contactForces[0].fn;
      EXPECT_NEAR(fn, elastic - pull, 2e-5 * (elastic + pull)) << at << ": two spheres, elastic " << elastic
                                                                << ", attraction " << pull;
      // The ground (its override), then the wall (its material's or its own coefficient).
      const double dc = rad(2) - pos(2, 2), dd = rad(3) - (0.1 - pos(3, 0));
      const double gElastic = c.hertz ? 4.0 / 3.0 * ystar(kE1, kNu1, 0.0, 0.0) * std::sqrt(rad(2)) * std::pow(dc, 1.5)
                                      : kKground * dc;
      const double gPull = pullOf(c, c.ground(), dc, rad(2), 0.0);
      EXPECT_NEAR(d.force[3][3 * 2 + 2], gElastic - gPull, 2e-5 * (gElastic + gPull)) << at << ": the ground";
      const auto wallForce = [&](double delta) {
        const double elastic = c.hertz ? 4.0 / 3.0 * ystar(kE1, kNu1, kE2, kNu2) * std::sqrt(rad(3)) * std::pow(delta, 1.5)
                                       : kKwall * delta;
        return elastic - pullOf(c, c.hertz ? std::sqrt(c.sphere() * c.wall()) : c.wall(), delta, rad(3), 0.0);
      };
      const double ulp = 0.1 * 1.2e-7, slope = std::fabs(wallForce(dd + ulp) - wallForce(dd - ulp)) / (2.0 * ulp);
      if (frac > 1e-4) {  // (a depth of 1e-6 r is below the resolution of x near the wall)
        EXPECT_NEAR(-d.force[3][3 * 3 + 0], wallForce(dd), 2e-5 * std::fabs(wallForce(dd)) + 2.0 * ulp * slope)
            << at << ": the wall";
      }
      if (c.model == Cohesion::Dmt && frac < 1e-4) {  // the pull-off force: the tension as the overlap vanishes
        // (1e-6 r: the spring's part is below 1 %, hooke-history's k_n δ the largest)
        EXPECT_NEAR(-fn, 2.0 * kPi * mixed * reff, 1e-2 * 2.0 * kPi * mixed * reff) << at;
        EXPECT_NEAR(-d.force[3][3 * 2 + 2], 2.0 * kPi * c.ground() * rad(2), 1e-2 * 2.0 * kPi * c.ground() * rad(2)) << at;
      }
    }
}

// The overlap at which a sphere of radius r and mass m rests on the ground under gravity g with
// the ground's coefficient `value`: F_spring(δ) = m g + F_c(δ), by bisection in double.
double restingOverlap(const Case& c, double value, double m, double r, double g) {
  const auto spring = [&](double delta) {
    return c.hertz ? 4.0 / 3.0 * ystar(kE1, kNu1, 0.0, 0.0) * std::sqrt(r) * std::pow(delta, 1.5) : kKground * delta;
  };
  double lo = 0.0, hi = r;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (spring(mid) - m * g - pullOf(c, value, mid, r, 0.0) > 0.0 ? hi : lo) = mid;
  }
  return lo;
}

// A sphere dropped onto the ground comes to rest where the spring carries its weight and the
// attraction: F_spring(δ) = m g + F_c(δ), solved by bisection in double. The ground is at −r so
// that the sphere's centre comes to rest near z = 0, where its float position resolves the
// slowest motion (a centre at z = r = 2 mm moves by no less than 1.2e-10 m a step: a sphere
// slower than that freezes, its dashpot holding part of the load, 1.5e-3 of the overlap off).
TEST_P(CohesionTest, SettlesAtTheEquilibriumOverlap) {
  TUMBLE_NEED_BACKEND(GetParam());
  for (const Case& c : kCases) {
    const double r = 0.002, g = 9.81;
    std::string text = "[scene]\nname = \"cohesion-rest\"\ndt = DT\nsteps = 40000\ngravity = [0, 0, -9.81]\n" + lawText(c) +
                       "[[shape]]\nname = \"s\"\n[[shape.sphere]]\nradius = 0.002\nmaterial = \"m\"\n"
                       "[[body]]\nshape = \"s\"\nposition = [0, 0, 0.00001]\n";
    replaceAll(text, "height = 0.0", "height = -0.002");
    replaceAll(text, "restitution = 0.5", "restitution = 0.2");
    if (!c.hertz) replaceAll(text, "gamma_n = 0", "gamma_n = 400");
    replaceAll(text, "DT", c.hertz ? "2e-6" : "2e-5");
    const Scene scene = parseScene(text, c.name() + ", resting");
    const World w = World::fromScene(scene);
    const double m = w.bodyMass[0];
    const double lo = restingOverlap(c, c.ground(), m, r, g);
    const auto spring = [&](double delta) {
      return c.hertz ? 4.0 / 3.0 * ystar(kE1, kNu1, 0.0, 0.0) * std::sqrt(r) * std::pow(delta, 1.5) : kKground * delta;
    };
    auto p = makePipeline(GetParam());
    p->load(w);
    p->step(scene.steps);
    BodyState s;
    p->readState(s);
    const double overlap = -double(s.pz[0]);
    std::printf("%s: resting overlap %.6g m, equilibrium %.6g m (without cohesion %.3g m)\n", c.name().c_str(), overlap,
                lo, c.hertz ? std::pow(m * g / spring(1.0), 2.0 / 3.0) : m * g / kKground);
    EXPECT_NEAR(overlap, lo, 1e-3 * lo) << c.name();
  }
}

// Elastic collisions (no damping) of two spheres and of a sphere with the ground: the energy with
// the cohesive potential stays constant through the contact (the guard's time series, which must
// not trip), and each rebounds at its speed; with the attraction at work inside the contact the
// overlap is deeper than without.
TEST_P(CohesionTest, ElasticCollisionsConserveTheEnergyWithTheCohesivePotential) {
  TUMBLE_NEED_BACKEND(GetParam());
  for (const Case& c : kCases) {
    std::string text = "[scene]\nname = \"cohesion-elastic\"\ndt = DT\nsteps = 1\ngravity = [0, 0, 0]\n" + lawText(c) +
                       "[[shape]]\nname = \"s\"\n[[shape.sphere]]\nradius = 0.002\nmaterial = \"m\"\n"
                       "[[body]]\nshape = \"s\"\nposition = [-0.00201, 0, 0.01]\nvelocity = [0.05, 0, 0]\n"
                       "[[body]]\nshape = \"s\"\nposition = [0.00201, 0, 0.01]\nvelocity = [-0.05, 0, 0]\n"
                       "[[body]]\nshape = \"s\"\nposition = [0.02, 0, 0.00201]\nvelocity = [0, 0, -0.05]\n";
    replaceAll(text, "restitution = 0.5", "restitution = 1");
    replaceAll(text, "DT", "1e-6");
    if (!c.hertz) replaceAll(text, "material = \"m\"\n[[body]]", "material = \"m\"\nelasticity = 1.0\n[[body]]");
    const Scene scene = parseScene(text, c.name() + ", elastic");
    const World w = World::fromScene(scene);
    auto p = makePipeline(GetParam());
    p->load(w);
    RunGuard guard(w, *p);
    const ThermoSample s0 = guard.sample();
    double worst = 0.0, peak = 0.0, deepest = 0.0;
    const int steps = 6000;
    for (int k = 0; k < steps / 10; ++k) {
      p->step(10);
      ASSERT_FALSE(guard.check(*p)) << c.name() << ": the guard tripped at step " << 10 * (k + 1);
      const ThermoSample& s = guard.sample();
      worst = std::max(worst, std::fabs(s.energy() - s0.energy()));
      peak = std::max(peak, s.kineticTranslation + s.kineticRotation);
      deepest = std::max(deepest, s.maxOverlap * 0.002);
    }
    BodyState st;
    p->readState(st);
    std::printf("%s: energy %.6g J, largest change %.3g J, kinetic energy up to %.3g J; speeds after %.6g %.6g %.6g m/s\n",
                c.name().c_str(), s0.energy(), worst, peak, double(st.vx[0]), double(st.vx[1]), double(st.vz[2]));
    // The kinetic energy is of the velocities half a step off the positions (kick-drift): within a
    // contact the sum moves by about F v dt, 0.25 % of the kinetic energy here without cohesion.
    EXPECT_LT(worst, 5e-3 * peak) << c.name();
    // Without cohesion the deepest overlap of the pair (relative speed 0.1 m/s, m* = m / 2, R* = r / 2)
    // and of the sphere on the ground (0.05 m/s, m, r): Hertz's (15 m* v^2 / (16 Y* sqrt(R*)))^(2/5)
    // or Hooke's v sqrt(m* / k).
    const double m = w.bodyMass[0], r = 0.002;
    const double dry =
        c.hertz ? std::max(std::pow(15.0 * 0.5 * m * 0.01 / (16.0 * ystar(kE1, kNu1, kE1, kNu1) * std::sqrt(0.5 * r)), 0.4),
                           std::pow(15.0 * m * 0.0025 / (16.0 * ystar(kE1, kNu1, 0.0, 0.0) * std::sqrt(r)), 0.4))
                : std::max(0.1 * std::sqrt(0.5 * m / kKn), 0.05 * std::sqrt(m / kKground));
    std::printf("  deepest overlap %.4g m, %.4g m without cohesion\n", deepest, dry);
    EXPECT_GT(deepest, 1.01 * dry) << c.name() << ": the attraction pulls the surfaces deeper";
    EXPECT_NEAR(st.vx[0], -0.05, 2e-3 * 0.05) << c.name() << ": the pair's rebound";
    EXPECT_NEAR(st.vx[1], 0.05, 2e-3 * 0.05) << c.name();
    EXPECT_NEAR(st.vz[2], 0.05, 2e-3 * 0.05) << c.name() << ": the ground's rebound";
  }
}

// The load that caps friction and rolling resistance (docs/model.md#cohesion): the normal force
// without the attraction under sjkr, F_n + 2 F_c under dmt; on the ground that is m g + F_c and
// m g + 2 F_c for a sphere resting at its equilibrium overlap. A sphere set sliding there at
// v0 = 5 cm/s without spin decelerates at μ load / m until it rolls, then at μ_r load / (1.4 m)
// (the constant rolling torque μ_r r load); each rate is measured over a window of its phase and
// must be within 2 % (without cohesion the load would be m g: 2.7 and 2.5 times less here).
TEST_P(CohesionTest, FrictionAndRollingResistanceCarryTheShiftedLoad) {
  TUMBLE_NEED_BACKEND(GetParam());
  const double r = 0.002, g = 9.81, mu = 0.3, muR = 0.05, v0 = 0.05, dt = 1e-6;
  for (const Case& c : {Case{true, Cohesion::Sjkr}, Case{false, Cohesion::Dmt}}) {
    // The ground's own coefficient: a load of a few m g.
    const double value = c.model == Cohesion::Sjkr ? 5e4 : 0.05;
    std::string text = "[scene]\nname = \"cohesion-load\"\ndt = 1e-6\nsteps = 1\ngravity = [0, 0, -9.81]\n" + lawText(c) +
                       "[[shape]]\nname = \"s\"\n[[shape.sphere]]\nradius = 0.002\nmaterial = \"m\"\n";
    replaceAll(text, "height = 0.0", "height = -0.002\nfriction = 0.3\nrolling_friction = 0.05");
    char was[96], own[96];  // the ground's line, as lawText() writes it, and this test's
    std::snprintf(was, sizeof was, "%s = %.17g\n[[wall]]", c.key().c_str(), c.ground());
    std::snprintf(own, sizeof own, "%s = %.17g\n[[wall]]", c.key().c_str(), value);
    ASSERT_NE(text.find(was), std::string::npos);
    replaceAll(text, was, own);
    if (!c.hertz) replaceAll(text, "gamma_n = 0", "gamma_n = 400");
    World w = World::fromScene(parseScene(text + "[[body]]\nshape = \"s\"\nposition = [0, 0, 0]\n", c.name() + ", load"));
    const double m = w.bodyMass[0], delta = restingOverlap(c, value, m, r, g);
    const double fc = pullOf(c, value, delta, r, 0.0);
    const double load = m * g + (c.model == Cohesion::Sjkr ? fc : 2.0 * fc);
    char body[160];
    std::snprintf(body, sizeof body, "[[body]]\nshape = \"s\"\nposition = [0, 0, %.17g]\nvelocity = [%.17g, 0, 0]\n",
                  -delta, v0);
    w = World::fromScene(parseScene(text + body, c.name() + ", load"));
    auto p = makePipeline(GetParam());
    p->load(w);
    const double slide = mu * load / m, roll = muR * load / (1.4 * m);
    const auto speedAfter = [&](std::uint64_t steps) {
      p->step(steps - p->stepCount());
      BodyState s;
      p->readState(s);
      return double(s.vx[0]);
    };
    // Sliding ends at t = (2/7) v0 / slide; measured over [0.1, 0.6] of that.
    const double tSlide = 2.0 / 7.0 * v0 / slide;
    const std::uint64_t s1 = std::uint64_t(0.1 * tSlide / dt), s2 = std::uint64_t(0.6 * tSlide / dt);
    const double va = speedAfter(s1), vb = speedAfter(s2);
    const double measuredSlide = (va - vb) / (double(s2 - s1) * dt);
    // Rolling from 4 tSlide on (the tangential spring rings for a while after the sliding ends), over
    // 8 tSlide (the rolling lasts some 19).
    const std::uint64_t s3 = std::uint64_t(4.0 * tSlide / dt), s4 = s3 + std::uint64_t(8.0 * tSlide / dt);
    const double vc = speedAfter(s3), vd = speedAfter(s4);
    const double measuredRoll = (vc - vd) / (double(s4 - s3) * dt);
    std::printf("%s: load %.4g N (m g %.4g N, F_c %.4g N); sliding %.5g m/s^2 (expected %.5g), rolling %.5g (expected %.5g) "
                "from %.5g to %.5g m/s\n",
                c.name().c_str(), load, m * g, fc, measuredSlide, slide, measuredRoll, roll, vc, vd);
    EXPECT_NEAR(measuredSlide, slide, 0.02 * slide) << c.name() << ": friction's load";
    EXPECT_NEAR(measuredRoll, roll, 0.02 * roll) << c.name() << ": rolling resistance's load";
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, CohesionTest, ::testing::ValuesIn(compiledBackends()), tumble_test::backendName);

}  // namespace
