// SPDX-License-Identifier: MIT
// tumble::exportRecording (docs/export.md): names, frame selection, stopping, bad folders. The
// file contents are read back by VTK itself in examples/tumble/export_test.py (ctest export_vtk).
#include "tumble/export.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tumble/error.hpp"

namespace {

namespace fs = std::filesystem;
using tumble::ExportFormat;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Two single-sphere bodies on a ground, `frames` frames one step apart, in a fresh folder.
struct ExportFile : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("tumble_export_test_" + std::to_string(::getpid()));
  std::string rec = (dir / "r.bin").string();
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
    tumble::World w;
    w.params.name = "two";
    w.params.dt = 1e-3f;
    w.params.ground.enabled = true;
    w.params.ground.height = -0.5f;
    w.radius = {0.5f, 0.25f};
    w.mass = {1.0f, 2.0f};
    w.elasticity = {0.5f, 0.9f};
    w.groundDamping.assign(2, 0.0f);
    w.body = {0, 1};
    w.ux = w.uy = w.uz = {0.0f, 0.0f};
    w.bodyMass = {1.0f, 2.0f};
    w.invMass = {1.0f, 0.5f};
    w.first = {0, 1};
    w.numParticlesOf = {1, 1};
    w.maxRadius = 0.5f;
    tumble::RecordingWriter writer(rec, w, /*debug=*/false, /*stepsPerFrame=*/1);
    tumble::BodyState s;
    s.px = {0.0f, 2.0f};
    s.py = s.pz = {0.0f, 0.0f};
    s.qw = {1.0f, 1.0f};
    s.qx = s.qy = s.qz = {0.0f, 0.0f};
    for (auto* c : {&s.vx, &s.vy, &s.vz, &s.lx, &s.ly, &s.lz}) c->assign(2, 0.0f);
    for (int k = 0; k < 12; ++k) {
      s.pz = {0.1f * static_cast<float>(k), 0.0f};
      writer.writeFrame(static_cast<std::uint64_t>(k), 1e-3 * k, 0, s);
    }
    writer.close();
  }
  void TearDown() override { fs::remove_all(dir); }
};

TEST(Export, FrameNamesArePaddedToTheLargestIndex) {
  EXPECT_EQ(tumble::exportFrameName("a", 0, 10, ExportFormat::Vtk), "a_000000.vtp");
  EXPECT_EQ(tumble::exportFrameName("a", 999999, 1000000, ExportFormat::Csv), "a_999999.csv");
  EXPECT_EQ(tumble::exportFrameName("a", 5, 1000001, ExportFormat::Vtk), "a_0000005.vtp");
}

TEST_F(ExportFile, EveryFifthFrameWithTheGroundAsPartOne) {
  tumble::RecordingReader reader(rec);
  tumble::ExportOptions o;
  o.every = 5;
  o.name = "m";
  const tumble::ExportResult r = tumble::exportRecording(reader, (dir / "out").string(), o);
  EXPECT_EQ(r.frames, 3u);  // frames 0, 5, 10 of 12
  EXPECT_FALSE(r.stopped);
  const std::string pvd = slurp(dir / "out" / "m.pvd");
  EXPECT_EQ(count(pvd, "part=\"0\""), 3u) << pvd;
  EXPECT_EQ(count(pvd, "part=\"1\" file=\"m_ground.vtp\""), 3u) << pvd;
  EXPECT_NE(pvd.find("timestep=\"0.01\" part=\"0\" file=\"m_000002.vtp\""), std::string::npos) << pvd;
  EXPECT_TRUE(fs::exists(dir / "out" / "m_000002.vtp"));
  EXPECT_FALSE(fs::exists(dir / "out" / "m_000003.vtp"));
  EXPECT_NE(slurp(dir / "out" / "m_000001.vtp").find("NumberOfPoints=\"2\""), std::string::npos);
}

TEST_F(ExportFile, CsvIndexListsTheRecordingsFrames) {
  tumble::RecordingReader reader(rec);
  tumble::ExportOptions o;
  o.format = ExportFormat::Csv;
  o.every = 4;
  o.name = "c";
  tumble::exportRecording(reader, (dir / "csv").string(), o);
  EXPECT_EQ(slurp(dir / "csv" / "c_frames.csv"),
            "frame,step,time,file\n0,0,0,c_000000.csv\n4,4,0.004,c_000001.csv\n8,8,0.008,c_000002.csv\n");
  EXPECT_EQ(slurp(dir / "csv" / "c_000002.csv"),
            "particle,body,x,y,z,r,mass,elasticity\n0,0,0,0,0.8,0.5,1,0.5\n1,1,2,0,0,0.25,2,0.9\n");
}

TEST_F(ExportFile, AStopKeepsTheFramesWrittenAndTheirIndex) {
  tumble::RecordingReader reader(rec);
  tumble::ExportOptions o;
  o.name = "s";
  std::size_t polls = 0;
  o.stop = [&polls] { return ++polls > 2; };
  const tumble::ExportResult r = tumble::exportRecording(reader, (dir / "s").string(), o);
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.frames, 2u);
  EXPECT_EQ(count(slurp(dir / "s" / "s.pvd"), "part=\"0\""), 2u);
}

TEST_F(ExportFile, BadFoldersAndNamesAreRefused) {
  tumble::RecordingReader reader(rec);
  tumble::ExportOptions o;
  EXPECT_THROW(tumble::exportRecording(reader, rec, o), tumble::Error);  // a file is in the way
  o.name = "a/b";
  EXPECT_THROW(tumble::exportRecording(reader, (dir / "x").string(), o), tumble::Error);
  o.name = "ok";
  o.every = 0;
  EXPECT_THROW(tumble::exportRecording(reader, (dir / "x").string(), o), tumble::Error);
  EXPECT_FALSE(fs::exists(dir / "x"));
}

}  // namespace
