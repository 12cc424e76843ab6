// SPDX-License-Identifier: MIT
// `tumble pairs PARTICLES.csv`: the broadphase alone. Input: header `x,y,z,r,body`, one particle
// per row. Output: `i,j` per overlapping pair (0-based rows, i < j), sorted.
#include <cerrno>
#include <cstring>
#include <memory>

#include "commands.hpp"
#include "tumble/factory.hpp"
#include "tumble/particle_csv.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::cli {
namespace {

struct PairsOptions {
  std::string file;
  int threads = 0;
  std::string pipeline = "cpu";
  float cellSize = 0.0f;
};

void pairs(const PairsOptions& o) {
  const ParticleCloud c = readParticleCsv(o.file);
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
  c->add_option("--pipeline", o->pipeline, "Pipeline (default cpu)")->check(pipelineName());
  c->add_option("--cell-size", o->cellSize, "Cell side of the 2-D subdivision (0 = automatic)")
      ->check(CLI::NonNegativeNumber);
  c->callback([o] { pairs(*o); });
}

}  // namespace tumble::cli
