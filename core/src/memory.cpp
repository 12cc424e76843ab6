// SPDX-License-Identifier: MIT
#include "tumble/memory.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

namespace tumble {

namespace {

// A "Key:  N kB" line of a /proc file, in bytes. No heap allocation (the detection asks at
// every rebuild, and a step allocates nothing once sizes have settled).
std::optional<std::uint64_t> procKilobytes(const char* file, const char* wanted) {
  const int fd = ::open(file, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  char buf[8192];
  std::size_t len = 0;
  for (ssize_t n; len < sizeof buf - 1 && (n = ::read(fd, buf + len, sizeof buf - 1 - len)) > 0;)
    len += static_cast<std::size_t>(n);
  ::close(fd);
  buf[len] = '\0';
  const std::size_t keyLen = std::strlen(wanted);
  for (const char* line = buf; *line != '\0';) {
    if (std::strncmp(line, wanted, keyLen) == 0) {
      const char* p = line + keyLen;
      while (*p == ' ' || *p == '\t') ++p;
      if (*p < '0' || *p > '9') return std::nullopt;
      std::uint64_t kb = 0;
      for (; *p >= '0' && *p <= '9'; ++p) kb = 10 * kb + static_cast<std::uint64_t>(*p - '0');
      return kb * 1024;
    }
    const char* nl = std::strchr(line, '\n');
    if (nl == nullptr) break;
    line = nl + 1;
  }
  return std::nullopt;
}

// The room under a soft resource limit, given what the process uses of it; nothing when unset.
std::optional<std::uint64_t> roomUnder(int resource, const char* usedKey) {
  rlimit lim{};
  if (getrlimit(resource, &lim) != 0 || lim.rlim_cur == RLIM_INFINITY) return std::nullopt;
  const std::uint64_t used = procKilobytes("/proc/self/status", usedKey).value_or(0);
  return lim.rlim_cur > used ? lim.rlim_cur - used : 0;
}

struct Available {
  std::uint64_t bytes;
  bool byLimit;  // a limit, not the machine's memory, is the lower
};

std::optional<Available> available() {
  std::optional<Available> have;
  if (const auto m = procKilobytes("/proc/meminfo", "MemAvailable:")) have = Available{*m, false};
  for (const auto room : {roomUnder(RLIMIT_AS, "VmSize:"), roomUnder(RLIMIT_DATA, "VmData:")}) {
    if (room && (!have || *room < have->bytes)) have = Available{*room, true};
  }
  return have;
}

std::string text(const Available& a) {
  return "the " + bytesText(a.bytes) +
         (a.byLimit ? " this process may still allocate (ulimit -v or -d)" : " this machine has available");
}

}  // namespace

std::optional<std::uint64_t> availableMemory() {
  if (const auto a = available()) return a->bytes;
  return std::nullopt;
}

std::string availableMemoryText() {
  const auto a = available();
  return a ? text(*a) : "the memory available";
}

std::string bytesText(std::uint64_t bytes) {
  char buf[32];
  if (bytes >= (std::uint64_t{1} << 30))
    std::snprintf(buf, sizeof buf, "%.1f GiB", double(bytes) / double(std::uint64_t{1} << 30));
  else
    std::snprintf(buf, sizeof buf, "%.0f MiB", double(bytes) / double(1u << 20));
  return buf;
}

std::string memoryShortfall(std::uint64_t bytes) {
  if (bytes < (std::uint64_t{1} << 30)) return {};  // small: not worth asking the system
  const std::optional<Available> have = available();
  if (!have || bytes <= have->bytes) return {};
  return "about " + bytesText(bytes) + ", more than " + text(*have);
}

}  // namespace tumble
