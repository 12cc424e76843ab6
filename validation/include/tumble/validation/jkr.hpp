// SPDX-License-Identifier: MIT
/// @file jkr.hpp
/// JKR's theory written out in double (Johnson, Kendall & Roberts 1971; docs/model.md#cohesion),
/// the oracle of the JKR tests (validation/tests/jkr_test.cpp) and of the study's `jkr_sticking`,
/// and the head-on impacts both run.
#pragma once
#include <string>

#include "tumble/factory.hpp"

namespace tumble::validation {

/// JKR's curve for R*, Y* and the work of adhesion γ, parametrised by the contact radius a:
/// δ(a) = a²/R* − √(2πγa/Y*), F(a) = 4Y*a³/(3R*) − √(8πγY*a³).
struct JkrCurve {
  double reff, ystar, gamma;
  double delta(double a) const;
  double force(double a) const;
  double dDelta(double a) const;  ///< dδ/da
  double aEnd() const;            ///< the neck's end: dδ/da = 0, δ_c = delta(aEnd())
  double aTouch() const;          ///< where the surfaces touch, δ = 0
  double aPull() const;           ///< the pull-off point, dF/da = 0
  double pullOff() const;         ///< 3/2 π γ R*
  double work(double a0, double a1) const;  ///< ∫ F dδ from a0 to a1 along the curve (Simpson)
  /// The energy that breaks a neck, ∫_{δ_c}^0 |F| dδ (Thornton & Ning's loss of an elastic impact).
  double neckWork() const;
  double radiusAt(double f) const;  ///< a on the stable branch (a > aPull) where F = f
};

/// The material of the JKR cases: E 1 MPa, ν 0.3, density 2500, γ 0.5 J/m², spheres of radius
/// 2 mm; Y* of two spheres or of a sphere on the rigid ground.
inline constexpr double kJkrE = 1.0e6, kJkrNu = 0.3, kJkrGamma = 0.5, kJkrDensity = 2500.0, kJkrRadius = 0.002;
double jkrYstar(bool plane);

/// A hertz-mindlin + jkr scene of that material (restitution e, gravity g along z, dt), its
/// ground at z = −r (so that a sphere touching it has its centre near z = 0, where a float
/// resolves the slowest motion), shape "s", with `bodies` ([[body]] tables) appended.
std::string jkrSceneText(double e, double g, double dt, const std::string& bodies);

/// The [[body]] tables of a head-on impact at relative speed v: two of the spheres 20 µm apart
/// along x, each at v/2 towards the other, or one 10 µm above the ground falling at v.
std::string jkrHeadOnBodies(bool plane, double v);

/// A head-on impact without damping at relative speed v (jkrHeadOnBodies()): two of the spheres (R* = r/2, m* = m/2)
/// or one on the ground (r, m), with the energy tally on, run for 30000 steps of 1 µs. The
/// relative speed after (positive: apart), the gap between the surfaces at the end (negative:
/// overlapping or a neck), and the tally's dissipated_cohesion.
struct JkrImpact {
  double after, gap, neckEnergy;
};
JkrImpact jkrImpact(Backend backend, bool plane, double v);

}  // namespace tumble::validation
