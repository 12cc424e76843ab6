// SPDX-License-Identifier: MIT
// Revolved walls (issue 12): cylinders, cones, disks and rings, and walls whose surface moves.
// The kernels' distance from a sphere centre to the surface equals a brute-force oracle (a
// dense search over the surface in double) on random points and on the hard cases (on a rim,
// on the axis, exactly touching, on the surface); a sphere bounces off the inside and the
// outside of a cylinder with its restitution; a ball rests on the rim of a hole narrower than
// itself at the height its geometry gives; a belt (a moving plane) carries a ball to 2/7 of its
// speed; a turning drum drags a ball at μ g while it slips, and stops turning at its stop time;
// a drum of clumps gives the same bits for any thread count, numbering and skin, and resumes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <unistd.h>

#include "tumble/checkpoint.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/wall.hpp"
#include "tumble/math.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The segment (0, r0)–(length, r1) about the axis from `point` along `axis` (length |axis|;
// for a disk or ring, `axis` is its normal and length 0).
WallDef revolved(Vec3f point, Vec3f axis, float length, float r0, float r1, const GroundParams& c) {
  WallDef w = revolvedWall(point, axis, length, r0, r1);
  w.contact = c;
  return w;
}
WallDef cylinder(Vec3f point, Vec3f axis, float r, const GroundParams& c) {
  return revolved(point, axis, std::sqrt(dot(axis, axis)), r, r, c);
}

// The oracle: the distance from x to the surface P(t, φ) = c + (s0 + t L) a + (r0 + t (r1 − r0))
// (cos φ u + sin φ v), t ∈ [0, 1], by a grid search refined four times about its best cell,
// in double, and the nearest point.
double oracleDistance(const Wall& w, const double x[3], double nearest[3]) {
  const double a[3] = {w.n.x, w.n.y, w.n.z}, u[3] = {w.t1.x, w.t1.y, w.t1.z}, v[3] = {w.t2.x, w.t2.y, w.t2.z};
  const double c[3] = {w.centre.x, w.centre.y, w.centre.z};
  const auto at = [&](double t, double phi, double p[3]) {
    const double rho = w.radius0 + t * (double(w.radius1) - w.radius0), s = w.start + t * double(w.length);
    for (int k = 0; k < 3; ++k) p[k] = c[k] + s * a[k] + rho * (std::cos(phi) * u[k] + std::sin(phi) * v[k]);
  };
  double best = 1e300, bt = 0.0, bp = 0.0;
  double t0 = 0.0, t1 = 1.0, p0 = 0.0, p1 = 2.0 * kPi;
  for (int round = 0; round < 5; ++round) {
    const int nt = round == 0 ? 200 : 60, np = round == 0 ? 720 : 60;
    const double dt = (t1 - t0) / nt, dp = (p1 - p0) / np;
    for (int i = 0; i <= nt; ++i)
      for (int j = 0; j <= np; ++j) {
        const double t = std::clamp(t0 + i * dt, 0.0, 1.0), phi = p0 + j * dp;
        double p[3];
        at(t, phi, p);
        const double d = std::hypot(x[0] - p[0], x[1] - p[1], x[2] - p[2]);
        if (d < best) best = d, bt = t, bp = phi;
      }
    t0 = bt - 2.0 * dt, t1 = bt + 2.0 * dt, p0 = bp - 2.0 * dp, p1 = bp + 2.0 * dp;
  }
  at(bt, bp, nearest);
  return best;
}

}  // namespace

