// SPDX-License-Identifier: MIT
/// @file contact_list.hpp
/// The canonical contact list (SPEC §4) and what builds it, written once for both pipelines.
///
/// Detection (any method, any knob) only proposes candidates; the contact list does not depend
/// on how they were found:
/// 1. **Candidates.** At a rebuild the sweep runs on radii grown by skin/2 and reports every
///    pair within r_i + r_j + skin once (its forward lists by record, and their transpose).
///    candidateCount() / fillCandidates() turn that into particle i's row of a CSR list with
///    both directions, sorted by the partner's *scene* index: a unique result for a given set,
///    whatever order the sweep produced it in.
/// 2. **Contacts.** Every step the exact predicate spheresOverlap() filters each row (the
///    force stage, kernels/step.hpp): the touching partners of i in ascending scene index.
/// 3. **Skin.** The list stays valid while no two particles can have closed in by the skin since
///    the rebuild (less a rounding margin, skinClosureLimit(); Drift): two particles that touch now
///    were then within r_i + r_j + skin. The tests are on a max and a bounding box of the
///    displacements, exact in any order.
/// 4. **Near list (CPU).** A second, thinner skin g inside the first: fillNear() keeps of each
///    row the partners within r_i + r_j + g now, and the forces read that subsequence while no
///    two particles can have closed in by g since (the same rule), refreshing it from the
///    candidate list when they can; the candidate list then holds while a bound on the closure
///    since the rebuild stays below its skin: the bound at the last refresh (the smaller of the
///    closures summed over the near list's intervals and the closure since the rebuild measured
///    at that refresh) plus the closure since. Fewer candidates per step, the same contacts in
///    the same order.
/// 5. **Reordering.** At each rebuild the bodies are renumbered in Morton order of their
///    centres (mortonKey()), particles following their bodies, so that a row's candidates lie
///    near it in memory. Outputs and sums are by scene index, so this changes no bit.
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/math.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// The sweep's output (the broadphase's CSR contact list in two halves; internal numbering):
/// particle i's records are recFirst[i]..recFirst[i+1], record r sits at sorted position
/// inv[r] and lists the forward neighbours nbr[nbrOffsets[s] .. nbrOffsets[s+1]); the backward
/// neighbours are back[backOffsets[i] .. backOffsets[i+1]).
struct SweepListView {
  const std::uint32_t* recFirst;
  const std::uint32_t* inv;
  const std::uint32_t* nbrOffsets;
  const std::uint32_t* nbr;
  const std::uint32_t* backOffsets;
  const std::uint32_t* back;
};

/// Number of candidates of particle i (both directions).
TUMBLE_HD_INLINE std::uint32_t candidateCount(const SweepListView& s, std::uint32_t i) {
  std::uint32_t n = s.backOffsets[i + 1] - s.backOffsets[i];
  for (std::uint32_t r = s.recFirst[i]; r < s.recFirst[i + 1]; ++r) {
    const std::uint32_t sp = s.inv[r];
    n += s.nbrOffsets[sp + 1] - s.nbrOffsets[sp];
  }
  return n;
}

