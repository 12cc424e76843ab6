// SPDX-License-Identifier: MIT
// Checkpoint and resume (docs/checkpoint.md): a run stopped and continued equals the
// uninterrupted run bit for bit; the file is validated like any untrusted input.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <unistd.h>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/mesh.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/compare.hpp"
#include "tumble/validation/scenes.hpp"

using namespace tumble;
using namespace tumble::validation;

namespace {

class CheckpointTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "tumble_" + std::to_string(::getpid()) + "_" + name;
}

World scene(const std::string& file, RotationScheme scheme) {
  Scene s = readSceneFile(sourcePath(file));
  s.integrator.rotation = scheme;
  return World::fromScene(s);
}

BodyState straight(Backend b, const World& w, std::uint64_t steps) {
  auto p = makePipeline(b);
  p->load(w);
  p->step(steps);
  BodyState s;
  p->readState(s);
  return s;
}

/// `first` steps, a checkpoint through a file, a fresh pipeline resumed from it, `second` more.
BodyState resumed(Backend b, const World& w, std::uint64_t first, std::uint64_t second, Checkpoint* outCk = nullptr) {
  const std::string path = tempPath("resume.ck");
  {
    auto p = makePipeline(b);
    p->load(w);
    p->step(first);
    Checkpoint::of(w, *p).write(path);
  }
  const Checkpoint ck = Checkpoint::read(path);
  std::remove(path.c_str());
  if (outCk) *outCk = ck;
  std::string warning;
  const World w2 = ck.resume(w, &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  auto p = makePipeline(b);
  p->load(w2);
  EXPECT_EQ(p->stepCount(), first);
  p->step(second);
  EXPECT_EQ(p->stepCount(), first + second);
  BodyState s;
  p->readState(s);
  return s;
}

}  // namespace

TEST_P(CheckpointTest, ResumeEqualsTheUninterruptedRun) {
  for (const char* file : {"scenes/molecules.toml", "scenes/bench-16k.toml"}) {
    for (RotationScheme scheme : {RotationScheme::Report, RotationScheme::Splitting}) {
      SCOPED_TRACE(std::string(file) + ", rotation " + toString(scheme));
      const World w = scene(file, scheme);
      const BodyState a = straight(GetParam(), w, 300);
      Checkpoint ck;
      const BodyState b = resumed(GetParam(), w, 150, 150, &ck);
      const auto d = firstDifference(a, b);
      EXPECT_FALSE(d.has_value()) << "resumed run differs: " << d->describe();
      // The negative control: the ground springs carry the contact history; a resume that
      // dropped them would not give the same bits (so this test can fail).
      std::size_t springing = 0;
      for (float x : ck.state.groundSpringX) springing += x != 0.0f;
      if (springing > 0) {
        Checkpoint forgetful = ck;
        forgetful.state.groundSpringX.assign(forgetful.state.groundSpringX.size(), 0.0f);
        forgetful.state.groundSpringY.assign(forgetful.state.groundSpringY.size(), 0.0f);
        auto p = makePipeline(GetParam());
        p->load(forgetful.resume(w, nullptr));
        p->step(150);
        BodyState c;
        p->readState(c);
        EXPECT_TRUE(firstDifference(a, c).has_value()) << "without the ground springs the run must differ";
      }
      std::printf("%s, %s: resumed at 150 equals 300 straight; %zu particles held by a ground spring at the checkpoint\n",
                  file, toString(scheme), springing);
    }
  }
}

// The contact histories of hooke-history are part of the state: a resume carries them, and
// one that dropped them would differ (the negative control). At step 600 of molecules the
// checkpoint holds 91 (hertz-mindlin) and 67 (hooke-history) histories: the test needs more
// than 20, not a settled heap (CI runs it under TSan too, at about 30 times its Release time).
TEST_P(CheckpointTest, ResumeCarriesTheContactHistories) {
  const Scene molecules = readSceneFile(sourcePath("scenes/molecules.toml"));
  int lacked = 0;
  for (const ContactLaw law : {ContactLaw::HertzMindlin, ContactLaw::HookeHistory}) {
  SCOPED_TRACE(toString(law));
  if (const auto why = tumble_test::notSupported(GetParam(), modelProbe(law))) {
    std::printf("%s: NotSupported: %s\n", toString(law), why->c_str());
    ++lacked;
    continue;
  }
  const World w = World::fromScene(law == ContactLaw::HookeHistory ? withHookeHistory(molecules)
                                                                   : withHertzMindlin(molecules, 1.0e6f, true));
  constexpr std::uint64_t kHalf = 600;
  const BodyState a = straight(GetParam(), w, 2 * kHalf);
  Checkpoint ck;
  const BodyState b = resumed(GetParam(), w, kHalf, kHalf, &ck);
  const auto d = firstDifference(a, b);
  EXPECT_FALSE(d.has_value()) << "resumed run differs: " << d->describe();
  std::printf("molecules, %s: resumed at %llu equals %llu straight; %zu contact histories at the checkpoint\n",
              toString(law), static_cast<unsigned long long>(kHalf), static_cast<unsigned long long>(2 * kHalf),
              ck.state.contacts.size());
  ASSERT_GT(ck.state.contacts.size(), 20u);
  // A history naming a particle the scene lacks is refused at resume, wherever it sits in the list.
  Checkpoint alien = ck;
  alien.state.contacts.front().j = static_cast<std::uint32_t>(w.numParticles());
  EXPECT_THROW(alien.resume(w, nullptr), Error);
  Checkpoint forgetful = ck;
  forgetful.state.contacts.clear();
  auto p = makePipeline(GetParam());
  p->load(forgetful.resume(w, nullptr));
  p->step(kHalf);
  BodyState c;
  p->readState(c);
  EXPECT_TRUE(firstDifference(a, c).has_value()) << "without the contact histories the run must differ";
  }
  if (lacked == 2) GTEST_SKIP() << "NotSupported: neither law with history (printed above)";
}

