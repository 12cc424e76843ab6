// SPDX-License-Identifier: MIT
/// @file size_distribution.hpp
/// The sizes of the bodies a `[[fill]]` or a `[[pour]]` draws (docs/scenes.md#size-distributions):
/// a scale factor per body (the shape as given is size 1; radii and offsets times the factor,
/// masses times its cube), from a fixed value, a uniform, a normal or a log-normal distribution
/// truncated at given bounds, or a tabulated cumulative distribution, each either by number (the
/// fraction of the bodies) or by volume (the fraction of their volume, and so of their mass).
///
/// A draw takes one uniform of the group's generator and inverts the number distribution: by
/// volume, the number density is the volume density over s³ (a body of size s holds s³ times
/// the volume of one of size 1). The inversion is a table made once, in double: a tabulated
/// distribution's exactly (number: linear in each interval; volume: the number density ∝ s⁻³
/// in each interval, integrated in closed form); a normal's and a log-normal's from the density
/// integrated by Simpson's rule on 4096 intervals even in ln s over the bounds within 40 σ of its
/// centre, taken as linear within each (the cumulative distribution within about 1e-7 of the
/// exact one, what rounding a size to float moves it; one narrower than a float's step gives that
/// float). The same draws on every thread
/// count: a group's draws are made in order, by one thread.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tumble/random.hpp"

namespace tumble {

/// e^x and ln x (x > 0) of tumble's own, a fixed sequence of IEEE operations (with
/// -ffp-contract=off), within a few ulp of the C library's: the same bits with any C library.
double portableExp(double x);
double portableLog(double x);

class SizeDistribution {
 public:
  enum class Kind : std::uint8_t { Fixed, Uniform, Normal, LogNormal, Table };
  /// What the distribution gives the fraction of: the bodies, or their volume (mass).
  enum class Weight : std::uint8_t { Number, Volume };

  /// Every body of size s (> 0).
  static SizeDistribution fixed(float s);
  /// Uniform in [lo, hi] (0 < lo ≤ hi). By number it draws Rng::uniform(lo, hi) (the `scale =
  /// [min, max]` of earlier versions, bit for bit).
  static SizeDistribution uniform(float lo, float hi, Weight by);
  /// A normal of `mean` and standard deviation `sd` (> 0) truncated to [lo, hi] (0 < lo < hi).
  static SizeDistribution normal(double mean, double sd, float lo, float hi, Weight by);
  /// A log-normal of `median` (e^μ, > 0) and `sigma` (σ of ln s, > 0) truncated to [lo, hi].
  static SizeDistribution logNormal(double median, double sigma, float lo, float hi, Weight by);
  /// The bounds of a normal (mean ∓ 3 sd) or a log-normal (median e^∓3σ) where none are given.
  static std::array<double, 2> defaultBounds(Kind kind, double centre, double width);
  /// A cumulative distribution through the points (sizes[i], cumulative[i]), linear between
  /// them: sizes > 0 strictly increasing, cumulative non-decreasing from 0 to 1, at least two.
  static SizeDistribution table(std::vector<double> sizes, std::vector<double> cumulative, Weight by);

  Kind kind() const { return m_kind; }
  Weight weight() const { return m_weight; }
  /// The smallest and largest size drawn.
  float min() const { return m_lo; }
  float max() const { return m_hi; }
  /// Whether a draw takes a uniform (every kind but a fixed size, or a range of one value).
  bool varies() const { return m_lo != m_hi; }
  /// A size from one uniform of `rng` (none when !varies()), in [min(), max()].
  float draw(Rng& rng) const;
  /// The size at u in [0, 1) of the number distribution (what draw() does with its uniform).
  float at(double u) const;

 private:
  SizeDistribution() = default;
  /// The inversion table from the number density at s (normal, log-normal: grid and Simpson).
  template <class Density>
  void tabulate(const Density& density, double lo, double hi);

  Kind m_kind = Kind::Fixed;
  Weight m_weight = Weight::Number;
  float m_lo = 1.0f, m_hi = 1.0f;
  std::vector<double> m_s;   ///< the nodes, increasing
  std::vector<double> m_c;   ///< the number distribution's cumulative mass at each node (unnormalized)
  std::vector<double> m_f;   ///< a normal's or log-normal's number density at each node (none: a table)
  bool m_cubic = false;      ///< within an interval the number density ∝ s⁻³ (a table by volume), else constant
};

}  // namespace tumble