namespace detail {

/// Sorts (key, value) pairs of one row by key (keys distinct): insertion sort for short rows,
/// heap sort (O(n log n), no extra memory, no recursion) for long ones. The result is unique
/// because the keys are distinct, so the algorithm does not matter for the bits. val may be
/// nullptr: the keys alone (a mesh candidate row, kernels/mesh.hpp); kVal decides that once per
/// row, outside the loops.
template <bool kVal>
TUMBLE_HD_INLINE void swapEntries(std::uint32_t* key, std::uint32_t* val, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t k = key[a];
  key[a] = key[b];
  key[b] = k;
  if constexpr (kVal) {
    const std::uint32_t v = val[a];
    val[a] = val[b];
    val[b] = v;
  }
}

template <bool kVal>
TUMBLE_HD_INLINE void siftDown(std::uint32_t* key, std::uint32_t* val, std::uint32_t root, std::uint32_t n) {
  for (;;) {
    std::uint32_t c = 2 * root + 1;
    if (c >= n) return;
    if (c + 1 < n && key[c + 1] > key[c]) ++c;
    if (!(key[c] > key[root])) return;
    swapEntries<kVal>(key, val, c, root);
    root = c;
  }
}

template <bool kVal>
TUMBLE_HD_INLINE void sortRowOf(std::uint32_t* key, std::uint32_t* val, std::uint32_t n) {
  if (n <= 24) {
    for (std::uint32_t a = 1; a < n; ++a) {
      const std::uint32_t k = key[a];
      std::uint32_t v = 0u;
      if constexpr (kVal) v = val[a];
      std::uint32_t b = a;
      for (; b > 0 && key[b - 1] > k; --b) {
        key[b] = key[b - 1];
        if constexpr (kVal) val[b] = val[b - 1];
      }
      key[b] = k;
      if constexpr (kVal) val[b] = v;
    }
    return;
  }
  for (std::uint32_t r = n / 2; r-- > 0;) siftDown<kVal>(key, val, r, n);
  for (std::uint32_t end = n - 1; end > 0; --end) {
    swapEntries<kVal>(key, val, 0, end);
    siftDown<kVal>(key, val, 0, end);
  }
}

TUMBLE_HD_INLINE void sortRow(std::uint32_t* key, std::uint32_t* val, std::uint32_t n) {
  if (val != nullptr)
    sortRowOf<true>(key, val, n);
  else
    sortRowOf<false>(key, nullptr, n);
}

}  // namespace detail

/// Writes the candidates of the sweep's particle a (forward, then backward) to cand[e..], each
/// neighbour b as map(b) (the identity, except for a periodic detection's ghost images, which
/// stand for their particles), with its key orig[map(b)] at key[e..]; returns the new e.
template <class Map>
TUMBLE_HD_INLINE std::uint32_t appendCandidates(const SweepListView& s, const std::uint32_t* orig, std::uint32_t a,
                                                Map&& map, std::uint32_t* cand, std::uint32_t* key, std::uint32_t e) {
  for (std::uint32_t r = s.recFirst[a]; r < s.recFirst[a + 1]; ++r) {
    const std::uint32_t sp = s.inv[r];
    for (std::uint32_t t = s.nbrOffsets[sp]; t < s.nbrOffsets[sp + 1]; ++t, ++e) {
      cand[e] = map(s.nbr[t]);
      key[e] = orig[cand[e]];
    }
  }
  for (std::uint32_t t = s.backOffsets[a]; t < s.backOffsets[a + 1]; ++t, ++e) {
    cand[e] = map(s.back[t]);
    key[e] = orig[cand[e]];
  }
  return e;
}

/// Writes particle i's row cand[offsets[i] .. offsets[i+1]) (internal indices) sorted by the
/// partners' scene indices orig[·]; `key` is scratch of the list's size (receives orig of each
/// entry). Each row has one writer, and its content is unique: the sort keys are distinct.
TUMBLE_HD_INLINE void fillCandidates(const SweepListView& s, const std::uint32_t* orig, const std::uint32_t* offsets,
                                     std::uint32_t* cand, std::uint32_t* key, std::uint32_t i) {
  appendCandidates(s, orig, i, [](std::uint32_t b) { return b; }, cand, key, offsets[i]);
  const std::uint32_t a = offsets[i];
  detail::sortRow(key + a, cand + a, offsets[i + 1] - a);
}

/// Whether entry e of l (particle i at pi, its partner at pj) was a contact of the last step: the
/// exact predicate (through the minimum image in `box`), or under JKR (l.held) the force stage's
/// own decision, which its spring keeps (a held neck beyond touching too; kernels/history.hpp).
TUMBLE_HD_INLINE bool listedContact(const CandidateListView& l, std::uint32_t e, const PosRow& pi, const PosRow& pj,
                                    const PeriodicBox& box) {
  if (l.held != nullptr) return !isZeroSpring(l.held[l.heldSlot != nullptr ? l.heldSlot[e] : e]);
  return spheresOverlap(box, pi.x, pi.y, pi.z, pi.r, pj.x, pj.y, pj.z, pj.r);
}

