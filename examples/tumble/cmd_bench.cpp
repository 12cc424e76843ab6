// SPDX-License-Identifier: MIT
// `tumble bench`: the report's performance table (SPEC §7) for the pipelines in this build.
// Full steps (contacts, integration, and the rebuilds of the candidate list they need) of the
// bench scene or of any scene file, timed over a window of steps as the peers time theirs
// (steps 500–2500 by default): the mean over the window includes the rebuilds, which a median
// would hide. The window is stepped in calls of kCall steps, as a run steps between its outputs:
// the CUDA pipeline takes a call's steps with no host round trip between them (one per step
// would be timed otherwise); the median is that of the calls, per step.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "commands.hpp"
#include "tumble/cpu/bandwidth.hpp"
#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/scenes.hpp"

namespace tumble::cli {
namespace {

struct BenchOptions {
  std::vector<std::uint32_t> sizes{16000, 128000, 960000};
  std::vector<std::string> scenes;  // scene files instead of the bench scene
  std::vector<std::string> sets;    // overrides of the scene files' keys
  std::vector<int> threads{0};
  std::vector<std::string> pipelines{"cpu"};
  std::optional<float> skin;
  int warmup = 500;  // the peers time steps 500–2500: by then the lattice is landing and packing
  int steps = 2000;
};

struct Row {
  std::string scene;
  std::uint32_t n;
  std::string pipeline;
  int threads;
  double meanMs, medianMs;
  StepStats stats;
  double trafficBytes;  // Pipeline::stepTraffic(), summed (0: not counted)
};

Row benchOne(const World& world, const std::string& name, const std::string& pl, int threads,
             const BenchOptions& o) {
  PipelineOptions po;
  po.threads = threads;
  requireBackend(backendFromString(pl));
  auto p = makePipeline(backendFromString(pl), po);
  p->load(world);
  std::fprintf(stderr, "bench: %s (%u particles), %s, threads %s: %d warm-up steps...", name.c_str(),
               world.numParticles(), pl.c_str(), threads ? std::to_string(threads).c_str() : "all", o.warmup);
  p->step(static_cast<std::uint64_t>(o.warmup));
  p->resetStats();
  std::fprintf(stderr, " %d timed steps...", o.steps);
  constexpr int kCall = 16;
  std::vector<double> ms;  // per call, per step
  ms.reserve(static_cast<std::size_t>(o.steps / kCall + 1));
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < o.steps; s += kCall) {
    const int k = std::min(kCall, o.steps - s);
    const auto t0 = std::chrono::steady_clock::now();
    p->step(static_cast<std::uint64_t>(k));
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / k);
  }
  const double total = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::sort(ms.begin(), ms.end());
  double traffic = 0.0;
  for (const TrafficLine& l : p->stepTraffic()) traffic += l.bytes;
  Row r{name, world.numParticles(), pl, threads, total / o.steps, ms[ms.size() / 2], p->stats(), traffic};
  std::fprintf(stderr, " %.3f ms/step, %.1f ns per particle-step\n", r.meanMs, 1e6 * r.meanMs / r.n);
  return r;
}

