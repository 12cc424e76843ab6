// SPDX-License-Identifier: MIT
// Plane walls (issue 12): the ground as a wall gives the ground's bits under every law; a box
// holds its spheres for any thread count, numbering and skin, and resumes from a checkpoint;
// a ball rolls down an inclined wall at 5/7 g sin θ; a sphere bounces off a wall at an angle
// with the restitution of its elasticity; a box turned to a general orientation (the general
// frame of wall.hpp) gives the aligned box's trajectory turned.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/math.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

WallDef plane(Vec3f point, Vec3f normal, const GroundParams& contact) {
  WallDef w;
  w.point = point;
  w.normal = normal;
  w.contact = contact;
  w.contact.enabled = true;
  return w;
}

// benchScene(n) without its ground, in a closed box of six walls with the ground's parameters
// around the lattice (its floor where the ground was).
Scene boxed(Scene s) {
  const GroundParams g = s.ground;
  s.ground.enabled = false;
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (const BodyDef& b : s.bodies) {
    const float p[3] = {b.position.x, b.position.y, b.position.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
  const float reach = static_cast<float>(shapeExtent(s.shapes[0])) + 0.05f;
  for (int a = 0; a < 3; ++a) {
    float p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    p[a] = a == 2 ? g.height : lo[a] - reach;
    n[a] = 1.0f;
    s.walls.push_back(plane(Vec3f{p[0], p[1], p[2]}, Vec3f{n[0], n[1], n[2]}, g));
    p[a] = hi[a] + reach + (a == 2 ? 2.0f : 0.0f);
    n[a] = -1.0f;
    s.walls.push_back(plane(Vec3f{p[0], p[1], p[2]}, Vec3f{n[0], n[1], n[2]}, g));
  }
  return s;
}

}  // namespace

// The ground and the wall through (0, 0, h) with normal +z and the ground's parameters are the
// same plane: the same bits, under the three laws, with clumps falling and piling on it.
TEST(WallTest, TheGroundAsAWallIsTheGround) {
  const Scene base = benchScene(2000);
  for (int law = 0; law < 3; ++law) {
    Scene s = law == 0 ? base : law == 1 ? withHookeHistory(base) : withHertzMindlin(base, 1.0e6f, true);
    s.ground.height = 0.125f;
    SCOPED_TRACE(toString(s.contact.law));
    const BodyState ground = runCpu(World::fromScene(s), 1600);
    Scene w = s;
    w.ground.enabled = false;
    w.walls = {plane(Vec3f{3.0f, -2.0f, s.ground.height}, Vec3f{0.0f, 0.0f, 1.0f}, s.ground)};
    const BodyState wall = runCpu(World::fromScene(w), 1600);
    std::size_t held = 0;
    for (std::size_t i = 0; i < ground.groundSpringX.size(); ++i)
      held += ground.groundSpringX[i] != 0.0f || ground.groundSpringY[i] != 0.0f;
    std::printf("%s: %zu of %zu particles held by the plane's stick spring at step 1600\n", toString(s.contact.law), held,
                ground.groundSpringX.size());
    EXPECT_GT(held, 0u) << "the clumps reached the plane";
    const auto d = firstDifference(ground, wall);
    EXPECT_FALSE(d.has_value()) << d->describe();
  }
}

// Clumps thrown about in a closed box: none leaves it; the run is the same bits for 1 and 2
// threads, without the renumbering and with skin 0; 300 steps straight equal 150, a
// checkpoint, a resume and 150 (the walls' stick springs carry).
TEST(WallTest, ABoxHoldsItsClumpsAndResumes) {
  for (const bool hooke : {false, true}) {
    Scene s = boxed(benchScene(2000));
    if (hooke) s = withHookeHistory(s);
    SCOPED_TRACE(toString(s.contact.law));
    for (BodyDef& b : s.bodies) b.velocity = Vec3f{8.0f * b.velocity.x, 8.0f * b.velocity.y, 8.0f * b.velocity.z};
    const World w = World::fromScene(s);
    const BodyState a = runCpu(w, 300, PipelineOptions{2, true});
    const BodyState one = runCpu(w, 300, PipelineOptions{1, false});
    Scene s0 = s;
    s0.broadphase.skin = 0.0f;
    const BodyState noSkin = runCpu(World::fromScene(s0), 300);
    for (const BodyState* o : {&one, &noSkin}) {
      const auto d = firstDifference(a, *o);
      EXPECT_FALSE(d.has_value()) << d->describe();
    }
    std::size_t held = 0;
    for (float x : a.groundSpringX) held += x != 0.0f;
    EXPECT_GT(held, 50u) << "some walls hold some spheres at step 300";
    ASSERT_EQ(a.groundSpringX.size(), 6 * w.numParticles());

    const std::string path = "/tmp/tumble_wall_test_" + std::to_string(::getpid()) + ".ck";
    {
      auto p = makePipeline(Backend::Cpu);
      p->load(w);
      p->step(150);
      Checkpoint::of(w, *p).write(path);
    }
    std::string warning;
    const World w2 = Checkpoint::read(path).resume(w, &warning);
    std::remove(path.c_str());
    EXPECT_TRUE(warning.empty()) << warning;
    auto p = makePipeline(Backend::Cpu);
    p->load(w2);
    p->step(150);
    BodyState resumed;
    p->readState(resumed);
    const auto d = firstDifference(a, resumed);
    EXPECT_FALSE(d.has_value()) << "resumed: " << d->describe();

    // None left the box: every centre inside it, at most a small overlap with a wall.
    const World end = [&] {
      World e = w;
      e.state = a;
      return e;
    }();
    auto q = makePipeline(Backend::Cpu);
    q->load(end);
    std::vector<float> x;
    q->readLocalPositions(x);
    double worst = 0.0;
    for (std::uint32_t i = 0; i < w.numParticles(); ++i)
      for (const WallDef& wall : s.walls) {
        const double d = (x[3 * i] - wall.point.x) * wall.normal.x + (x[3 * i + 1] - wall.point.y) * wall.normal.y +
                         (x[3 * i + 2] - wall.point.z) * wall.normal.z;
        worst = std::max(worst, (w.radius[i] - d) / w.radius[i]);
      }
    std::printf("%s: deepest overlap with a wall %.3f radii\n", toString(s.contact.law), worst);
    EXPECT_LT(worst, 0.5) << "a sphere went through a wall";
  }
}

// A ball set on a plane inclined at θ = 20° (a general normal) with μ = 0.5 > 2/7 tan θ rolls
// without slipping: its centre accelerates at 5/7 g sin θ down the slope and ω r = v.
TEST(WallTest, BallRollsDownAnInclinedWallAtFiveSevenths) {
  const double g = 9.81, r = 0.05, m = 0.1, k = 1.0e5, th = 20.0 * 3.14159265358979 / 180.0, T = 0.5;
  for (const ContactLaw law : {ContactLaw::HookeHistory, ContactLaw::HertzMindlin}) {
    SCOPED_TRACE(toString(law));
    Scene s;
    s.dt = 1e-4f;
    s.contact.law = law;
    s.ground.enabled = false;
    const GroundParams c = wallContact(float(k), 0.5f);
    const Vec3f n{float(std::sin(th)), 0.0f, float(std::cos(th))};  // the slope goes down along +x
    s.walls = {plane(Vec3f{0, 0, 0}, n, c)};
    s.shapes = {sphereShape(float(r), float(m), 0.5f)};
    double sink = m * g * std::cos(th) / k;
    if (law == ContactLaw::HertzMindlin) {
      s.materials = {MaterialDef{"soft", 0.0f, 1.0e7f, 0.3f, 0.5f, 0.5f, 0.0f}};
      sink = std::pow(m * g * std::cos(th) / (4.0 / 3.0 * 1.0e7 / (1.0 - 0.09) * std::sqrt(r)), 2.0 / 3.0);
    }
    BodyDef ball;
    ball.position = {float(n.x * (r - sink)), 0.0f, float(n.z * (r - sink))};
    s.bodies = {ball};
    auto p = makePipeline(Backend::Cpu);
    p->load(World::fromScene(s));
    p->step(static_cast<std::uint64_t>(T / s.dt));
    BodyState st;
    p->readState(st);
    const double down[3] = {std::cos(th), 0.0, -std::sin(th)};
    const double v = st.vx[0] * down[0] + st.vz[0] * down[2];
    const double want = 5.0 / 7.0 * g * std::sin(th) * T;
    const double omegaR = st.ly[0] / (0.4 * m * r * r) * r;
    const double off = st.px[0] * n.x + st.pz[0] * n.z - (r - sink);  // from the surface, in m
    std::printf("%s: v %.5f m/s vs 5/7 g sin(theta) t = %.5f; omega r %.5f; off the slope by %.2e m\n", toString(law),
                v, want, omegaR, off);
    EXPECT_NEAR(v, want, 0.005 * want);
    EXPECT_NEAR(omegaR, v, 0.005 * want) << "rolling: omega r = v";
    EXPECT_LT(std::abs(off), 0.05 * r) << "it stays on the slope";
  }
}

// A sphere hits a wall at 40° from its normal (gravity off, μ = 0): the normal velocity comes
// back times its elasticity e (the report's damping from e), the tangential one unchanged; on
// an aligned wall (normal −x) and on a general one.
TEST(WallTest, SphereBouncesOffAWallAtAnAngle) {
  const double e = 0.8, speed = 2.0, phi = 40.0 * 3.14159265358979 / 180.0;
  for (const double turn : {0.0, 0.7}) {
    const Vec3f n{float(-std::cos(turn)), float(-std::sin(turn)), 0.0f};  // the wall faces −x, turned about z
    const Vec3f t{-n.y, n.x, 0.0f};
    Scene s;
    s.dt = 1e-5f;
    s.gravity = {0, 0, 0};
    s.ground.enabled = false;
    const GroundParams c = wallContact(1.0e5f, 0.0f);
    s.walls = {plane(Vec3f{0, 0, 0}, n, c)};
    s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
    BodyDef b;
    b.position = {0.101f * n.x, 0.101f * n.y, 0.0f};  // 1 mm off the wall, on its side
    const double vn = -speed * std::cos(phi), vt = speed * std::sin(phi);  // towards the wall
    b.velocity = {float(vn * n.x + vt * t.x), float(vn * n.y + vt * t.y), 0.0f};
    s.bodies = {b};
    auto p = makePipeline(Backend::Cpu);
    p->load(World::fromScene(s));
    p->step(4000);
    BodyState st;
    p->readState(st);
    const double outN = st.vx[0] * n.x + st.vy[0] * n.y, outT = st.vx[0] * t.x + st.vy[0] * t.y;
    std::printf("turned %.1f rad: normal %.5f -> %.5f (e %.4f), tangential %.6f -> %.6f\n", turn, vn, outN, -outN / vn,
                vt, outT);
    EXPECT_NEAR(-outN / vn, e, 0.02 * e);
    EXPECT_NEAR(outT, vt, 1e-5 * speed) << "no friction: the tangential velocity stays";
    EXPECT_EQ(st.vz[0], 0.0f);
  }
}

// The same clump thrown into a box with friction, once with the box aligned and once with the
// whole scene turned by a rotation Q (every wall then a general plane): the turned trajectory
// is Q times the aligned one (float rounding apart).
TEST(WallTest, ATurnedBoxGivesTheTurnedTrajectory) {
  const double half = 0.3, an = std::sin(half) / std::sqrt(14.0);  // 0.6 rad about (1, 2, 3)
  const Quatf Q{float(std::cos(half)), float(an), float(2.0 * an), float(3.0 * an)};
  const Mat3f R = rotationMatrix(Q);
  const auto turn = [&](Vec3f v, bool on) { return on ? mul(R, v) : v; };
  BodyState st[2];
  for (int on = 0; on < 2; ++on) {
    Scene s;
    s.dt = 1e-4f;
    s.contact.law = ContactLaw::HookeHistory;
    s.gravity = turn(Vec3f{0, 0, -9.81f}, on);
    s.ground.enabled = false;
    s.shapes = {ShapeDef{"odd",
                         {SphereDef{{0, 0, 0}, 0.3f, 2.0f, 0.5f}, SphereDef{{0.5f, 0, 0}, 0.2f, 1.0f, 0.5f},
                          SphereDef{{0, 0.35f, 0.1f}, 0.15f, 0.5f, 0.5f}}}};
    const GroundParams c = wallContact(1.0e5f, 0.4f);
    for (int a = 0; a < 3; ++a)
      for (const float sgn : {1.0f, -1.0f}) {
        float p[3] = {0, 0, 0}, nv[3] = {0, 0, 0};
        p[a] = -1.5f * sgn;
        nv[a] = sgn;
        s.walls.push_back(plane(turn(Vec3f{p[0], p[1], p[2]}, on), turn(Vec3f{nv[0], nv[1], nv[2]}, on), c));
      }
    BodyDef b;
    b.position = turn(Vec3f{0.2f, -0.1f, 0.3f}, on);
    b.velocity = turn(Vec3f{3.0f, 1.5f, -2.0f}, on);
    b.angularVelocity = turn(Vec3f{2.0f, -5.0f, 1.0f}, on);
    if (on) b.orientation = Q;
    s.bodies = {b};
    auto p = makePipeline(Backend::Cpu);
    p->load(World::fromScene(s));
    p->step(6500);
    p->readState(st[on]);
  }
  const Vec3f x0{st[0].px[0], st[0].py[0], st[0].pz[0]}, v0{st[0].vx[0], st[0].vy[0], st[0].vz[0]};
  const Vec3f x1 = turn(x0, true), v1 = turn(v0, true);
  const double dx = std::hypot(x1.x - st[1].px[0], x1.y - st[1].py[0], x1.z - st[1].pz[0]);
  const double dv = std::hypot(v1.x - st[1].vx[0], v1.y - st[1].vy[0], v1.z - st[1].vz[0]);
  // Free flight for 0.65 s would end at (0.2 + 1.95, -0.1 + 0.975, 0.3 - 1.3 - 2.07): the walls
  // turned it (it hits the +x wall and the floor at about 0.33 s and slides). Each impact of the
  // clump multiplies the rounding differences of the turned scene by 5-10 (1e-5 m before the
  // first, 1.4e-3 m/s after the third at 0.7 s), so the comparison stops before that.
  const double flight = std::hypot(double(x0.x) - 2.15, double(x0.y) - 0.875, double(x0.z) + 3.07);
  std::printf("after 0.65 s: aligned at (%.4f, %.4f, %.4f), %.2f m from free flight; turned differs by %.2e m, "
              "%.2e m/s\n", x0.x, x0.y, x0.z, flight, dx, dv);
  EXPECT_GT(flight, 1.0) << "it met the walls";
  EXPECT_LT(std::max({std::abs(x0.x), std::abs(x0.y), std::abs(x0.z)}), 1.5f) << "inside the box";
  EXPECT_LT(dx, 1e-3);
  EXPECT_LT(dv, 1e-2);
}

// A general plane is held as x·n = h, h from its point in double: the same plane given by a
// point 1.25e5 m along it rolls the same ball to the same bits (with the point itself in the
// frame, x − p carried the rounding of 1e5 m and the ball hopped and gained energy: review).
// The shortest contact time counts the walls' stiffness; a sphere behind a wall is refused.
TEST(WallTest, APlaneIsTheSameWhereverItsPointIs) {
  BodyState st[3];
  const Vec3f points[3] = {{0.0f, 0.0f, 0.0f}, {1.0e4f, 0.0f, -7.5e3f}, {-1.0e5f, 0.0f, 7.5e4f}};
  for (int k = 0; k < 3; ++k) {
    Scene s;
    s.dt = 1e-4f;
    s.contact.law = ContactLaw::HookeHistory;
    s.ground.enabled = false;
    GroundParams c;
    c.stiffness = 1.0e5f;
    s.walls = {plane(points[k], Vec3f{3.0f, 0.0f, 4.0f}, c)};  // normalised to (0.6, 0, 0.8) at load
    s.shapes = {sphereShape(0.05f, 0.1f, 0.5f)};
    BodyDef b;
    b.position = {0.6f * 0.05f, 0.0f, 0.8f * 0.05f};
    b.velocity = {0.8f, 0.3f, -0.6f};
    s.bodies = {b};
    const World w = World::fromScene(s);
    st[k] = runCpu(w, 3000);
    if (k == 0) {
      EXPECT_NEAR(shortestContactTime(w), 3.14159265358979 * std::sqrt(0.1 / 1.0e5), 1e-9);
      s.walls[0].contact.stiffness = 1.0e9f;
      EXPECT_NEAR(shortestContactTime(World::fromScene(s)), 3.14159265358979 * std::sqrt(0.1 / 1.0e9), 1e-12)
          << "the stiffest wall sets the contact time";
    }
  }
  for (int k = 1; k < 3; ++k) {
    const auto d = firstDifference(st[0], st[k]);
    EXPECT_FALSE(d.has_value()) << "point " << k << ": " << d->describe();
  }
  EXPECT_GT(std::hypot(st[0].px[0], st[0].py[0]), 0.2) << "it travelled";

  {  // h beyond single precision is refused, not converted
    Scene far;
    far.ground.enabled = false;
    far.walls = {plane(Vec3f{3.0e38f, 3.0e38f, 0.0f}, Vec3f{1.0f, 1.0f, 0.0f}, GroundParams{})};
    far.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
    far.bodies = {BodyDef{}};
    try {
      (void)World::fromScene(far);
      ADD_FAILURE() << "a plane beyond single precision was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("beyond single precision"), std::string::npos) << e.what();
    }
  }
  Scene s;
  s.ground.enabled = false;
  GroundParams c;
  s.walls = {plane(Vec3f{1.0f, 0.0f, 0.0f}, Vec3f{-1.0f, 0.0f, 0.0f}, c)};
  s.walls[0].where = "[[wall]] #1 (test)";
  s.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
  BodyDef b;
  b.position = {5.0f, 0.0f, 0.0f};
  s.bodies = {BodyDef{}, b};
  try {
    (void)World::fromScene(s);
    ADD_FAILURE() << "a sphere behind a wall was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("[[wall]] #1 (test): body 1 has a sphere whose centre is 4 m behind the wall"),
              std::string::npos)
        << e.what();
  }
}