/// Calls f(j, partner) for each contact of particle i with a partner of a higher scene index
/// (the pairs i < j that pairs() lists for i), in row order (ascending partner), decided at the
/// positions `pos` (listedContact()); j is the partner's internal index, partner its scene index. (The caller may
/// skip the particles that the force stage saw touch nothing: StepView::touching.) With periodic
/// boundaries (`box`), the pairs meet through their minimum image, as in the force stage.
/// Returns how many.
template <class F>
TUMBLE_HD_INLINE std::uint32_t forContactsAbove(const PosRow* pos, const std::uint32_t* orig,
                                                const CandidateListView& l, std::uint32_t i, F&& f,
                                                const PeriodicBox& box = PeriodicBox{}) {
  const PosRow pi = pos[i];
  const std::uint32_t me = orig[i];
  std::uint32_t n = 0;
  for (std::uint32_t e = l.begin[i]; e < l.end[i]; ++e) {
    const std::uint32_t j = l.cand[e];
    const PosRow pj = pos[j];
    const std::uint32_t other = orig[j];
    if (other > me && listedContact(l, e, pi, pj, box)) {
      f(j, other);
      ++n;
    }
  }
  return n;
}

/// How many contacts the particles of body b had in the last step, each from its particle's
/// side (HaloPipeline::contactsOf): the force stage's count per particle (touching), or where it
/// is capped (255), the particle's row walked again at that step's positions `pos`.
TUMBLE_HD_INLINE std::uint64_t bodyContactCount(const BodyRow& b, const std::uint8_t* touching, const PosRow* pos,
                                                const CandidateListView& l, const PeriodicBox& box) {
  std::uint64_t total = 0;
  for (std::uint32_t p = b.first; p < b.first + b.count; ++p) {
    if (touching[p] < 255) {  // the count, unless capped
      total += touching[p];
      continue;
    }
    const PosRow pi = pos[p];
    for (std::uint32_t e = l.begin[p]; e < l.end[p]; ++e) total += listedContact(l, e, pi, pos[l.cand[e]], box) ? 1u : 0u;
  }
  return total;
}

/// Number of those contacts.
TUMBLE_HD_INLINE std::uint32_t contactsAbove(const PosRow* pos, const std::uint32_t* orig, const CandidateListView& l,
                                             std::uint32_t i, const PeriodicBox& box = PeriodicBox{}) {
  return forContactsAbove(pos, orig, l, i, [](std::uint32_t, std::uint32_t) {}, box);
}

/// Writes those contacts as scene-index pairs (i, j), ascending j, from outI/outJ[at] on (room
/// for the whole row suffices); returns how many.
TUMBLE_HD_INLINE std::uint32_t emitContactsAbove(const PosRow* pos, const std::uint32_t* orig,
                                                 const CandidateListView& l, std::uint32_t i, std::uint32_t at,
                                                 std::uint32_t* outI, std::uint32_t* outJ,
                                                 const PeriodicBox& box = PeriodicBox{}) {
  const std::uint32_t me = orig[i];
  std::uint32_t n = 0;
  return forContactsAbove(
      pos, orig, l, i,
      [&](std::uint32_t, std::uint32_t other) {
        outI[at + n] = me;
        outJ[at + n] = other;
        ++n;
      },
      box);
}

/// The rounding margin of the skin test (skinClosureLimit()), 16 · 2^-24 · (2 r_max + skin/2 + W);
/// also what the periodic detection grows radii by so that its candidates hold every contact.
inline double roundingMargin(float skin, float maxRadius, double periodicReach = 0.0) {
  return 16.0 * std::ldexp(1.0, -24) * (2.0 * double(maxRadius) + 0.5 * double(skin) + periodicReach);
}

/// The skin test's limit on how far two particles may have closed in since the rebuild (see
/// Drift, closureOf): the skin less twice a margin for the rounding of the three float tests
/// involved (the candidate test at the build on grown radii, the contact test now, the
/// displacements themselves; each within a few units of 2^-24 relative, docs/model.md),
/// margin = 16 · 2^-24 · (2 r_max + skin/2 + W). W = 0 without periodic boundaries; with them,
/// periodicRoundingReach() of the box (a difference across the boundary is rounded at the size
/// of the box, not of the pair). 0 (a rebuild every step) when the skin is below twice that
/// margin.
inline float skinClosureLimit(float skin, float maxRadius, double periodicReach = 0.0) {
  const double h = 0.5 * double(skin);
  const double margin = roundingMargin(skin, maxRadius, periodicReach);
  const double t = h - margin;
  return t > 0.0 ? static_cast<float>(2.0 * t) : 0.0f;
}

