// SPDX-License-Identifier: MIT
// Broadphase alone (bounds, axis, keys, sort, sweep → CSR contact list) on random clouds:
// uniform and clustered, n from 4^5 to 4^11, threads 1 and 2. The result is checked against the
// brute-force oracle once (small n) before timing. TUMBLE_BENCH_SMOKE=1: n = 1024 only.
#include <benchmark/benchmark.h>

#include <cstdlib>

#include "tumble/factory.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/random.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/scenes.hpp"

namespace {

// Uniform: density ~0.5 particles per unit³, radius 0.5. Clustered: 16 dense blobs.
tumble::ParticleCloud makeCloud(std::uint32_t n, bool clustered) {
  if (!clustered) {
    const float box = std::cbrt(float(n) / 0.5f);
    return tumble::validation::randomCloud(n, 99, box, 0.5f, 0.5f, 8);
  }
  tumble::Rng rng(7);
  tumble::ParticleCloud c;
  const float box = std::cbrt(float(n) / 0.5f) * 2.0f;
  float cx[16], cy[16], cz[16];
  for (int k = 0; k < 16; ++k) cx[k] = rng.uniform(0, box), cy[k] = rng.uniform(0, box), cz[k] = rng.uniform(0, box);
  const float blob = std::cbrt(float(n) / 16.0f / 1.0f);
  for (std::uint32_t i = 0; i < n; ++i) {
    const int k = static_cast<int>(i % 16);
    c.x.push_back(cx[k] + rng.uniform(0, blob));
    c.y.push_back(cy[k] + rng.uniform(0, blob));
    c.z.push_back(cz[k] + rng.uniform(0, blob));
    c.r.push_back(0.5f);
    c.body.push_back(i / 8);
  }
  return c;
}

void BM_Broadphase(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const bool clustered = state.range(1) != 0;
  tumble::PipelineOptions o;
  o.threads = static_cast<int>(state.range(2));
  auto p = tumble::makePipeline(tumble::Backend::Cpu, o);
  const auto cloud = makeCloud(n, clustered);
  if (n <= 4096 && p->findPairs(cloud, {}) != tumble::validation::bruteForcePairs(cloud)) {
    state.SkipWithError("pair set differs from the brute-force oracle");
    return;
  }
  std::size_t pairs = 0;
  for (auto _ : state) pairs = p->findPairs(cloud, {}).size();
  state.counters["pairs_per_particle"] = double(pairs) / double(n);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * n);
}

}  // namespace

int main(int argc, char** argv) {
  const bool smoke = std::getenv("TUMBLE_BENCH_SMOKE") != nullptr;
  auto* b = benchmark::RegisterBenchmark("BM_Broadphase", BM_Broadphase);
  for (long n = 1024; n <= (smoke ? 1024 : (1L << 22)); n *= 4)
    for (long dist : {0L, 1L})
      for (long t : {1L, 2L}) b->Args({n, dist, t});
  b->ArgNames({"n", "clustered", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
  benchmark::AddCustomContext("pipeline", "cpu");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
