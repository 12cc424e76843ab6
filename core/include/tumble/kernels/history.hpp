// SPDX-License-Identifier: MIT
/// @file history.hpp
/// Histories across a rebuild of a candidate list, written once for both pipelines: the
/// tangential springs ξ of the laws with a history (per entry of the candidate list, keyed by the
/// partner's scene index) and the mesh springs (per entry of the mesh candidate list, keyed by
/// the triangle). Before a rebuild the non-zero ξ of each particle's row are kept by scene index,
/// each with its key, in the row's order (ascending key): count (takenCount, TakeAll) → scan →
/// fill (takeRow). After it, each row of the new list takes the ξ of its keys from the kept row, by a
/// merge of the two sorted rows, and zero for the others (restoreRow). So a history depends on
/// the contacts only, not on the list, the skin or the numbering. The same count → scan → fill
/// reads them out (BodyState::contacts, meshContacts). Each function writes only particle i's
/// outputs.
#pragma once
#include <cstdint>
#include <cstring>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// Whether a spring is out of contact: all bits of its three components zero (+0; the force
/// pass writes +0 to release one). A spring of value zero in contact may hold a negative zero:
/// kept like any other, which keeps its sign across rebuilds too; JKR marks its held contacts
/// so (heldSpring()).
TUMBLE_HD_INLINE bool isZeroSpring(Vec3f h) {
  std::uint32_t a, b, c;
  memcpy(&a, &h.x, sizeof a);
  memcpy(&b, &h.y, sizeof b);
  memcpy(&c, &h.z, sizeof c);
  return (a | b | c) == 0u;
}

/// A JKR contact's spring ξ, marked as held (Cohesion::Jkr): one whose bits are all zero is out
/// of contact (isZeroSpring()), so a held one of value zero keeps a negative zero, which
/// computes as zero everywhere. The lists, their rebuilds, checkpoints and MPI carry whether a
/// neck holds (δ < 0) with the spring, at no cost of memory.
TUMBLE_HD_INLINE Vec3f heldSpring(Vec3f x) {
  if (isZeroSpring(x)) x.z = -0.0f;
  return x;
}

/// The same for a plane's spring (its two components, BodyState's per plane and particle).
TUMBLE_HD_INLINE bool isZeroPlaneSpring(float tx, float ty) { return isZeroSpring(Vec3f{tx, ty, 0.0f}); }
TUMBLE_HD_INLINE void heldPlaneSpring(float* tx, float* ty) {
  if (isZeroPlaneSpring(*tx, *ty)) *ty = -0.0f;
}

/// The key of a candidate-list entry: its partner's scene index.
struct PartnerKey {
  const std::uint32_t* orig;
  const std::uint32_t* cand;
  TUMBLE_HD_INLINE std::uint32_t operator()(std::uint32_t e) const { return orig[cand[e]]; }
};

/// The key of a mesh candidate-list entry: its triangle.
struct TriangleKey {
  const std::uint32_t* tri;
  TUMBLE_HD_INLINE std::uint32_t operator()(std::uint32_t e) const { return tri[e]; }
};

/// Kept histories: CSR by scene index (row o: offsets[o] .. offsets[o + 1]), keys ascending.
struct KeptView {
  const std::uint32_t* offsets;
  const std::uint32_t* key;
  const Vec3f* hist;
};

/// Which entries of a row count, take(me, key) with `me` the row's scene index: every one (kept
/// across a rebuild; BodyState::meshContacts), or those whose partner has a higher scene index
/// (BodyState::contacts: each pair once, i < j).
struct TakeAll {
  TUMBLE_HD_INLINE bool operator()(std::uint32_t, std::uint32_t) const { return true; }
};
struct TakeAbove {
  TUMBLE_HD_INLINE bool operator()(std::uint32_t me, std::uint32_t key) const { return key > me; }
};

/// The number of entries of row i (rows at `offsets`, internal numbering; `me` its scene index)
/// that `take` accepts and whose ξ is non-zero.
template <class KeyOf, class Take>
TUMBLE_HD_INLINE std::uint32_t takenCount(const std::uint32_t* offsets, const Vec3f* hist, const KeyOf& keyOf,
                                          const Take& take, std::uint32_t i, std::uint32_t me) {
  std::uint32_t c = 0;
  for (std::uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) c += take(me, keyOf(e)) && !isZeroSpring(hist[e]) ? 1u : 0u;
  return c;
}

/// Those entries with their keys, written from `at` on (the scan of takenCount() by scene
/// index: at = outOffsets[me]), in row order.
template <class KeyOf, class Take>
TUMBLE_HD_INLINE void takeRow(const std::uint32_t* offsets, const Vec3f* hist, const KeyOf& keyOf, const Take& take,
                              std::uint32_t i, std::uint32_t me, std::uint32_t at, std::uint32_t* outKey,
                              Vec3f* outHist) {
  for (std::uint32_t e = offsets[i]; e < offsets[i + 1]; ++e)
    if (take(me, keyOf(e)) && !isZeroSpring(hist[e])) {
      outKey[at] = keyOf(e);
      outHist[at++] = hist[e];
    }
}

/// Row i of a new list (rows at `offsets`, keys ascending) takes the kept ξ of particle i's scene
/// index `o` for the keys it has, zero for the others.
template <class KeyOf>
TUMBLE_HD_INLINE void restoreRow(const KeptView& kept, std::uint32_t o, const std::uint32_t* offsets, const KeyOf& keyOf,
                                 std::uint32_t i, Vec3f* hist) {
  std::uint32_t k = kept.offsets[o];
  const std::uint32_t kEnd = kept.offsets[o + 1];
  for (std::uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
    const std::uint32_t key = keyOf(e);
    while (k < kEnd && kept.key[k] < key) ++k;
    hist[e] = k < kEnd && kept.key[k] == key ? kept.hist[k] : Vec3f{0.0f, 0.0f, 0.0f};
  }
}

}  // namespace tumble