/// How the particles have moved since the skin test's reference (the last rebuild, or the near
/// list's last refresh): the largest squared displacement, and
/// the bounding box of the displacement vectors (per axis the least and the largest component).
/// Both are a max or a min over the particles: exact in any order, so the rebuild decision does
/// not depend on the scheduling.
///
/// The list stays valid while two particles cannot have closed in by the skin. Their distance
/// has changed by at most |Δx_i − Δx_j|, which is below 2 max |Δx| and below the box's diagonal;
/// so the list is kept while the smaller of the two (closureOf()) is below the skin less the
/// margin (skinClosureLimit()). The first is the classic rule; the second keeps the list through
/// a common motion, such as a pile falling as one, which the first cannot.
struct Drift {
  float max2;
  float lo[3], hi[3];
};

TUMBLE_HD_INLINE Drift noDrift() { return Drift{0.0f, {FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}}; }

/// A drift no list survives: a NaN or an overflow makes both criteria fail.
TUMBLE_HD_INLINE void saturateDrift(Drift& d) {
  d.max2 = FLT_MAX;
  for (int a = 0; a < 3; ++a) {
    d.lo[a] = -FLT_MAX;
    d.hi[a] = FLT_MAX;
  }
}

/// Adds one particle's displacement. A NaN makes both criteria fail (max2 and the box become
/// infinite), so that it forces a rebuild, whose bounds check reports the non-finite particle.
TUMBLE_HD_INLINE void addDisplacement(Drift& d, float dx, float dy, float dz) {
  const float d2 = dx * dx + dy * dy + dz * dz;
  if (!(d2 <= FLT_MAX)) {  // NaN or overflow
    saturateDrift(d);
    return;
  }
  if (d2 > d.max2) d.max2 = d2;
  const float c[3] = {dx, dy, dz};
  for (int a = 0; a < 3; ++a) {
    if (c[a] < d.lo[a]) d.lo[a] = c[a];
    if (c[a] > d.hi[a]) d.hi[a] = c[a];
  }
}

/// Adds the displacement of a particle from its reference ref (the skin test's: the positions at
/// the last rebuild or refresh) to x; kPeriodic: the minimum image in `box`, so that a body's
/// wrap does not count as motion.
template <bool kPeriodic>
TUMBLE_HD_INLINE void addParticleDisplacement(Drift& d, const PosRow& x, const PosRow& ref, const PeriodicBox& box) {
  if constexpr (kPeriodic) {
    const Vec3f dx = periodicDifference(box, Vec3f{x.x, x.y, x.z}, Vec3f{ref.x, ref.y, ref.z});
    addDisplacement(d, dx.x, dx.y, dx.z);
  } else {
    addDisplacement(d, x.x - ref.x, x.y - ref.y, x.z - ref.z);
  }
}

/// Adds the displacements of a body's particles as a box about its centre's, d ± e per axis
/// (bodyDrift()): |Δx| ≤ |d| + e, each component within [d_a − e, d_a + e], rounded outwards. A
/// NaN makes both criteria fail, as in addDisplacement().
TUMBLE_HD_INLINE void addBodyDisplacement(Drift& d, float dx, float dy, float dz, float e) {
  const float len = (sqrtf(dx * dx + dy * dy + dz * dz) + e) * (1.0f + 0x1p-20f);
  const float m2 = len * len;
  if (!(m2 <= FLT_MAX)) {  // NaN or overflow
    saturateDrift(d);
    return;
  }
  if (m2 > d.max2) d.max2 = m2;
  const float c[3] = {dx, dy, dz};
  const float grow = e + 0x1p-23f * len;  // the rounding of c ± e
  for (int a = 0; a < 3; ++a) {
    if (c[a] - grow < d.lo[a]) d.lo[a] = c[a] - grow;
    if (c[a] + grow > d.hi[a]) d.hi[a] = c[a] + grow;
  }
}

TUMBLE_HD_INLINE void mergeDrift(Drift& d, const Drift& o) {
  if (o.max2 > d.max2) d.max2 = o.max2;
  for (int a = 0; a < 3; ++a) {
    if (o.lo[a] < d.lo[a]) d.lo[a] = o.lo[a];
    if (o.hi[a] > d.hi[a]) d.hi[a] = o.hi[a];
  }
}

