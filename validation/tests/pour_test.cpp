// SPDX-License-Identifier: MIT
// [[pour]] (issue 12): bodies enter a run at the pour's rate, in batches, each placed where it
// overlaps nothing; a body that finds no place waits, with those after it, for room. The run
// goes on from the pipeline's state bit for bit, so the bits do not depend on the thread count,
// the skin or the numbering, and a run checkpointed and resumed (at a batch step or between
// two) equals the one that never stopped.
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
#include "tumble/pour.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

// A silo (a cylinder on the ground) with a few balls at the bottom, and a pour of balls and
// dimers (scaled 0.8-1.2) from above at 500 per second, every 100 steps.
const char* kSilo = R"(
[scene]
dt = 5e-5
steps = 100
seed = 3
[contact]
law = "hooke-history"
stiffness = 2e4
gamma_n = 1500
friction = 0.5
[ground]
[[wall]]
type = "cylinder"
point = [0, 0, 0]
axis = [0, 0, 0.6]
radius = 0.1
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.01
mass = 0.0105
[[shape]]
name = "dimer"
[[shape.sphere]]
radius = 0.01
offset = [-0.006, 0, 0]
mass = 0.0105
[[shape.sphere]]
radius = 0.01
offset = [0.006, 0, 0]
mass = 0.0105
[[fill]]
shape = "ball"
count = 30
region = "cylinder"
point = [0, 0, 0]
axis = [0, 0, 0.1]
radius = 0.1
[[pour]]
shapes = ["ball", "dimer"]
count = 200
rate = 500
region = "cylinder"
point = [0, 0, 0.4]
axis = [0, 0, 0.15]
radius = 0.09
velocity = [0, 0, -1]
scale = [0.8, 1.2]
)";

}  // namespace

// Bodies enter at the pour's rate (those due by each batch step), none overlapping a particle
// already there (brute force over the positions they start from) or the silo's wall.
TEST(PourTest, BodiesEnterAtTheRateWithoutOverlap) {
  const Scene s = parseScene(kSilo, "silo.toml");
  ASSERT_EQ(s.pourBodies.size(), 200u);
  const Pouring pouring(s);
  ASSERT_EQ(pouring.initialBodies(), 30u);
  std::size_t batches = 0, worst = 0;
  pourRun(s, 9000, {}, [&](const World& w, const Pipeline& p, std::size_t before, double t) {
    ++batches;
    // Due by t: the bodies of index i with i / rate <= t (all of them have room here).
    std::size_t due = 0;
    while (due < 200 && double(due) / 500.0 <= t) ++due;
    EXPECT_EQ(w.numBodies(), 30 + due) << "at t = " << t;
    std::vector<float> x;
    p.readLocalPositions(x);
    for (std::uint32_t i = 0; i < w.numParticles(); ++i) {
      if (w.body[i] < before) continue;  // a new body's particle against every other body's
      for (std::uint32_t j = 0; j < w.numParticles(); ++j) {
        if (w.body[j] == w.body[i]) continue;
        const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
        const double gap = std::sqrt(dx * dx + dy * dy + dz * dz) - w.radius[i] - w.radius[j];
        if (gap < 0.0) ++worst;
      }
      EXPECT_LE(std::hypot(x[3 * i], x[3 * i + 1]) + w.radius[i], 0.09 + 1e-6) << "inside the pour's region";
    }
  });
  std::printf("%zu batches, %zu overlaps at entry\n", batches, worst);
  EXPECT_EQ(worst, 0u);
  EXPECT_EQ(batches, 81u) << "every 100 steps from step 0 until the 200 are in (0.4 s)";
}

