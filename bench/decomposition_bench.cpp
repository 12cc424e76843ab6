// SPDX-License-Identifier: MIT
// The MPI decomposition on the bench scenes' clumps at their initial positions (docs/mpi.md,
// docs/performance.md#mpi-communication-and-a-scaling-model): for 2 to 64 ranks, recursive
// bisection and slabs, the time to cut the domain and find every rank's halo (what each rank
// computes at a redistribution), and as counters the particles per rank, the ghosts (mean and
// largest), the largest halo as a share of a rank's particles, the most neighbours and the most
// bytes a rank sends per step (a BodyMotion row, 108 bytes, a ghost body). The halo's reach is the
// one a run with the automatic skin uses (haloReach() of twice that skin). TUMBLE_BENCH_SMOKE=1:
// 16 000 particles, 4 ranks.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "tumble/cpu/cpu_pipeline.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/mpi/decomposition.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/world.hpp"

namespace {

struct Layout {
  std::vector<tumble::Vec3f> centres;
  std::vector<std::uint32_t> first, count;
  std::vector<float> positions;
  double reach = 0.0;
};

const Layout& layoutOf(std::uint32_t particles) {
  static std::uint32_t cached = 0;
  static Layout l;
  if (cached == particles) return l;
  const tumble::World w = tumble::World::fromScene(tumble::validation::benchScene(particles));
  l = Layout{};
  l.first = w.first;
  l.count = w.numParticlesOf;
  for (std::uint32_t k = 0; k < w.numBodies(); ++k) {
    const tumble::Vec3f X{w.state.px[k], w.state.py[k], w.state.pz[k]};
    const tumble::Mat3f R = tumble::rotationMatrix(tumble::Quatf{w.state.qw[k], w.state.qx[k], w.state.qy[k], w.state.qz[k]});
    l.centres.push_back(X);
    for (std::uint32_t i = w.first[k]; i < w.first[k] + w.numParticlesOf[k]; ++i) {
      const tumble::Vec3f x = tumble::particlePosition(X, R, tumble::Vec3f{w.ux[i], w.uy[i], w.uz[i]});
      l.positions.insert(l.positions.end(), {x.x, x.y, x.z});
    }
  }
  double largest = 0.0;
  for (const float c : l.positions) largest = std::max(largest, std::abs(double(c)));
  l.reach = tumble::mpi::haloReach(w.maxRadius, tumble::mpi::kHaloSkinPerSkin * tumble::effectiveSkin(w), largest);
  cached = particles;
  return l;
}

void BM_Decomposition(benchmark::State& state) {
  const auto particles = static_cast<std::uint32_t>(state.range(0));
  const int ranks = static_cast<int>(state.range(1));
  const auto how = state.range(2) ? tumble::mpi::Decomposition::Slabs : tumble::mpi::Decomposition::Rcb;
  const Layout& l = layoutOf(particles);
  std::vector<int> owner;
  std::vector<std::vector<std::uint32_t>> ghosts;
  for (auto _ : state) {
    owner = tumble::mpi::decompose(l.centres, l.count, ranks, how);
    ghosts = tumble::mpi::ghostsOf(owner, l.positions, l.first, l.count, ranks, l.reach);
  }
  std::vector<double> owned(static_cast<std::size_t>(ranks), 0.0), sent(static_cast<std::size_t>(ranks), 0.0);
  for (std::size_t k = 0; k < owner.size(); ++k) owned[static_cast<std::size_t>(owner[k])] += l.count[k];
  double ghostMean = 0.0, ghostMax = 0.0, shareMax = 0.0, neighboursMax = 0.0;
  for (int r = 0; r < ranks; ++r) {
    double g = 0.0;
    std::set<int> from;
    for (const std::uint32_t k : ghosts[static_cast<std::size_t>(r)]) {
      g += l.count[k];
      from.insert(owner[k]);
      sent[static_cast<std::size_t>(owner[k])] += double(sizeof(tumble::BodyMotion));  // a ghost row
    }
    ghostMean += g / ranks;
    ghostMax = std::max(ghostMax, g);
    shareMax = std::max(shareMax, owned[static_cast<std::size_t>(r)] > 0 ? g / owned[static_cast<std::size_t>(r)] : 0.0);
    neighboursMax = std::max(neighboursMax, double(from.size()));
  }
  state.counters["owned"] = double(particles) / ranks;
  state.counters["ghosts_mean"] = ghostMean;
  state.counters["ghosts_max"] = ghostMax;
  state.counters["halo_max"] = shareMax;
  state.counters["neighbours_max"] = neighboursMax;
  state.counters["sent_B_max"] = *std::max_element(sent.begin(), sent.end());
}

}  // namespace

int main(int argc, char** argv) {
  const bool smoke = std::getenv("TUMBLE_BENCH_SMOKE") != nullptr;
  auto* b = benchmark::RegisterBenchmark("BM_Decomposition", BM_Decomposition);
  b->ArgNames({"particles", "ranks", "slabs"})->Unit(benchmark::kMillisecond);
  if (smoke) {
    b->Args({16000, 4, 0});
  } else {
    for (const int particles : {128000, 960000})
      for (const int slabs : {0, 1})
        for (const int ranks : {2, 4, 8, 16, 32, 64}) b->Args({particles, ranks, slabs});
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