// The kernels' distance and nearest point against the oracle, for a cylinder, a cone, a disk
// and a ring at general orientations, on random points around them (seed printed) and on the
// hard cases, whose values are exact.
TEST(RevolvedWallTest, DistanceMatchesABruteForceOracle) {
  const GroundParams c = wallContact(1e5f, 0.5f);
  const Vec3f axis{0.3f, -0.5f, 0.8f};
  Scene s;
  s.ground.enabled = false;
  s.walls = {cylinder(Vec3f{0.2f, 0.1f, -0.3f}, Vec3f{0.6f, -1.0f, 1.6f}, 0.7f, c),
             revolved(Vec3f{-0.1f, 0.4f, 0.0f}, axis, 1.5f, 0.1f, 0.9f, c),   // a hopper's cone
             revolved(Vec3f{0.0f, 0.0f, 0.5f}, axis, 0.0f, 0.0f, 0.8f, c),    // a disk
             revolved(Vec3f{0.3f, 0.0f, 0.0f}, axis, 0.0f, 0.25f, 0.8f, c)};  // a ring (a silo's orifice)
  const std::vector<Wall> walls = kernelWalls(s, LocalFrame{});
  // Fixed, as the other random tests (a random seed once found the frame drifting from unit
  // length near the axis, fixed by projecting twice; 40 random seeds pass since).
  const unsigned seed = 20261203;
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::printf("seed %u\n", seed);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-1.6, 1.6);
  double worst = 0.0, worstPoint = 0.0;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const Wall& w = walls[k];
    ASSERT_EQ(w.axis, kRevolvedWall);
    for (int n = 0; n < 60; ++n) {
      const Vec3f x{float(w.centre.x + coord(rng)), float(w.centre.y + coord(rng)), float(w.centre.z + coord(rng))};
      const double xd[3] = {x.x, x.y, x.z};
      double p[3];
      const double want = oracleDistance(w, xd, p);
      const RevolvedPoint got = revolvedContact(w, x);
      worst = std::max(worst, std::abs(double(got.dist) - want));
      EXPECT_NEAR(got.dist, want, 2e-6) << "wall " << k << " at (" << x.x << ", " << x.y << ", " << x.z << ")";
      // The nearest point x − dist n, where the oracle's is (both are unique off the axis).
      const Vec3f q{x.x - w.centre.x, x.y - w.centre.y, x.z - w.centre.z};
      const float along = dot(q, w.n);
      if (dot(q, q) - along * along > 1e-4f && want > 1e-3) {
        const double np = std::hypot(x.x - got.dist * got.frame.n.x - p[0], x.y - got.dist * got.frame.n.y - p[1],
                                     x.z - got.dist * got.frame.n.z - p[2]);
        worstPoint = std::max(worstPoint, np);
        EXPECT_LT(np, 1e-4) << "wall " << k << ": the nearest point";
      }
      // The contact frame is orthonormal and right-handed.
      const Wall& f = got.frame;
      EXPECT_NEAR(dot(f.n, f.n), 1.0f, 1e-6f);
      EXPECT_NEAR(dot(f.t1, f.t1), 1.0f, 1e-6f);
      EXPECT_NEAR(dot(f.t2, f.t2), 1.0f, 1e-6f);
      EXPECT_NEAR(dot(f.t1, f.n), 0.0f, 1e-6f);
      EXPECT_NEAR(dot(f.t2, f.n), 0.0f, 1e-6f);
      const Vec3f c3 = cross(f.t1, f.t2);
      EXPECT_NEAR(dot(c3, f.n), 1.0f, 1e-6f);
    }
  }
  std::printf("240 random points: largest |kernel - oracle| %.2e m in the distance, %.2e m in the nearest point\n",
              worst, worstPoint);

  // The hard cases, on a cylinder of radius 1 from z = 0 to z = 2 and a ring 0.5–1 at z = 0.
  Scene h;
  h.ground.enabled = false;
  h.walls = {cylinder(Vec3f{0, 0, 0}, Vec3f{0, 0, 2}, 1.0f, c), revolved(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0, 0.5f, 1.0f, c),
             revolved(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0, 0.0f, 1.0f, c)};
  const std::vector<Wall> hw = kernelWalls(h, LocalFrame{});
  {  // inside the cylinder, 0.5 from its side: a sphere of radius 0.5 exactly touches, and is not in contact
    const RevolvedPoint p = revolvedContact(hw[0], Vec3f{0.5f, 0.0f, 1.0f});
    EXPECT_EQ(p.dist, 0.5f);
    EXPECT_EQ(p.frame.n.x, -1.0f);
    EXPECT_FALSE(0.5f - p.dist > 0.0f) << "exactly touching is not a contact (as two spheres)";
    EXPECT_TRUE(0.5000001f - p.dist > 0.0f);
  }
  {  // beyond the top rim, diagonally: the rim point (1, 0, 2), once
    const RevolvedPoint p = revolvedContact(hw[0], Vec3f{2.0f, 0.0f, 3.0f});
    EXPECT_FLOAT_EQ(p.dist, std::sqrt(2.0f));
    EXPECT_FLOAT_EQ(p.frame.n.x, std::sqrt(0.5f));
    EXPECT_FLOAT_EQ(p.frame.n.z, std::sqrt(0.5f));
  }
  {  // on the cylinder's axis: every point of its side is as near; one of them
    const RevolvedPoint p = revolvedContact(hw[0], Vec3f{0.0f, 0.0f, 1.0f});
    EXPECT_EQ(p.dist, 1.0f);
    EXPECT_NEAR(dot(p.frame.n, p.frame.n), 1.0f, 1e-6f);
  }
  {  // on the ring's axis 0.3 above it: the inner rim at sqrt(0.3² + 0.5²); on the disk's, 0.3 straight down
    EXPECT_FLOAT_EQ(revolvedContact(hw[1], Vec3f{0.0f, 0.0f, 0.3f}).dist, std::sqrt(0.34f));
    const RevolvedPoint p = revolvedContact(hw[2], Vec3f{0.0f, 0.0f, 0.3f});
    EXPECT_FLOAT_EQ(p.dist, 0.3f);
    EXPECT_FLOAT_EQ(p.frame.n.z, 1.0f);
    EXPECT_FLOAT_EQ(revolvedContact(hw[2], Vec3f{0.0f, 0.0f, -0.3f}).frame.n.z, -1.0f) << "a disk has two sides";
  }
  {  // on the surface: distance 0 and the segment's normal, finite
    const RevolvedPoint p = revolvedContact(hw[0], Vec3f{0.0f, 1.0f, 1.0f});
    EXPECT_EQ(p.dist, 0.0f);
    EXPECT_TRUE(std::isfinite(p.frame.n.x) && std::isfinite(p.frame.n.y) && std::isfinite(p.frame.n.z));
    EXPECT_NEAR(std::abs(p.frame.n.y), 1.0f, 1e-6f);
  }
}

