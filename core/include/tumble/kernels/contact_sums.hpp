// SPDX-License-Identifier: MIT
/// @file contact_sums.hpp
/// The guard's per-contact terms (docs/model.md#guards): the spring energy of a touching pair,
/// the allowance for the rounding of its positions and its overlap. Accumulated per body (the
/// body of the pair's lower scene index, over its particles in scene order and each particle's
/// partners in ascending scene index: the order of Pipeline::pairs()), so that a pipeline that
/// walks its own contact list and the guard's fallback that walks pairs() add the same terms in
/// the same order and get the same bits.
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "tumble/hd.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// The energy law of the contact springs: linear, ½ k δ² (the report's law, hooke-history), or
/// Hertz, ⅖ K δ^{5/2} with K = 4/3 Y* √R* and Y* of the pair's materials (hertz-mindlin; the
/// tables of World::materialPairs, `material` in scene order, nullptr for one material); with
/// cohesion, plus its potential (cohesivePotential(), ≤ 0) with the pair's coefficient (Hertz:
/// HertzPair::cohesion; linear: `cohesionValue`).
struct SpringLaw {
  double k = 0.0;
  const HertzPair* hertz = nullptr;
  const std::uint16_t* material = nullptr;
  std::uint32_t numMaterials = 0;
  Cohesion cohesion = Cohesion::None;
  double cohesionValue = 0.0;
};

/// Adds a contact's cohesive potential U ≤ 0 at overlap δ to *springs, −U to *bound and the
/// energy its rounding e can move to *slack (value: the pair's k_c or γ; rj unread for a plane;
/// ystar: the pair's Y*, read by jkr).
TUMBLE_HD_INLINE void addCohesiveSum(double* springs, double* slack, double* bound, Cohesion model, double value,
                                     double delta, double e, double ri, double rj, bool plane, double ystar = 0.0) {
  const double u = cohesivePotential(model, value, delta, ri, rj, plane, ystar);
  *springs += u;
  *bound -= u;
  *slack += fabs(u - cohesivePotential(model, value, delta + e, ri, rj, plane, ystar));
}

/// K of Hertz's F = K δ^{3/2}, E = ⅖ K δ^{5/2}, for a pair c and effective radius R*.
TUMBLE_HD_INLINE double hertzStiffness(const HertzPair& c, double reff) { return (4.0 / 3.0) * c.ystar * sqrt(reff); }

/// The sums over a set of contacts (one body's, or all).
struct ContactSums {
  double springs = 0.0;     ///< Σ ½ k δ² (Hertz: ⅖ K δ^{5/2}) over the pairs with δ = r_i + r_j − |x_i − x_j| > 0
  double slack = 0.0;       ///< Σ k e (δ + e) (Hertz: K (δ + e)^{3/2} e), e = 1.8 (err_i + err_j): the energy error of rounded positions
  double bound = 0.0;       ///< with cohesion: Σ −U, the energy the cohesion holds (springs has U)
  double maxOverlap = 0.0;  ///< the largest δ / min(r_i, r_j)
  std::uint32_t deepestI = 0, deepestJ = 0;  ///< its pair (scene particle indices), the first among equals
};

/// The rounding of a float coordinate of magnitude |v|: ½ ulp, and as much again for the
/// particle position computed from it (x = X + R u in float): the step from |v| to the next
/// float. Infinite for a non-finite |v| or one beyond the largest float.
TUMBLE_HD_INLINE double floatRounding(double v) {
  const float a = fabsf(static_cast<float>(v));
  if (!(a < FLT_MAX)) return HUGE_VAL;
  std::uint32_t u;
  memcpy(&u, &a, sizeof u);  // the next float above a non-negative finite a is the next bit pattern
  ++u;
  float next;
  memcpy(&next, &u, sizeof next);
  return double(next) - a;
}

/// The rounding of a body's position X (largest axis): what the guard allows each of its
/// particles' coordinates.
TUMBLE_HD_INLINE double bodyRounding(float x, float y, float z) {
  const float ax = fabsf(x), ay = fabsf(y), az = fabsf(z);
  return floatRounding(ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az));
}

