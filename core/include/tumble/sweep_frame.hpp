// SPDX-License-Identifier: MIT
/// @file sweep_frame.hpp
/// Host-side pieces of the broadphase shared by the CPU and CUDA pipelines, written once so
/// that both give the same bits: the bounds reduction (per fixed chunk, merged in order), the
/// PCA axis from the covariance chunk partials (Eigen, in core/src/sweep_frame.cpp), the sweep
/// frame and cell grid, the sweep window, the initial angular velocities and the sorted pair
/// list. Valid C++17 (also included by .cu files). Internal: namespace tumble::detail.
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#include "tumble/hd.hpp"
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/history.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"
#include "tumble/soa.hpp"
#include "tumble/world.hpp"

namespace tumble::detail {

/// Fixed reduction chunk: bounds and covariance partials are per 4096 particles, combined on
/// the host in chunk order (the same on every backend and thread count).
inline constexpr std::uint32_t kChunk = 4096;

/// Bounding box of the finite particles plus the lowest index of a non-finite one
/// (FLT_MAX is std::numeric_limits<float>::max()).
struct BoundsPartial {
  float lo[3];
  float hi[3];
  std::uint32_t firstBad;
};

TUMBLE_HD_INLINE BoundsPartial emptyBounds() {
  return BoundsPartial{{FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}, 0xFFFFFFFFu};
}

/// Adds particle i exactly as the CPU's computeBounds does: a particle with a non-finite
/// coordinate or radius only lowers firstBad.
TUMBLE_HD_INLINE void addParticle(BoundsPartial& b, std::uint32_t i, float x, float y, float z, float r) {
  if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && std::isfinite(r))) {
    if (i < b.firstBad) b.firstBad = i;
    return;
  }
  const float v[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    b.lo[k] = v[k] < b.lo[k] ? v[k] : b.lo[k];  // std::min(lo, v): keeps lo unless v < lo
    b.hi[k] = b.hi[k] < v[k] ? v[k] : b.hi[k];  // std::max(hi, v): keeps hi unless hi < v
  }
}

/// left ∪ right, where `left` covers lower particle indices than `right`. std::min/std::max
/// keep their first argument on ties, so this keeps the LOWEST-index value among equal extrema
/// (which matters only for −0 vs +0). Associative, so any tree that combines contiguous ranges
/// in order gives the same bits as the CPU's ordered parallel_reduce.
TUMBLE_HD_INLINE void mergeBounds(BoundsPartial& left, const BoundsPartial& right) {
  for (int k = 0; k < 3; ++k) {
    left.lo[k] = right.lo[k] < left.lo[k] ? right.lo[k] : left.lo[k];
    left.hi[k] = left.hi[k] < right.hi[k] ? right.hi[k] : left.hi[k];
  }
  left.firstBad = right.firstBad < left.firstBad ? right.firstBad : left.firstBad;
}

/// The bounds of particles [begin, end) added in index order (empty when begin ≥ end): a CPU
/// chunk.
TUMBLE_HD_INLINE BoundsPartial boundsOfRange(const BroadphaseInput& in, std::uint32_t begin, std::uint32_t end) {
  BoundsPartial b = emptyBounds();
  for (std::uint32_t i = begin; i < end; ++i) addParticle(b, i, in.x[i], in.y[i], in.z[i], in.r[i]);
  return b;
}

/// A chunk's covariance sums (k: Σx, Σy, Σz, Σx², Σy², Σz², Σxy, Σxz, Σyz of the coordinates
/// shifted by particle 0).
struct CovariancePartial {
  double a[9];
};

/// Adds one particle to a covariance chunk partial a[9] (CovariancePartial::a)
/// with the coordinates shifted by (sx, sy, sz): one rounding per operation, never contracted
/// (__dadd_rn and __dmul_rn on the device, -ffp-contract=off on the host), so that both
/// pipelines' partials, summed in index order within each chunk, are the same bits.
TUMBLE_HD_INLINE void addCovariance(double* a, float px, float py, float pz, double sx, double sy, double sz) {
#if defined(__CUDA_ARCH__)
  const double x = __dsub_rn(static_cast<double>(px), sx);
  const double y = __dsub_rn(static_cast<double>(py), sy);
  const double z = __dsub_rn(static_cast<double>(pz), sz);
  a[0] = __dadd_rn(a[0], x);
  a[1] = __dadd_rn(a[1], y);
  a[2] = __dadd_rn(a[2], z);
  a[3] = __dadd_rn(a[3], __dmul_rn(x, x));
  a[4] = __dadd_rn(a[4], __dmul_rn(y, y));
  a[5] = __dadd_rn(a[5], __dmul_rn(z, z));
  a[6] = __dadd_rn(a[6], __dmul_rn(x, y));
  a[7] = __dadd_rn(a[7], __dmul_rn(x, z));
  a[8] = __dadd_rn(a[8], __dmul_rn(y, z));
#else
  const double x = static_cast<double>(px) - sx;
  const double y = static_cast<double>(py) - sy;
  const double z = static_cast<double>(pz) - sz;
  a[0] += x;
  a[1] += y;
  a[2] += z;
  a[3] += x * x;
  a[4] += y * y;
  a[5] += z * z;
  a[6] += x * y;
  a[7] += x * z;
  a[8] += y * z;
#endif
}

