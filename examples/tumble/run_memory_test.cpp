// SPDX-License-Identifier: MIT
// The memory estimate the scene reader refuses scenes with (runMemoryEstimate(),
// tumble/run_memory.hpp) against what `tumble run` holds: for each scene, the command runs in a
// child process and its peak resident memory (wait4's ru_maxrss) less that of the same command
// on a scene of 8 spheres (the program and its libraries) must be within 25 % of the estimate.
// The old estimate (400 bytes per body besides its BodyDef, 150 per particle) was a third of
// the measured peak, which this test would have refused too.
// usage: run_memory_test TUMBLE_BINARY [gtest options]
#include <gtest/gtest.h>

#include <fcntl.h>
#include <malloc.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tumble/run_memory.hpp"
#include "tumble/scene_io.hpp"

namespace {

std::string g_tumble;  // the tumble command (argv[1])

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return true;
#else
  const char* env = std::getenv("TUMBLE_TEST_SANITIZED");
  return env != nullptr && std::string(env) == "1";
#endif
}

struct Child {
  int status = -1;
  std::uint64_t peakBytes = 0;  // ru_maxrss
};

// `tumble run scene` for a few steps (the guard checking every 10, the state written at the
// end as --state-out does), its output to `log`.
Child runScene(const std::string& scene, const std::string& dir, const std::string& log) {
  const std::string state = dir + "/state.csv";
  std::vector<std::string> args = {g_tumble, "run", scene, "--steps", "20", "--guard-every", "10", "-q",
                                   "--state-out", state};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
    ::execv(argv[0], argv.data());
    _exit(127);
  }
  Child c;
  if (pid < 0) return c;
  rusage ru{};
  int status = 0;
  if (::wait4(pid, &status, 0, &ru) != pid) return c;
  c.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  c.peakBytes = static_cast<std::uint64_t>(ru.ru_maxrss) * 1024;  // kilobytes on Linux
  return c;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A binary STL of a square plate of side 100 at z = 0 cut into cells × cells squares of two
// triangles each.
void writePlate(const std::string& path, std::uint32_t cells) {
  std::ofstream out(path, std::ios::binary);
  const char header[80] = {};
  out.write(header, sizeof header);
  const std::uint32_t count = 2 * cells * cells;
  out.write(reinterpret_cast<const char*>(&count), 4);
  const float h = 100.0f / float(cells);
  for (std::uint32_t i = 0; i < cells; ++i)
    for (std::uint32_t j = 0; j < cells; ++j) {
      const float x0 = -50.0f + float(i) * h, y0 = -50.0f + float(j) * h, x1 = x0 + h, y1 = y0 + h;
      const float tri[2][12] = {{0, 0, 1, x0, y0, 0, x1, y0, 0, x1, y1, 0}, {0, 0, 1, x0, y0, 0, x1, y1, 0, x0, y1, 0}};
      for (const auto& t : tri) {
        out.write(reinterpret_cast<const char*>(t), sizeof t);
        out.write("\0\0", 2);
      }
    }
}

const char* kHead = R"([scene]
name = "memory"
dt = 1e-4
steps = 20
[ground]
height = 0.0
stiffness = 2.0e4
friction = 0.5
)";
const char* kReport = "[contact]\nstiffness = 2.0e4\ndamping = 10\n";
const char* kHistory = "[contact]\nlaw = \"hooke-history\"\nstiffness = 2.0e4\ngamma_n = 100\nfriction = 0.5\n";
const char* kBall = "[[shape]]\nname = \"ball\"\n[[shape.sphere]]\nradius = 0.5\nmass = 1.0\n";

// A lattice of single spheres pressed together (spacing 0.999 m for a diameter of 1 m): three
// candidate pairs and three contacts per particle, where a settled heap has about 4.25 and 2.3
// and the estimate assumes 4 and 2 (kCandidatePairsPerParticle, kContactsPerParticle).
std::string spheres(const char* contact, int nx, int ny, int nz) {
  return std::string(kHead) + contact + kBall + "[[group]]\nshape = \"ball\"\ncount = [" + std::to_string(nx) + ", " +
         std::to_string(ny) + ", " + std::to_string(nz) + "]\nspacing = 0.999\norigin = [0.5, 0.5, 0.55]\n";
}

// Clumps of 8 spheres at the corners of a cube of edge 0.5 (the bench scenes' shape) on a lattice
// of spacing 1.6: 4.3 candidate pairs between bodies per particle, no contact yet.
std::string clumps(int nx, int ny, int nz) {
  std::string s = std::string(kHead) + kReport + "[[shape]]\nname = \"clump\"\n";
  for (int k = 0; k < 8; ++k)
    s += "[[shape.sphere]]\noffset = [" + std::string(k & 1 ? "0.25" : "-0.25") + ", " + (k & 2 ? "0.25" : "-0.25") +
         ", " + (k & 4 ? "0.25" : "-0.25") + "]\nradius = 0.5\nmass = 1.0\n";
  return s + "[[group]]\nshape = \"clump\"\ncount = [" + std::to_string(nx) + ", " + std::to_string(ny) + ", " +
         std::to_string(nz) + "]\nspacing = 1.6\norigin = [0.8, 0.8, 0.8]\n";
}

