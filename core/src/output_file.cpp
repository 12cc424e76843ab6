// SPDX-License-Identifier: MIT
#include "tumble/output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "tumble/error.hpp"

namespace tumble {

namespace fs = std::filesystem;

std::string outputTarget(const std::string& path) {
  fs::path p = path;
  for (int links = 0;; ++links) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p.string();
    if (links == 40) throw Error("cannot write " + path + ": too many levels of symbolic links");
    const fs::path t = fs::read_symlink(p, ec);
    if (ec) throw Error("cannot write " + path + ": " + ec.message());
    p = t.is_absolute() ? t : p.parent_path() / t;
  }
}

namespace {

unsigned currentUmask() {
  const mode_t m = ::umask(0);  // the only way to read it; set back at once
  ::umask(m);
  return static_cast<unsigned>(m);
}

}  // namespace

OutputFile::OutputFile(const std::string& path) : m_path(path), m_target(outputTarget(path)) {
  struct stat st{};
  if (::stat(m_target.c_str(), &st) == 0) {
    m_existed = true;
    m_mode = static_cast<unsigned>(st.st_mode) & 07777u;
    m_direct = !S_ISREG(st.st_mode);
    if (S_ISDIR(st.st_mode)) throw Error("cannot write " + path + ": it is a directory");
  }
  if (m_direct) {
    m_writing = m_target;
    m_file = std::fopen(m_target.c_str(), "wb");
    if (m_file == nullptr) throw Error("cannot write " + path + ": " + std::strerror(errno));
    return;
  }
  std::string name = m_target + ".part-XXXXXX";
  std::vector<char> buf(name.begin(), name.end());
  buf.push_back('\0');
  const int fd = ::mkstemp(buf.data());
  if (fd < 0) throw Error("cannot write " + path + ": " + std::strerror(errno) + " (creating a file next to " + m_target + ")");
  m_writing = buf.data();
  m_file = ::fdopen(fd, "wb");
  if (m_file == nullptr) {
    const int e = errno;
    ::close(fd);
    std::remove(m_writing.c_str());
    throw Error("cannot write " + path + ": " + std::strerror(e));
  }
}

OutputFile::~OutputFile() { abandon(); }

void OutputFile::commit() {
  if (m_file == nullptr) throw Error("cannot write " + m_path + ": the file was already closed");
  bool ok = std::fflush(m_file) == 0;
  int err = ok ? 0 : errno;
  const unsigned mode = m_existed ? m_mode : (0666u & ~currentUmask());
  if (ok && !m_direct && ::fchmod(::fileno(m_file), static_cast<mode_t>(mode)) != 0) {
    ok = false;
    err = errno;
  }
  if (std::fclose(m_file) != 0 && ok) {
    ok = false;
    err = errno;
  }
  m_file = nullptr;
  if (!ok) {
    if (!m_direct) std::remove(m_writing.c_str());
    throw Error("cannot write " + m_path + ": " + std::strerror(err));
  }
  if (m_direct) return;
  if (std::rename(m_writing.c_str(), m_target.c_str()) != 0) {
    err = errno;
    std::remove(m_writing.c_str());
    throw Error("cannot write " + m_path + ": " + std::strerror(err) + " (renaming " + m_writing + ")");
  }
}

void OutputFile::abandon() noexcept {
  if (m_file == nullptr) return;
  std::fclose(m_file);
  m_file = nullptr;
  if (!m_direct) std::remove(m_writing.c_str());
}

std::string OutputFile::keep() noexcept {
  if (m_file != nullptr) std::fclose(m_file);
  m_file = nullptr;
  return m_writing;
}

}  // namespace tumble