// A sphere thrown radially at the side of a cylinder (gravity and friction off), from inside
// and from outside: the radial velocity comes back times its elasticity e, the axial one stays.
TEST(RevolvedWallTest, ASphereBouncesOffACylinderFromEitherSide) {
  const double e = 0.8, speed = 2.0;
  for (const bool inside : {true, false}) {
    Scene s;
    s.dt = 1e-5f;
    s.gravity = {0, 0, 0};
    s.ground.enabled = false;
    s.walls = {cylinder(Vec3f{0, 0, -5}, Vec3f{0, 0, 10}, 1.0f, wallContact(1e5f, 0.0f))};
    s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
    BodyDef b;
    const Vec3f er{0.6f, 0.8f, 0.0f};
    const float at = inside ? 0.899f : 1.101f;  // 1 mm from the side
    b.position = {at * er.x, at * er.y, 0.0f};
    const float vr = inside ? float(speed) : -float(speed);
    b.velocity = {vr * er.x, vr * er.y, 0.5f};
    s.bodies = {b};
    const BodyState st = runCpu(World::fromScene(s), 4000);
    const double out = st.vx[0] * er.x + st.vy[0] * er.y;
    std::printf("%s: radial %.4f -> %.5f (e %.4f), axial %.6f\n", inside ? "inside" : "outside", double(vr), out,
                -out / vr, double(st.vz[0]));
    EXPECT_NEAR(-out / vr, e, 0.02 * e);
    EXPECT_FLOAT_EQ(st.vz[0], 0.5f) << "no friction: the axial velocity stays";
  }
}

