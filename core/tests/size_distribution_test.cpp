// SPDX-License-Identifier: MIT
// Tests of the size distributions of [[fill]] and [[pour]] (tumble/size_distribution.hpp):
// the sizes drawn against the requested distribution (Kolmogorov–Smirnov against the number
// distribution, computed here independently: in closed form where there is one, else by a
// quadrature of its own; and the volume fraction below each size against the requested one,
// the check Lethe's users made, issue 2014), the scene keys and their errors, and the same
// bodies on 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "scene_io_test_util.hpp"
#include "tumble/random.hpp"
#include "tumble/size_distribution.hpp"

using namespace scene_io_test;
using tumble::SizeDistribution;
using Weight = SizeDistribution::Weight;

namespace {

constexpr std::uint64_t kSeed = 20261207;
constexpr std::size_t kDraws = 20000;
/// Kolmogorov's critical value at a significance of 0.001 (1.949 / sqrt(n), n large).
const double kCritical = 1.949 / std::sqrt(double(kDraws));

std::vector<double> drawn(const SizeDistribution& d, std::uint64_t seed) {
  tumble::Rng rng(seed);
  std::vector<double> s(kDraws);
  for (double& v : s) v = double(d.draw(rng));
  std::sort(s.begin(), s.end());
  return s;
}

/// The Kolmogorov–Smirnov statistic of sorted samples against the distribution function F.
double ksStatistic(const std::vector<double>& sorted, const std::function<double(double)>& F) {
  double D = 0.0;
  const double n = double(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double f = F(sorted[i]);
    D = std::max({D, f - double(i) / n, double(i + 1) / n - f});
  }
  return D;
}

double Phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

/// The distribution function of a density on [lo, hi], by the trapezoid rule on 200 000 steps
/// (the code under test uses Simpson on 2048 steps even in ln s).
std::function<double(double)> byQuadrature(const std::function<double(double)>& density, double lo, double hi) {
  constexpr int kSteps = 200000;
  auto cdf = std::make_shared<std::vector<double>>(kSteps + 1, 0.0);
  const double h = (hi - lo) / kSteps;
  for (int i = 0; i < kSteps; ++i)
    (*cdf)[i + 1] = (*cdf)[i] + 0.5 * h * (density(lo + i * h) + density(lo + (i + 1) * h));
  const double total = cdf->back();
  return [=](double s) {
    const double x = std::clamp((s - lo) / h, 0.0, double(kSteps));
    const int i = std::min(int(x), kSteps - 1);
    return ((*cdf)[i] + (x - i) * ((*cdf)[i + 1] - (*cdf)[i])) / total;
  };
}

/// The volume fraction of the sample at or below each of `at` against the requested volume
/// distribution function V, each within 5 standard errors of the ratio estimate.
void expectVolumeFractions(const std::vector<double>& sorted, const std::function<double(double)>& V,
                           const std::vector<double>& at, const char* what) {
  double total = 0.0;
  for (double s : sorted) total += s * s * s;
  for (double x : at) {
    double below = 0.0;
    for (double s : sorted)
      if (s <= x) below += s * s * s;
    const double f = below / total, want = V(x);
    double var = 0.0;  // the ratio estimator's variance: sum w^2 (I - f)^2 / (sum w)^2
    for (double s : sorted) {
      const double w = s * s * s, e = (s <= x ? 1.0 : 0.0) - f;
      var += w * w * e * e;
    }
    const double se = std::sqrt(var) / total;
    EXPECT_NEAR(f, want, 5.0 * se + 1e-4) << what << ": the volume fraction at or below " << x;
  }
}

}  // namespace

