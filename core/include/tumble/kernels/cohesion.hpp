// SPDX-License-Identifier: MIT
/// @file cohesion.hpp
/// Cohesion of a contact (docs/model.md#cohesion), on top of hooke-history or hertz-mindlin,
/// written once for both pipelines and the guard: an attraction F_c ≥ 0 that pulls the two
/// surfaces together while they overlap (δ > 0), added to the normal force, and the shift it
/// gives the load that caps friction and rolling resistance. A scene without cohesion reads the
/// model (Cohesion::None) and nothing else.
#pragma once
#include <cstdint>

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

/// The cohesive potential of a contact at overlap δ > 0 (double, for the guard and the time
/// series): U = −∫₀^δ F_c, ≤ 0. sjkr on two spheres: −k_c π δ²/4 (S − δ/3 − D²/(S − δ)); on a
/// plane (rj = 0 here means a plane): −k_c π (r δ² − δ³/3); dmt: −2 π γ R* δ.
TUMBLE_HD_INLINE double cohesivePotential(Cohesion model, double value, double delta, double ri, double rj,
                                          bool plane) {
  constexpr double kPiD = 3.14159265358979323846;
  if (model == Cohesion::Sjkr) {
    if (plane) return -kPiD * value * (ri * delta * delta - delta * delta * delta / 3.0);
    const double s = ri + rj, dd = ri - rj;
    return -kPiD * value * 0.25 * delta * delta * (s - delta / 3.0 - dd * dd / (s - delta));
  }
  if (model == Cohesion::Dmt) return -2.0 * kPiD * value * (plane ? ri : ri * rj / (ri + rj)) * delta;
  return 0.0;
}

}  // namespace tumble