// A ball of radius r set on the axis of a ring whose hole (radius a) is narrower than itself
// rests on the hole's rim: its centre settles where the rim point's normal spring (no friction)
// carries its weight,
// k δ h / d = m g with d = √(h² + a²) = r − δ (the geometry of a sphere on an edge).
TEST(RevolvedWallTest, ABallRestsOnTheRimOfAHole) {
  const double r = 0.1, a = 0.06, m = 0.1, g = 9.81, k = 1e5;
  double lo = 0.0, hi = r;  // solve k (r − d) h / d = m g for h by bisection
  for (int it = 0; it < 200; ++it) {
    const double h = 0.5 * (lo + hi), d = std::hypot(h, a);
    (k * (r - d) * h / d > m * g ? lo : hi) = h;
  }
  const double want = 0.5 * (lo + hi);
  Scene s;
  s.dt = 1e-5f;
  s.contact.law = ContactLaw::HookeHistory;
  s.ground.enabled = false;
  // Without friction: the stick spring along the rim's meridian would carry part of the weight.
  s.walls = {revolved(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.0f, float(a), 0.5f, wallContact(float(k), 0.0f))};
  s.shapes = {sphereShape(float(r), float(m), 0.3f)};
  BodyDef b;
  b.position = {0.0f, 0.0f, float(std::sqrt(r * r - a * a))};
  s.bodies = {b};
  const BodyState st = runCpu(World::fromScene(s), 40000);
  const double off = std::hypot(st.px[0], st.py[0]);
  std::printf("ball on a %.2f m hole: centre at %.6f m (the edge's equilibrium %.6f m), %.2e m off the axis, "
              "speed %.2e m/s\n", a, double(st.pz[0]), want, off, std::hypot(st.vx[0], st.vy[0], st.vz[0]));
  EXPECT_NEAR(st.pz[0], want, 0.02 * (std::sqrt(r * r - a * a) - want)) << "it rests on the rim";
  EXPECT_LT(off, 0.01 * r) << "centred on the hole";
}

// A ball set at rest on a belt (a plane whose surface moves at u along itself): friction μ m g
// speeds it up and spins it until it rolls, at t = 2u / (7 μ g) with v = 2u/7, and then it
// keeps that speed.
TEST(RevolvedWallTest, ABeltCarriesABallToTwoSevenths) {
  const double u = 1.0, mu = 0.3, g = 9.81, r = 0.05, m = 0.1, k = 1e5;
  for (const ContactLaw law : {ContactLaw::HookeHistory, ContactLaw::HertzMindlin}) {
    SCOPED_TRACE(toString(law));
    Scene s;
    s.dt = 1e-4f;
    s.contact.law = law;
    s.ground.enabled = false;
    WallDef belt;
    belt.contact = wallContact(float(k), float(mu));
    belt.velocity = {float(u), 0.0f, 0.0f};
    s.walls = {belt};
    s.shapes = {sphereShape(float(r), float(m), 0.5f)};
    if (law == ContactLaw::HertzMindlin) s.materials = {MaterialDef{"soft", 0.0f, 1.0e7f, 0.3f, 0.5f, float(mu), 0.0f}};
    BodyDef b;
    b.position = {0.0f, 0.0f, float(r) - 1e-5f};
    s.bodies = {b};
    const World w = World::fromScene(s);
    const double tRoll = 2.0 * u / (7.0 * mu * g);
    const BodyState half = runCpu(w, std::uint64_t(0.5 * tRoll / s.dt));
    const BodyState end = runCpu(w, std::uint64_t(3.0 * tRoll / s.dt));
    std::printf("%s: v at t_roll/2 %.4f m/s (mu g t = %.4f); at 3 t_roll %.5f m/s (2u/7 = %.5f), omega r %.5f\n",
                toString(law), double(half.vx[0]), mu * g * 0.5 * tRoll, double(end.vx[0]), 2.0 * u / 7.0,
                -double(end.ly[0]) / (0.4 * m * r * r) * r);
    EXPECT_NEAR(half.vx[0], mu * g * 0.5 * tRoll, 0.03 * mu * g * 0.5 * tRoll) << "slipping: a = mu g";
    EXPECT_NEAR(end.vx[0], 2.0 * u / 7.0, 0.01 * u) << "rolling on the belt";
    EXPECT_NEAR(double(end.vx[0]) - double(end.ly[0]) / (0.4 * m * r * r) * r, u, 0.01 * u)
        << "its bottom moves with the belt: v - omega_y r = u";
  }
}

