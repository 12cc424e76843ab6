// SPDX-License-Identifier: MIT
// Per-contact forces (issue 37, item 3: force chains): the contacts of a step with their forces
// (Pipeline::readDebug(), ParticleDebug::contactForces), checked against what the pipeline
// integrated and against the geometry of the step's positions, under each contact law, on every
// backend; and through a run's recording (RecordSettings::contactForces), whose frames must hold
// the same contacts and forces as the debug capture of every step.
//
// The oracle: the forces of each body's contacts (normal + tangential, +F on i, −F on j) summed
// in double equal the repulsion + damping + shear of the debug capture summed over the body's
// particles, within the float rounding of those sums; the pairs are Pipeline::pairs() (checked
// there against brute force); the normal part lies along x_i − x_j, the tangential part across
// it, and the overlap is r_i + r_j − |x_i − x_j| of the positions the step started from.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "tumble/factory.hpp"
#include "tumble/recording.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"
#include "tumble_test/cuda_gate.hpp"

using namespace tumble;

namespace {

// Dimers, trimers and balls of two sizes packed into a column that collapses onto a rough ground
// with a jitter in place and velocity (seed 11): contacts that slide, stick and roll from the
// first steps. LAW is replaced by each law's [contact] section.
const char* kScene = R"(
[scene]
name = "contact-forces"
dt = 2e-5
steps = 400
seed = 11
gravity = [0, 0, -9.81]
LAW
[ground]
height = 0.0
friction = 0.6
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.010
mass = 0.010
elasticity = 0.4
[[shape]]
name = "dimer"
[[shape.sphere]]
radius = 0.008
offset = [-0.005, 0, 0]
mass = 0.006
elasticity = 0.4
[[shape.sphere]]
radius = 0.008
offset = [0.005, 0, 0]
mass = 0.006
elasticity = 0.4
[[shape]]
name = "trimer"
[[shape.sphere]]
radius = 0.007
offset = [0, 0, 0]
mass = 0.004
elasticity = 0.4
[[shape.sphere]]
radius = 0.007
offset = [0.006, 0.003, 0]
mass = 0.004
elasticity = 0.4
[[shape.sphere]]
radius = 0.007
offset = [0, 0.007, 0.002]
mass = 0.004
elasticity = 0.4
[[group]]
shapes = ["ball", "dimer", "trimer"]
count = [5, 5, 6]
spacing = 0.0185
origin = [-0.037, -0.037, 0.011]
jitter = 0.002
velocity_jitter = 0.3
)";

struct Law {
  const char* name;
  const char* section;
};
const Law kLaws[] = {
    {"report", "[contact]\nstiffness = 4000.0\ndamping = 2.0\nshear = 1.0"},
    {"hooke-history",
     "[contact]\nlaw = \"hooke-history\"\nstiffness = 4000.0\ngamma_n = 50.0\nfriction = 0.5\nrolling_friction = 0.05"},
    {"hertz-mindlin",
     "[contact]\nlaw = \"hertz-mindlin\"\n[[material]]\nname = \"m\"\ndensity = 2500\nyoungs_modulus = 5e6\n"
     "poisson_ratio = 0.25\nrestitution = 0.4\nfriction = 0.5\nrolling_friction = 0.05"},
};

Scene sceneOf(const Law& law) {
  std::string text = kScene;
  text.replace(text.find("LAW"), 3, law.section);
  if (std::string(law.name) == "hertz-mindlin")  // the restitution is the material's
    for (std::size_t at; (at = text.find("elasticity = 0.4\n")) != std::string::npos;) text.erase(at, 17);
  return parseScene(text, std::string("contact forces, ") + law.name + " (contact_forces_test.cpp)");
}