// A ball resting on a tilted plane 100 m up (a local frame), the plane given by a point 1e6 m
// along it: the guard sees the plane where the pipeline has it (both build it from the world's
// point and the frame). It stays quiet, and the spring energy it reports is the ball's rest
// overlap's, ½ (m g)² / k (review: the guard's plane was off by the rounding of p − o, and it
// tripped on a resting ball, "the energy grew").
TEST(WallTest, TheGuardSeesAFarTiltedPlaneWhereThePipelineHasIt) {
  const double g = 9.81, m = 0.1, k = 1.0e5, r = 0.05;
  Scene s;
  s.dt = 1e-4f;
  s.contact.law = ContactLaw::HookeHistory;
  s.ground.enabled = false;
  s.gravity = {float(-0.6 * g), 0.0f, float(-0.8 * g)};  // along −n
  GroundParams c;
  c.stiffness = float(k);
  s.walls = {plane(Vec3f{8.0e5f, 0.0f, -599875.0f}, Vec3f{3.0f, 0.0f, 4.0f}, c)};  // x·n = 100 m
  s.shapes = {sphereShape(float(r), float(m), 0.5f)};
  BodyDef b;
  const double sink = m * g / k, at = 100.0 + r - sink;
  b.position = {float(0.6 * at), 0.0f, float(0.8 * at)};
  s.bodies = {b};
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  ASSERT_TRUE(p->frame().active()) << "the scene is far from the origin: a local frame";
  RunGuard guard(w, *p);
  for (int n = 0; n < 40; ++n) {
    p->step(125);
    const auto t = guard.check(*p);
    ASSERT_FALSE(t.has_value()) << "step " << (n + 1) * 125 << ": " << t->message;
  }
  BodyState st;
  p->readState(st);
  std::printf("ball centre %.6f m above the plane (r - sink = %.6f), speed %.2e m/s\n",
              0.6 * st.px[0] + 0.8 * st.pz[0] - 100.0, r - sink, std::hypot(st.vx[0], st.vz[0]));
  const double want = 0.5 * m * m * g * g / k;
  std::printf("resting ball: springs %.3e J (1/2 (m g)^2 / k = %.3e), max overlap %.2e\n", guard.sample().springs, want,
              guard.sample().maxOverlap);
  EXPECT_NEAR(guard.sample().springs, want, 0.2 * want);
}

