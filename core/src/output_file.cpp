// SPDX-License-Identifier: MIT
#include "tumble/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>
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

// The umask, from /proc/self/status (umask() itself can only be read by setting it, which races
// with other threads creating files); that trick only where /proc has no answer.
unsigned currentUmask() {
  if (std::FILE* f = std::fopen("/proc/self/status", "r")) {
    char line[256];
    unsigned mask = 0;
    bool found = false;
    while (!found && std::fgets(line, sizeof line, f)) found = std::sscanf(line, "Umask: %o", &mask) == 1;
    std::fclose(f);
    if (found) return mask;
  }
  const mode_t m = ::umask(0);
  ::umask(m);
  return static_cast<unsigned>(m);
}

// The descriptor a path names itself: /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N; -1
// for any other. Written through a duplicate of it, so that a pipe or a file opened for
// appending (`>> log`) gets the bytes as the shell set it up, instead of being reopened.
int namedDescriptor(const std::string& path) {
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  for (const char* prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    const std::string p = prefix;
    if (path.size() > p.size() && path.compare(0, p.size(), p) == 0) {
      int fd = 0;
      for (std::size_t i = p.size(); i < path.size(); ++i) {
        if (path[i] < '0' || path[i] > '9' || fd > 1000000) return -1;
        fd = 10 * fd + (path[i] - '0');
      }
      return fd;
    }
  }
  return -1;
}

}  // namespace

bool namesDescriptor(const std::string& path) { return namedDescriptor(path) >= 0; }

namespace {
volatile std::sig_atomic_t g_writeStop = 0;
}  // namespace

void requestWriteStop() noexcept { g_writeStop = 1; }
void clearWriteStop() noexcept { g_writeStop = 0; }
bool writeStopRequested() noexcept { return g_writeStop != 0; }

namespace {
// A FIFO's open() for writing blocks until a reader opens it, and with SA_RESTART (tumble run's
// stop handler) a stop signal only restarts it. It is opened without blocking instead, retried
// every 20 ms until a reader comes or a stop is requested (requestWriteStop(); then -1 and errno
// EINTR, as a signal that interrupts the wait gives too), and made blocking again for the writes.
int openFifoForWriting(const std::string& path) {
  for (;;) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0) {
      const int flags = ::fcntl(fd, F_GETFL);
      if (flags >= 0 && ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0) return fd;
      const int e = errno;
      ::close(fd);
      errno = e;
      return -1;
    }
    if (errno != ENXIO) return -1;  // ENXIO: no reader yet
    if (writeStopRequested()) {
      errno = EINTR;
      return -1;
    }
    struct timespec pause {0, 20 * 1000 * 1000};
    if (::nanosleep(&pause, nullptr) != 0 && !writeStopRequested()) return -1;  // EINTR: a signal, not a stop
  }
}
}  // namespace

bool writeFully(std::FILE* file, const void* data, std::size_t size) {
  const auto* p = static_cast<const unsigned char*>(data);
  while (size > 0) {
    errno = 0;
    const std::size_t n = std::fwrite(p, 1, size, file);
    p += n;
    size -= n;
    if (size == 0) break;
    if (!std::ferror(file)) {
      if (n > 0) continue;  // a short write without an error: go on
      errno = EIO;
      return false;
    }
    if (errno != EINTR || writeStopRequested()) return false;
    std::clearerr(file);
  }
  return true;
}

Appended appendWhole(const OutputFile& out, const void* data, std::size_t size, std::uint64_t& complete, int& error) {
  std::FILE* file = out.file();
  if (writeFully(file, data, size) && std::fflush(file) == 0) {
    complete += size;
    return Appended::Whole;
  }
  error = errno != 0 ? errno : EIO;
  std::clearerr(file);  // unbuffered: nothing of the record is left to be written later
  if (out.direct() || ::ftruncate(::fileno(file), static_cast<off_t>(complete)) != 0 ||
      std::fseek(file, static_cast<long>(complete), SEEK_SET) != 0)
    return Appended::Torn;
  return Appended::CutBack;
}

