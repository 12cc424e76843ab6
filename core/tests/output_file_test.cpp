// SPDX-License-Identifier: MIT
// Outputs (tumble/output_file.hpp): a link is written through to its target, a device or FIFO is
// written in place and never replaced, the temporary has an unpredictable name created
// exclusively (a planted link at the old fixed name TARGET.part is not followed), a failure
// leaves the target and its directory as they were, and a replaced file keeps its permissions.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

namespace fs = std::filesystem;
using tumble::OutputFile;

namespace {

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() / ("tumble_output_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(m_dir, ec);
  }
  std::string file(const std::string& name) const { return (m_dir / name).string(); }
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(m_dir)) ++n;
    return n;
  }
  fs::path m_dir;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void put(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

void write(const std::string& path, const std::string& text) {
  OutputFile out(path);
  ASSERT_EQ(std::fwrite(text.data(), 1, text.size(), out.file()), text.size());
  out.commit();
}

}  // namespace

TEST_F(OutputFileTest, ReplacesAFileOnlyAtCommit) {
  const std::string path = file("out.txt");
  put(path, "old");
  {
    OutputFile out(path);
    EXPECT_EQ(out.writingTo().rfind(path + ".part-", 0), 0u) << out.writingTo();
    std::fputs("new", out.file());
    EXPECT_EQ(slurp(path), "old");
    out.commit();
  }
  EXPECT_EQ(slurp(path), "new");
  EXPECT_EQ(entries(), 1u) << "no temporary left";
}

TEST_F(OutputFileTest, AFailureLeavesTheTargetAndNoTemporary) {
  const std::string path = file("out.txt");
  put(path, "old");
  try {
    OutputFile out(path);
    std::fputs("half", out.file());
    throw std::runtime_error("the writer failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(slurp(path), "old");
  EXPECT_EQ(entries(), 1u);
  try {
    OutputFile out(file("no/such/dir/out.txt"));
    FAIL() << "expected tumble::Error";
  } catch (const tumble::Error& e) {
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
}

TEST_F(OutputFileTest, WritesThroughASymlinkToItsTarget) {
  const std::string target = file("real.txt"), link = file("link.txt"), link2 = file("link2.txt");
  put(target, "old");
  fs::create_symlink("real.txt", link);   // relative, as ln -s makes them
  fs::create_symlink(link, link2);        // a chain
  write(link2, "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link))) << "the link stays a link";
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link2)));
  EXPECT_EQ(slurp(target), "new");
  EXPECT_EQ(entries(), 3u);
  // A dangling link: its target is created.
  const std::string dangling = file("dangling.txt");
  fs::create_symlink("made.txt", dangling);
  write(dangling, "made");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dangling)));
  EXPECT_EQ(slurp(file("made.txt")), "made");
  // A loop is an error, not a hang.
  fs::create_symlink("loop2", file("loop1"));
  fs::create_symlink("loop1", file("loop2"));
  EXPECT_THROW(OutputFile{file("loop1")}, tumble::Error);
}

TEST_F(OutputFileTest, ADeviceIsWrittenInPlaceNotReplaced) {
  // As root, renaming over /dev/null would replace the device with a regular file.
  OutputFile out("/dev/null");
  EXPECT_EQ(out.writingTo(), "/dev/null");
  std::fputs("discarded", out.file());
  out.commit();
  struct stat st{};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/null is still a character device";
}

TEST_F(OutputFileTest, AFifoIsWrittenInPlace) {
  const std::string fifo = file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = slurp(fifo); });
  write(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  struct stat st{};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(entries(), 1u);
}

TEST_F(OutputFileTest, APlantedLinkAtTheOldTemporaryNameIsNotFollowed) {
  const std::string path = file("out.txt"), victim = file("victim.txt");
  put(victim, "precious");
  fs::create_symlink(victim, path + ".part");
  write(path, "new");
  EXPECT_EQ(slurp(victim), "precious");
  EXPECT_EQ(slurp(path), "new");
}

TEST_F(OutputFileTest, AReplacedFileKeepsItsPermissions) {
  const std::string path = file("out.txt");
  put(path, "old");
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write(path, "new");
  EXPECT_EQ(fs::status(path).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  // A new file: 0666 less the umask (mkstemp's 0600 would hide it from the group).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  write(file("fresh.txt"), "x");
  EXPECT_EQ(static_cast<unsigned>(fs::status(file("fresh.txt")).permissions() & fs::perms::all), 0666u & ~unsigned(mask));
}
