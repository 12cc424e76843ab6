// SPDX-License-Identifier: MIT
// Detection in a periodic box (docs/model.md#periodic-boundaries). The sweep knows nothing of
// the boundaries: it runs on the particles with their periodic coordinates wrapped into the box,
// plus ghost images of those near the box's lower ends, and each particle's candidate row
// gathers what it and its ghosts found, as particles, each partner once. Internal to tumble::cpu.
#pragma once
#include <cstdint>
#include <vector>

#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/kernels/records.hpp"

namespace tumble::cpu::detail {

/// The images a periodic detection sweeps: the n particles (periodic coordinates wrapped into the
/// box [−h, h)), then ghosts: one shifted by +L on x of every particle within `reach` of −h on x,
/// one shifted on y likewise, one shifted on both (the corner) of every particle within reach of
/// both. Any two particles whose minimum image lies within reach (< L) are then within reach
/// through some pair of images (the one nearer a lower end carries the shift, per axis, and a pair
/// of ghosts carries opposite shifts), so the sweep finds every such pair, some more than once.
/// Ghost g (sweep index n + g) stands for particle ghostOf[g]; particle i's ghosts are
/// n + ghostFirst[i] .. n + ghostFirst[i + 1].
class PeriodicImages {
 public:
  /// Builds the images of in's particles (radii and maxRadius as the sweep is to use them).
  void build(const BroadphaseInput& in, const PeriodicBox& box, float reach);
  /// The sweep's input over the images (the ghosts have their particles' radii and bodies, so a
  /// body never meets its own image).
  const BroadphaseInput& input() const { return m_in; }
  std::uint32_t numGhosts() const { return static_cast<std::uint32_t>(m_ghostOf.size()); }
  /// The particle that sweep index a stands for.
  std::uint32_t particleOf(std::uint32_t a) const { return a < m_n ? a : m_ghostOf[a - m_n]; }
  /// Room for particle i's row: the candidates of i and of its ghosts, a partner found through
  /// several pairs of images counted each time.
  std::uint32_t rowBound(const SweepListView& s, std::uint32_t i) const;
  /// Particle i's row from the sweep over the images: the partners of i and of its ghosts as
  /// particles, in ascending orig[·] (scene index), each once, at cand (room: rowBound(); key is
  /// scratch of the same size). Returns its length.
  std::uint32_t fillRow(const SweepListView& s, const std::uint32_t* orig, std::uint32_t i, std::uint32_t* cand,
                        std::uint32_t* key) const;

 private:
  std::uint32_t m_n = 0;
  BroadphaseInput m_in{};
  std::vector<float> m_x, m_y, m_z, m_r;
  std::vector<std::uint32_t> m_body, m_count, m_ghostFirst, m_ghostOf;
  std::vector<std::byte> m_temp;
};

}  // namespace tumble::cpu::detail