// A ball at rest at the bottom of a horizontal drum (a cylinder along y) that turns at ω
// (angular_velocity, about +y): the drum's surface under it moves at −ω R x̂, and drags the
// ball at μ g while it slips. The drum stops at its stop time: up to it the run is the same
// bits as that of a drum that keeps turning, and after it not.
TEST(RevolvedWallTest, ATurningDrumDragsABallAndStopsOnTime) {
  const double R = 0.5, r = 0.05, m = 0.1, g = 9.81, mu = 0.4, omega = 4.0, k = 1e5;
  Scene s;
  s.dt = 1e-4f;
  s.contact.law = ContactLaw::HookeHistory;
  s.ground.enabled = false;
  WallDef drum = cylinder(Vec3f{0, -0.5f, 0}, Vec3f{0, 1.0f, 0}, float(R), wallContact(float(k), float(mu)));
  drum.angularVelocity = float(omega);
  s.walls = {drum};
  s.shapes = {sphereShape(float(r), float(m), 0.5f)};
  BodyDef b;
  b.position = {0.0f, 0.0f, float(-(R - r) + m * g / k)};
  s.bodies = {b};
  const DrumStop d = drumDragAndStop(s);
  std::printf("drum: v_x after 0.02 s %.5f m/s (-mu g t = %.5f)\n", d.earlyVx, -mu * g * 0.02);
  EXPECT_NEAR(d.earlyVx, -mu * g * 0.02, 0.05 * mu * g * 0.02) << "slipping (ω R = 2 m/s)";
  EXPECT_TRUE(d.sameBeforeTheStop) << "before the stop: " << d.before;
  EXPECT_TRUE(d.differentAfter) << "the drum stopped at 0.05 s";
  std::printf("at 0.15 s: v_x %.4f m/s turning, %.4f m/s stopped at 0.05 s\n", d.turningVx, d.stoppedVx);
}