double norm3(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// Checks the capture of the step just taken from positions `x0` (readLocalPositions() before it;
// the frame is inactive near the origin, so they are the world's) against the debug forces;
// returns the number of contacts.
std::size_t checkStep(const Pipeline& p, const World& w, const std::vector<float>& x0, const std::string& at) {
  ParticleDebug d;
  p.readDebug(d);
  const std::size_t n = w.numParticles(), nb = w.numBodies();
  EXPECT_EQ(d.contactForces.size(), d.contacts.size()) << at;
  if (d.contactForces.size() != d.contacts.size()) return 0;
  std::vector<double> particleSum(3 * n, 0.0), particleScale(n, 0.0);
  int geometryFailures = 0;
  for (std::size_t c = 0; c < d.contactForces.size(); ++c) {
    const ContactForce& k = d.contactForces[c];
    EXPECT_TRUE(k.i == d.contacts[c].i && k.j == d.contacts[c].j) << at << ": contact " << c << " is not pairs()'";
    const Vec3f normal = k.normal();
    const double f[3] = {double(normal.x) + k.tangential.x, double(normal.y) + k.tangential.y,
                         double(normal.z) + k.tangential.z};
    const double fn[3] = {normal.x, normal.y, normal.z}, ft[3] = {k.tangential.x, k.tangential.y, k.tangential.z};
    const double mag = norm3(fn) + norm3(ft);
    for (int a = 0; a < 3; ++a) {
      particleSum[3 * k.i + a] += f[a];
      particleSum[3 * k.j + a] -= f[a];
    }
    particleScale[k.i] += mag;
    particleScale[k.j] += mag;
    // Geometry: n from the step's start positions, in double.
    double dx[3];
    for (int a = 0; a < 3; ++a) dx[a] = double(x0[3 * k.i + a]) - x0[3 * k.j + a];
    const double dist = norm3(dx);
    const double n3[3] = {dx[0] / dist, dx[1] / dist, dx[2] / dist};
    const double cross[3] = {fn[1] * n3[2] - fn[2] * n3[1], fn[2] * n3[0] - fn[0] * n3[2], fn[0] * n3[1] - fn[1] * n3[0]};
    const double along = ft[0] * n3[0] + ft[1] * n3[1] + ft[2] * n3[2];
    const double overlap = double(w.radius[k.i]) + w.radius[k.j] - dist;
    // The unit normal along x_i − x_j, and the branch contactBranch() gives from it.
    const double nd[3] = {k.n.x - n3[0], k.n.y - n3[1], k.n.z - n3[2]};
    const std::array<double, 3> l = contactBranch(k, w.radius[k.i], w.radius[k.j]);
    const double ld[3] = {l[0] - dx[0], l[1] - dx[1], l[2] - dx[2]};
    const bool ok = norm3(cross) <= 1e-5 * mag + 1e-30 && std::fabs(along) <= 1e-5 * mag + 1e-30 &&
                    std::fabs(k.overlap - overlap) <= 2e-6 * w.radius[k.i] && k.overlap > -1e-6f * w.radius[k.i] &&
                    norm3(nd) <= 1e-6 && norm3(ld) <= 4e-6 * w.radius[k.i];
    if (!ok && ++geometryFailures <= 3)
      ADD_FAILURE() << at << ": contact (" << k.i << ", " << k.j << "): |normal x n| " << norm3(cross)
                    << ", tangential . n " << along << " (forces " << mag << "), overlap " << k.overlap << " vs "
                    << overlap;
  }
  // Per particle and per body: the contacts' forces against the repulsion + damping + shear the
  // pipeline added to the particle's force.
  std::vector<double> bodySum(3 * nb, 0.0), bodyDebug(3 * nb, 0.0), bodyScale(nb, 0.0);
  int sumFailures = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = w.body[i];
    for (int a = 0; a < 3; ++a) {
      const double dbg = double(d.force[0][3 * i + a]) + d.force[1][3 * i + a] + d.force[2][3 * i + a];
      if (std::fabs(particleSum[3 * i + a] - dbg) > 1e-5 * particleScale[i] + 1e-30 && ++sumFailures <= 3)
        ADD_FAILURE() << at << ": particle " << i << " axis " << a << ": its contacts sum to " << particleSum[3 * i + a]
                      << ", the step's contact force is " << dbg;
      bodySum[3 * b + a] += particleSum[3 * i + a];
      bodyDebug[3 * b + a] += dbg;
    }
    bodyScale[b] += particleScale[i];
  }
  for (std::size_t b = 0; b < nb; ++b)
    for (int a = 0; a < 3; ++a)
      if (std::fabs(bodySum[3 * b + a] - bodyDebug[3 * b + a]) > 1e-5 * bodyScale[b] + 1e-30 && ++sumFailures <= 6)
        ADD_FAILURE() << at << ": body " << b << " axis " << a << ": its contacts sum to " << bodySum[3 * b + a]
                      << ", the pipeline integrated " << bodyDebug[3 * b + a];
  return d.contactForces.size();
}

