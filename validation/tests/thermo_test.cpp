// SPDX-License-Identifier: MIT
// The time series (thermo.hpp, docs/thermo.md): the guard's measurements against quantities
// computed here from the state, conservation laws of free motion, and the same bits for any
// thread count.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/thermo.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/world.hpp"

using namespace tumble;

namespace {

// Dumbbells spinning and flying apart far from the origin, no ground, no contacts: gravity g.
Scene tumblers(float gz) {
  Scene s;
  s.dt = 1e-3f;
  s.gravity = {0.0f, 0.0f, gz};
  s.ground.enabled = false;
  s.integrator.rotation = RotationScheme::Splitting;
  s.shapes = {ShapeDef{"dumbbell", {SphereDef{{-0.2f, 0, 0}, 0.1f, 1.0f, 0.5f}, SphereDef{{0.3f, 0, 0}, 0.15f, 3.0f, 0.5f}}}};
  for (int i = 0; i < 4; ++i) {
    BodyDef b;
    b.position = {1000.0f + 2.0f * float(i), -50.0f + float(i), 20.0f};
    b.velocity = {0.5f * float(i), -0.3f, 0.2f * float(i - 2)};
    b.angularVelocity = {1.0f + float(i), -2.0f, 0.5f * float(i)};
    b.orientation = Quatf{1.0f, 0.1f * float(i), 0.2f, 0.0f};
    s.bodies.push_back(b);
  }
  return s;
}

}  // namespace

// Without forces, P, L about the origin and E stay constant (the splitting scheme keeps |L| of
// each body exactly, its energy to rounding); with gravity, P_z falls by M g t and E drifts by
// exactly what the kick-drift scheme gives.
TEST(Thermo, ConservationInFreeMotion) {
  for (const float gz : {0.0f, -9.81f}) {
    const World w = World::fromScene(tumblers(gz));
    auto p = makePipeline(Backend::Cpu);
    p->load(w);
    RunGuard guard(w, *p);
    const ThermoSample s0 = guard.sample();
    double mass = 0.0;
    for (float m : w.bodyMass) mass += m;
    EXPECT_GT(s0.kineticRotation, 1.0);
    EXPECT_GT(s0.kineticTranslation, 1.0);
    for (int c = 0; c < 20; ++c) {
      p->step(50);
      ASSERT_FALSE(guard.check(*p));
      const ThermoSample& s = guard.sample();
      EXPECT_EQ(s.step, std::uint64_t(50 * (c + 1)));
      // Kick-drift sampled at whole steps: E_n = E_0 − ½ M g² dt² n exactly in free fall (v_n is
      // the velocity of the step that ends at x_n).
      const double drift = 0.5 * mass * double(gz) * gz * double(w.params.dt) * w.params.dt * double(s.step);
      EXPECT_NEAR(s.energy(), s0.energy() - drift, 1e-5 * std::abs(s0.gravity) + 1e-4) << "gz " << gz << ", step " << s.step;
      EXPECT_NEAR(s.momentum[0], s0.momentum[0], 1e-4);
      EXPECT_NEAR(s.momentum[1], s0.momentum[1], 1e-4);
      EXPECT_NEAR(s.momentum[2], s0.momentum[2] + mass * gz * s.time, 2e-5 * std::abs(s.momentum[2]) + 1e-4) << "gz " << gz;
      if (gz == 0.0f) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.angularMomentum[k], s0.angularMomentum[k], 2e-3) << k;
      }
      EXPECT_EQ(s.contacts, 0u);
      EXPECT_EQ(s.springs, 0.0);
    }
  }
}

