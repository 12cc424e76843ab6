// SPDX-License-Identifier: MIT
// Full step of the bench scene (bodies of 8 particles) at 16k, 128k and 960k particles, threads
// swept, with the per-phase split as counters (ms per step); the guard's check against the steps
// between two checks. TUMBLE_BENCH_SMOKE=1: 16k only.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cstdlib>
#include <map>
#include <memory>

#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/validation/scenes.hpp"

namespace {

const tumble::World& benchWorld(std::uint32_t n) {
  static std::map<std::uint32_t, std::unique_ptr<tumble::World>> cache;
  auto& w = cache[n];
  if (!w) w = std::make_unique<tumble::World>(tumble::World::fromScene(tumble::validation::benchScene(n)));
  return *w;
}

std::uint64_t smokeWarmup() { return std::getenv("TUMBLE_BENCH_SMOKE") ? 20 : 500; }

void BM_Step(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  tumble::PipelineOptions o;
  o.threads = threads;
  auto p = tumble::makePipeline(tumble::Backend::Cpu, o);
  p->load(benchWorld(n));
  p->step(smokeWarmup());  // warm-up: the lattice lands and packs (the peers time steps 500–2500)
  p->resetStats();
  for (auto _ : state) p->step(1);
  const auto& st = p->stats();
  for (int ph = 0; ph < tumble::kNumPhases; ++ph)
    state.counters[std::string("ms_") + tumble::toString(static_cast<tumble::Phase>(ph))] =
        1e3 * st.seconds[ph] / double(st.steps);
  state.counters["pairs"] = double(st.numPairs);
  state.counters["ns_per_particle"] = benchmark::Counter(double(n) * double(state.iterations()) * 1e-9,
                                                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * n);
}

// The guard's check against the steps between two checks (tumble run without a recording checks
// every kDefaultGuardEvery steps): the iteration time is the check alone; guard_share is the
// check's time over the steps' time, check_steps the check in steps.
void BM_GuardCheck(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const auto n = static_cast<std::uint32_t>(state.range(0));
  tumble::PipelineOptions o;
  o.threads = static_cast<int>(state.range(1));
  auto p = tumble::makePipeline(tumble::Backend::Cpu, o);
  p->load(benchWorld(n));
  tumble::RunGuard guard(benchWorld(n), *p);
  p->step(smokeWarmup());
  const std::uint64_t every = tumble::kDefaultGuardEvery;
  double stepSeconds = 0.0, checkSeconds = 0.0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    p->step(every);
    const auto t1 = Clock::now();
    const auto trip = guard.check(*p);
    const auto t2 = Clock::now();
    if (trip) state.SkipWithError(trip->message.c_str());
    stepSeconds += std::chrono::duration<double>(t1 - t0).count();
    const double c = std::chrono::duration<double>(t2 - t1).count();
    checkSeconds += c;
    state.SetIterationTime(c);
  }
  const double perStep = stepSeconds / (double(every) * double(state.iterations()));
  state.counters["guard_share"] = stepSeconds > 0.0 ? checkSeconds / stepSeconds : 0.0;
  state.counters["check_steps"] = perStep > 0.0 ? checkSeconds / double(state.iterations()) / perStep : 0.0;
  state.counters["ms_per_step"] = 1e3 * perStep;
}

// CUDA pipeline: the phase times come from CUDA events, so the iteration time is their sum
// (manual time); one untimed warm-up covers context creation and lazy kernel loading.
void BM_StepCuda(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  auto p = tumble::makePipeline(tumble::Backend::Cuda);
  p->load(benchWorld(n));
  p->step(smokeWarmup());
  p->resetStats();
  for (auto _ : state) {
    const double before = p->stats().totalSeconds();
    p->step(1);
    state.SetIterationTime(p->stats().totalSeconds() - before);
  }
  const auto& st = p->stats();
  for (int ph = 0; ph < tumble::kNumPhases; ++ph)
    state.counters[std::string("ms_") + tumble::toString(static_cast<tumble::Phase>(ph))] =
        1e3 * st.seconds[ph] / double(st.steps);
  state.counters["pairs"] = double(st.numPairs);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * n);
}

void registerAll() {
  if (tumble::cudaAvailable()) {
    auto* c = benchmark::RegisterBenchmark("BM_StepCuda", BM_StepCuda);
    for (long n : {16000L, 128000L, 960000L, 4000000L, 10000000L})
      if (!std::getenv("TUMBLE_BENCH_SMOKE") || n == 16000) c->Arg(n);
    c->ArgName("particles")->UseManualTime()->Unit(benchmark::kMillisecond);
  }
  const bool smoke = std::getenv("TUMBLE_BENCH_SMOKE") != nullptr;
  auto* b = benchmark::RegisterBenchmark("BM_Step", BM_Step);
  for (long n : {16000L, 128000L, 960000L}) {
    if (smoke && n != 16000) continue;
    for (long t : {1L, 2L}) b->Args({n, t});
  }
  b->ArgNames({"particles", "threads"})->UseRealTime()->Unit(benchmark::kMillisecond);
  auto* g = benchmark::RegisterBenchmark("BM_GuardCheck", BM_GuardCheck);
  for (long n : {16000L, 128000L, 960000L})
    if (!smoke || n == 16000) g->Args({n, 2});
  g->ArgNames({"particles", "threads"})->UseManualTime()->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::AddCustomContext("pipeline", tumble::cudaAvailable() ? "cpu,cuda" : "cpu");
#ifdef NDEBUG
  benchmark::AddCustomContext("build", "release");
#else
  benchmark::AddCustomContext("build", "debug");
#endif
  registerAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