class ContactForcesTest : public ::testing::TestWithParam<Backend> {};

TEST_P(ContactForcesTest, SumToTheForcesTheStepIntegrated) {
  TUMBLE_NEED_BACKEND(GetParam());
  for (const Law& law : kLaws) {
    const Scene scene = sceneOf(law);
    std::printf("%s: seed 11 (kScene's jitter)\n", law.name);
    const World w = World::fromScene(scene);
    auto p = makePipeline(GetParam());
    p->load(w);
    ASSERT_FALSE(p->frame().active());
    p->setDebugCapture(true);
    std::vector<float> x0;
    std::size_t most = 0, checked = 0;
    for (int s = 1; s <= 300; ++s) {
      p->readLocalPositions(x0);
      p->step(1);
      if (s % 15 != 0 && s > 3) continue;
      most = std::max(most, checkStep(*p, w, x0, std::string(law.name) + ", step " + std::to_string(s)));
      ++checked;
      if (HasFailure()) return;
    }
    std::printf("%s: %zu steps checked, up to %zu contacts in one\n", law.name, checked, most);
    EXPECT_GT(most, 100u) << law.name << ": the column must press its grains together";
  }
}

// A recording with contact forces (only the step before each frame captured) holds, frame for
// frame, the contacts and forces of a debug recording that captures every step, bit for bit;
// its frames start after a step; and the debug one, with both blocks, passes the sums above.
TEST_P(ContactForcesTest, RecordingHoldsTheCapture) {
  TUMBLE_NEED_BACKEND(GetParam());
  const Scene scene = sceneOf(kLaws[1]);
  const std::string dir = ::testing::TempDir() + "contact_forces_" + toString(GetParam());
  std::filesystem::create_directories(dir);
  std::vector<Recording> recs;
  for (const bool debug : {false, true}) {
    tumble::Run run(scene);
    run.load(makePipeline(GetParam()));
    RecordSettings rs;
    rs.path = dir + (debug ? "/both.bin" : "/contacts.bin");
    rs.stepsPerFrame = 25;
    rs.debug = debug;
    rs.contactForces = true;
    run.record(rs);
    run.advance(200);
    run.closeRecording();
    recs.push_back(Recording::read(rs.path));
  }
  const Recording &only = recs[0], &both = recs[1];
  EXPECT_EQ(only.info.version, kRecordingVersion);
  EXPECT_TRUE(only.info.contactForces && !only.info.debug);
  ASSERT_EQ(only.frames.size(), 8u);  // steps 25 … 200: no frame at step 0
  ASSERT_EQ(both.frames.size(), only.frames.size());
  std::size_t total = 0;
  for (std::size_t k = 0; k < only.frames.size(); ++k) {
    const RecordedFrame &a = only.frames[k], &b = both.frames[k];
    EXPECT_EQ(a.step, 25 * (k + 1));
    EXPECT_EQ(a.step, b.step);
    EXPECT_EQ(a.px, b.px) << "frame " << k << ": the capture changed the trajectory";
    ASSERT_EQ(a.debug.contactForces.size(), b.debug.contactForces.size()) << "frame " << k;
    EXPECT_TRUE(a.debug.v.empty());
    for (std::size_t c = 0; c < a.debug.contactForces.size(); ++c) {
      const ContactForce &x = a.debug.contactForces[c], &y = b.debug.contactForces[c];
      EXPECT_TRUE(x.i == y.i && x.j == y.j && x.n.x == y.n.x && x.n.z == y.n.z && x.fn == y.fn &&
                  x.tangential.y == y.tangential.y && x.overlap == y.overlap)
          << "frame " << k << ", contact " << c;
    }
    total += a.debug.contactForces.size();
    // The debug frame's blocks against each other: per body, the recorded contact forces sum to
    // the recorded repulsion + damping + shear.
    std::vector<double> sum(3 * both.info.numBodies, 0.0), dbg(3 * both.info.numBodies, 0.0),
        scale(both.info.numBodies, 0.0);
    for (const ContactForce& x : b.debug.contactForces) {
      const Vec3f normal = x.normal();
      const float f[3] = {normal.x + x.tangential.x, normal.y + x.tangential.y, normal.z + x.tangential.z};
      const double mag = std::fabs(f[0]) + std::fabs(f[1]) + std::fabs(f[2]);
      for (int a = 0; a < 3; ++a) {
        sum[3 * both.body[x.i] + a] += f[a];
        sum[3 * both.body[x.j] + a] -= f[a];
      }
      scale[both.body[x.i]] += mag;
      scale[both.body[x.j]] += mag;
    }
    for (std::size_t i = 0; i < both.body.size(); ++i)
      for (int a = 0; a < 3; ++a)
        dbg[3 * both.body[i] + a] += double(b.debug.force[0][3 * i + a]) + b.debug.force[1][3 * i + a] +
                                     b.debug.force[2][3 * i + a];
    for (std::size_t body = 0; body < both.info.numBodies; ++body)
      for (int a = 0; a < 3; ++a)
        EXPECT_LE(std::fabs(sum[3 * body + a] - dbg[3 * body + a]), 1e-5 * scale[body] + 1e-30)
            << "frame " << k << ", body " << body << ", axis " << a;
  }
  EXPECT_GT(total, 500u);
  std::filesystem::remove_all(dir);
}