void bench(BenchOptions o) {
  if (o.steps < 1) throw Error("--steps must be >= 1");
  std::vector<std::pair<std::string, World>> worlds;
  if (!o.scenes.empty()) {
    for (const auto& f : o.scenes) worlds.emplace_back(f, World::fromScene(readSceneFile(f, o.sets)));
  } else {
    // The bench scene is built in code, not read: there is no file for --set to change.
    if (!o.sets.empty())
      throw Error("--set changes the keys of scene files and needs --scene FILE; the bench scene is built in code "
                  "(scenes/bench-16k.toml, bench-128k.toml and bench-960k.toml are the same scenes as files)");
    for (std::uint32_t n : o.sizes) {
      if (n == 0 || n % 8 != 0) throw Error("--sizes: " + std::to_string(n) + " is not a positive multiple of 8");
      worlds.emplace_back("bench-" + std::to_string(n), World::fromScene(validation::benchScene(n)));
    }
  }
  if (o.skin) {
    if (!(*o.skin >= 0.0f) || !std::isfinite(*o.skin)) throw Error("--skin must be a finite number >= 0");
    for (auto& w : worlds) w.second.params.broadphase.skin = *o.skin;
  }
  std::vector<Row> rows;
  for (const auto& [name, world] : worlds)
    for (const auto& pl : o.pipelines)
      for (int t : o.threads) rows.push_back(benchOne(world, name, pl, t, o));
  // The memory floor of the CPU rows: their bytes per step over this machine's streaming
  // bandwidth, measured now on the same threads (docs/performance.md, "The memory floor").
  std::vector<cpu::Bandwidth> bandwidths;
  for (int t : o.threads) {
    if (std::none_of(rows.begin(), rows.end(), [&](const Row& r) { return r.threads == t && r.trafficBytes > 0.0; }))
      continue;
    std::fprintf(stderr, "bench: streaming bandwidth on %s threads...", t ? std::to_string(t).c_str() : "all");
    bandwidths.push_back(cpu::streamingBandwidth(t));
    bandwidths.back().threads = t;
    std::fprintf(stderr, " %.1f GB/s\n", 1e-9 * bandwidths.back().bytesPerSecond);
  }
  const auto bandwidthOf = [&](int t) {
    for (const cpu::Bandwidth& b : bandwidths)
      if (b.threads == t) return b.bytesPerSecond;
    return 0.0;
  };

  std::printf("Full steps (contacts, integration and the rebuilds of the candidate list they need), timed over "
              "steps %d to %d; threads 0 = all cores.\n",
              o.warmup, o.warmup + o.steps);
  std::printf("ms/step: mean over the window (rebuilds included), stepped in calls of 16 steps; median ms: the "
              "median of the calls, per step; ns: per particle-step; rebuilds and near-list refreshes per 1000 "
              "steps; phase columns: mean ms per step; floor: the bytes a step moves per particle "
              "(Pipeline::stepTraffic()), the time they take at the streaming bandwidth below, and the step as a "
              "multiple of it.\n");
  for (const cpu::Bandwidth& b : bandwidths)
    std::printf("Streaming bandwidth, threads %d: %.1f GB/s (bytes read + written; the best of 5 copies of %.0f MiB)\n",
                b.threads, 1e-9 * b.bytesPerSecond, double(b.bufferBytes) / double(1u << 20));
  std::printf("\n");
  std::printf("| scene | particles | report (Intel Iris 6100) | pipeline | threads | ms/step | median ms | ns | "
              "speedup vs cpu | contacts | skin | rebuilds/1000 | near/1000 |");
  for (int ph = 0; ph < kNumPhases; ++ph) std::printf(" %s |", toString(static_cast<Phase>(ph)));
  std::printf(" floor B | floor ns | x floor |");
  std::printf("\n|---|---|---|---|---|---|---|---|---|---|---|---|---|");
  for (int ph = 0; ph < kNumPhases; ++ph) std::printf("---|");
  std::printf("---|---|---|\n");
  for (const Row& r : rows) {
    const char* rep = r.n == 16000 ? "3.9 ms" : r.n == 128000 ? "12 ms" : r.n == 960000 ? "87 ms" : "-";
    // Speedup against the fastest CPU row of the same scene.
    double cpuBest = 0.0;
    for (const Row& q : rows)
      if (q.scene == r.scene && q.pipeline == "cpu" && (cpuBest == 0.0 || q.meanMs < cpuBest)) cpuBest = q.meanMs;
    char speedup[32] = "-";
    if (cpuBest > 0.0) std::snprintf(speedup, sizeof speedup, "%.2fx", cpuBest / r.meanMs);
    std::printf("| %s | %u | %s | %s | %d | %.3f | %.3f | %.1f | %s | %llu | %g | %.1f | %.1f |", r.scene.c_str(), r.n, rep,
                r.pipeline.c_str(), r.threads, r.meanMs, r.medianMs, 1e6 * r.meanMs / r.n, speedup,
                static_cast<unsigned long long>(r.stats.numPairs), r.stats.skin, r.stats.rebuildsPer1000(),
                r.stats.per1000(r.stats.numNearRefreshes));
    for (int ph = 0; ph < kNumPhases; ++ph)
      std::printf(" %.3f |", 1e3 * r.stats.seconds[ph] / double(std::max<std::uint64_t>(1, r.stats.steps)));
    const double bw = bandwidthOf(r.threads);
    if (r.trafficBytes > 0.0 && bw > 0.0) {
      const double floorNs = 1e9 * r.trafficBytes / bw / r.n, stepNs = 1e6 * r.meanMs / r.n;
      std::printf(" %.0f | %.2f | %.1f |\n", r.trafficBytes / r.n, floorNs, stepNs / floorNs);
    } else {
      std::printf(" - | - | - |\n");
    }
  }
}

}  // namespace

void addBench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* c = app.add_subcommand("bench", "Time the steps of the bench scene (or of scene files) per pipeline, size and thread count on this machine: ms per step, its phases and the memory floor (the bytes a step moves at a streaming bandwidth measured here)");
  c->add_option("--sizes", o->sizes, "Particle counts of the bench scene (multiples of 8)")->delimiter(',')
      ->check(countIn(8, 100000000));
  c->add_option("--scene", o->scenes, "Time these scene files instead of the bench scene")->delimiter(',');
  addSetOption(c, o->sets, "; applies to every --scene file (and needs one); --skin wins over it");
  c->add_option("--threads", o->threads, "Thread counts to sweep, 0 = all cores")->delimiter(',')
      ->check(countIn(0, kMaxThreads));
  c->add_option("--pipeline", o->pipelines, "Pipelines to time, comma-separated (default cpu)")->delimiter(',')
      ->check(pipelineName());
  c->add_option("--skin", o->skin, "Verlet skin (0 = detect every step; default: the scene's, else automatic)");
  c->add_option("--warmup", o->warmup, "Untimed steps before the window")->check(CLI::NonNegativeNumber);
  c->add_option("--steps", o->steps, "Steps in the timed window")->check(CLI::PositiveNumber);
  c->callback([o] { bench(*o); });
}

}  // namespace tumble::cli