/// Adds the pair (i, j), i < j scene particle indices, at positions (xi, yi, zi) and (xj, yj, zj)
/// (integration frame), with radii ri, rj, the rounding errI, errJ of their bodies' positions
/// (bodyRounding) and the springs' law; with periodic boundaries (`box`) through the minimum image.
TUMBLE_HD_INLINE void addContactSum(ContactSums& a, float xi, float yi, float zi, float ri, float xj, float yj, float zj,
                                    float rj, double errI, double errJ, const SpringLaw& law, std::uint32_t i,
                                    std::uint32_t j, const PeriodicBox& box = PeriodicBox{}) {
  double dx = double(xi) - xj;
  double dy = double(yi) - yj;
  const double dz = double(zi) - zj;
  if (box.on(0)) dx = minimumImage<double>(dx, box.half[0], box.length[0]);
  if (box.on(1)) dy = minimumImage<double>(dy, box.half[1], box.length[1]);
  const double delta = double(ri) + rj - sqrt(dx * dx + dy * dy + dz * dz);
  if (delta <= 0.0) return;
  const double e = 1.8 * (errI + errJ);
  double cohesion = law.cohesionValue, ystar = 0.0;
  if (law.hertz != nullptr) {
    const HertzPair& c =
        law.hertz[materialPairIndex(materialOf(law.material, i), materialOf(law.material, j), law.numMaterials)];
    const double K = hertzStiffness(c, double(ri) * rj / (double(ri) + rj));
    a.springs += 0.4 * K * delta * delta * sqrt(delta);
    a.slack += K * (delta + e) * sqrt(delta + e) * e;
    cohesion = c.cohesion;
    ystar = c.ystar;
  } else {
    a.springs += 0.5 * law.k * delta * delta;
    a.slack += law.k * e * (delta + e);
  }
  if (law.cohesion != Cohesion::None)
    addCohesiveSum(&a.springs, &a.slack, &a.bound, law.cohesion, cohesion, delta, e, ri, rj, false, ystar);
  const double frac = delta / (ri < rj ? ri : rj);
  if (frac > a.maxOverlap) {
    a.maxOverlap = frac;
    a.deepestI = i;
    a.deepestJ = j;
  }
}

/// Body b's entry of Pipeline::contactSumsPerBody() where a pipeline keeps its contacts (one
/// writer per body, both pipelines): the pairs() contacts of its particles, the rows `list`
/// decided at `was` (the positions of the last step; touching: the particles that touched
/// something there), each term at `now` with its bodies' rounding (bodyRounding of their
/// centres; bodyOf: a particle's body), in the order of contactSumsOfPairs(). Internal numbering;
/// orig: the scene indices, as law.material reads them.
TUMBLE_HD_INLINE ContactSums bodyContactSums(const BodyRow* bodies, const std::uint32_t* bodyOf,
                                             const std::uint8_t* touching, const PosRow* was, const PosRow* now,
                                             const std::uint32_t* orig, const CandidateListView& list,
                                             const SpringLaw& law, const PeriodicBox& box, std::uint32_t b) {
  const BodyRow& row = bodies[b];
  const double errI = bodyRounding(row.x.x, row.x.y, row.x.z);
  ContactSums a;
  for (std::uint32_t p = row.first, e = row.first + row.count; p < e; ++p) {
    if (touching[p] == 0) continue;  // the last step saw it touch nothing
    const PosRow xi = now[p];
    const std::uint32_t me = orig[p];
    forContactsAbove(
        was, orig, list, p,
        [&](std::uint32_t j, std::uint32_t other) {
          const PosRow& xj = now[j];
          const Vec3f& xb = bodies[bodyOf[j]].x;
          addContactSum(a, xi.x, xi.y, xi.z, xi.r, xj.x, xj.y, xj.z, xj.r, errI, bodyRounding(xb.x, xb.y, xb.z), law,
                        me, other, box);
        },
        box);
  }
  return a;
}

/// Appends the sums r of the contacts that come after those of l (in pair order).
TUMBLE_HD_INLINE void mergeContactSums(ContactSums& l, const ContactSums& r) {
  l.springs += r.springs;
  l.slack += r.slack;
  l.bound += r.bound;
  if (r.maxOverlap > l.maxOverlap) {  // the first pair among equals, as a serial loop
    l.maxOverlap = r.maxOverlap;
    l.deepestI = r.deepestI;
    l.deepestJ = r.deepestJ;
  }
}

}  // namespace tumble