// Centres 1e-22 m apart: |d|² is a denormal float, and the capture's normal is still a unit
// vector, so that the recording the run writes reads back (a reviewer's case).
TEST_P(ContactForcesTest, NearlyCoincidentCentresRecordAUnitNormal) {
  TUMBLE_NEED_BACKEND(GetParam());
  const Scene scene = parseScene(
      "[scene]\ndt = 1e-4\nsteps = 4\ngravity = [0, 0, 0]\n[[shape]]\nname = \"b\"\n[[shape.sphere]]\nradius = 0.01\n"
      "mass = 0.01\n[[body]]\nshape = \"b\"\nposition = [0, 0, 0]\n[[body]]\nshape = \"b\"\nposition = [1e-22, 0, 0]\n",
      "near (contact_forces_test.cpp)");
  const std::string path = ::testing::TempDir() + "near_" + toString(GetParam()) + ".bin";
  {
    tumble::Run run(scene);
    run.load(makePipeline(GetParam()));
    RecordSettings rs;
    rs.path = path;
    rs.stepsPerFrame = 1;
    rs.contactForces = true;
    run.record(rs);
    run.advance(2);
    run.closeRecording();
  }
  const Recording r = Recording::read(path);
  ASSERT_EQ(r.frames.size(), 2u);
  ASSERT_EQ(r.frames[0].debug.contactForces.size(), 1u);
  const Vec3f n = r.frames[0].debug.contactForces[0].n;
  EXPECT_NEAR(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z, 1.0, 1e-6);
  std::filesystem::remove(path);
}

INSTANTIATE_TEST_SUITE_P(Backends, ContactForcesTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);

}  // namespace
