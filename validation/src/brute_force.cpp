// SPDX-License-Identifier: MIT
#include "tumble/validation/brute_force.hpp"

#include <tbb/parallel_for.h>

#include "tumble/kernels/integrate.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/periodic.hpp"

namespace tumble::validation {

std::vector<Pair> bruteForcePairs(const ParticleCloud& c) {
  const std::size_t n = c.size();
  std::vector<std::vector<Pair>> rows(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    for (std::size_t j = i + 1; j < n; ++j)
      if (c.body[i] != c.body[j] &&
          spheresOverlap(c.periodic, c.x[i], c.y[i], c.z[i], c.r[i], c.x[j], c.y[j], c.z[j], c.r[j]))
        rows[i].push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)});
  });
  std::vector<Pair> out;
  for (auto& r : rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

ParticleCloud cloudOf(const World& w, const BodyState& s) {
  ParticleCloud c;
  const std::uint32_t n = w.numParticles();
  c.x.resize(n); c.y.resize(n); c.z.resize(n);
  c.r = w.radius;
  c.body = w.body;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t k = w.body[i];
    const Vec3f X{s.px[k], s.py[k], s.pz[k]};
    // The pipelines' expression (particlePosition), so that the oracle sees the same bits.
    const Vec3f x = w.hasClumps ? particlePosition(X, rotationMatrix(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}),
                                                   Vec3f{w.ux[i], w.uy[i], w.uz[i]})
                                : X;
    c.x[i] = x.x;
    c.y[i] = x.y;
    c.z[i] = x.z;
  }
  return c;
}

}  // namespace tumble::validation
