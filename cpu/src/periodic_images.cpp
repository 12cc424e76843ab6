// SPDX-License-Identifier: MIT
// Ghost images for the detection in a periodic box (periodic_images.hpp): the count → scan →
// fill of kernels/periodic_images.hpp over the particles.
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
  forEach(n, [&](std::uint32_t i) {
    m_count[i] = wrapImage(in, box, reach, i, m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data());
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
    writeGhosts(box, reach, n, i, m_ghostFirst.data(), m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(),
                m_ghostOf.data());
  });
  m_in = BroadphaseInput{m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(), n + numGhosts,
                         in.maxRadius, in.cellRadius};
}

}  // namespace tumble::cpu::detail
