// SPDX-License-Identifier: MIT
/// @file energy.hpp
/// The energy tally of the time series (docs/thermo.md#energy-balance), written once for both
/// pipelines: each step, the power the contacts take out of the bodies' motion (by the normal
/// dashpots, the tangential dashpots, friction) and the power moving walls put in, summed per
/// particle and per body in the force pass (kernels/step.hpp, its debug instantiation), times
/// dt, are added to a running sum in fixed point (kEnergyQuantum joules). Integer sums do not
/// depend on their order, so the tally is the same bits for any thread count, numbering, MPI
/// rank count and either pipeline, without sorting anything.
#pragma once
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"

namespace tumble {

/// Powers (W) of one particle or body in one step: taken out of the motion by the normal
/// dashpots, by the tangential dashpots while the contacts stick, by the rest of the tangential
/// forces and the rolling resistance (friction; with the energy the stick springs hold), into
/// JKR's necks (contacts stretched beyond touching, δ < 0: lost when a neck breaks), and put in
/// by moving walls (the wall force dotted with the wall's velocity there).
struct EnergyFlows {
  float normal, tangential, friction, cohesion, wall;
};
inline constexpr int kEnergyFlows = 5;

TUMBLE_HD_INLINE EnergyFlows noFlows() { return EnergyFlows{0.0f, 0.0f, 0.0f, 0.0f, 0.0f}; }
TUMBLE_HD_INLINE void addFlows(EnergyFlows& a, const EnergyFlows& b) {
  a.normal += b.normal;
  a.tangential += b.tangential;
  a.friction += b.friction;
  a.cohesion += b.cohesion;
  a.wall += b.wall;
}

/// The tally's unit: 2^-80 J (8.3e-25 J). A step's energy of a body is rounded to it; the tally
/// holds ±2^47 J (1.4e14 J) in 128 bits.
inline constexpr double kEnergyQuantum = 0x1p-80;

/// Sums of energies in units of kEnergyQuantum, each split into limbs that integer additions
/// (and atomics) add exactly in any order: value = hi 2^64 + mid 2^32 + lo, hi signed in two's
/// complement (unsigned words: their sums wrap, defined, to the signed sum's bits), mid and lo
/// each below 2^32 per term, so 2^32 terms add without overflow. The atomics' own word type.
struct EnergyLimbs {
  unsigned long long hi[kEnergyFlows], mid[kEnergyFlows], lo[kEnergyFlows];
};

TUMBLE_HD_INLINE EnergyLimbs noLimbs() {
  EnergyLimbs l;
  for (int c = 0; c < kEnergyFlows; ++c) l.hi[c] = l.mid[c] = l.lo[c] = 0;
  return l;
}

/// The limbs of p dt in units of kEnergyQuantum, rounded to the nearest (ties to even): p dt
/// and its scaling are exact in double, so is the split. |p dt| must be below 2^46 J.
TUMBLE_HD_INLINE void energyLimbs(float p, float dt, unsigned long long* hi, unsigned long long* mid,
                                   unsigned long long* lo) {
  const double x = double(p) * double(dt) * 0x1p80;
  if (fabs(x) < 0x1p62) {  // most energies of a step (below 3.8e-6 J): one integer, two's complement
    const auto u = static_cast<unsigned long long>(static_cast<long long>(llrint(x)));
    *hi = x < 0.0 && u != 0 ? ~0ull : 0ull;
    *mid = u >> 32;
    *lo = u & 0xffffffffu;
    return;
  }
  const double e = rint(x);
  const double h = floor(e * 0x1p-64);
  const double r = e - h * 0x1p64;  // 0 ≤ r < 2^64, exact
  const double m = floor(r * 0x1p-32);
  *hi = static_cast<unsigned long long>(static_cast<long long>(h));
  *mid = static_cast<unsigned long long>(m);
  *lo = static_cast<unsigned long long>(r - m * 0x1p32);
}

/// Adds a body's step, its powers f over dt, to l.
TUMBLE_HD_INLINE void addEnergy(EnergyLimbs& l, const EnergyFlows& f, float dt) {
  const float p[kEnergyFlows] = {f.normal, f.tangential, f.friction, f.cohesion, f.wall};
  for (int c = 0; c < kEnergyFlows; ++c) {
    unsigned long long h, m, o;
    energyLimbs(p[c], dt, &h, &m, &o);
    l.hi[c] += h;
    l.mid[c] += m;
    l.lo[c] += o;
  }
}

TUMBLE_HD_INLINE void addLimbs(EnergyLimbs& a, const EnergyLimbs& b) {
  for (int c = 0; c < kEnergyFlows; ++c) {
    a.hi[c] += b.hi[c];
    a.mid[c] += b.mid[c];
    a.lo[c] += b.lo[c];
  }
}

/// The energies of EnergyFlows (J) since the tally began.
struct EnergyTotals {
  double normal = 0.0, tangential = 0.0, friction = 0.0, cohesion = 0.0, wall = 0.0;
  EnergyTotals& operator+=(const EnergyTotals& o) {
    normal += o.normal, tangential += o.tangential, friction += o.friction, cohesion += o.cohesion, wall += o.wall;
    return *this;
  }
  /// What flowed since `base` was taken.
  EnergyTotals operator-(const EnergyTotals& base) const {
    return EnergyTotals{normal - base.normal, tangential - base.tangential, friction - base.friction,
                        cohesion - base.cohesion, wall - base.wall};
  }
};

/// A running tally (host side): the exact sum of the limbs added, in 128 bits per flow.
class EnergyTally {
 public:
  void add(const EnergyLimbs& l) {
    for (int c = 0; c < kEnergyFlows; ++c)
      m_sum[c] += static_cast<Wide>(static_cast<long long>(l.hi[c])) * kTwo64 + static_cast<Wide>(l.mid[c]) * kTwo32 +
                  static_cast<Wide>(l.lo[c]);
  }
  void clear() { *this = EnergyTally{}; }
  /// In joules, each within an ulp of the double nearest to the sum.
  EnergyTotals joules() const {
    double j[kEnergyFlows];
    for (int c = 0; c < kEnergyFlows; ++c) {
      const Wide s = m_sum[c];
      const Wide a = s < 0 ? -s : s;
      // The high and low 64 bits apart, each converted to double (the high part exactly below
      // 2^53), then added: at most two roundings.
      const double high = double(static_cast<std::uint64_t>(a >> 64)) * 0x1p64;
      const double v = (high + double(static_cast<std::uint64_t>(a))) * kEnergyQuantum;
      j[c] = s < 0 ? -v : v;
    }
    return EnergyTotals{j[0], j[1], j[2], j[3], j[4]};
  }

 private:
  __extension__ typedef __int128 Wide;
  static constexpr Wide kTwo32 = Wide(1) << 32, kTwo64 = Wide(1) << 64;
  Wide m_sum[kEnergyFlows] = {0, 0, 0, 0, 0};
};

}  // namespace tumble