// Walls that move (WallDef::velocity with a part along the normal): a piston, a moving box.
// A wall moving at u meets a ball at rest as a wall at rest meets a ball thrown at −u: the
// ball leaves at (1 + e) u (its restitution e, the wall infinitely heavy). Checked for a plane
// (aligned and turned: the exact and the general frame), for a box moving as a whole and,
// in revolved_wall_test, for a moving cylinder.
TEST(WallTest, APistonThrowsABallAtOnePlusETimesItsSpeed) {
  const double e = 0.8, u = 1.5;
  for (const double turn : {0.0, 0.6}) {
    const Vec3f n{float(std::cos(turn)), float(std::sin(turn)), 0.0f};  // the piston faces +x, turned about z
    Scene s;
    s.dt = 1e-5f;
    s.gravity = {0, 0, 0};
    s.ground.enabled = false;
    const GroundParams c = wallContact(1.0e5f, 0.0f);
    WallDef w = plane(Vec3f{-0.2f * n.x, -0.2f * n.y, 0.0f}, n, c);
    w.velocity = {float(u * n.x), float(u * n.y), 0.0f};
    w.stop = 0.2;  // it stops after it has thrown the ball (0.1 m at 1.5 m/s: 0.067 s)
    s.walls = {w};
    s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
    s.bodies = {BodyDef{}};
    const World world = World::fromScene(s);
    const BodyState st = runCpu(world, 30000);  // 0.3 s
    const double out = st.vx[0] * n.x + st.vy[0] * n.y;
    std::printf("turned %.1f rad: ball at %.5f m/s, (1 + e) u = %.5f\n", turn, out, (1.0 + e) * u);
    EXPECT_NEAR(out, (1.0 + e) * u, 0.02 * (1.0 + e) * u);
    EXPECT_NEAR(st.vx[0] * n.y - st.vy[0] * n.x, 0.0, 1e-5) << "along the normal only";
    // The plane stopped at 0.2 s, 0.3 m further: the ball, at (1 + e) u, is well ahead of it.
    EXPECT_GT(st.px[0] * n.x + st.py[0] * n.y, 0.1 + 0.2 * u);
  }
}

