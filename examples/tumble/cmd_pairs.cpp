// SPDX-License-Identifier: MIT
// `tumble pairs PARTICLES.csv`: the broadphase alone. Input: header `x,y,z,r,body`, one particle
// per row. Output: `i,j` per overlapping pair (0-based rows, i < j), sorted.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "commands.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::cli {
namespace {

struct PairsOptions {
  std::string file;
  int threads = 0;
  std::string pipeline = "cpu";
  float cellSize = 0.0f;
};

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

ParticleCloud readCloud(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string line;
  long lineNo = 0;
  if (!std::getline(in, line)) throw InputError(path, 1, "empty file; expected the header line x,y,z,r,body");
  ++lineNo;
  // A NUL byte would end a field early for strtof (0.9<NUL>garbage read as 0.9).
  const auto noNul = [&] {
    if (line.find('\0') != std::string::npos)
      throw InputError(path, lineNo, "contains a NUL byte (is this a text CSV file?)");
  };
  noNul();
  {
    std::string h;
    for (char c : line)
      if (c != ' ' && c != '\t' && c != '\r') h += c;
    if (h != "x,y,z,r,body") throw InputError(path, 1, "header must be x,y,z,r,body (got '" + trim(line) + "')");
  }
  ParticleCloud c;
  static const char* names[5] = {"x", "y", "z", "r", "body"};
  while (std::getline(in, line)) {
    ++lineNo;
    noNul();
    if (trim(line).empty()) continue;
    std::string field[5];
    int nf = 0;
    std::size_t start = 0;
    for (;;) {
      const auto comma = line.find(',', start);
      if (nf == 5) throw InputError(path, lineNo, "too many fields (expected 5: x,y,z,r,body)");
      field[nf++] = trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
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
  if (in.bad()) throw InputError(path, lineNo, "read error");
  return c;
}

void pairs(const PairsOptions& o) {
  const ParticleCloud c = readCloud(o.file);
  PipelineOptions po;
  po.threads = o.threads;
  auto p = makePipeline(backendFromString(o.pipeline), po);
  BroadphaseParams bp;
  bp.cellSize = o.cellSize;
  bp.pcaEvery = 1;
  const auto result = p->findPairs(c, bp);
  // Streamed in blocks: the text is not held as a whole next to the pairs.
  std::string out;
  out.reserve(1 << 20);
  char buf[32];
  const auto flush = [&] {
    if (std::fwrite(out.data(), 1, out.size(), stdout) != out.size())
      throw Error(std::string("cannot write the pairs to standard output: ") + std::strerror(errno));
    out.clear();
  };
  for (const Pair& pr : result) {
    const int len = std::snprintf(buf, sizeof buf, "%u,%u\n", pr.i, pr.j);
    out.append(buf, static_cast<std::size_t>(len));
    if (out.size() > (1u << 20) - 32) flush();
  }
  flush();
  if (std::fflush(stdout) != 0)
    throw Error(std::string("cannot write the pairs to standard output: ") + std::strerror(errno));
}

}  // namespace

void addPairs(CLI::App& app) {
  auto o = std::make_shared<PairsOptions>();
  CLI::App* c = app.add_subcommand("pairs", "Broadphase alone: print every overlapping pair i,j of a CSV particle list");
  c->add_option("particles", o->file, "CSV file: header x,y,z,r,body then one particle per row")->required();
  c->add_option("--threads", o->threads, "Worker threads, 0 = all cores")->check(countIn(0, kMaxThreads));
  c->add_option("--pipeline", o->pipeline, "Pipeline: cpu or cuda")->check(CLI::IsMember({"cpu", "cuda"}));
  c->add_option("--cell-size", o->cellSize, "Cell side of the 2-D subdivision (0 = automatic)")
      ->check(CLI::NonNegativeNumber);
  c->callback([o] { pairs(*o); });
}

}  // namespace tumble::cli