/// Combines per-chunk partials in chunk order (host).
BoundsPartial combineBounds(const BoundsPartial* part, std::uint32_t numChunks);

/// Principal axis from the covariance chunk partials, summed in chunk order, then the same Eigen
/// solve and sign rule as the CPU's principalAxis. n ≥ 2.
Vec3f principalAxisFromPartials(const CovariancePartial* part, std::uint32_t numChunks, std::uint32_t n);

/// The most the sweep holds: the particles' half-extents along x, y and z plus their reach (the
/// largest radius, grown by half the skin) [m]; beyond it a projected coordinate or a difference
/// of two would overflow single precision. computeFrame() refuses more, and load refuses a skin
/// whose half alone passes it (effectiveSkin()).
inline constexpr double kSweepRange = 1.0e38;

/// The CPU's Broadphase::computeFrame after the bounds and axis: frame axes, centre, slack,
/// cell size and cell counts. Returns the number of cell bits of the sort key. The automatic
/// cell size (params.cellSize 0) is 3 diameters of cellRadius (0: of maxRadius), but at least
/// 1/32 of the largest diameter, so that one large sphere covers at most about 32 × 32 cells,
/// and at least 8 slacks, so that the rounding margin alone never spans many cells; a given
/// cell size is raised to 8 slacks too (speed only). Throws tumble::Error beyond kSweepRange.
int computeFrame(const BoundsPartial& b, Vec3f axis, float maxRadius, float cellRadius, const BroadphaseParams& params,
                 SweepFrame* outFrame);

/// The radius that sizes the automatic cells: the 99th percentile of the radii, so that a few
/// large spheres among many small ones do not make every cell hold hundreds of small ones (the
/// sweep then tests them all against each other). All radii equal: that radius. 0 for none.
float sizingRadius(const float* radius, std::size_t n);

/// The reordering's Morton grid over the bounds of the body centres (kernels/contact_list.hpp):
/// 1024 cells along the largest extent. Any grid gives correct results; this one only sets the
/// memory order.
MortonGrid mortonGridOf(const BoundsPartial& bodyCentres);

/// The pipelines' rows of a loaded world (in its integration frame), in scene order: body rows
/// with Ω (initialOmega) and R, the bodies' static rows, and the particles' own rows.
void initialRows(const World& world, std::vector<BodyRow>* outBodies, std::vector<BodyStatic>* outStatic,
                 std::vector<OwnRow>* outOwn);

/// Ω = R I0⁻¹ Rᵀ L of every body that rotates: every clump, and the single-sphere bodies too
/// under a law that turns spheres (ContactParams::rotatesSpheres); 0 for the others (they do
/// not rotate; their L is kept but never used). The pipelines' load().
std::vector<Vec3f> initialOmega(const World& world);

/// How far beyond a particle's radius its mesh row reaches at a rebuild (forMeshRow()):
/// skin/2 and the rounding margin of the skin test.
inline float meshRowGrowth(float skin, float maxRadius) {
  return static_cast<float>(0.5 * double(skin) + roundingMargin(skin, maxRadius));
}

/// Contact histories kept across a rebuild (kernels/history.hpp), on the host: CSR by scene
/// index (row o: offsets[o] .. offsets[o + 1]), each row's keys ascending.
struct KeptRows {
  std::vector<std::uint32_t> offsets, key;
  std::vector<Vec3f> hist;
};

/// The kept form of a loaded state's contact histories (BodyState::contacts: pairs i < j,
/// sorted) for n particles: each pair in both rows, ξ negated in row j's; row p holds its
/// partners below p, then those above, each ascending. The pipelines' load().
KeptRows keptOfContacts(std::uint32_t n, const std::vector<ContactHistory>& contacts);
/// The same of the mesh springs (BodyState::meshContacts, sorted by (particle, triangle)).
KeptRows keptOfMeshContacts(std::uint32_t n, const std::vector<MeshContactHistory>& contacts);

