// SPDX-License-Identifier: MIT
// The readers of scenes, meshes and particle lists take regular files of a bounded size (issue 34,
// item 4): /dev/zero and a sparse 30 GB file ended in std::bad_alloc after seconds of reading.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tumble/error.hpp"
#include "tumble/mesh.hpp"
#include "tumble/particle_csv.hpp"
#include "tumble/scene_io.hpp"

namespace {

using tumble::InputError;

std::string tempDir() {
  char tmpl[] = "/tmp/tumble_reader_limits.XXXXXX";
  const char* d = mkdtemp(tmpl);
  EXPECT_NE(d, nullptr);
  return d ? d : "/tmp";
}

// A sparse file of `bytes` (no disk used).
std::string sparse(const std::string& dir, const std::string& name, std::uintmax_t bytes) {
  const std::string p = dir + "/" + name;
  std::ofstream(p) << "";
  std::filesystem::resize_file(p, bytes);
  return p;
}

template <class Read>
void expectRefused(Read&& read, const std::string& path, const std::string& needle) {
  try {
    read(path);
    ADD_FAILURE() << path << " was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

const auto readScene = [](const std::string& p) { (void)tumble::readSceneFile(p, {}); };
const auto readMesh = [](const std::string& p) { (void)tumble::readMeshFile(p); };
const auto readParticles = [](const std::string& p) { (void)tumble::readParticleCsv(p); };

}  // namespace

TEST(ReaderLimits, DevicesAndFifosAreNotRead) {
  for (const auto& read : {+[](const std::string& p) { readScene(p); }, +[](const std::string& p) { readMesh(p); },
                           +[](const std::string& p) { readParticles(p); }})
    expectRefused(read, "/dev/zero", "not a regular file (a device, a FIFO or a socket)");
  const std::string dir = tempDir();
  const std::string fifo = dir + "/scene.toml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectRefused(readScene, fifo, "not a regular file");  // refused before it is opened: no writer, no wait
  std::filesystem::remove_all(dir);
}

TEST(ReaderLimits, FilesBeyondTheLimitAreRefusedBeforeTheyAreRead) {
  const std::string dir = tempDir();
  expectRefused(readScene, sparse(dir, "big.toml", std::uintmax_t{300} << 20),
                "300 MiB, more than the 256 MiB tumble reads as a scene file; list many bodies with [[group]]");
  expectRefused(readMesh, sparse(dir, "big.stl", std::uintmax_t{30} << 30), "more than the 1.0 GiB tumble reads as a mesh file");
  expectRefused(readParticles, sparse(dir, "big.csv", std::uintmax_t{30} << 30), "more than the 16.0 GiB tumble reads as a particle file; split");
  std::filesystem::remove_all(dir);
}
