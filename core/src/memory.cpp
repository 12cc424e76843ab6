// SPDX-License-Identifier: MIT
#include "tumble/memory.hpp"

#include <cstdio>
#include <fstream>
#include <string>

namespace tumble {

std::optional<std::uint64_t> availableMemory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return std::nullopt;
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
  const std::optional<std::uint64_t> have = availableMemory();
  if (!have || bytes <= *have) return {};
  return "about " + bytesText(bytes) + ", more than the " + bytesText(*have) + " this machine has available";
}

}  // namespace tumble
