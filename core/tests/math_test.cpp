// SPDX-License-Identifier: MIT
// The shared math kernels (math.hpp) on the values a diverging run hands them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tumble/math.hpp"

using tumble::sinCos;

// A rotation angle ω dt of 1.7e27 rad (found by the scene fuzz target with dt = 1e14 s) reached
// the conversion to long long, beyond its range: undefined behaviour (UBSan). Every finite angle
// now gives a bounded sine and cosine, and ±∞ or NaN give NaN.
TEST(Math, SinCosOfAnyAngle) {
  for (const float a : {1.0e5f, 1.5e5f, -3.0e6f, 1.0e14f, 1.6777e27f, -1.0e30f, 3.40282347e38f, -3.40282347e38f}) {
    float s = 0.0f, c = 0.0f;
    sinCos(a, &s, &c);
    EXPECT_TRUE(std::isfinite(s) && std::isfinite(c)) << a;
    EXPECT_NEAR(double(s) * s + double(c) * c, 1.0, 1e-5) << a;
  }
  for (const float a : {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                        std::numeric_limits<float>::quiet_NaN()}) {
    float s = 0.0f, c = 0.0f;
    sinCos(a, &s, &c);
    EXPECT_TRUE(std::isnan(s) && std::isnan(c)) << a;
  }
  // Unchanged where the reduction is exact: the library's sine within a few ulp.
  for (float a = -1.0e5f; a <= 1.0e5f; a += 997.31f) {
    float s = 0.0f, c = 0.0f;
    sinCos(a, &s, &c);
    EXPECT_NEAR(s, std::sin(double(a)), 4e-6) << a;
    EXPECT_NEAR(c, std::cos(double(a)), 4e-6) << a;
  }
}