/// How far two particles can have closed in under this drift: min(2 max |Δx|, the box's
/// diagonal), rounded up; infinite (FLT_MAX) after a NaN.
TUMBLE_HD_INLINE float closureOf(const Drift& d) {
  float diag2 = 0.0f;
  for (int a = 0; a < 3; ++a) {
    const float w = d.hi[a] > d.lo[a] ? d.hi[a] - d.lo[a] : 0.0f;
    diag2 += w * w;
  }
  const float m2 = 4.0f * d.max2 < diag2 ? 4.0f * d.max2 : diag2;
  if (!(m2 < FLT_MAX)) return FLT_MAX;
  return sqrtf(m2) * (1.0f + 0x1p-20f);
}

/// The same bound for a static wall (a mesh, whose candidate triangles are found within
/// r + skin/2 + margin at a rebuild): a particle may have closed in on it by max |Δx|, which
/// the common motion of a pile does not hide; doubled, 2 max |Δx| rounded up, so that it is
/// held against the same limit (skinClosureLimit()) as closureOf(): the list holds while every
/// particle has moved less than skin/2 − margin. At least closureOf().
TUMBLE_HD_INLINE float wallClosureOf(const Drift& d) {
  const float m2 = 4.0f * d.max2;
  if (!(m2 < FLT_MAX)) return FLT_MAX;
  return sqrtf(m2) * (1.0f + 0x1p-20f);
}

/// Whether the candidate list is still valid after this drift (limit = skinClosureLimit()).
TUMBLE_HD_INLINE bool listStillValid(const Drift& d, float limit) { return closureOf(d) < limit; }

/// The near list, a second skin inside the first. Row i of the near list is the candidates j of
/// row i that are within r_i + r_j + g now (|d|² < (r_i + r_j + g)², in row order, so in
/// ascending scene index); it is written at the same offsets as the candidate row (nearCand has
/// the candidate list's size) and its end is returned. A partner left out cannot touch i until
/// the two have closed in by g (less a rounding margin: skinClosureLimit(g, ·)), so while that holds
/// the forces may iterate the near list instead of the candidate list: the same contacts in the
/// same order, so the same bits. It is refreshed from the candidate list (point 4 above).
/// kPeriodic: the distances are minimum images in `box` (kernels/periodic.hpp).
///
/// Laws with a history (`history`: ξ per candidate entry; nullptr otherwise): the near entry's
/// candidate entry goes to nearSlot (StepView::historySlot), and a partner left out forgets its
/// history now. It does not touch now (r_i + g + r_j ≥ r_i + r_j in float too), so the forces
/// over the candidate list would zero its ξ at this step (particleForce()); left out, it is not
/// visited again before the next refresh, where it is left out or taken back with ξ = 0 as the
/// candidate list's pass would have it: the same histories, so the same bits.
template <bool kPeriodic = false>
TUMBLE_HD_INLINE std::uint32_t fillNear(const PosRow* pos, const CandidateListView& l, float g, std::uint32_t* nearCand,
                                        std::uint32_t i, const PeriodicBox& box = PeriodicBox{}, Vec3f* history = nullptr,
                                        std::uint32_t* nearSlot = nullptr) {
  const PosRow pi = pos[i];
  std::uint32_t out = l.begin[i];
  for (std::uint32_t e = l.begin[i]; e < l.end[i]; ++e) {
    const std::uint32_t j = l.cand[e];
    const PosRow pj = pos[j];
    nearCand[out] = j;
    bool near;
    if constexpr (kPeriodic)
      near = spheresOverlap(box, pi.x, pi.y, pi.z, pi.r + g, pj.x, pj.y, pj.z, pj.r);
    else
      near = spheresOverlap(pi.x, pi.y, pi.z, pi.r + g, pj.x, pj.y, pj.z, pj.r);
    if (history != nullptr) {
      nearSlot[out] = e;
      if (!near) history[e] = Vec3f{0.0f, 0.0f, 0.0f};
    }
    out += near ? 1u : 0u;
  }
  return out;
}