/// BodyState::contacts and meshContacts entries: make(me, key, ξ) of readRows().
struct MakeContact {
  ContactHistory operator()(std::uint32_t me, std::uint32_t other, Vec3f h) const { return {me, other, h.x, h.y, h.z}; }
};
struct MakeMeshContact {
  MeshContactHistory operator()(std::uint32_t me, std::uint32_t t, Vec3f h) const { return {me, t, h.x, h.y, h.z}; }
};

/// The entries of rows CSR by scene index (as KeptRows: offsets of n + 1) that take(me, key)
/// accepts (TakeAll, TakeAbove) and whose ξ is non-zero, as make(me, key, ξ), in row order:
/// BodyState::contacts and meshContacts from the kept rows, or from rows a pipeline took out of
/// its lists (takenCount() → scan → takeRow()).
template <class Out, class Take, class Make>
std::vector<Out> readRows(std::uint32_t n, const std::uint32_t* offsets, const std::uint32_t* key, const Vec3f* hist,
                          const Take& take, const Make& make) {
  std::vector<Out> out;
  out.reserve(offsets[n]);
  for (std::uint32_t me = 0; me < n; ++me)
    for (std::uint32_t k = offsets[me]; k < offsets[me + 1]; ++k)
      if (take(me, key[k]) && !isZeroSpring(hist[k])) out.push_back(make(me, key[k], hist[k]));
  return out;
}

/// Pairs (i < j), sorted, from the forward half of the CSR contact list (the CPU's
/// Broadphase::sortedPairs).
std::vector<Pair> sortedPairs(std::uint32_t n, const std::uint32_t* recFirst, const std::uint32_t* inv,
                              const std::uint32_t* nbrOffsets, const std::uint32_t* nbr, std::uint64_t numEntries);

}  // namespace tumble::detail

namespace tumble::detail {

/// The detection's 32-bit scans and buffers hold at most 2^31 − 1 entries, on both backends.
/// Records are cells overlapped per particle, a few in a typical scene whatever its density:
/// more than 4096 per particle on average (beyond 2^24) means a cell size far too small for the
/// radii, or coordinates so spread that the rounding slack spans many cells. Candidate pairs grow
/// with the density instead, and are bounded by the scans only. Both totals are summed in 64 bits
/// before the 32-bit scans and refused with a clear error (checkTotal) instead of wrapping or
/// exhausting memory.
inline constexpr std::uint64_t kMaxEntries = 0x7fffffffull;

/// The least memory per record (64-bit key and 32-bit value, sorted into a second pair of
/// buffers) and per candidate pair (the forward and backward lists, then both directions of the
/// candidate list with their sort keys, or the sorted pair list of findPairs).
inline constexpr std::uint64_t kRecordBytes = 24;
inline constexpr std::uint64_t kCandidateBytes = 32;

/// The most records a detection of n particles may have (see kMaxEntries).
std::uint64_t recordLimit(std::uint32_t n);

/// Throws tumble::Error when `total` entries (`what`: "cell records", "candidate pairs") exceed
/// `limit`, naming the count, the limit and `cause`. Also refused: a total within the limit whose
/// buffers (bytesEach per entry, at least; 0: not checked, as for device memory) exceed the memory
/// the system has available, which would end in std::bad_alloc after a long wait. Only the growth
/// counts: `held` entries are in buffers the detection already has (a run's earlier detections),
/// which the available memory no longer includes. `atLeast`: the count stopped there.
void checkTotal(std::uint64_t total, std::uint64_t limit, std::uint64_t bytesEach, std::uint64_t held, std::uint32_t n,
                const char* what, const char* cause, bool atLeast = false);

/// checkTotal() of a detection's record total, with the cause: a cell size too small for the
/// radii, or particles spread too far apart.
void checkRecordTotal(std::uint64_t total, std::uint32_t n, float cellSize, float maxRadius, std::uint64_t bytesEach,
                      std::uint64_t held);

/// The cause named when the candidate pairs exceed the limit.
inline constexpr const char* kDenseCause =
    "the particles overlap too densely for one detection (in a run, a smaller skin lowers the count)";

/// The sweep's two window constants, computed exactly as the CPU's Broadphase::run does:
/// reach = maxRadius + 2·slack; every record's window is r_s + reach, and maxWindow = 2·reach
/// bounds them all.
struct SweepWindow {
  float reach;
  float maxWindow;
};
SweepWindow sweepWindow(float maxRadius, const SweepFrame& f);

}  // namespace tumble::detail