TEST_P(CheckpointTest, ResumeKeepsTheLocalFrameOfAFarScene) {
  // 1e5 m from the origin: the run integrates in a local frame chosen at its start; the resumed
  // run must keep that frame (choosing one from the checkpoint's state would round differently).
  Scene s = readSceneFile(sourcePath("scenes/molecules.toml"));
  for (auto& b : s.bodies) b.position.x += 1.0e5f;
  const World w = World::fromScene(s);
  const BodyState a = straight(GetParam(), w, 200);
  const BodyState b = resumed(GetParam(), w, 80, 120);
  const auto d = firstDifference(a, b);
  EXPECT_FALSE(d.has_value()) << d->describe();
}

TEST(Checkpoint, RejectsAnotherScene) {
  const World w = World::fromScene(readSceneFile(sourcePath("scenes/molecules.toml")));
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  p->step(3);
  const Checkpoint ck = Checkpoint::of(w, *p);
  const World other = World::fromScene(readSceneFile(sourcePath("scenes/spheres.toml")));
  EXPECT_THROW(ck.resume(other, nullptr), Error);
  Scene s = readSceneFile(sourcePath("scenes/molecules.toml"));
  s.integrator.rotation = RotationScheme::Splitting;  // other body frames
  EXPECT_THROW(ck.resume(World::fromScene(s), nullptr), Error);
  s = readSceneFile(sourcePath("scenes/molecules.toml"));
  s.dt *= 0.5f;  // other physics: allowed, with a warning
  std::string warning;
  EXPECT_NO_THROW(ck.resume(World::fromScene(s), &warning));
  EXPECT_NE(warning.find("differ"), std::string::npos) << warning;
}

namespace {

// Every cut and every flipped byte of a checkpoint of `w` after 5 steps is refused; `version` is
// the one it must have (1, or 2 with mesh springs), with `meshSprings` of them.
void expectEveryDamageRefused(const World& w, int version, std::size_t meshSprings) {
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  p->step(5);
  const std::string path = tempPath("damage.ck");
  Checkpoint::of(w, *p).write(path);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), version == 2 ? 100u : 200u);
  EXPECT_EQ(bytes[8], version) << "the version";
  const Checkpoint good = Checkpoint::read(path);
  EXPECT_EQ(good.step, 5u);
  EXPECT_EQ(good.state.meshContacts.size(), meshSprings);
  auto writeBytes = [&](const std::string& b) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(b.data(), std::streamsize(b.size()));
  };
  int errors = 0;
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    writeBytes(bytes.substr(0, cut));
    try {
      Checkpoint::read(path);
      ADD_FAILURE() << "a file cut at byte " << cut << " was accepted";
    } catch (const InputError&) {
      ++errors;
    }
  }
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::string b = bytes;
    b[at] = static_cast<char>(b[at] ^ 0x10);
    writeBytes(b);
    try {
      Checkpoint::read(path);
      ADD_FAILURE() << "a file with byte " << at << " flipped was accepted";
    } catch (const InputError& e) {
      ++errors;
      if (at == 0) {
        EXPECT_NE(std::string(e.what()).find("not a tumble checkpoint"), std::string::npos) << e.what();
      }
    }
  }
  writeBytes(bytes + "x");
  EXPECT_THROW(Checkpoint::read(path), InputError) << "trailing bytes";
  std::remove(path.c_str());
  EXPECT_THROW(Checkpoint::read(path), InputError) << "a missing file";
  EXPECT_EQ(errors, int(2 * bytes.size()));
}

World someBodies(const std::string& file, std::size_t first, std::size_t n) {
  Scene s = readSceneFile(sourcePath(file));
  s.bodies.erase(s.bodies.begin(), s.bodies.begin() + std::ptrdiff_t(first));
  s.bodies.resize(n);
  return World::fromScene(s);
}