/// The grid of the reordering: 1024 cells per axis over a box (lo, with 1/cell as scale).
struct MortonGrid {
  Vec3f lo;
  float scale;  ///< cells per unit length
};

namespace detail {
/// Spreads the low 10 bits of v to every third bit.
TUMBLE_HD_INLINE std::uint32_t spreadBits3(std::uint32_t v) {
  v &= 0x3FFu;
  v = (v | (v << 16)) & 0x030000FFu;
  v = (v | (v << 8)) & 0x0300F00Fu;
  v = (v | (v << 4)) & 0x030C30C3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}
TUMBLE_HD_INLINE std::uint32_t gridCell(float c) {
  if (!(c > 0.0f)) return 0u;  // also NaN
  if (c >= 1023.0f) return 1023u;
  return static_cast<std::uint32_t>(c);
}
}  // namespace detail

/// 30-bit Morton (Z-order) key of a body centre on the grid; positions outside the box (or not
/// finite) are clamped to its faces, so any input gives a key.
TUMBLE_HD_INLINE std::uint32_t mortonKey(const MortonGrid& g, Vec3f x) {
  const std::uint32_t a = detail::gridCell((x.x - g.lo.x) * g.scale);
  const std::uint32_t b = detail::gridCell((x.y - g.lo.y) * g.scale);
  const std::uint32_t c = detail::gridCell((x.z - g.lo.z) * g.scale);
  return detail::spreadBits3(a) | (detail::spreadBits3(b) << 1) | (detail::spreadBits3(c) << 2);
}

}  // namespace tumble

namespace tumble {

/// Particle i's detection input at a rebuild: its position, and its radius grown by h (skin/2,
/// plus the periodic rounding margin where there are periodic boundaries).
TUMBLE_HD_INLINE void detectionInput(const PosRow* pos, std::uint32_t i, float h, float* x, float* y, float* z,
                                     float* r) {
  const PosRow p = pos[i];
  x[i] = p.x;
  y[i] = p.y;
  z[i] = p.z;
  r[i] = p.r + h;
}

/// The per-particle columns the reordering moves with their bodies. material, springX/springY
/// (numPlanes × n, plane-major) and planeDamping ((numPlanes − 1) × n, the planes after the
/// first) may be null: the columns a scene does not have.
struct ReorderColumns {
  OwnRow* own;
  float* radius;
  float* mass;
  std::uint16_t* material;
  std::uint32_t* orig;
  std::uint32_t* bodyOf;
  float* springX;
  float* springY;
  float* planeDamping;
};

/// Body k of the new order (the reordering, 5. above): body perm[k] of the old order, whose
/// particles move to first[k] on (the scan of the counts in the new order), each particle's
/// columns with it and its body index k. One writer per output element.
TUMBLE_HD_INLINE void moveBody(const BodyRow* bodies, const BodyStatic* bodyStatic, const std::uint32_t* perm,
                               const std::uint32_t* first, std::uint32_t k, std::uint32_t n, std::uint32_t numPlanes,
                               const ReorderColumns& from, BodyRow* outBodies, BodyStatic* outStatic,
                               const ReorderColumns& to) {
  const BodyRow b = bodies[perm[k]];
  outStatic[k] = bodyStatic[perm[k]];
  for (std::uint32_t t = 0; t < b.count; ++t) {
    const std::uint32_t a = b.first + t, c = first[k] + t;
    to.own[c] = from.own[a];
    to.radius[c] = from.radius[a];
    to.mass[c] = from.mass[a];
    if (from.material != nullptr) to.material[c] = from.material[a];
    to.orig[c] = from.orig[a];
    to.bodyOf[c] = k;
    if (from.springX != nullptr)
      for (std::uint32_t p = 0; p < numPlanes; ++p) {
        to.springX[std::size_t(p) * n + c] = from.springX[std::size_t(p) * n + a];
        to.springY[std::size_t(p) * n + c] = from.springY[std::size_t(p) * n + a];
      }
    if (from.planeDamping != nullptr)
      for (std::uint32_t p = 1; p < numPlanes; ++p)
        to.planeDamping[std::size_t(p - 1) * n + c] = from.planeDamping[std::size_t(p - 1) * n + a];
  }
  BodyRow moved = b;
  moved.first = first[k];
  outBodies[k] = moved;
}

}  // namespace tumble
