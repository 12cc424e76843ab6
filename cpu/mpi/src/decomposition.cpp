// SPDX-License-Identifier: MIT
// The decomposition of the domain among the ranks (tumble/mpi/decomposition.hpp). Nothing here
// reaches a result: it decides which rank computes which body, and every rank computes the
// same answer from the same gathered state (a total order, integer arithmetic).
#include "tumble/mpi/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "tumble/error.hpp"

namespace tumble::mpi {
namespace {

float coord(const Vec3f& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// The axis of the longest extent of the centres of bodies [first, last) (the lowest axis among equals).
int longestAxis(const std::vector<Vec3f>& centres, const std::uint32_t* first, const std::uint32_t* last) {
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  float hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (const std::uint32_t* b = first; b != last; ++b)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], coord(centres[*b], a));
      hi[a] = std::max(hi[a], coord(centres[*b], a));
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (double(hi[a]) - lo[a] > double(hi[axis]) - lo[axis]) axis = a;
  return axis;
}

struct Cutter {
  const std::vector<Vec3f>& centres;
  const std::vector<std::uint32_t>& particles;
  Decomposition how;
  int wholeAxis;
  std::vector<int>& owner;

  void cut(std::uint32_t* first, std::uint32_t* last, int rank0, int ranks) {
    if (first == last) return;  // ranks without bodies
    if (ranks == 1) {
      for (std::uint32_t* b = first; b != last; ++b) owner[*b] = rank0;
      return;
    }
    const int axis = how == Decomposition::Slabs ? wholeAxis : longestAxis(centres, first, last);
    std::sort(first, last, [&](std::uint32_t a, std::uint32_t b) {
      const float ca = coord(centres[a], axis), cb = coord(centres[b], axis);
      return ca != cb ? ca < cb : a < b;  // a total order: the same on every rank
    });
    const int below = ranks / 2;
    std::uint64_t total = 0;
    for (std::uint32_t* b = first; b != last; ++b) total += particles[*b];
    // The cut m whose particles below, times `ranks`, are closest to total × below (exact in
    // integers); the first such m.
    const std::uint64_t target = total * std::uint64_t(below);
    std::uint64_t sum = 0;
    std::uint32_t* m = first;
    while (m != last && (sum + particles[*m]) * std::uint64_t(ranks) <= target) sum += particles[*m++];
    if (m != last) {
      const std::uint64_t under = target - sum * std::uint64_t(ranks);
      const std::uint64_t over = (sum + particles[*m]) * std::uint64_t(ranks) - target;
      if (over < under) sum += particles[*m++];
    }
    cut(first, m, rank0, below);
    cut(m, last, rank0 + below, ranks - below);
  }
};

}  // namespace

const char* toString(Decomposition d) { return d == Decomposition::Slabs ? "slabs" : "rcb"; }

Decomposition decompositionFromString(const std::string& s) {
  if (s == "rcb") return Decomposition::Rcb;
  if (s == "slabs") return Decomposition::Slabs;
  throw Error("unknown decomposition '" + s + "': expected rcb or slabs");
}

std::vector<int> decompose(const std::vector<Vec3f>& centres, const std::vector<std::uint32_t>& particles, int ranks,
                           Decomposition how) {
  const std::size_t nb = centres.size();
  std::vector<int> owner(nb, 0);
  if (nb == 0 || ranks <= 1) return owner;
  std::vector<std::uint32_t> order(nb);
  std::iota(order.begin(), order.end(), 0u);
  Cutter c{centres, particles, how, longestAxis(centres, order.data(), order.data() + nb), owner};
  c.cut(order.data(), order.data() + nb, 0, ranks);
  return owner;
}

double haloReach(float maxRadius, float haloSkin, double largestCoordinate) {
  return (2.0 * double(maxRadius) + double(haloSkin)) * (1.0 + 1e-3) + 1e-6 * largestCoordinate;
}

std::vector<std::vector<std::uint32_t>> ghostsOf(const std::vector<int>& owner, const std::vector<float>& positions,
                                                 const std::vector<std::uint32_t>& first,
                                                 const std::vector<std::uint32_t>& count, int ranks, double reach) {
  struct Box {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    bool empty() const { return lo[0] > hi[0]; }
    bool holds(const float* x) const {
      for (int a = 0; a < 3; ++a)
        if (!(x[a] >= lo[a] && x[a] <= hi[a])) return false;
      return true;
    }
  };
  std::vector<Box> box(static_cast<std::size_t>(ranks));
  const std::size_t nb = owner.size();
  for (std::size_t k = 0; k < nb; ++k) {
    Box& b = box[static_cast<std::size_t>(owner[k])];
    for (std::uint32_t i = first[k]; i < first[k] + count[k]; ++i)
      for (int a = 0; a < 3; ++a) {
        const double x = positions[3 * std::size_t(i) + a];
        b.lo[a] = std::min(b.lo[a], x);
        b.hi[a] = std::max(b.hi[a], x);
      }
  }
  for (Box& b : box)
    if (!b.empty())
      for (int a = 0; a < 3; ++a) {
        b.lo[a] -= reach;
        b.hi[a] += reach;
      }
  std::vector<std::vector<std::uint32_t>> ghosts(static_cast<std::size_t>(ranks));
  for (std::size_t k = 0; k < nb; ++k)
    for (int r = 0; r < ranks; ++r) {
      const Box& b = box[static_cast<std::size_t>(r)];
      if (r == owner[k] || b.empty()) continue;
      for (std::uint32_t i = first[k]; i < first[k] + count[k]; ++i)
        if (b.holds(&positions[3 * std::size_t(i)])) {
          ghosts[static_cast<std::size_t>(r)].push_back(static_cast<std::uint32_t>(k));
          break;
        }
    }
  return ghosts;
}

}  // namespace tumble::mpi