// Eight spheres above a mesh wall of about 200 000 triangles (`plate`).
std::string onMesh(const std::string& plate) {
  return std::string(kHead) + kReport + "[[wall]]\ntype = \"mesh\"\nfile = \"" + plate +
         "\"\nstiffness = 2.0e4\nfriction = 0.3\n" + kBall +
         "[[group]]\nshape = \"ball\"\ncount = [2, 2, 2]\nspacing = 1.05\norigin = [0.5, 0.5, 0.55]\n";
}

class RunMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    if (sanitized()) GTEST_SKIP() << "a sanitizer build's resident memory is its shadow memory, not the run's";
    ASSERT_FALSE(g_tumble.empty()) << "usage: run_memory_test TUMBLE_BINARY";
    char dir[] = "/tmp/tumble_run_memory_XXXXXX";
    ASSERT_NE(::mkdtemp(dir), nullptr);
    m_dir = dir;
    write(m_dir + "/tiny.toml", spheres(kReport, 2, 2, 2));
    const Child base = runScene(m_dir + "/tiny.toml", m_dir, m_dir + "/tiny.log");
    ASSERT_EQ(base.status, 0) << slurp(m_dir + "/tiny.log");
    m_baseline = base.peakBytes;
    std::printf("baseline (8 spheres): %.1f MB\n", double(m_baseline) / 1e6);
  }
  void TearDown() override {
    if (!m_dir.empty()) std::filesystem::remove_all(m_dir);
  }

  // Runs the scene, prints the measured peak, the estimate and the old estimate, and checks the
  // estimate within 25 % of the measured peak (less the baseline), where the old one was not.
  void check(const std::string& name, const std::string& text) {
    const std::string path = m_dir + "/" + name + ".toml";
    write(path, text);
    const Child run = runScene(path, m_dir, m_dir + "/" + name + ".log");
    ASSERT_EQ(run.status, 0) << slurp(m_dir + "/" + name + ".log");
    ASSERT_GT(run.peakBytes, m_baseline);
    const double measured = double(run.peakBytes - m_baseline);
    // The scene is read here after the runs: a child's ru_maxrss counts what it inherited at the
    // fork too, which must stay small next to the baseline (and malloc_trim gives the scene's
    // memory back before the next test's baseline).
    tumble::RunSize size;
    std::uint64_t bodies = 0;
    {
      const tumble::Scene scene = tumble::readSceneFile(path);
      bodies = scene.bodies.size();
      std::uint64_t particles = 0;
      for (const tumble::BodyDef& b : scene.bodies) particles += scene.shapes[b.shape].spheres.size();
      size = tumble::runSizeOf(scene, bodies, 0, particles);
    }
    ::malloc_trim(0);
    const double estimate = double(tumble::runMemoryEstimate(size));
    const double old = double(bodies) * (400.0 + sizeof(tumble::BodyDef)) + 150.0 * double(size.particles);
    std::printf("%-10s %8llu bodies %8llu particles: measured %7.1f MB, estimate %7.1f MB (%+.1f %%), old %7.1f MB (%+.1f %%)\n",
                name.c_str(), static_cast<unsigned long long>(bodies), static_cast<unsigned long long>(size.particles), measured / 1e6,
                estimate / 1e6, 100.0 * (estimate / measured - 1.0), old / 1e6, 100.0 * (old / measured - 1.0));
    EXPECT_NEAR(estimate / measured, 1.0, 0.25) << name << ": estimate " << estimate << " B, measured " << measured
                                                << " B";
    if (size.meshTriangles == 0) {  // the old estimate had no term for meshes
      EXPECT_GT(std::abs(old / measured - 1.0), 0.25) << name << ": the test would not tell the old estimate";
    }
  }

  std::string m_dir;
  std::uint64_t m_baseline = 0;
};

TEST_F(RunMemory, SingleSpheres) { check("spheres", spheres(kReport, 100, 100, 20)); }

TEST_F(RunMemory, ClumpsOfEight) { check("clumps", clumps(50, 50, 10)); }

TEST_F(RunMemory, HistoryLaw) { check("history", spheres(kHistory, 100, 100, 20)); }

TEST_F(RunMemory, MeshWall) {
  writePlate(m_dir + "/plate.stl", 316);
  check("mesh", onMesh(m_dir + "/plate.stl"));
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (argc > 1) g_tumble = argv[1];
  return RUN_ALL_TESTS();
}