// A ball sliding on a mesh floor (hooke-history): one mesh spring.
World aBallOnAMeshFloor() {
  Scene m;
  m.ground.enabled = false;
  m.contact.law = ContactLaw::HookeHistory;
  auto floor = std::make_shared<TriangleMesh>();
  floor->vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  floor->triangles = {0, 1, 2, 0, 2, 3};
  floor->source = {1, 2};
  WallDef w;
  w.shape = WallDef::Shape::Mesh;
  w.mesh = floor;
  m.walls = {w};
  m.shapes = {ShapeDef{"ball", {SphereDef{{0, 0, 0}, 0.05f, 0.1f, 0.5f}}}};
  BodyDef b;
  b.position = {0.0f, 0.0f, 0.0499f};
  b.velocity = {1.0f, 0.5f, 0.0f};
  m.bodies = {b};
  return World::fromScene(m);
}

}  // namespace

// Version 1 (molecules; the periodic chute: the image counters' block) and version 2 (with mesh
// springs): every cut and every flipped byte is refused.
TEST(Checkpoint, EveryTruncationAndEveryFlippedByteIsAnInputError) {
  expectEveryDamageRefused(someBodies("scenes/molecules.toml", 0, 12), 1, 0);
  expectEveryDamageRefused(someBodies("scenes/chute.toml", 8, 12), 1, 0);
  expectEveryDamageRefused(aBallOnAMeshFloor(), 2, 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, CheckpointTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);

namespace {

// The checkpoint of four molecules after two steps on the CPU pipeline.
Checkpoint fourMoleculesStepped() {
  Scene s = readSceneFile(sourcePath("scenes/molecules.toml"));
  s.bodies.resize(4);
  const World w = World::fromScene(s);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  p->step(2);
  return Checkpoint::of(w, *p);
}

}  // namespace

// A diverged state (a run with --no-guard) is refused when written, since read() would refuse
// it; the file already at the path stays as it was.
TEST(Checkpoint, ADivergedStateIsNotWritten) {
  const std::string path = tempPath("diverged.ck");
  const Checkpoint good = fourMoleculesStepped();
  good.write(path);
  for (std::vector<float> BodyState::*column : {&BodyState::lx, &BodyState::vz, &BodyState::groundSpringY}) {
    Checkpoint bad = good;
    std::vector<float>& c = bad.state.*column;
    ASSERT_FALSE(c.empty());
    c.back() = std::numeric_limits<float>::infinity();
    try {
      bad.write(path);
      ADD_FAILURE() << "a non-finite state was written";
    } catch (const SimulationError& e) {
      EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
    }
    EXPECT_EQ(Checkpoint::read(path).step, 2u);  // the previous file, intact
  }
  std::remove(path.c_str());
}

// Crafted checkpoints with valid checksums (issue 34, item 9): values no run can have are refused
// by read() as the scene reader refuses them, with the byte and the body: an origin of 1e300 ran
// and wrote inf to --state-out, a zero orientation was accepted, one of length 2e30 stopped the
// run at its first step.
TEST(Checkpoint, ValuesNoRunCanHaveAreRefused) {
  const Checkpoint good = fourMoleculesStepped();
  const std::string path = tempPath("crafted.ck");
  struct Craft {
    const char* what;
    void (*apply)(Checkpoint&);
    const char* message;
  };
  const Craft crafts[] = {
      {"origin 1e300", [](Checkpoint& c) { c.frame.x = 1e300; }, "body 0's position x (the frame origin's"},
      {"origin beyond float", [](Checkpoint& c) { c.frame.z = 3.5e38; }, "is beyond +-2^60 m"},
      {"origin beyond 2^60 m", [](Checkpoint& c) { c.frame.y = 2e18; }, "body 0's position y (the frame origin's"},
      {"zero orientation", [](Checkpoint& c) { c.state.qw[1] = c.state.qx[1] = c.state.qy[1] = c.state.qz[1] = 0.0f; },
       "body 1's orientation is not a unit quaternion (its length is 0"},
      {"huge orientation", [](Checkpoint& c) { c.state.qw[2] = 2e30f; }, "body 2's orientation is not a unit quaternion"},
  };
  for (const Craft& craft : crafts) {
    Checkpoint bad = good;
    craft.apply(bad);
    bad.write(path);  // finite: written, with valid checksums
    try {
      (void)Checkpoint::read(path);
      ADD_FAILURE() << craft.what << ": read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(craft.message), std::string::npos) << craft.what << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("byte "), std::string::npos) << e.what();
    }
  }
  good.write(path);
  EXPECT_NO_THROW((void)Checkpoint::read(path)) << "the run's own checkpoint";
  std::remove(path.c_str());
}