OutputFile::OutputFile(const std::string& path, Temporary temporary) : m_path(path) {
  if (const int fd = namedDescriptor(path); fd >= 0) {
    m_direct = m_descriptor = true;
    m_target = m_writing = path;
    const int copy = ::dup(fd);
    m_file = copy >= 0 ? ::fdopen(copy, "wb") : nullptr;
    if (m_file == nullptr) {
      const int e = errno;
      if (copy >= 0) ::close(copy);
      throw Error("cannot write " + path + ": " + std::strerror(e));
    }
    return;
  }
  m_target = outputTarget(path);
  struct stat st{};
  if (::stat(m_target.c_str(), &st) == 0) {
    m_existed = true;
    m_mode = static_cast<unsigned>(st.st_mode) & 0777u;  // not set-id bits onto a new file
    m_direct = !S_ISREG(st.st_mode);
    if (S_ISDIR(st.st_mode)) throw Error("cannot write " + path + ": it is a directory");
  }
  if (m_direct && S_ISFIFO(st.st_mode)) {
    m_writing = m_target;
    const int fd = openFifoForWriting(m_target);
    if (fd < 0 && errno == EINTR && writeStopRequested())
      throw Error("cannot write " + path + ": stopped while waiting for a reader of the FIFO");
    if (fd < 0) throw Error("cannot write " + path + ": " + std::strerror(errno));
    m_file = ::fdopen(fd, "wb");
    if (m_file == nullptr) {
      const int e = errno;
      ::close(fd);
      throw Error("cannot write " + path + ": " + std::strerror(e));
    }
    return;
  }
  if (m_direct) {
    m_writing = m_target;
    m_file = std::fopen(m_target.c_str(), "wb");
    if (m_file == nullptr) throw Error("cannot write " + path + ": " + std::strerror(errno));
    return;
  }
  int fd = -1;
  if (temporary == Temporary::Live) {
    m_writing = m_target + ".part";
    const unsigned mode = m_existed ? m_mode : 0666u;  // less the umask, as commit() gives it
    fd = ::open(m_writing.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, static_cast<mode_t>(mode));
    if (fd < 0 && errno == EEXIST)
      throw Error("cannot write " + path + ": " + m_writing +
                  " exists (another run is writing " + path + ", or one was stopped before it finished; "
                  "remove " + m_writing + " if no run writes it)");
    if (fd < 0) throw Error("cannot write " + path + ": " + std::strerror(errno) + " (creating " + m_writing + ")");
    if (m_existed && ::fchmod(fd, static_cast<mode_t>(mode)) != 0) {  // the umask aside: the target's bits
      const int e = errno;
      ::close(fd);
      std::remove(m_writing.c_str());
      throw Error("cannot write " + path + ": " + std::strerror(e));
    }
  } else {
    std::string name = m_target + ".part-XXXXXX";
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back('\0');
    fd = ::mkstemp(buf.data());
    if (fd < 0) throw Error("cannot write " + path + ": " + std::strerror(errno) + " (creating a file next to " + m_target + ")");
    m_writing = buf.data();
  }
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

namespace {

// The file `path` names once its links are followed: whether it exists and is a regular file,
// and a canonical path to compare (for a path that does not exist yet, its folder made canonical).
struct FileKey {
  bool exists = false, regular = false;
  std::filesystem::path key;
};

FileKey fileKey(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target = outputTarget(path);
  const fs::file_status st = fs::status(target, ec);
  FileKey k;
  k.exists = !ec && fs::exists(st);
  k.regular = k.exists && fs::is_regular_file(st);
  k.key = fs::weakly_canonical(fs::absolute(target, ec), ec);
  if (ec) k.key = fs::absolute(target).lexically_normal();
  return k;
}

}  // namespace

bool sameFile(const std::string& a, const std::string& b) {
  const FileKey ka = fileKey(a), kb = fileKey(b);
  std::error_code ec;
  if (ka.exists && kb.exists) return ka.regular && kb.regular && std::filesystem::equivalent(ka.key, kb.key, ec);
  return !ka.exists && !kb.exists && ka.key == kb.key;
}

}  // namespace tumble