// The same bits for any thread count, skin and numbering, and across a checkpoint taken at a
// batch step (the resumed run pours there first, as the straight one did) or between two.
TEST(PourTest, TheSameForAnyThreadsSkinAndResume) {
  const Scene s = parseScene(kSilo, "silo.toml");
  const PourRun a = pourRun(s, 6000);
  ASSERT_EQ(a.world.numBodies(), 178u) << "30, and 148 due by the last batch (t = 0.295 s)";
  Scene noSkin = s;
  noSkin.broadphase.skin = 0.0f;
  for (const PourRun& o : {pourRun(s, 6000, PipelineOptions{1, false}), pourRun(noSkin, 6000)}) {
    const auto d = firstDifference(a.state, o.state);
    EXPECT_FALSE(d.has_value()) << d->describe();
  }
  for (const std::uint64_t at : {std::uint64_t{300}, std::uint64_t{351}}) {
    const Pouring pouring(s);
    World w = pouring.worldWith(pouring.initialBodies());
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    pouring.step(*p, w, at, nullptr);
    const std::string path = "/tmp/tumble_pour_test_" + std::to_string(::getpid()) + ".ck";
    Checkpoint::of(w, *p).write(path);
    const Checkpoint ck = Checkpoint::read(path);
    std::remove(path.c_str());
    const PourRun resumed = pourRun(s, 6000, {}, {}, &ck);
    const auto d = firstDifference(a.state, resumed.state);
    EXPECT_FALSE(d.has_value()) << "resumed at step " << at << ": " << d->describe();
  }
}

// A pour into a region one body wide, with no gravity: a body enters only when the one before it
// has moved out of the way, so the bodies enter late but never overlap, and all of them do.
TEST(PourTest, ABodyWaitsForRoom) {
  Scene s = parseScene(R"(
[scene]
dt = 1e-4
steps = 10
gravity = [0, 0, 0]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.1
mass = 1
[[pour]]
shape = "ball"
count = 10
rate = 1000
interval = 0.001
region = "box"
min = [-0.11, -0.11, -0.1]
max = [0.11, 0.11, 0.14]
velocity = [0, 0, 2]
attempts = 10000
)", "queue.toml");
  std::vector<double> entered;
  const PourRun r = pourRun(s, 12000, {}, [&](const World& w, const Pipeline&, std::size_t before, double t) {
    EXPECT_EQ(w.numBodies(), before + 1) << "one at a time: the region holds one";
    entered.push_back(t);
  });
  ASSERT_EQ(r.world.numBodies(), 10u) << "all of them entered";
  // Each waits until the one before has risen about 0.2 m (0.08-0.1 s at 2 m/s), however early
  // it is due.
  for (std::size_t k = 1; k < entered.size(); ++k)
    EXPECT_GE(entered[k] - entered[k - 1], 0.08 - 1e-9) << "body " << k + 1;
  std::printf("the 10th entered at %.4f s (due at %.4f s)\n", entered.back(), 9 / 1000.0);
  for (std::size_t k = 1; k < r.state.size(); ++k) {
    const double dx = r.state.px[k - 1] - r.state.px[k], dy = r.state.py[k - 1] - r.state.py[k];
    const double dz = r.state.pz[k - 1] - r.state.pz[k];
    EXPECT_GE(std::sqrt(dx * dx + dy * dy + dz * dz), 0.2) << "bodies " << k << " and " << k + 1 << " apart";
  }
}