// Every kind, by number and by volume: the KS statistic of 20 000 draws against the number
// distribution (for the volume-weighted ones, the volume density over s^3) below the critical
// value at 0.001, and the volume-weighted ones' volume fractions as requested. The same
// draws against the other weighting's distribution fail it: the test can tell them apart.
TEST(SizeDistribution, DrawsFollowTheRequestedDistribution) {
  std::printf("size distribution seed %llu, %zu draws, KS critical value %.4f (alpha = 0.001)\n",
              static_cast<unsigned long long>(kSeed), kDraws, kCritical);
  const double lo = 0.5, hi = 2.0;
  // Log-normal, median 1, sigma 0.35, truncated to [0.5, 2]; by volume its number distribution
  // is the log-normal of median e^(-3 sigma^2) (Hatch and Choate 1929), truncated alike.
  const double sigma = 0.35;
  const auto logNormalCdf = [=](double median) {
    return [=](double s) {
      const auto z = [&](double x) { return Phi((std::log(x) - std::log(median)) / sigma); };
      return (z(std::clamp(s, lo, hi)) - z(lo)) / (z(hi) - z(lo));
    };
  };
  const auto normalCdf = [=](double s) {
    const auto z = [](double x) { return Phi((x - 1.1) / 0.3); };
    return (z(std::clamp(s, lo, hi)) - z(lo)) / (z(hi) - z(lo));
  };
  const auto normalVolumeAsNumber =
      byQuadrature([](double s) { return std::exp(-0.5 * (s - 1.1) * (s - 1.1) / 0.09) / (s * s * s); }, lo, hi);
  const auto uniformNumber = [=](double s) { return (std::clamp(s, lo, hi) - lo) / (hi - lo); };
  const auto uniformVolumeAsNumber = [=](double s) {
    const double x = std::clamp(s, lo, hi);
    return (1.0 / (lo * lo) - 1.0 / (x * x)) / (1.0 / (lo * lo) - 1.0 / (hi * hi));
  };
  // A table: sizes 0.5, 1, 2 at 0, 0.3, 1 (piecewise linear).
  const std::vector<double> ts{0.5, 1.0, 2.0}, tc{0.0, 0.3, 1.0};
  const auto tableCdf = [=](double s) {
    const double x = std::clamp(s, lo, hi);
    return x <= 1.0 ? 0.3 * (x - 0.5) / 0.5 : 0.3 + 0.7 * (x - 1.0);
  };
  // The table by volume as a number distribution: volume density c_i in each interval, number
  // density c_i / s^3, integrated by quadrature.
  const auto tableVolumeAsNumber =
      byQuadrature([](double s) { return (s <= 1.0 ? 0.3 / 0.5 : 0.7 / 1.0) / (s * s * s); }, lo, hi);
  // The volume-weighted draws' volume distribution, requested (closed form).
  const auto logNormalVolumeCdf = logNormalCdf(1.0);
  const auto normalVolumeCdf = normalCdf;
  struct Case {
    const char* name;
    SizeDistribution d;
    std::function<double(double)> number;     // the number distribution function
    std::function<double(double)> wrong;      // the other weighting's: must fail
    std::function<double(double)> volume;     // by volume: the requested one
  };
  const std::vector<Case> cases{
      {"uniform by number", SizeDistribution::uniform(0.5f, 2.0f, Weight::Number), uniformNumber,
       uniformVolumeAsNumber, nullptr},
      {"uniform by volume", SizeDistribution::uniform(0.5f, 2.0f, Weight::Volume), uniformVolumeAsNumber,
       uniformNumber, uniformNumber},
      {"normal by number", SizeDistribution::normal(1.1, 0.3, 0.5f, 2.0f, Weight::Number), normalCdf,
       normalVolumeAsNumber, nullptr},
      {"normal by volume", SizeDistribution::normal(1.1, 0.3, 0.5f, 2.0f, Weight::Volume), normalVolumeAsNumber,
       normalCdf, normalVolumeCdf},
      {"lognormal by number", SizeDistribution::logNormal(1.0, sigma, 0.5f, 2.0f, Weight::Number),
       logNormalCdf(1.0), logNormalCdf(std::exp(-3.0 * sigma * sigma)), nullptr},
      {"lognormal by volume", SizeDistribution::logNormal(1.0, sigma, 0.5f, 2.0f, Weight::Volume),
       logNormalCdf(std::exp(-3.0 * sigma * sigma)), logNormalCdf(1.0), logNormalVolumeCdf},
      {"table by number", SizeDistribution::table(ts, tc, Weight::Number), tableCdf, tableVolumeAsNumber, nullptr},
      {"table by volume", SizeDistribution::table(ts, tc, Weight::Volume), tableVolumeAsNumber, tableCdf, tableCdf},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const Case& c = cases[k];
    const std::vector<double> s = drawn(c.d, kSeed + k);
    EXPECT_GE(s.front(), 0.5);
    EXPECT_LE(s.back(), 2.0);
    const double D = ksStatistic(s, c.number), wrong = ksStatistic(s, c.wrong);
    std::printf("  %-20s seed %llu: D = %.4f against its own, %.4f against the other weighting's\n", c.name,
                static_cast<unsigned long long>(kSeed + k), D, wrong);
    EXPECT_LT(D, kCritical) << c.name;
    EXPECT_GT(wrong, kCritical) << c.name << ": the test cannot tell the weightings apart";
    if (c.volume) expectVolumeFractions(s, c.volume, {0.7, 0.9, 1.0, 1.2, 1.5}, c.name);
  }
}