// Clumps tumbling in a turning drum closed by two turning end disks (hooke-history): the same
// bits for 1 and 2 threads, without the renumbering and with skin 0; 1000 steps straight equal
// 500, a checkpoint, a resume and 500, across the drum's stop time (the springs and the
// motion carry); the guard stays quiet in a drum at rest.
TEST(RevolvedWallTest, ADrumOfClumpsIsTheSameForAnyThreadsSkinAndResume) {
  Scene s = withHookeHistory(benchScene(2000));
  s.ground.enabled = false;
  // The clumps on a 7 x 6 x 7 block (x, y, z) instead of the bench's flat layer, in a drum along y.
  const float reach = static_cast<float>(shapeExtent(s.shapes[0])) + 0.05f, step = 2.0f * reach;
  for (std::size_t k = 0; k < s.bodies.size(); ++k)
    s.bodies[k].position = Vec3f{step * float(k % 7), step * float((k / 7) % 6), step * float(k / 42)};
  const Vec3f c{3.0f * step, -reach, 3.0f * step};
  const float R = std::sqrt(18.0f) * step + reach, L = 5.0f * step + 2.0f * reach;
  const GroundParams g = wallContact(s.ground.stiffness, 0.5f);
  s.walls = {cylinder(c, Vec3f{0, L, 0}, R, g), revolved(c, Vec3f{0, 1, 0}, 0.0f, 0.0f, R, g),
             revolved(Vec3f{c.x, c.y + L, c.z}, Vec3f{0, 1, 0}, 0.0f, 0.0f, R, g)};
  for (WallDef& w : s.walls) w.angularVelocity = 3.0f, w.stop = 0.07;
  for (BodyDef& b : s.bodies) b.velocity = Vec3f{8.0f * b.velocity.x, 8.0f * b.velocity.y, 8.0f * b.velocity.z};
  const World w = World::fromScene(s);
  const BodyState a = runCpu(w, 1000, PipelineOptions{2, true});
  const BodyState one = runCpu(w, 1000, PipelineOptions{1, false});
  Scene s0 = s;
  s0.broadphase.skin = 0.0f;
  const BodyState noSkin = runCpu(World::fromScene(s0), 1000);
  for (const BodyState* o : {&one, &noSkin}) {
    const auto d = firstDifference(a, *o);
    EXPECT_FALSE(d.has_value()) << d->describe();
  }
  std::size_t held = 0;
  for (float x : a.groundSpringX) held += x != 0.0f;
  std::printf("drum of %u clumps: %zu wall springs held at step 1000\n", w.numBodies(), held);
  EXPECT_GT(held, 10u) << "the drum holds some spheres";
  ASSERT_EQ(a.groundSpringX.size(), 3 * w.numParticles());

  const std::string path = "/tmp/tumble_revolved_test_" + std::to_string(::getpid()) + ".ck";
  {
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    p->step(500);
    Checkpoint::of(w, *p).write(path);
  }
  std::string warning;
  const World w2 = Checkpoint::read(path).resume(w, &warning);
  std::remove(path.c_str());
  EXPECT_TRUE(warning.empty()) << warning;
  const BodyState resumed = runCpu(w2, 500);
  const auto d = firstDifference(a, resumed);
  EXPECT_FALSE(d.has_value()) << "resumed: " << d->describe();

  // At rest (no spin), the guard measures the drum's springs and finds no growth or deep overlap.
  Scene still = s;
  for (WallDef& x : still.walls) x.angularVelocity = 0.0f, x.stop = std::numeric_limits<double>::infinity();
  const World ws = World::fromScene(still);
  auto p = makePipeline(Backend::Cpu);
  p->load(ws);
  RunGuard guard(ws, *p);
  for (int n = 0; n < 8; ++n) {
    p->step(100);
    const auto t = guard.check(*p);
    ASSERT_FALSE(t.has_value()) << t->message;
  }
  EXPECT_GT(guard.sample().springs, 0.0) << "the guard sees the drum's springs";
}

// A long pipe is the same wherever its given point lies along its axis: the kernels measure from
// the axis's point nearest the frame's origin, and off the rims the distance does not read the
// position along the axis at all. A ball rolls and sways at the bottom of a horizontal pipe 30
// km long (hooke-history: its stick spring turns with the surface), the pipe given by a point 10
// km or 20 km behind the ball: the same bits. (Measured from the given point, the position
// along the axis, 1e4 m, had a rounding of 1 mm and the ball hopped.)
TEST(RevolvedWallTest, APipeIsTheSameWhereverItsPointIs) {
  const Vec3f axis{0.96f, 0.28f, 0.0f};  // unit length in float
  BodyState got[2];
  for (int k = 0; k < 2; ++k) {
    Scene s;
    s.dt = 1e-4f;
    s.ground.enabled = false;
    s.contact.law = ContactLaw::HookeHistory;
    s.contact.gammaN = 50.0f;
    const float back = k == 0 ? 1e4f : 2e4f;
    s.walls = {cylinder(Vec3f{-back * axis.x, -back * axis.y, 0.0f}, Vec3f{3e4f * axis.x, 3e4f * axis.y, 0.0f}, 0.3f,
                        wallContact(1e4f, 0.4f))};
    s.shapes = {sphereShape(0.05f, 0.1f, 0.5f)};
    BodyDef b;
    b.position = {0.0f, 0.0f, -0.25f};
    b.velocity = {0.3f, -0.6f, 0.0f};  // along and across the pipe: it climbs the side and rolls back
    s.bodies = {b};
    got[k] = runCpu(World::fromScene(s), 6000);
  }
  std::printf("ball at (%.4f, %.4f, %.4f) after 0.6 s\n", double(got[0].px[0]), double(got[0].py[0]),
              double(got[0].pz[0]));
  EXPECT_LT(got[0].pz[0], -0.2f) << "still in the pipe's lower half";
  EXPECT_GT(std::hypot(got[0].px[0], got[0].py[0]), 0.05f) << "it moved";
  const auto d = firstDifference(got[0], got[1]);
  EXPECT_FALSE(d.has_value()) << d->describe();
}