// Each column against its definition, computed here from the state the pipeline hands out
// (world coordinates), on a pile with contacts and the ground.
TEST(Thermo, ColumnsAreTheirDefinitions) {
  Scene sc = readSceneFile(validation::sourcePath("scenes/molecules.toml"));
  sc.bodies.resize(200);
  const World w = World::fromScene(sc);
  auto p = makePipeline(Backend::Cpu);
  p->load(w);
  RunGuard guard(w, *p);
  p->step(2000);
  ASSERT_FALSE(guard.check(*p));
  const ThermoSample& s = guard.sample();
  BodyState st;
  p->readState(st);
  double kt = 0.0, grav = 0.0, vmax = 0.0, P[3] = {0, 0, 0}, L[3] = {0, 0, 0};
  for (std::size_t k = 0; k < st.size(); ++k) {
    const double m = w.bodyMass[k];
    const double v[3] = {st.vx[k], st.vy[k], st.vz[k]}, x[3] = {st.px[k], st.py[k], st.pz[k]};
    kt += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    grav -= m * (double(sc.gravity.x) * x[0] + double(sc.gravity.y) * x[1] + double(sc.gravity.z) * x[2]);
    vmax = std::max(vmax, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    for (int c = 0; c < 3; ++c) P[c] += m * v[c];
    L[0] += m * (x[1] * v[2] - x[2] * v[1]) + st.lx[k];
    L[1] += m * (x[2] * v[0] - x[0] * v[2]) + st.ly[k];
    L[2] += m * (x[0] * v[1] - x[1] * v[0]) + st.lz[k];
  }
  EXPECT_NEAR(s.kineticTranslation, kt, 1e-9 * kt);
  EXPECT_NEAR(s.gravity, grav, 1e-9 * std::abs(grav));
  EXPECT_NEAR(s.maxSpeed, vmax, 1e-12);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.momentum[c], P[c], 1e-9);
    EXPECT_NEAR(s.angularMomentum[c], L[c], 1e-9);
  }
  EXPECT_EQ(s.contacts, p->pairs().size());
  EXPECT_GE(s.contacts, 5u);
  EXPECT_GT(s.springs, 0.0);
  EXPECT_GT(s.maxOverlap, 0.0);
  EXPECT_NEAR(s.energy(), guard.energy(), 1e-9 * std::abs(guard.energy()));
}

// The samples are the same bits for 1 and 2 threads (fixed-order sums).
TEST(Thermo, SameBitsForAnyThreadCount) {
  Scene sc = readSceneFile(validation::sourcePath("scenes/molecules.toml"));
  sc.bodies.resize(300);
  sc.pulls.active = kPullSwirl;
  const World w = World::fromScene(sc);
  std::vector<ThermoSample> runs[2];
  for (int t = 0; t < 2; ++t) {
    PipelineOptions po;
    po.threads = t + 1;
    auto p = makePipeline(Backend::Cpu, po);
    p->load(w);
    RunGuard guard(w, *p);
    for (int c = 0; c < 5; ++c) {
      p->step(100);
      (void)guard.check(*p);
      runs[t].push_back(guard.sample());
    }
  }
  auto fields = [](const ThermoSample& a) {
    return std::vector<double>{double(a.step), a.time, a.kineticTranslation, a.kineticRotation, a.gravity,
                               a.pullPotential, a.springs, a.pullWork, double(a.contacts), a.maxOverlap, a.maxSpeed,
                               a.momentum[0], a.momentum[1], a.momentum[2], a.angularMomentum[0],
                               a.angularMomentum[1], a.angularMomentum[2]};
  };
  for (std::size_t c = 0; c < runs[0].size(); ++c) {
    const std::vector<double> a = fields(runs[0][c]), b = fields(runs[1][c]);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "sample " << c;
  }
  EXPECT_NE(runs[0].back().pullWork, 0.0);  // the swirl did work
}

// A full disk (here a file size limit, which fails writes the same way) in the middle of a row:
// the torn row is cut off again, and the finished file holds the header and every whole row,
// as a recording keeps its whole frames (issue 34, item 6).
TEST(Thermo, ARowThatCannotBeWrittenIsCutOff) {
  char tmpl[] = "/tmp/tumble_thermo_test.XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl, path = dir + "/t.csv";
  ThermoSample s;
  s.finite = true;
  s.kineticTranslation = 1.25;
  s.time = 0.5;
  struct rlimit old {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);  // EFBIG instead of the signal
  std::string what;
  {
    ThermoWriter w(path, 1e-3f);
    w.write(s);
    s.step = 10;
    w.write(s);
    std::uintmax_t written = 0;  // the temporary's size: the header and two rows
    for (const auto& e : std::filesystem::directory_iterator(dir)) written = std::filesystem::file_size(e.path());
    struct rlimit small = old;
    small.rlim_cur = written + 20;  // the next row stops after 20 bytes
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    s.step = 20;
    try {
      w.write(s);
    } catch (const Error& e) {
      what = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    EXPECT_NE(what.find("t.csv: File too large; it keeps the 2 whole rows written before"), std::string::npos) << what;
    EXPECT_EQ(w.rows(), 2u);
    w.close();
  }
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 3u) << "the header and the two whole rows";
  for (const std::string& l : lines) EXPECT_EQ(std::count(l.begin(), l.end(), ','), long(kThermoColumns - 1)) << l;
  EXPECT_EQ(lines[2].rfind("10,", 0), 0u) << lines[2];
  std::filesystem::remove_all(dir);
}