// A ball resting on a floor that sinks at 0.5 m/s from t = 0.1 s to 0.5 s (a lift): it rides
// down with it and rests 0.2 m lower; the run resumed from a checkpoint taken while the floor
// moves gives the same bits, and the guard stays quiet (it skips the energy test while a wall
// moves, and poses the floor where the pipeline has it: with the floor where it was given, the
// ball would be 200 % of its radius into it).
TEST(WallTest, ALiftCarriesABallAndResumes) {
  Scene s;
  s.dt = 1e-4f;
  s.ground.enabled = false;
  const GroundParams c = wallContact(1.0e4f, 0.5f);
  WallDef floor = plane(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, c);
  floor.velocity = {0.0f, 0.0f, -0.5f};
  floor.start = 0.1;
  floor.stop = 0.5;
  s.walls = {floor};
  s.shapes = {sphereShape(0.1f, 1.0f, 0.5f)};
  BodyDef b;
  b.position = {0.0f, 0.0f, 0.1f - 9.81f / 1e4f};
  s.bodies = {b};
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  RunGuard guard(w, *p);
  BodyState st;
  p->step(4000);  // t = 0.4 s: rising for 0.3 s (the jolt at the start decays in about 0.05 s)
  p->readState(st);
  std::printf("at 0.4 s: z %.5f (floor at -0.15 m), vz %.4f\n", double(st.pz[0]), double(st.vz[0]));
  EXPECT_NEAR(st.vz[0], -0.5, 0.01) << "carried at the floor's speed";
  EXPECT_NEAR(st.pz[0], -0.15 + 0.1 - 9.81 / 1e4, 1e-3);
  for (int k = 0; k < 6; ++k) {
    p->step(1000);
    const auto trip = guard.check(*p);
    ASSERT_FALSE(trip.has_value()) << trip->message;
  }
  p->readState(st);  // t = 1.0 s
  std::printf("at 1.0 s: z %.5f (floor at -0.2 m), vz %.2e\n", double(st.pz[0]), double(st.vz[0]));
  EXPECT_NEAR(st.pz[0], -0.2 + 0.1 - 9.81 / 1e4, 1e-4) << "at rest on the lowered floor";
  EXPECT_NEAR(st.vz[0], 0.0, 1e-3);

  const BodyState straight = runCpu(w, 4000);
  const std::string path = "/tmp/tumble_lift_test_" + std::to_string(::getpid()) + ".ck";
  {
    auto q = makePipeline(Backend::Cpu);
    q->load(w);
    q->step(2000);  // t = 0.2 s: the floor moves
    Checkpoint::of(w, *q).write(path);
  }
  std::string warning;
  const World w2 = Checkpoint::read(path).resume(w, &warning);
  std::remove(path.c_str());
  const BodyState resumed = runCpu(w2, 2000);
  const auto d = firstDifference(straight, resumed);
  EXPECT_FALSE(d.has_value()) << d->describe();
}

