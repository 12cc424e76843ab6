// SPDX-License-Identifier: MIT
// JKR's sticking velocity (docs/model.md#jkr-and-its-hysteresis): the coefficient of restitution
// of elastic adhesive impacts against Thornton & Ning's (1998) criterion.
#include <cmath>
#include <vector>

#include "study_physics_common.hpp"
#include "tumble/validation/jkr.hpp"

namespace tumble::validation::study::physics {

CaseResult jkrSticking(const CaseContext& ctx) {
  CaseResult r;
  r.id = "jkr_sticking";
  r.title = "JKR: elastic adhesive impacts stick below Thornton & Ning's velocity";
  constexpr double kPi = 3.14159265358979323846;
  const double m = kJkrDensity * 4.0 / 3.0 * kPi * kJkrRadius * kJkrRadius * kJkrRadius;
  const std::vector<double> ratios = ctx.depth == Depth::Quick ? std::vector<double>{0.5, 0.9, 1.1, 1.5, 2.5}
                                                               : std::vector<double>{0.5, 0.7, 0.9, 0.97, 1.03, 1.1, 1.25,
                                                                                     1.5, 2.0, 2.5, 3.0};
  Table t{"restitution", {"case", "v_over_vs", "e_measured", "e_theory"}, {}};
  std::string parts;
  for (const bool plane : {false, true}) {
    const JkrCurve c{plane ? kJkrRadius : 0.5 * kJkrRadius, jkrYstar(plane), kJkrGamma};
    const double w = c.neckWork(), vs = std::sqrt(2.0 * w / (plane ? m : 0.5 * m));
    double worst = 0.0, worstLoss = 0.0;
    int wrongSide = 0;
    for (const double f : ratios) {
      const JkrImpact i = jkrImpact(ctx.backend, plane, f * vs);
      const bool stuck = i.gap < -c.delta(c.aEnd());  // within the neck's reach
      const double e = stuck ? 0.0 : i.after / (f * vs), want = f > 1.0 ? std::sqrt(1.0 - 1.0 / (f * f)) : 0.0;
      t.rows.push_back({plane ? 1.0 : 0.0, f, e, want});
      wrongSide += stuck != (f < 1.0) ? 1 : 0;
      if (f > 1.0) {
        worst = std::max(worst, std::fabs(e - want));
        worstLoss = std::max(worstLoss, std::fabs(i.neckEnergy - w) / w);
      }
    }
    const char* name = plane ? "a sphere on the ground" : "two spheres";
    r.checks.push_back(zeroCheck(fmt("%s: impacts on the wrong side of V_s", name), "stuck iff v < V_s", wrongSide));
    r.checks.push_back(absCheck(fmt("%s: restitution above V_s", name), "e = √(1 − (V_s/v)²)", worst, 0.0, 0.01, "e"));
    r.checks.push_back(boundCheck(fmt("%s: dissipated_cohesion / W above V_s − 1", name), "W = ∫ |F| dδ over the neck",
                                  worstLoss, 0.01, "relative"));
    parts += fmt("%s%s: V_s %.4g m/s, W %.4g J, restitution within %.2g, the tally's neck energy within %.2g of W",
                 parts.empty() ? "" : "; ", name, vs, w, worst, worstLoss);
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"restitution", "restitution of elastic JKR impacts against v / V_s", "restitution", "v_over_vs",
                         "v / V_s", "e", {"e_measured", "e_theory"}, false, false, "case"});
  r.summary = fmt(
      "Head-on impacts without damping (restitution 1) of two spheres (case 0) and of a sphere on the rigid ground "
      "(case 1) under hertz-mindlin + jkr (E 1 MPa, ν 0.3, γ 0.5 J/m², r 2 mm, 1 µs steps, the CPU pipeline or the "
      "study's backend). JKR's hysteresis takes W = ∫_{δ_c}^0 |F| dδ (7.09 (γ⁵R*⁴/Y*²)^{1/3}) from every impact that "
      "breaks its neck: below V_s = √(2W/m*) the pair sticks, above it rebounds with e = √(1 − (V_s/v)²) "
      "(Thornton & Ning 1998). %s.",
      parts.c_str());
  return r;
}

}  // namespace tumble::validation::study::physics