// On a disk's face the contact frame is the disk's own, fixed as a plane's: a ball sliding across
// a disk through a point 1 mm from its axis moves as it does on a plane wall in the same place
// (an azimuthal frame turned the stick spring by half a turn as the ball passed the axis, and
// the friction with it).
TEST(RevolvedWallTest, ADiskFaceIsAPlane) {
  BodyState got[2];
  for (int k = 0; k < 2; ++k) {
    Scene s;
    s.dt = 1e-5f;
    s.ground.enabled = false;
    s.contact.law = ContactLaw::HookeHistory;
    WallDef w = k == 0 ? revolved(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.0f, 0.0f, 1.0f, wallContact(1e4f, 0.3f))
                       : WallDef{};
    if (k == 1) {
      w.point = {0, 0, 0};
      w.normal = {0, 0, 1};
      w.contact = wallContact(1e4f, 0.3f);
    }
    s.walls = {w};
    s.shapes = {sphereShape(0.05f, 0.1f, 0.5f)};
    BodyDef b;
    b.position = {-0.03f, 0.001f, 0.05f - 0.1f * 9.81f / 1e4f};  // resting depth
    b.velocity = {1.0f, 0.0f, 0.0f};  // sliding: it rolls after 2 v0 / (7 mu g) = 0.097 s
    s.bodies = {b};
    got[k] = runCpu(World::fromScene(s), 8000);
  }
  std::printf("disk: x %.6f y %.3e vx %.6f; plane: x %.6f y %.3e vx %.6f\n", double(got[0].px[0]),
              double(got[0].py[0]), double(got[0].vx[0]), double(got[1].px[0]), double(got[1].py[0]),
              double(got[1].vx[0]));
  EXPECT_GT(got[1].px[0], 0.03f) << "it crossed the axis";
  EXPECT_NEAR(got[0].px[0], got[1].px[0], 1e-5);
  EXPECT_NEAR(got[0].py[0], got[1].py[0], 1e-5) << "no sideways kick at the axis";
  EXPECT_NEAR(got[0].vx[0], got[1].vx[0], 1e-4);
  EXPECT_NEAR(got[0].vy[0], got[1].vy[0], 1e-4);
}

// A cylinder moving across its axis (a pipe swept sideways) meets a ball at rest inside it as
// a plane does: the ball leaves at (1 + e) u.
TEST(RevolvedWallTest, AMovingCylinderThrowsABallAtOnePlusETimesItsSpeed) {
  const double e = 0.9, u = 0.8;
  Scene s;
  s.dt = 1e-5f;
  s.gravity = {0, 0, 0};
  s.ground.enabled = false;
  WallDef w = cylinder(Vec3f{0, 0, -1}, Vec3f{0, 0, 2}, 0.5f, wallContact(1e5f, 0.0f));
  w.velocity = {float(u * 0.6), float(u * 0.8), 0.0f};
  w.stop = 0.6;
  s.walls = {w};
  s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
  s.bodies = {BodyDef{}};
  const BodyState st = runCpu(World::fromScene(s), 70000);  // it arrives after 0.4 m, at 0.5 s
  const double along = st.vx[0] * 0.6 + st.vy[0] * 0.8;
  std::printf("ball at %.5f m/s along the motion, (1 + e) u = %.5f; across %.2e\n", along, (1.0 + e) * u,
              st.vx[0] * 0.8 - st.vy[0] * 0.6);
  EXPECT_NEAR(along, (1.0 + e) * u, 0.02 * (1.0 + e) * u);
  EXPECT_NEAR(st.vx[0] * 0.8 - st.vy[0] * 0.6, 0.0, 1e-5);
  EXPECT_EQ(st.vz[0], 0.0f);
}