// The inversion table against the exact quantiles of a log-normal (truncated 8 sigma out, where the
// truncation changes nothing at double precision): F(at(u)) within 3e-7 of u (the rounding of a
// size to float alone moves F by up to about 1.2e-7 here; a density taken as constant within
// each interval was 2.2e-6 off).
TEST(SizeDistribution, TheInversionIsAccurate) {
  const double sigma = 0.2;
  const SizeDistribution d = SizeDistribution::logNormal(1.0, sigma, float(std::exp(-8 * sigma)),
                                                         float(std::exp(8 * sigma)), Weight::Number);
  double worst = 0.0;
  for (int k = 1; k < 1000; ++k) {
    const double u = k / 1000.0;
    worst = std::max(worst, std::fabs(Phi(std::log(double(d.at(u))) / sigma) - u));
  }
  std::printf("log-normal inversion: largest |F(at(u)) - u| %.2e\n", worst);
  EXPECT_LT(worst, 3e-7);
  // A distribution far narrower than its bounds (the table spans 40 sigma of it, not the
  // bounds: 2048 intervals over the bounds drew a normal of sd 1e-3 in [0.1, 10] 9.6 % too wide),
  // and one far wider.
  const auto worstOf = [](const SizeDistribution& x, const std::function<double(double)>& F) {
    double w = 0.0;
    for (int k = 1; k < 1000; ++k) w = std::max(w, std::fabs(F(double(x.at(k / 1000.0))) - k / 1000.0));
    return w;
  };
  const double narrow = worstOf(SizeDistribution::normal(1.0, 1e-3, 0.1f, 10.0f, Weight::Number),
                                [](double s) { return Phi((s - 1.0) / 1e-3); });
  const double wide = worstOf(SizeDistribution::logNormal(1.0, 0.1, 1e-6f, 1e6f, Weight::Number),
                              [](double s) { return Phi(std::log(s) / 0.1); });
  std::printf("normal sd 1e-3 in [0.1, 10]: %.2e; log-normal sigma 0.1 in [1e-6, 1e6]: %.2e\n", narrow, wide);
  EXPECT_LT(narrow, 1e-4) << "sizes near 1 are floats 6e-8 apart: F moves by up to 2.4e-5 between them";
  EXPECT_LT(wide, 3e-7);
  // Narrower than a float's step: every size is the float at the centre.
  const SizeDistribution point = SizeDistribution::normal(1.5, 1e-300, 0.5f, 2.0f, Weight::Number);
  EXPECT_EQ(point.at(0.1), 1.5f);
  EXPECT_EQ(point.at(0.9), 1.5f);
  // tumble's exp and log against the C library's, within a few ulp (an exp cut at r^5 is 2e-6 off).
  double worstExp = 0.0, worstLog = 0.0;
  for (int k = -7000; k <= 7000; ++k) {
    const double x = k * 0.1003;
    worstExp = std::max(worstExp, std::fabs(tumble::portableExp(x) / std::exp(x) - 1.0));
    const double y = std::exp(k * 0.0137);
    worstLog = std::max(worstLog, std::fabs(tumble::portableLog(y) - std::log(y)) / std::max(1.0, std::fabs(std::log(y))));
  }
  std::printf("portableExp: largest relative difference %.2e; portableLog %.2e\n", worstExp, worstLog);
  EXPECT_LT(worstExp, 1e-15);
  EXPECT_LT(worstLog, 1e-15);
  // A uniform by number is Rng::uniform(lo, hi), as scale = [min, max] drew it.
  const SizeDistribution u = SizeDistribution::uniform(0.3f, 1.7f, Weight::Number);
  tumble::Rng a(7), b(7);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(u.draw(a), b.uniform(0.3f, 1.7f));
}

