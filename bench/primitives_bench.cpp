// SPDX-License-Identifier: MIT
// Benchmarks of the TBB primitives: radixSortPairs<uint64_t, uint32_t> on 41-bit keys (the width
// of our cell keys) with uniform and clustered keys, and exclusiveSum<uint32_t> on small counts.
// Axes: n = 4^k from 2^10 to 2^22 and TBB threads 1 and 2 (tbb::global_control). Times are
// real time (UseRealTime), rates are items/s. Each case is verified once before timing.
//
// The n = 2^10 case of every family is registered as "<family>/small", which is what the CTest
// smoke run selects (--benchmark_filter=/small). With TUMBLE_BENCH_SMOKE set in the environment
// only those small cases are registered.
//
// radixSortPairs/digits:<b> compares digit widths (detail::radixSort<b, ...>) at the hot-path
// sizes; detail::kRadixDigitBits was chosen from it.
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/version.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr int kKeyBits = 41;
constexpr std::uint64_t kKeyMask = (std::uint64_t{1} << kKeyBits) - 1;

enum class KeyDist { Uniform, Clustered };

/// Uniform: every 41-bit key equally likely. Clustered: 64 random centres with keys within
/// 4096 of them, like particles piled into a few regions of the grid (long runs of equal
/// high digits, many duplicate keys).
std::vector<std::uint64_t> makeKeys(KeyDist dist, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::uint64_t> keys(n);
  std::uint64_t centres[64];
  for (auto& c : centres) c = rng() & kKeyMask;
  for (auto& k : keys) {
    const std::uint64_t r = rng();
    k = dist == KeyDist::Uniform ? (r & kKeyMask) : ((centres[r & 63] + ((r >> 8) & 4095)) & kKeyMask);
  }
  return keys;
}

/// The public radixSortPairs for the default digit width, the detail template otherwise.
template <int kDigitBits>
void sortPairs(void* temp, std::size_t& tempBytes, const std::uint64_t* keysIn, std::uint64_t* keysOut,
               const std::uint32_t* valuesIn, std::uint32_t* valuesOut, std::size_t n) {
  if constexpr (kDigitBits == tumble::cpu::detail::kRadixDigitBits)
    tumble::cpu::radixSortPairs<std::uint64_t, std::uint32_t>(temp, tempBytes, keysIn, keysOut,
                                                              valuesIn, valuesOut, n, 0, kKeyBits);
  else
    tumble::cpu::detail::radixSort<kDigitBits, std::uint64_t, std::uint32_t>(
        temp, tempBytes, keysIn, keysOut, valuesIn, valuesOut, n, 0, kKeyBits);
}

template <int kDigitBits>
void benchRadixSortPairs(benchmark::State& state, KeyDist dist) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto threads = static_cast<std::size_t>(state.range(1));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);

  const std::vector<std::uint64_t> keys = makeKeys(dist, n, 42 + n);
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  std::vector<std::uint64_t> outKeys(n);
  std::vector<std::uint32_t> outValues(n);
  std::size_t tempBytes = 0;
  sortPairs<kDigitBits>(nullptr, tempBytes, keys.data(), outKeys.data(), values.data(),
                        outValues.data(), n);
  std::vector<unsigned char> temp(tempBytes);

  sortPairs<kDigitBits>(temp.data(), tempBytes, keys.data(), outKeys.data(), values.data(),
                        outValues.data(), n);
  for (std::size_t i = 0; i < n; ++i) {
    if ((i > 0 && (outKeys[i - 1] > outKeys[i] ||
                   (outKeys[i - 1] == outKeys[i] && outValues[i - 1] > outValues[i]))) ||
        keys[outValues[i]] != outKeys[i]) {
      state.SkipWithError("radixSortPairs output is not the stable sort of the input");
      return;
    }
  }

  for (auto _ : state) {
    sortPairs<kDigitBits>(temp.data(), tempBytes, keys.data(), outKeys.data(), values.data(),
                          outValues.data(), n);
    benchmark::DoNotOptimize(outKeys.data());
    benchmark::DoNotOptimize(outValues.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n));
  state.counters["threads"] = static_cast<double>(threads);
}

