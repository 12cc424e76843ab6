// SPDX-License-Identifier: MIT
#include "tumble/particle_csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"

namespace tumble {
namespace {

std::string_view trim(std::string_view s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

}  // namespace

ParticleCloud parseParticleCsv(std::string_view text, const std::string& path) {
  long lineNo = 0;
  std::size_t at = 0;
  std::string_view line;
  const auto nextLine = [&] {
    if (at >= text.size()) return false;
    const auto nl = text.find('\n', at);
    line = text.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
    at = nl == std::string_view::npos ? text.size() : nl + 1;
    ++lineNo;
    // A NUL byte would end a field early for strtof (0.9<NUL>garbage read as 0.9).
    if (line.find('\0') != std::string_view::npos)
      throw InputError(path, lineNo, "contains a NUL byte (is this a text CSV file?)");
    return true;
  };
  if (!nextLine()) throw InputError(path, 1, "empty file; expected the header line x,y,z,r,body");
  {
    std::string h;
    for (char c : line)
      if (c != ' ' && c != '\t' && c != '\r') h += c;
    if (h != "x,y,z,r,body")
      throw InputError(path, 1, "header must be x,y,z,r,body (got '" + std::string(trim(line)) + "')");
  }
  ParticleCloud c;
  static const char* const names[5] = {"x", "y", "z", "r", "body"};
  while (nextLine()) {
    if (trim(line).empty()) continue;
    std::string field[5];
    int nf = 0;
    std::size_t start = 0;
    for (;;) {
      const auto comma = line.find(',', start);
      if (nf == 5) throw InputError(path, lineNo, "too many fields (expected 5: x,y,z,r,body)");
      field[nf++] = trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (nf != 5) throw InputError(path, lineNo, "expected 5 fields x,y,z,r,body, got " + std::to_string(nf));
    float v[4];
    for (int k = 0; k < 4; ++k) {
      char* end = nullptr;
      errno = 0;
      v[k] = std::strtof(field[k].c_str(), &end);
      if (field[k].empty() || *end != '\0')
        throw InputError(path, lineNo, std::string(names[k]) + " is not a number: '" + field[k] + "'");
      if (!std::isfinite(v[k]))
        throw InputError(path, lineNo, std::string(names[k]) + " must be finite (got '" + field[k] + "')");
    }
    if (!(v[3] > 0.0f)) throw InputError(path, lineNo, "r must be > 0 (got '" + field[3] + "')");
    if (const std::string why = sphereOutOfRange(v[0], v[1], v[2], v[3]); !why.empty())
      throw InputError(path, lineNo, "the sphere: " + why);
    char* end = nullptr;
    errno = 0;
    const unsigned long long b = std::strtoull(field[4].c_str(), &end, 10);
    if (field[4].empty() || field[4][0] == '-' || *end != '\0' || errno == ERANGE || b > 0xFFFFFFFFull)
      throw InputError(path, lineNo, "body must be a non-negative integer below 2^32 (got '" + field[4] + "')");
    c.x.push_back(v[0]);
    c.y.push_back(v[1]);
    c.z.push_back(v[2]);
    c.r.push_back(v[3]);
    c.body.push_back(static_cast<std::uint32_t>(b));
  }
  return c;
}

ParticleCloud readParticleCsv(const std::string& path) {
  return parseParticleCsv(detail::readWholeFile(path, "", detail::kParticleFileLimit), path);
}

}  // namespace tumble