// A closed box moving as a whole (each face with the box's velocity: the one it moves towards
// a piston, the ones along it belts) throws a ball at rest inside it at (1 + e) u, as a plane
// does; its side faces do not touch the ball.
TEST(WallTest, AMovingBoxThrowsABallAsAPlaneDoes) {
  const double e = 0.7, u = 1.0;
  Scene s;
  s.dt = 1e-5f;
  s.gravity = {0, 0, 0};
  s.ground.enabled = false;
  const GroundParams c = wallContact(1.0e5f, 0.0f);
  const float lo[3] = {-0.5f, -0.5f, -0.5f}, hi[3] = {0.5f, 0.5f, 0.5f};
  for (int a = 0; a < 3; ++a)
    for (const bool atMax : {false, true}) {
      float p[3] = {0, 0, 0}, nv[3] = {0, 0, 0};
      p[a] = atMax ? hi[a] : lo[a];
      nv[a] = atMax ? -1.0f : 1.0f;
      WallDef f = plane(Vec3f{p[0], p[1], p[2]}, Vec3f{nv[0], nv[1], nv[2]}, c);
      f.velocity = {float(u), 0.0f, 0.0f};
      f.stop = 0.5;
      s.walls.push_back(f);
    }
  s.shapes = {sphereShape(0.1f, 1.0f, float(e))};
  s.bodies = {BodyDef{}};
  const BodyState st = runCpu(World::fromScene(s), 45000);  // the -x face arrives at 0.4 s
  std::printf("box: ball at (%.5f, %.2e, %.2e) m/s, (1 + e) u = %.5f\n", double(st.vx[0]), double(st.vy[0]),
              double(st.vz[0]), (1.0 + e) * u);
  EXPECT_NEAR(st.vx[0], (1.0 + e) * u, 0.02 * (1.0 + e) * u);
  EXPECT_EQ(st.vy[0], 0.0f);
  EXPECT_EQ(st.vz[0], 0.0f);
}

