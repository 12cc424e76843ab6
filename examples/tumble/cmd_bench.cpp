// SPDX-License-Identifier: MIT
// `tumble bench`: the report's performance table (SPEC §7) for the pipelines in this build.
// Full step (detection, response, integration) of the bench scene, medians over timed steps.
#include <algorithm>
#include <chrono>
#include <memory>
#include <sstream>
#include <vector>

#include "commands.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/validation/scenes.hpp"

namespace tumble::cli {
namespace {

struct BenchOptions {
  std::vector<std::uint32_t> sizes{16000, 128000, 960000};
  std::vector<int> threads{0};
  std::vector<std::string> pipelines{"cpu"};
  int warmup = 500;  // the peers time steps 500–2500: by then the lattice has landed and packs
  int steps = 20;
};

struct Row {
  std::uint32_t n;
  std::string pipeline;
  int threads;
  double medianMs, minMs;
  StepStats stats;
};

void bench(const BenchOptions& o) {
  std::vector<Row> rows;
  for (std::uint32_t n : o.sizes) {
    const World world = World::fromScene(validation::benchScene(n));
    for (const auto& pl : o.pipelines)
      for (int t : o.threads) {
        PipelineOptions po;
        po.threads = t;
        auto p = makePipeline(backendFromString(pl), po);
        p->load(world);
        if (backendFromString(pl) == Backend::Cuda && !cudaAvailable())
          throw Error("--pipeline cuda: this build of tumble has no CUDA pipeline or no CUDA device");
        std::fprintf(stderr, "bench: %u particles, %s, threads %s: %d warm-up steps...", n, pl.c_str(),
                     t ? std::to_string(t).c_str() : "all", o.warmup);
        p->step(static_cast<std::uint64_t>(o.warmup));  // the lattice falls and packs: contacts appear
        p->resetStats();
        std::vector<double> ms;
        for (int s = 0; s < o.steps; ++s) {
          const auto t0 = std::chrono::steady_clock::now();
          p->step(1);
          ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        std::sort(ms.begin(), ms.end());
        rows.push_back({n, pl, t, ms[ms.size() / 2], ms.front(), p->stats()});
        std::fprintf(stderr, " median %.2f ms\n", rows.back().medianMs);
      }
  }
  std::printf("Full step (detection, response, integration), bench scene: bodies of 8 particles.\n");
  std::printf("Median of %d timed steps after %d warm-up steps; threads 0 = all cores.\n\n", o.steps, o.warmup);
  std::printf("| particles | report (Intel Iris 6100) | [1] (Tesla C1060, detection) | pipeline | threads | "
              "median ms | min ms | speedup vs cpu | pairs |");
  for (int ph = 0; ph < kNumPhases; ++ph) std::printf(" %s |", toString(static_cast<Phase>(ph)));
  std::printf("\n|---|---|---|---|---|---|---|---|---|");
  for (int ph = 0; ph < kNumPhases; ++ph) std::printf("---|");
  std::printf("\n");
  for (const Row& r : rows) {
    const char* rep = r.n == 16000 ? "3.9 ms" : r.n == 128000 ? "12 ms" : r.n == 960000 ? "87 ms" : "-";
    const char* ref = r.n == 16000 ? "3 ms" : r.n == 128000 ? "11 ms" : r.n == 960000 ? "161 ms" : "-";
    // Speedup against the fastest CPU row of the same size.
    double cpuBest = 0.0;
    for (const Row& q : rows)
      if (q.n == r.n && q.pipeline == "cpu" && (cpuBest == 0.0 || q.medianMs < cpuBest)) cpuBest = q.medianMs;
    const std::string speedup = cpuBest > 0.0 ? std::to_string(cpuBest / r.medianMs).substr(0, 5) + "x" : "-";
    std::printf("| %u | %s | %s | %s | %d | %.2f | %.2f | %s | %llu |", r.n, rep, ref, r.pipeline.c_str(), r.threads,
                r.medianMs, r.minMs, speedup.c_str(), static_cast<unsigned long long>(r.stats.numPairs));
    for (int ph = 0; ph < kNumPhases; ++ph)
      std::printf(" %.2f |", 1e3 * r.stats.seconds[ph] / double(std::max<std::uint64_t>(1, r.stats.steps)));
    std::printf("\n");
  }
  std::printf("\nPhase columns: mean ms per step. ns per particle-step = median ms x 1e6 / particles.\n");
}

}  // namespace

void addBench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* c = app.add_subcommand("bench", "Print the report's step-time table (SPEC §7) for this machine");
  c->add_option("--sizes", o->sizes, "Particle counts (multiples of 8)")->delimiter(',');
  c->add_option("--threads", o->threads, "Thread counts to sweep, 0 = all cores")->delimiter(',');
  c->add_option("--pipeline", o->pipelines, "Pipelines: cpu and/or cuda")->delimiter(',')
      ->check(CLI::IsMember({"cpu", "cuda"}));
  c->add_option("--warmup", o->warmup, "Untimed steps before timing")->check(CLI::NonNegativeNumber);
  c->add_option("--steps", o->steps, "Timed steps per configuration")->check(CLI::PositiveNumber);
  c->callback([o] { bench(*o); });
}

}  // namespace tumble::cli
