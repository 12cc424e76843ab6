// SPDX-License-Identifier: MIT
// The sizes a [[fill]] or a [[pour]] draws (tumble/size_distribution.hpp).
#include "tumble/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tumble/error.hpp"

namespace tumble {
namespace {

/// Intervals of the normal's and log-normal's table, even in ln s.
constexpr int kIntervals = 4096;

/// ln 2 split as fdlibm does (its high part ends in 21 zero bits: k ln2_hi is exact for every k
/// here, |k| < 1100).
constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;

/// What a body of size s weighs in the number density: 1 by number, 1/s³ by volume.
double numberWeight(SizeDistribution::Weight by, double s) {
  return by == SizeDistribution::Weight::Volume ? 1.0 / (s * s * s) : 1.0;
}

}  // namespace

double portableExp(double x) {
  if (!(x > -746.0)) return x != x ? x : 0.0;
  if (!(x < 710.0)) return HUGE_VAL;
  const double k = std::floor(x * 1.44269504088896338700 + 0.5);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  double p = 1.0;
  for (int n = 14; n >= 1; --n) p = 1.0 + p * r / n;
  return std::ldexp(p, int(k));
}

// ln x: x = m 2^e with m in [√½, √2), ln m = 2 atanh f, f = (m − 1)/(m + 1) (|f| ≤ 0.172),
// its series to f^25 / 25 (< 1e-19).
double portableLog(double x) {
  int e = 0;
  double m = std::frexp(x, &e);
  if (m < 0.70710678118654752440) m *= 2.0, --e;
  const double f = (m - 1.0) / (m + 1.0), f2 = f * f;
  double series = 0.0;
  for (int n = 25; n >= 3; n -= 2) series = f2 * (1.0 / n + series);
  const double logm = 2.0 * f * (1.0 + series);
  return e * kLn2Hi + (e * kLn2Lo + logm);
}

SizeDistribution SizeDistribution::fixed(float s) {
  SizeDistribution d;
  d.m_lo = d.m_hi = s;
  return d;
}

SizeDistribution SizeDistribution::uniform(float lo, float hi, Weight by) {
  if (by == Weight::Number || lo == hi) {
    SizeDistribution d = fixed(lo);
    d.m_kind = Kind::Uniform;
    d.m_weight = by;
    d.m_hi = hi;
    return d;
  }
  // By volume: the volume density constant, so the number density ∝ s⁻³ (a table of one interval).
  SizeDistribution d = table({double(lo), double(hi)}, {0.0, 1.0}, by);
  d.m_kind = Kind::Uniform;
  return d;
}

template <class Density>
void SizeDistribution::tabulate(const Density& density, double lo, double hi) {
  // lo, hi: the bounds within 40 of its σ of its centre (beyond, its density is below e^-800).
  if (!(lo <= hi))
    throw Error("the distribution puts no sizes between min and max (its centre is more than 40 of its standard "
                "deviations outside them): move the bounds towards its centre");
  if (float(lo) == float(hi)) {  // narrower than a float's step: every size is that float
    m_s = {double(float(lo))};
    m_c = {0.0};
    return;
  }
  const double a = portableLog(lo), b = portableLog(hi);
  m_s.resize(kIntervals + 1);
  m_f.resize(kIntervals + 1);
  m_c.assign(kIntervals + 1, 0.0);
  for (int i = 0; i <= kIntervals; ++i) m_s[i] = portableExp(a + (b - a) * i / kIntervals);
  m_s.front() = lo, m_s.back() = hi;
  for (int i = 0; i <= kIntervals; ++i) m_f[i] = density(m_s[i]);
  for (int i = 0; i < kIntervals; ++i) {
    const double s0 = m_s[i], s1 = m_s[i + 1];
    const double mass = (s1 - s0) / 6.0 * (m_f[i] + 4.0 * density(0.5 * (s0 + s1)) + m_f[i + 1]);
    m_c[i + 1] = m_c[i] + mass;
  }
  if (!(m_c.back() > 0.0) || !std::isfinite(m_c.back()))
    throw Error("the distribution puts (next to) no sizes between min and max: move the bounds towards its centre");
}

std::array<double, 2> SizeDistribution::defaultBounds(Kind kind, double centre, double width) {
  if (kind == Kind::LogNormal) return {centre * portableExp(-3.0 * width), centre * portableExp(3.0 * width)};
  return {centre - 3.0 * width, centre + 3.0 * width};
}

SizeDistribution SizeDistribution::normal(double mean, double sd, float lo, float hi, Weight by) {
  SizeDistribution d = fixed(lo);
  d.m_kind = Kind::Normal;
  d.m_weight = by;
  d.m_hi = hi;
  d.tabulate(
      [&](double s) {
        const double z = (s - mean) / sd;
        return portableExp(-0.5 * z * z) * numberWeight(by, s);
      },
      std::max(double(lo), mean - 40.0 * sd), std::min(double(hi), mean + 40.0 * sd));
  return d;
}

SizeDistribution SizeDistribution::logNormal(double median, double sigma, float lo, float hi, Weight by) {
  SizeDistribution d = fixed(lo);
  d.m_kind = Kind::LogNormal;
  d.m_weight = by;
  d.m_hi = hi;
  const double mu = portableLog(median);
  d.tabulate(
      [&](double s) {
        const double z = (portableLog(s) - mu) / sigma;
        return portableExp(-0.5 * z * z) / s * numberWeight(by, s);
      },
      std::max(double(lo), median * portableExp(-40.0 * sigma)), std::min(double(hi), median * portableExp(40.0 * sigma)));
  return d;
}

SizeDistribution SizeDistribution::table(std::vector<double> sizes, std::vector<double> cumulative, Weight by) {
  SizeDistribution d = fixed(float(sizes.front()));
  d.m_kind = Kind::Table;
  d.m_weight = by;
  d.m_hi = float(sizes.back());
  d.m_cubic = by == Weight::Volume;
  d.m_c.assign(sizes.size(), 0.0);
  for (std::size_t i = 0; i + 1 < sizes.size(); ++i) {
    const double s0 = sizes[i], s1 = sizes[i + 1], p = cumulative[i + 1] - cumulative[i];
    // By volume the interval's volume density p / (s1 - s0) over s³, integrated: its number.
    const double mass = d.m_cubic ? p / (s1 - s0) * 0.5 * (1.0 / (s0 * s0) - 1.0 / (s1 * s1)) : p;
    d.m_c[i + 1] = d.m_c[i] + mass;
  }
  d.m_s = std::move(sizes);
  return d;
}

float SizeDistribution::at(double u) const {
  if (m_s.empty()) return m_lo + (m_hi - m_lo) * float(u);  // fixed, or uniform by number
  if (m_s.size() == 1) return float(m_s[0]);                // narrower than a float's step
  const double target = u * m_c.back();
  // The interval [s_i, s_i+1) whose cumulative mass holds the target (never one of no mass).
  const std::size_t i = std::min<std::size_t>(
      std::size_t(std::upper_bound(m_c.begin(), m_c.end(), target) - m_c.begin()), m_c.size() - 1) - 1;
  const double s0 = m_s[i], s1 = m_s[i + 1], mass = m_c[i + 1] - m_c[i];
  const double q = mass > 0.0 ? (target - m_c[i]) / mass : 1.0;  // (u = 1 at an end of no mass)
  double s = 0.0;
  if (m_cubic) {  // ∫ s⁻³ from s0 to s is q of the interval's
    s = 1.0 / std::sqrt(1.0 / (s0 * s0) - q * (1.0 / (s0 * s0) - 1.0 / (s1 * s1)));
  } else if (m_f.empty()) {  // a constant density
    s = s0 + q * (s1 - s0);
  } else {  // the density linear from f0 to f1: f0 t + (f1 − f0) t² / 2 = q (f0 + f1) / 2, solved stably
    const double f0 = m_f[i], f1 = m_f[i + 1];
    const double t = q * (f0 + f1) / (f0 + std::sqrt(f0 * f0 + q * (f1 * f1 - f0 * f0)));
    s = s0 + (t == t ? t : q) * (s1 - s0);
  }
  return std::clamp(float(s), m_lo, m_hi);
}

float SizeDistribution::draw(Rng& rng) const {
  if (!varies()) return m_lo;
  if (m_s.empty()) return rng.uniform(m_lo, m_hi);  // earlier versions' scale = [min, max], bit for bit
  return at(double(rng.uniform()));
}

}  // namespace tumble