// A sphere hitting a wall at 60 degrees from its normal with friction (hooke-history, mu = 0.2,
// e = 0.8), on an aligned and on a turned wall: in the sliding regime (the contact point slips
// throughout, since v_t / |v_n| = 1.73 > mu (1 + e) (1 + m r^2 / I) = 1.26) impulse theory gives
// the normal velocity -e v_n, the tangential one v_t - mu (1 + e) |v_n| and the spin
// (5/2) mu (1 + e) |v_n| / r about the axis n x t.
TEST(WallTest, ASphereSlidingOffAWallLosesMuOnePlusETimesItsNormalSpeed) {
  const double e = 0.8, mu = 0.2, speed = 2.0, phi = 60.0 * 3.14159265358979 / 180.0, r = 0.1;
  for (const double turn : {0.0, 0.7}) {
    const Vec3f n{float(-std::cos(turn)), float(-std::sin(turn)), 0.0f};
    const Vec3f t{-n.y, n.x, 0.0f};
    Scene s;
    s.dt = 1e-5f;
    s.gravity = {0, 0, 0};
    s.ground.enabled = false;
    s.contact.law = ContactLaw::HookeHistory;
    const GroundParams c = wallContact(1.0e5f, float(mu));
    s.walls = {plane(Vec3f{0, 0, 0}, n, c)};
    s.shapes = {sphereShape(float(r), 1.0f, float(e))};
    BodyDef b;
    b.position = {0.101f * n.x, 0.101f * n.y, 0.0f};
    const double vn = -speed * std::cos(phi), vt = speed * std::sin(phi);
    b.velocity = {float(vn * n.x + vt * t.x), float(vn * n.y + vt * t.y), 0.0f};
    s.bodies = {b};
    const BodyState st = runCpu(World::fromScene(s), 4000);
    const double outN = st.vx[0] * n.x + st.vy[0] * n.y, outT = st.vx[0] * t.x + st.vy[0] * t.y;
    const double spin = st.lz[0] / (0.4 * r * r);  // L = I omega, about z = n x t
    const double wantT = vt - mu * (1.0 + e) * std::abs(vn), wantSpin = 2.5 * mu * (1.0 + e) * std::abs(vn) / r;
    std::printf("turned %.1f rad: e %.4f, v_t %.5f (theory %.5f), spin %.4f (theory %.4f)\n", turn, -outN / vn, outT,
                wantT, spin, wantSpin);
    EXPECT_NEAR(-outN / vn, e, 0.02 * e);
    EXPECT_NEAR(outT, wantT, 0.03 * (vt - wantT)) << "the tangential velocity lost";
    EXPECT_NEAR(spin, wantSpin, 0.03 * wantSpin);
  }
}