// Scene keys and errors; a scene whose bodies all come from a pour starting at t = 0.
TEST(PourTest, SceneKeysAndErrors) {
  const std::string head = "[scene]\ndt = 1e-4\nsteps = 10\n[[shape]]\nname = \"ball\"\n[[shape.sphere]]\nradius = 0.1\n"
                           "mass = 1\n";  // lines 1-8
  const std::string pour = "[[pour]]\nshape = \"ball\"\ncount = 5\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n";
  const Scene s = parseScene(head + pour + "rate = 100\nstart = 0.5\ninterval = 0.01\nattempts = 7\n", "p.toml");
  ASSERT_EQ(s.pours.size(), 1u);
  EXPECT_EQ(s.pours[0].rate, 100.0);
  EXPECT_EQ(s.pours[0].start, 0.5);
  EXPECT_EQ(s.pours[0].interval, 0.01);
  EXPECT_EQ(s.pours[0].attempts, 7u);
  ASSERT_EQ(s.pourBodies.size(), 5u);
  EXPECT_DOUBLE_EQ(s.pourBodies[4].time, 0.5 + 4 / 100.0);
  const auto expectError = [&](const std::string& text, long line, const std::string& needle) {
    try {
      (void)parseScene(text, "p.toml");
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectError(head + pour, 9, "missing required key 'rate'");
  expectError(head + pour + "rate = 0\n", 15, "rate must be > 0");
  expectError(head + pour + "rate = 1\nstart = -1\n", 16, "start must be >= 0");
  expectError(head + pour + "rate = 1\ninterval = 0\n", 16, "interval must be > 0");
  expectError(head + pour + "rate = 1\nspeed = 1\n", 16, "unknown key 'speed'");
  // A region no ball fits in poured nothing, without a word (issue 34, item 11).
  const std::string thin = "[[pour]]\nshape = \"ball\"\ncount = 5\nregion = \"box\"\nmin = [0, 0, 0]\nmax = [1, 1, 0.15]\n";
  expectError(head + thin + "rate = 1\n", 9,
              "its region is narrower than a sphere of shape 'ball' (radius 0.1 m, the region's half-width 0.075 m): "
              "no body could ever enter");
  const std::string narrow = "[[pour]]\nshape = \"ball\"\ncount = 5\nregion = \"cylinder\"\npoint = [0, 0, 0]\n"
                             "axis = [0, 0, 1]\nradius = 0.05\n";
  expectError(head + narrow + "rate = 1\n", 9, "the region's half-width 0.05 m");
  // Bodies only from the pour: it must start at 0, with room for the first.
  const Pouring now(parseScene(head + pour + "rate = 100\n", "p.toml"));
  EXPECT_EQ(now.worldWith(now.initialBodies()).numBodies(), 1u) << "the body due at t = 0";
  const Pouring late(parseScene(head + pour + "rate = 100\nstart = 0.5\n", "p.toml"));
  try {
    (void)late.worldWith(late.initialBodies());
    ADD_FAILURE() << "a run with no body at t = 0";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("none could enter at t = 0"), std::string::npos) << e.what();
  }
}

// A pour in a periodic box (a pour region wider than the box): every body enters with its
// centre in the box and apart from every particle through the nearest images.
TEST(PourTest, APeriodicPourKeepsClearAcrossTheBoundaries) {
  const Scene s = parseScene(R"(
[scene]
dt = 1e-4
steps = 10
[ground]
[periodic]
x = [-0.5, 0.5]
y = [-0.5, 0.5]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.05
mass = 0.1
[[pour]]
shape = "ball"
count = 150
rate = 3000
interval = 0.005
region = "box"
min = [-0.6, -0.6, 0.2]
max = [0.6, 0.6, 0.5]
velocity = [0, 0, -1]
)", "periodic-pour.toml");
  std::size_t overlaps = 0, near = 0;
  const PourRun r = pourRun(s, 3000, {}, [&](const World& w, const Pipeline& p, std::size_t before, double) {
    BodyState st;
    p.readLocalState(st);  // one step after the batch: the centres stay well inside at 1 m/s
    std::vector<float> x;
    p.readLocalPositions(x);
    for (std::size_t b = before; b < w.numBodies(); ++b) {
      EXPECT_GE(st.px[b], -0.5f);
      EXPECT_LT(st.px[b], 0.5f);
      EXPECT_GE(st.py[b], -0.5f);
      EXPECT_LT(st.py[b], 0.5f);
    }
    for (std::uint32_t i = 0; i < w.numParticles(); ++i) {
      if (w.body[i] < before) continue;
      for (std::uint32_t j = 0; j < w.numParticles(); ++j) {
        if (j == i) continue;
        double d[3] = {double(x[3 * i]) - x[3 * j], double(x[3 * i + 1]) - x[3 * j + 1],
                       double(x[3 * i + 2]) - x[3 * j + 2]};
        bool wrapped = false;
        for (int a = 0; a < 2; ++a)
          if (std::abs(d[a]) > 0.5) d[a] -= std::copysign(1.0, d[a]), wrapped = true;
        const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        overlaps += dist < 0.1 - 1e-3;  // a step of 1 m/s from apart: at most 0.1 mm closer
        near += wrapped && dist < 0.2;
      }
    }
  });
  std::printf("periodic pour: %u bodies, %zu near pairs across a boundary, %zu overlaps at entry\n",
              r.world.numBodies(), near, overlaps);
  EXPECT_EQ(r.world.numBodies(), 150u);
  EXPECT_EQ(overlaps, 0u);
  EXPECT_GT(near, 0u);
}
