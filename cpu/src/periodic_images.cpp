// SPDX-License-Identifier: MIT
// Ghost images for the detection in a periodic box (periodic_images.hpp).
//
// Design notes
// - Completeness. Wrapped into [−h, h), two particles i, j (x_i ≥ x_j on an axis) differ by D or
//   D − L through their nearest images, D in [0, L). When D − L is the one within reach, x_j
//   lies within reach of −h, so j has a ghost at x_j + L, within reach of x_i. Per axis the
//   particle nearer its lower end carries the shift; when the two axes shift different
//   particles, their two ghosts meet. Pairs found through several pairs of images are merged
//   in each particle's row (fillRow).
// - Determinism. The ghosts are numbered by a scan of per-particle counts (the particle order,
//   then x, y, corner), and each row is sorted by scene index with its duplicates dropped: the
//   rows do not depend on the threads or on how the sweep found them.
// - Rounding. A ghost's shifted coordinate and a difference across the boundary are rounded at
//   the size of the box; the skin's rounding margin has a term for it (skinClosureLimit's W),
//   and a stand-alone detection grows the radii by that margin and filters with the exact
//   predicate (CpuPipeline::findPairs).
#include "periodic_images.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "tumble/cpu/scan.hpp"
#include "grow.hpp"

namespace tumble::cpu::detail {
namespace {

constexpr std::uint32_t kGrain = 4096;

template <class F>
void forEach(std::uint32_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) f(i);
  });
}

}  // namespace

void PeriodicImages::build(const BroadphaseInput& in, const PeriodicBox& box, float reach) {
  const std::uint32_t n = in.n;
  m_n = n;
  for (auto* c : {&m_x, &m_y, &m_z, &m_r}) c->resize(n);
  m_body.resize(n);
  m_count.resize(std::size_t(n) + 1);
  m_ghostFirst.resize(std::size_t(n) + 1);
  const auto near = [&](float c, int a) { return box.on(a) && c < -box.half[a] + reach; };
  forEach(n, [&](std::uint32_t i) {
    Vec3f x{in.x[i], in.y[i], in.z[i]};
    std::int32_t image[2] = {0, 0};
    wrapIntoBox(box, &x, image);  // a particle lies within L/2 of its body's centre: one period at most
    m_x[i] = x.x;
    m_y[i] = x.y;
    m_z[i] = x.z;
    m_r[i] = in.r[i];
    m_body[i] = in.body[i];
    const bool nx = near(x.x, 0), ny = near(x.y, 1);
    m_count[i] = (nx ? 1u : 0u) + (ny ? 1u : 0u) + (nx && ny ? 1u : 0u);
  });
  m_count[n] = 0;
  std::size_t bytes = 0;
  exclusiveSum<std::uint32_t>(nullptr, bytes, m_count.data(), m_ghostFirst.data(), std::size_t(n) + 1);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, bytes), bytes, m_count.data(), m_ghostFirst.data(),
                              std::size_t(n) + 1);
  const std::uint32_t numGhosts = m_ghostFirst[n];
  for (auto* c : {&m_x, &m_y, &m_z, &m_r}) c->resize(std::size_t(n) + numGhosts);
  m_body.resize(std::size_t(n) + numGhosts);
  m_ghostOf.resize(numGhosts);
  forEach(n, [&](std::uint32_t i) {
    std::uint32_t g = m_ghostFirst[i];
    if (g == m_ghostFirst[i + 1]) return;
    const bool nx = near(m_x[i], 0), ny = near(m_y[i], 1);
    const auto add = [&](float x, float y) {
      m_x[n + g] = x;
      m_y[n + g] = y;
      m_z[n + g] = m_z[i];
      m_r[n + g] = m_r[i];
      m_body[n + g] = m_body[i];
      m_ghostOf[g++] = i;
    };
    if (nx) add(m_x[i] + box.length[0], m_y[i]);
    if (ny) add(m_x[i], m_y[i] + box.length[1]);
    if (nx && ny) add(m_x[i] + box.length[0], m_y[i] + box.length[1]);
  });
  m_in = BroadphaseInput{m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(), n + numGhosts,
                         in.maxRadius, in.cellRadius};
}

std::uint32_t PeriodicImages::rowBound(const SweepListView& s, std::uint32_t i) const {
  std::uint32_t c = candidateCount(s, i);
  for (std::uint32_t g = m_ghostFirst[i]; g < m_ghostFirst[i + 1]; ++g) c += candidateCount(s, m_n + g);
  return c;
}

std::uint32_t PeriodicImages::fillRow(const SweepListView& s, const std::uint32_t* orig, std::uint32_t i,
                                      std::uint32_t* cand, std::uint32_t* key) const {
  const auto map = [&](std::uint32_t a) { return particleOf(a); };
  std::uint32_t e = appendCandidates(s, orig, i, map, cand, key, 0);
  for (std::uint32_t g = m_ghostFirst[i]; g < m_ghostFirst[i + 1]; ++g)
    e = appendCandidates(s, orig, m_n + g, map, cand, key, e);
  tumble::detail::sortRow(key, cand, e);  // equal keys are the same partner: the order among them is moot
  std::uint32_t out = 0;
  for (std::uint32_t t = 0; t < e; ++t)
    if (t == 0 || key[t] != key[t - 1]) {
      key[out] = key[t];
      cand[out++] = cand[t];
    }
  return out;
}

}  // namespace tumble::cpu::detail