// Through a descriptor the process was given (`--thermo /dev/stdout >> runs.csv`), the file holds
// what others wrote before: a row that fails is never cut back there (it would cut their bytes).
TEST(Thermo, AFailedRowThroughADescriptorCutsNothing) {
  char tmpl[] = "/tmp/tumble_thermo_test.XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl, path = dir + "/runs.csv";
  const std::string before(4000, 'P');  // an earlier run's lines
  std::ofstream(path) << before;
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(fd, 0);
  struct rlimit old {};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
  std::string what;
  {
    ThermoWriter w("/dev/fd/" + std::to_string(fd), 1e-3f);
    ThermoSample s;
    s.finite = true;
    struct rlimit small = old;
    small.rlim_cur = std::filesystem::file_size(path) + 100;  // the next row stops within it
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    try {
      for (int k = 0; k < 10; ++k) w.write(s);
    } catch (const Error& e) {
      what = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    EXPECT_NE(what.find("File too large"), std::string::npos) << what;
    EXPECT_EQ(what.find("keeps"), std::string::npos) << "nothing was cut back: " << what;
  }
  ::close(fd);
  std::ifstream in(path, std::ios::binary);
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_GT(all.size(), before.size());
  EXPECT_EQ(all.compare(0, before.size(), before), 0) << "the earlier bytes are all there";
  std::filesystem::remove_all(dir);
}

// Times at the step's precision (issue 35, item 11): 200 steps of 5e-5 s are 0.01 s, not the
// binary sum 0.009999999747 that %.10g of the accumulated time printed.
TEST(Thermo, TimesArePrintedAtTheStepsPrecision) {
  double t = 0.0;
  for (int k = 0; k < 200; ++k) t += double(5e-5f);
  EXPECT_EQ(formatTime(t, 5e-5f), "0.01");
  EXPECT_EQ(formatTime(0.0, 1e-4f), "0");
  EXPECT_EQ(formatTime(1.5, 0.25f), "1.5");
  EXPECT_EQ(formatTime(3.0 * double(1e-3f), 1e-3f), "0.003");
  EXPECT_EQ(formatTime(1e6 + double(1e-4f), 1e-4f), "1000000.0001") << "a step far into a long run still shows";
  EXPECT_EQ(formatTime(std::nan(""), 1e-4f), "nan");
}

// The time series can be followed while it is written (issue 35, item 3): its rows are in the
// live name FILE.part, readable as FILE will be, until close() renames it; a second writer of the
// same FILE is refused while the first's live file is there.
TEST(Thermo, RowsCanBeReadInTheLiveFileWhileTheRunWrites) {
  char tmpl[] = "/tmp/tumble_thermo_test.XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl, path = dir + "/live.csv", live = path + ".part";
  const mode_t oldMask = ::umask(022);
  {
    ThermoWriter w(path, 5e-5f);
    ThermoSample s;
    s.step = 100;
    s.time = 100 * double(5e-5f);
    w.write(s);
    ASSERT_TRUE(std::filesystem::exists(live));
    EXPECT_FALSE(std::filesystem::exists(path));
    const auto perms = std::filesystem::status(live).permissions();
    EXPECT_NE(perms & std::filesystem::perms::others_read, std::filesystem::perms::none) << "readable as the file will be";
    std::ifstream in(live);
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(header, thermoHeader());
    EXPECT_EQ(row.rfind("100,0.005,", 0), 0u) << row;
    try {
      ThermoWriter second(path, 5e-5f);
      ADD_FAILURE() << "a second writer of " << path << " was not refused";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(live + " exists"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::filesystem::exists(live)) << "the refused writer left the first's rows alone";
    w.close();
  }
  ::umask(oldMask);
  EXPECT_TRUE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(live));
  std::filesystem::remove_all(dir);
}