namespace {
const char* kPolydisperse =
    "[[fill]]\nshape = \"ball\"\ncount = 300\nregion = \"box\"\nmin = [-8, -8, 1]\nmax = [8, 8, 9]\n"
    "size = { distribution = \"lognormal\", median = 0.6, sigma = 0.3, min = 0.3, max = 1.2, by = \"volume\" }\n"
    "[[pour]]\nshape = \"ball\"\ncount = 200\nrate = 100\nregion = \"box\"\nmin = [-8, -8, 10]\nmax = [8, 8, 14]\n"
    "[pour.size]\ndistribution = \"table\"\nsizes = [0.4, 0.6, 1.0]\ncumulative = [0, 0.5, 1]\nby = \"number\"\n";
}

// Through the scene: the fill's and the pour's bodies have radii in the bounds (the ball's 0.5 m
// times the size) and masses with the cube of the size, and are the same bits on 1 and 2 threads.
TEST(SceneIo, SizeDistributionsInFillsAndPours) {
  Scene one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = tumble::parseScene(withExtra(kPolydisperse), "test.toml");
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = tumble::parseScene(withExtra(kPolydisperse), "test.toml");
  }
  ASSERT_EQ(one.bodies.size(), 301u);
  ASSERT_EQ(one.pourBodies.size(), 200u);
  EXPECT_TRUE(sameBits(one, two));
  ASSERT_EQ(one.shapes.size(), two.shapes.size());
  for (std::size_t s = 0; s < one.shapes.size(); ++s) {
    EXPECT_EQ(one.shapes[s].spheres[0].radius, two.shapes[s].spheres[0].radius);
    EXPECT_EQ(one.shapes[s].spheres[0].mass, two.shapes[s].spheres[0].mass);
  }
  const auto check = [&](std::uint32_t shape, double lo, double hi) {
    const tumble::SphereDef& sp = one.shapes[shape].spheres[0];
    const double size = sp.radius / 0.5;
    EXPECT_GE(size, lo);
    EXPECT_LE(size, hi);
    EXPECT_NEAR(sp.mass, size * size * size, 1e-5 * size * size * size);
  };
  std::size_t distinct = 0;
  for (std::size_t b = 1; b < one.bodies.size(); ++b) {
    check(one.bodies[b].shape, 0.3, 1.2);
    distinct += one.bodies[b].shape != one.bodies[b - 1].shape;
  }
  EXPECT_GT(distinct, 250u) << "each body its own size";
  for (const tumble::PourBody& p : one.pourBodies) check(p.body.shape, 0.4, 1.0);
  EXPECT_EQ(countInitialOverlaps(particlesOf(one)), 0u);
}

// Through the scene reader: a fill by mass (the same as by volume) of a log-normal draws, by
// number, the log-normal of median e^(-3 sigma^2) (KS at 0.001 on its 3000 sizes), and scale =
// [min, max] draws the bodies of a uniform by number bit for bit.
TEST(SceneIo, SizeDistributionsAsRead) {
  const std::string fill = "[[fill]]\nshape = \"ball\"\ncount = 3000\nregion = \"box\"\nmin = [-40, -40, 2]\n"
                           "max = [40, 40, 12]\n";
  const Scene s = tumble::parseScene(
      withExtra(fill + "size = { distribution = \"lognormal\", median = 1, sigma = 0.3, min = 0.5, max = 2, by = \"mass\" }\n"),
      "test.toml");
  std::vector<double> sizes;
  for (std::size_t b = 1; b < s.bodies.size(); ++b) sizes.push_back(s.shapes[s.bodies[b].shape].spheres[0].radius / 0.5);
  std::sort(sizes.begin(), sizes.end());
  const double median = std::exp(-3.0 * 0.09);
  const auto F = [&](double x) {
    const auto z = [&](double v) { return Phi(std::log(v / median) / 0.3); };
    return (z(std::clamp(x, 0.5, 2.0)) - z(0.5)) / (z(2.0) - z(0.5));
  };
  const double D = ksStatistic(sizes, F), critical = 1.949 / std::sqrt(double(sizes.size()));
  std::printf("fill of 3000 by mass (scene seed): D = %.4f, critical %.4f\n", D, critical);
  EXPECT_LT(D, critical);
  const Scene a = tumble::parseScene(withExtra(fill + "scale = [0.5, 1]\n"), "test.toml");
  const Scene b = tumble::parseScene(withExtra(fill + "size = { distribution = \"uniform\", min = 0.5, max = 1 }\n"),
                                     "test.toml");
  EXPECT_TRUE(sameBits(a, b));
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (std::size_t k = 0; k < a.shapes.size(); ++k) EXPECT_EQ(a.shapes[k].spheres[0].radius, b.shapes[k].spheres[0].radius);
}

