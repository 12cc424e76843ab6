// SPDX-License-Identifier: MIT
#include "tumble/viewer/color_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "text.hpp"
#include "tumble/error.hpp"

namespace tumble::viewer {
namespace {

using detail::trim;

const char* const kFormat =
    "a colour file is one column: a header line naming the values (e.g. value or stress kPa: the legend's name), "
    "then one number per line, one per body (body 0 first) or one per particle";

// Appended, not chained: GCC 12 at -O3 warns, wrongly, about chains of temporaries (-Wrestrict).
[[noreturn]] void fail(const std::string& origin, long line, const std::string& what, const std::string& todo) {
  std::string m = what;
  m += "; ";
  m += todo;
  throw InputError(origin, line, m);
}

// The whole of `s` as a number (strtod's syntax, so "nan" and "inf" too).
bool isNumber(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s.c_str(), &end);
  return *end == '\0';
}

std::size_t columns(const std::string& line) { return 1 + static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')); }

}  // namespace

ColorFile parseColorFile(const std::string& text, const std::string& origin) {
  ColorFile out;
  out.origin = origin;
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(trim(line));
  }
  if (!lines.empty() && lines[0].compare(0, 3, "\xEF\xBB\xBF") == 0) lines[0] = trim(lines[0].substr(3));
  while (!lines.empty() && lines.back().empty()) lines.pop_back();  // blank lines at the end
  if (lines.empty()) fail(origin, 0, "the file is empty", kFormat);

  std::string header = lines[0];
  if (header.size() >= 2 && header.front() == '"' && header.back() == '"') header = trim(header.substr(1, header.size() - 2));
  double v = 0.0;
  if (header.empty()) fail(origin, 1, "the header is missing (the first line is blank)", kFormat);
  if (isNumber(header, v))
    fail(origin, 1, "the header is missing: the first line is the number " + header,
         "add a first line naming the values (e.g. value or stress kPa), which the legend shows");
  if (columns(header) > 1)
    fail(origin, 1, "expected one column, got " + std::to_string(columns(header)) + " (" + header + ")", kFormat);
  if (header.size() > kMaxColorFileName)
    fail(origin, 1, "the header is " + std::to_string(header.size()) + " characters long",
         "the legend shows at most " + std::to_string(kMaxColorFileName) + ": shorten it");
  out.name = header;

  for (std::size_t i = 1; i < lines.size(); ++i) {
    const long lineNo = static_cast<long>(i) + 1;
    const std::string& s = lines[i];
    if (s.empty())
      fail(origin, lineNo, "a blank line among the values",
           "every body (or particle) needs a value, one per line: fill it in or remove the line");
    if (columns(s) > 1)
      fail(origin, lineNo, "expected one value, got " + std::to_string(columns(s)) + " columns (" + s + ")", kFormat);
    if (!isNumber(s, v)) fail(origin, lineNo, "expected a number, got '" + s + "'", "write one number per line");
    if (!std::isfinite(v)) fail(origin, lineNo, "'" + s + "' is not a finite number", "every value must be finite");
    if (std::abs(v) > double(FLT_MAX))
      fail(origin, lineNo, "'" + s + "' is out of range", "values are drawn as floats: within -3.4e38 to 3.4e38");
    out.values.push_back(static_cast<float>(v));
  }
  if (out.values.empty())
    fail(origin, 0, "no values after the header (" + out.name + ")",
         "add one number per line, one per body (body 0 first) or one per particle");
  return out;
}

ColorFile readColorFile(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, "cannot open the colour file (--color-file): " + std::string(std::strerror(errno)));
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw InputError(path, 0, "cannot read the colour file (--color-file)");
  return parseColorFile(s.str(), path);
}

std::vector<float> ColorFile::particleValues(const ParticleTable& table, const std::string& recording) const {
  std::size_t numBodies = 0;
  for (const std::uint32_t b : table.body) numBodies = std::max<std::size_t>(numBodies, std::size_t(b) + 1);
  const std::size_t numParticles = table.size();
  std::vector<float> out(numParticles);
  if (values.size() == numBodies) {
    for (std::size_t i = 0; i < numParticles; ++i) out[i] = values[table.body[i]];
    return out;
  }
  if (values.size() == numParticles) return values;
  const std::string bodies = std::to_string(numBodies), particles = std::to_string(numParticles);
  std::string todo = numBodies == numParticles
                         ? "give " + bodies + " values after the header, one per body (body 0 first)"
                         : "give " + bodies + " values after the header, one per body (body 0 first), or " +
                               particles + ", one per particle";
  fail(origin, 0,
       std::to_string(values.size()) + " values after the header, but " + recording + " has " + bodies +
           (numBodies == 1 ? " body" : " bodies") +
           (numBodies == numParticles ? "" : " of " + particles + " particles"),
       todo);
}

}  // namespace tumble::viewer