void benchExclusiveSum(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto threads = static_cast<std::size_t>(state.range(1));
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);

  std::mt19937_64 rng(7 + n);
  std::vector<std::uint32_t> in(n);
  for (auto& x : in) x = static_cast<std::uint32_t>(rng() % 17);  // pair counts per particle
  std::vector<std::uint32_t> out(n);
  std::size_t tempBytes = 0;
  tumble::cpu::exclusiveSum<std::uint32_t>(nullptr, tempBytes, in.data(), out.data(), n);
  std::vector<unsigned char> temp(tempBytes);

  tumble::cpu::exclusiveSum<std::uint32_t>(temp.data(), tempBytes, in.data(), out.data(), n);
  std::vector<std::uint32_t> expected(n);
  std::exclusive_scan(in.begin(), in.end(), expected.begin(), 0u);
  if (out != expected) {
    state.SkipWithError("exclusiveSum output differs from std::exclusive_scan");
    return;
  }

  for (auto _ : state) {
    tumble::cpu::exclusiveSum<std::uint32_t>(temp.data(), tempBytes, in.data(), out.data(), n);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(n));
  state.counters["threads"] = static_cast<double>(threads);
}

/// Registers `name/small` (n = 2^10) and, unless smoke, `name` over n = 4^k in [2^12, 2^22],
/// each for 1 and 2 threads.
template <class Fn>
void registerSweep(const std::string& name, Fn fn, bool smoke) {
  constexpr std::int64_t kThreads[] = {1, 2};
  auto* small = benchmark::RegisterBenchmark((name + "/small").c_str(), fn);
  small->ArgNames({"n", "threads"})->UseRealTime();
  for (const std::int64_t t : kThreads) small->Args({1 << 10, t});
  if (smoke) return;
  auto* sweep = benchmark::RegisterBenchmark(name.c_str(), fn);
  sweep->ArgNames({"n", "threads"})->UseRealTime();
  for (std::int64_t n = 1 << 12; n <= (1 << 22); n *= 4)
    for (const std::int64_t t : kThreads) sweep->Args({n, t});
}

template <int kDigitBits>
void registerDigitWidth() {
  auto* b = benchmark::RegisterBenchmark(
      ("radixSortPairs/digits:" + std::to_string(kDigitBits) + "/uniform").c_str(),
      [](benchmark::State& s) { benchRadixSortPairs<kDigitBits>(s, KeyDist::Uniform); });
  b->ArgNames({"n", "threads"})->UseRealTime();
  for (const std::int64_t n : {std::int64_t{300000}, std::int64_t{2000000}})
    for (const std::int64_t t : {1, 2}) b->Args({n, t});
}

}  // namespace

int main(int argc, char** argv) {
  const bool smoke = std::getenv("TUMBLE_BENCH_SMOKE") != nullptr;
  constexpr int kBits = tumble::cpu::detail::kRadixDigitBits;
  registerSweep("radixSortPairs/u64u32/uniform",
                [](benchmark::State& s) { benchRadixSortPairs<kBits>(s, KeyDist::Uniform); }, smoke);
  registerSweep("radixSortPairs/u64u32/clustered",
                [](benchmark::State& s) { benchRadixSortPairs<kBits>(s, KeyDist::Clustered); }, smoke);
  registerSweep("exclusiveSum/u32", benchExclusiveSum, smoke);
  if (!smoke) {
    registerDigitWidth<8>();
    registerDigitWidth<11>();
  }

  benchmark::AddCustomContext("tbb_version", TBB_VERSION_STRING);
  benchmark::AddCustomContext("tbb_default_concurrency", std::to_string(tbb::info::default_concurrency()));
  benchmark::AddCustomContext("thread_sweep", "1,2 (tbb::global_control max_allowed_parallelism)");
#ifdef NDEBUG
  benchmark::AddCustomContext("build_type", "release (NDEBUG)");
#else
  benchmark::AddCustomContext("build_type", "debug (asserts on)");
#endif
  benchmark::AddCustomContext("radix_digit_bits", std::to_string(kBits));
  benchmark::AddCustomContext("radix_block_size", std::to_string(tumble::cpu::detail::kRadixBlockSize));
  benchmark::AddCustomContext("key_bits", std::to_string(kKeyBits));

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
