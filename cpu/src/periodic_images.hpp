// SPDX-License-Identifier: MIT
// Detection in a periodic box on the CPU: the images' columns and the ghosts' numbering, built
// by the shared per-element steps of kernels/periodic_images.hpp. Internal to tumble::cpu.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tumble/kernels/periodic_images.hpp"

namespace tumble::cpu::detail {

/// The images a periodic detection sweeps (PeriodicImagesView): the particles wrapped into the
/// box, then their ghosts.
class PeriodicImages {
 public:
  /// Builds the images of in's particles (radii and maxRadius as the sweep is to use them).
  void build(const BroadphaseInput& in, const PeriodicBox& box, float reach);
  /// The sweep's input over the images (the ghosts have their particles' radii and bodies, so a
  /// body never meets its own image).
  const BroadphaseInput& input() const { return m_in; }
  /// The rows' view of the images (periodicRowBound(), fillPeriodicRow()).
  PeriodicImagesView view() const { return {m_n, m_ghostFirst.data(), m_ghostOf.data()}; }

 private:
  std::uint32_t m_n = 0;
  BroadphaseInput m_in{};
  std::vector<float> m_x, m_y, m_z, m_r;
  std::vector<std::uint32_t> m_body, m_count, m_ghostFirst, m_ghostOf;
  std::vector<std::byte> m_temp;
};

}  // namespace tumble::cpu::detail
