// SPDX-License-Identifier: MIT
/// @file cohesion.hpp
/// Cohesion of a contact (docs/model.md#cohesion), on top of hooke-history or hertz-mindlin,
/// written once for both pipelines and the guard: an attraction F_c ≥ 0 that pulls the two
/// surfaces together while they overlap (δ > 0), added to the normal force, and the shift it
/// gives the load that caps friction and rolling resistance. A scene without cohesion reads the
/// model (Cohesion::None) and nothing else.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#include "tumble/hd.hpp"

namespace tumble {

/// The cohesion model of a scene (`[contact] cohesion`).
enum class Cohesion : std::uint8_t {
  None,
  /// LIGGGHTS's simplified JKR (`cohesion sjkr`): F_c = k_c A, A = π a² the area of the circle
  /// where the two surfaces cross, k_c the cohesion energy density [J/m³]; the friction's load is
  /// the normal force without the attraction (LIGGGHTS 3.8's default, tangential_reduce off).
  Sjkr,
  /// Derjaguin–Muller–Toporov: F_c = 2 π γ R*, γ the work of adhesion of the pair [J/m²] (the
  /// pull-off force); the friction's load is F_n + 2 F_c (Thornton; LAMMPS `pair granular dmt`).
  Dmt,
  /// Johnson–Kendall–Roberts (hertz-mindlin only): the Hertz spring replaced by JKR's force at
  /// the contact radius a that the overlap gives, δ = a²/R* − √(2 π γ a / Y*), γ the work of
  /// adhesion [J/m²]; a contact holds in tension (δ < 0, a neck) until δ_c, where a stops
  /// existing (jkrContact()); the friction's load is F_n + 3 π γ R* (twice the pull-off force).
  Jkr,
};

/// The attraction of a contact and the shift of its friction load (F_n + shift caps friction).
struct Attraction {
  float pull;   ///< F_c ≥ 0, towards the partner
  float shift;  ///< added to the normal force for the friction and rolling limits
};

/// a² of two spheres of radii ri, rj overlapping by δ: the squared radius of the circle where
/// their surfaces cross, a² = δ (2S − δ)(d − D)(d + D) / (4 d²), d = S − δ the distance of the
/// centres, S = ri + rj, D = ri − rj (the exact geometry LIGGGHTS's sjkr uses, written without
/// cancellation). Seen from j the same bits (D is negated, the products commute). 0 once one
/// sphere is inside the other (d ≤ |D|: no circle; also coincident centres, d = 0), an overlap
/// far beyond any contact law's that the guard stops.
TUMBLE_HD_INLINE float crossingRadius2(float delta, float ri, float rj) {
  const float s = ri + rj, d = s - delta, dd = ri - rj;
  if (!(d > (dd < 0.0f ? -dd : dd))) return 0.0f;
  return (delta * (2.0f * s - delta)) * ((d - dd) * (d + dd)) / (4.0f * d * d);
}

/// a² of a sphere of radius r pressed δ into a plane: δ (2r − δ) (0 once it is through, δ ≥ 2r).
TUMBLE_HD_INLINE float planeCrossingRadius2(float delta, float r) {
  const float a2 = delta * (2.0f * r - delta);
  return a2 > 0.0f ? a2 : 0.0f;
}

/// The attraction of a contact under `model` with the pair's coefficient `value` (k_c for sjkr,
/// γ for dmt; 0: none), a² of its crossing circle (read by sjkr) and its effective radius R*
/// (read by dmt; a plane: the sphere's radius).
TUMBLE_HD_INLINE Attraction attraction(Cohesion model, float value, float a2, float reff) {
  constexpr float kPiF = 3.14159265358979f;
  if (model == Cohesion::Sjkr) {
    const float pull = (kPiF * value) * a2;
    return Attraction{pull, pull};
  }
  if (model == Cohesion::Dmt) {
    const float pull = (2.0f * kPiF * value) * reff;
    return Attraction{pull, 2.0f * pull};
  }
  return Attraction{0.0f, 0.0f};
}

/// x^(1/3) of a positive normal float, the same bits everywhere (IEEE +, −, ×, ÷ only; the
/// libraries' cbrt may differ by an ulp between host and device): the exponent divided by 3
/// in the bits, then Newton's iterations, each of which about doubles the correct digits.
TUMBLE_HD_INLINE float cubeRoot(float x) {
  std::uint32_t u;
  memcpy(&u, &x, sizeof u);
  u = u / 3u + 709921077u;  // within a few per cent
  float y;
  memcpy(&y, &u, sizeof y);
  for (int k = 0; k < 4; ++k) y = y - (y * y * y - x) / (3.0f * (y * y));
  return y;
}

/// A JKR contact (Cohesion::Jkr) at overlap δ: its contact radius a, its normal force without
/// damping (elastic: positive pushes apart), the shift of its friction load (3 π γ R*), and
/// whether it holds (false: δ ≤ δ_c, the neck has broken; or δ ≤ 0 without adhesion).
struct JkrContact {
  float a, elastic, shift;
  bool held;
};

/// JKR (Johnson, Kendall & Roberts 1971) at overlap δ (negative: stretched) for effective radius
/// R*, Y* and the work of adhesion γ of the pair. With s = √a, δ = s⁴/R* − c s, c = √(2πγ/Y*),
/// so s is the largest root of s⁴ − c R* s − R* δ, found by Newton's iteration from above
/// (the quartic is convex there, so the iterates fall monotonically; they stop when one does
/// not, or when one would fall below s_c, where the quartic turns: within an ulp or two of δ_c
/// rounding can put an iterate there, whence it would run off to the other branch or to −∞):
/// from max(2 s_c, (2 R* δ)^{1/4}), which is above the root. The root exists while
/// δ > δ_c = −¾ c s_c, s_c³ = c R* / 4 (dδ/ds = 0: the neck's end). F = 4 Y* a³ / (3 R*) −
/// √(8 π γ Y* a³) = Y* s³ (4 s³ / (3 R*) − 2 c): −8/9 of the pull-off force 3/2 π γ R* at
/// δ = 0, the pull-off force itself at its minimum, −5/6 π γ R* at δ_c. Without adhesion
/// (γ = 0) Hertz's a = √(R* δ), holding only while δ > 0. Every operation is +, −, ×, ÷ or a
/// square root: the same bits in both pipelines, and for the two sides of a pair.
TUMBLE_HD_INLINE JkrContact jkrContact(float delta, float reff, float ystar, float gamma) {
  constexpr float kPiF = 3.14159265358979f;
  if (!(gamma > 0.0f)) {
    if (!(delta > 0.0f)) return JkrContact{0.0f, 0.0f, 0.0f, false};
    const float a = std::sqrt(reff * delta);
    return JkrContact{a, (4.0f / 3.0f) * ystar * a * a * a / reff, 0.0f, true};
  }
  const float c = std::sqrt((2.0f * kPiF) * gamma / ystar);
  const float x = c * reff;
  const float sc = cubeRoot(0.25f * x);
  if (!(delta > -0.75f * c * sc)) return JkrContact{0.0f, 0.0f, 0.0f, false};
  const float rd = reff * delta;
  float s = 2.0f * sc;
  if (rd > 0.0f) {
    const float h = std::sqrt(std::sqrt(2.0f * rd));
    if (h > s) s = h;
  }
  for (int k = 0; k < 64; ++k) {  // quadratic convergence; linear only at δ_c's double root
    const float s3 = s * s * s;
    const float next = s - ((s3 * s - x * s) - rd) / (4.0f * s3 - x);
    if (!(next < s)) break;
    if (!(next > sc)) {  // past the turn: the root is at s_c within rounding
      s = sc;
      break;
    }
    s = next;
  }
  const float s3 = s * s * s;
  return JkrContact{s * s, ystar * s3 * ((4.0f / 3.0f) * s3 / reff - 2.0f * c), (3.0f * kPiF * gamma) * reff, true};
}

/// JKR's energy of a contact at overlap δ (double, the guard and the time series): U = ∫₀^δ F,
/// from the moment the surfaces meet (δ = 0, s₀³ = c R*), along jkrContact()'s branch:
/// U = Y* (P(s) − P(s₀)), P(t) = 8/15 t¹⁰ / R*² − 4/3 c t⁷ / R* + ½ c² t⁴ (Hertz's
/// 8/15 Y* √R* δ^{5/2} without adhesion). δ > δ_c; s by Newton's iteration in double from
/// above (as jkrContact()), its start from cubeRoot() so that the result is the same bits on
/// any machine.
TUMBLE_HD_INLINE double jkrEnergy(double delta, double reff, double ystar, double gamma) {
  constexpr double kPiD = 3.14159265358979323846;
  const double c = sqrt(2.0 * kPiD * gamma / ystar), x = c * reff;
  double sc = gamma > 0.0 ? double(cubeRoot(float(0.25 * x))) : 0.0;
  for (int k = 0; k < 2 && sc > 0.0; ++k) sc = sc - (sc * sc * sc - 0.25 * x) / (3.0 * sc * sc);
  // s at R* δ = rd, as jkrContact() (from above, stopped at s_c).
  const auto root = [&](double rd) {
    double s = 2.0 * sc;
    if (rd > 0.0 && sqrt(sqrt(2.0 * rd)) > s) s = sqrt(sqrt(2.0 * rd));
    for (int k = 0; k < 200 && s > 0.0; ++k) {
      const double s3 = s * s * s;
      const double next = s - ((s3 * s - x * s) - rd) / (4.0 * s3 - x);
      if (!(next < s)) break;
      if (!(next > sc)) return sc;  // past the turn
      s = next;
    }
    return s;
  };
  const auto p = [&](double t) {
    const double t3 = t * t * t, t4 = t3 * t;
    return (8.0 / 15.0) * t4 * t4 * t * t / (reff * reff) - (4.0 / 3.0) * c * t4 * t3 / reff + 0.5 * c * c * t4;
  };
  return ystar * (p(root(reff * delta)) - p(root(0.0)));  // from s₀ = 4^{1/3} s_c, where δ = 0
}

/// The cohesive potential of a contact at overlap δ > 0 (double, for the guard and the time
/// series): U = −∫₀^δ F_c, ≤ 0. sjkr on two spheres: −k_c π δ²/4 (S − δ/3 − D²/(S − δ)); on a
/// plane (rj = 0 here means a plane): −k_c π (r δ² − δ³/3); dmt: −2 π γ R* δ; jkr: JKR's
/// energy less Hertz's (jkrEnergy() − 8/15 Y* √R* δ^{5/2}), so that with the Hertz spring's it
/// is JKR's.
TUMBLE_HD_INLINE double cohesivePotential(Cohesion model, double value, double delta, double ri, double rj,
                                          bool plane, double ystar = 0.0) {
  constexpr double kPiD = 3.14159265358979323846;
  if (model == Cohesion::Sjkr) {
    if (plane) return -kPiD * value * (ri * delta * delta - delta * delta * delta / 3.0);
    const double s = ri + rj, dd = ri - rj;
    return -kPiD * value * 0.25 * delta * delta * (s - delta / 3.0 - dd * dd / (s - delta));
  }
  const double reff = plane ? ri : ri * rj / (ri + rj);
  if (model == Cohesion::Dmt) return -2.0 * kPiD * value * reff * delta;
  if (model == Cohesion::Jkr)
    return jkrEnergy(delta, reff, ystar, value) - (8.0 / 15.0) * ystar * sqrt(reff) * delta * delta * sqrt(delta);
  return 0.0;
}

}  // namespace tumble