TEST(SceneIoErrors, SizeDistributions) {
  const std::string f = "[[fill]]\nshape = \"ball\"\ncount = 2\nregion = \"box\"\nmin = [0, 0, 2]\nmax = [9, 9, 9]\n";
  // lines 12-17; the size on line 18
  expectError(withExtra(f + "size = 2\n"), 18, {"size must be a table"});
  expectError(withExtra(f + "scale = 1\nsize = { distribution = \"uniform\", min = 1, max = 2 }\n"), 19,
              {"either scale", "or size"});
  expectError(withExtra(f + "size = { min = 1, max = 2 }\n"), 18, {"missing required key 'distribution'"});
  expectError(withExtra(f + "size = { distribution = \"weibull\" }\n"), 18, {"unknown distribution \"weibull\""});
  expectError(withExtra(f + "size = { distribution = \"normal\", mean = 1, sd = 0.1, median = 1 }\n"), 18,
              {"median is not a key of distribution = \"normal\"", "mean sd min max by"});
  expectError(withExtra(f + "size = { distribution = \"uniform\", min = 1, max = 2, by = \"count\" }\n"), 18,
              {"by must be \"number\"", "\"volume\""});
  expectError(withExtra(f + "size = { distribution = \"uniform\", min = 2, max = 1 }\n"), 18, {"max must be at least min"});
  expectError(withExtra(f + "size = { distribution = \"normal\", mean = 1, sd = 0.5 }\n"), 18,
              {"mean - 3 sd, is not above 0: give min"});
  expectError(withExtra(f + "size = { distribution = \"normal\", mean = 1, sd = 0.001, min = 2, max = 3 }\n"), 18,
              {"no sizes between min and max"});
  expectError(withExtra(f + "size = { distribution = \"lognormal\", median = 1, sigma = 300 }\n"), 18,
              {"median e^(-3 sigma), is not above 0"});
  expectError(withExtra(f + "size = { distribution = \"lognormal\", median = 1, sigma = 0.2, min = 1, max = 1 }\n"), 18,
              {"0 < min < max"});
  expectError(withExtra(f + "size = { distribution = \"table\", sizes = [1, 1, 2], cumulative = [0, 0.5, 1] }\n"), 18,
              {"sizes must increase (entry 2 is not above the one before in single precision)"});
  expectError(withExtra(f + "size = { distribution = \"table\", sizes = [1, 2], cumulative = [0, 0.9] }\n"), 18,
              {"cumulative must start at 0 and end at 1"});
  expectError(withExtra(f + "size = { distribution = \"table\", sizes = [1, 2, 3], cumulative = [0, 1] }\n"), 18,
              {"cumulative has 2 entries for 3 sizes"});
  expectError(withExtra(f + "size = { distribution = \"table\", sizes = [1, 2, 3], cumulative = [0, 0.6, 0.5] }\n"), 18,
              {"cumulative must not decrease (entry 3"});
  expectError(withExtra(f + "size = { distribution = \"uniform\", min = 1e-30, max = 1 }\n"), 18,
              {"size makes a sphere of shape 'ball' leave [2^-60, 2^60] m"});
}
