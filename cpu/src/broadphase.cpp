// SPDX-License-Identifier: MIT
// CPU broadphase (SPEC §3), after Liu et al. 2010: sweep and prune along the PCA axis with a
// 2-D subdivision of the perpendicular plane.
//
// Design notes
// - Exactness. Coordinates are projected relative to the centre of the bounding box, so a
//   scene offset by 1e6 loses no precision in differences. `slack` bounds the rounding error
//   of a projected coordinate (≤ 32 u Σ half-extents, u = 2^-24); cell ranges and the sweep
//   window are widened by it, which makes both conservative. The final decision is always the
//   shared predicate spheresOverlap() on the original coordinates, exactly as the oracle does.
// - Determinism. Keys are integers (cell, ordered z bits); the radix sort is stable with the
//   unsorted record number as value, so ties break by index. The sweep writes each record's
//   neighbours in a fixed order into fixed-size chunks whose concatenation does not depend on
//   how TBB schedules them. The covariance is summed in double in fixed chunks.
// - Once-only. Each record walks forwards through its cell and keeps a neighbour only in the
//   cell holding the lower corner of the two cell ranges' intersection (SPEC §3.7), so each
//   pair is found exactly once. The other side's view comes from a transpose: a stable radix
//   sort of (other particle, owner) by other particle. Both halves have a fixed order and
//   need no atomics.
#include "broadphase.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "grow.hpp"
#include "tumble/cpu/radix_sort.hpp"
#include "tumble/cpu/scan.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/overlap.hpp"

namespace tumble::cpu::detail {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr std::uint32_t kChunk = 4096;        // fixed reduction / sweep chunk (determinism)
constexpr std::uint32_t kSweepChunk = 2048;   // records per sweep output buffer

struct Bounds {
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                 std::numeric_limits<float>::max()};
  float hi[3] = {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                 -std::numeric_limits<float>::max()};
  std::uint32_t firstBad = std::numeric_limits<std::uint32_t>::max();
};

Bounds computeBounds(const BroadphaseInput& in) {
  const std::uint32_t numChunks = (in.n + kChunk - 1) / kChunk;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, numChunks), Bounds{},
      [&](const tbb::blocked_range<std::uint32_t>& rc, Bounds b) {
        for (std::uint32_t c = rc.begin(); c != rc.end(); ++c) {
          const std::uint32_t end = std::min(in.n, (c + 1) * kChunk);
          for (std::uint32_t i = c * kChunk; i < end; ++i) {
            const float v[3] = {in.x[i], in.y[i], in.z[i]};
            if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && std::isfinite(in.r[i]))) {
              b.firstBad = std::min(b.firstBad, i);
              continue;
            }
            for (int k = 0; k < 3; ++k) {
              b.lo[k] = std::min(b.lo[k], v[k]);
              b.hi[k] = std::max(b.hi[k], v[k]);
            }
          }
        }
        return b;
      },
      [](Bounds a, const Bounds& b) {  // min / max are exact: any combination order is fine
        for (int k = 0; k < 3; ++k) {
          a.lo[k] = std::min(a.lo[k], b.lo[k]);
          a.hi[k] = std::max(a.hi[k], b.hi[k]);
        }
        a.firstBad = std::min(a.firstBad, b.firstBad);
        return a;
      });
}

// Principal axis of the centred covariance (SPEC §3.1 fix), summed in double in fixed chunks.
Vec3f principalAxis(const BroadphaseInput& in) {
  if (in.n < 2) return {0.0f, 0.0f, 1.0f};
  const double sx = in.x[0], sy = in.y[0], sz = in.z[0];  // shift: keeps the sums well conditioned
  const std::uint32_t numChunks = (in.n + kChunk - 1) / kChunk;
  std::vector<std::array<double, 9>> part(numChunks);
  tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
    std::array<double, 9> a{};
    const std::uint32_t end = std::min(in.n, (c + 1) * kChunk);
    for (std::uint32_t i = c * kChunk; i < end; ++i) {
      const double x = in.x[i] - sx, y = in.y[i] - sy, z = in.z[i] - sz;
      a[0] += x; a[1] += y; a[2] += z;
      a[3] += x * x; a[4] += y * y; a[5] += z * z;
      a[6] += x * y; a[7] += x * z; a[8] += y * z;
    }
    part[c] = a;
  });
  std::array<double, 9> s{};
  for (const auto& a : part)
    for (int k = 0; k < 9; ++k) s[k] += a[k];
  const double n = in.n;
  const double mx = s[0] / n, my = s[1] / n, mz = s[2] / n;
  Eigen::Matrix3d cov;
  cov(0, 0) = s[3] / n - mx * mx;
  cov(1, 1) = s[4] / n - my * my;
  cov(2, 2) = s[5] / n - mz * mz;
  cov(0, 1) = cov(1, 0) = s[6] / n - mx * my;
  cov(0, 2) = cov(2, 0) = s[7] / n - mx * mz;
  cov(1, 2) = cov(2, 1) = s[8] / n - my * mz;
  if (!cov.allFinite() || cov.norm() == 0.0) return {0.0f, 0.0f, 1.0f};
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d v = es.eigenvectors().col(2);  // largest eigenvalue
  // Fixed sign: largest-magnitude component positive.
  int k = 0;
  for (int j = 1; j < 3; ++j)
    if (std::abs(v[j]) > std::abs(v[k])) k = j;
  if (v[k] < 0) v = -v;
  v.normalize();
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// The sweep's inner loop: tests `len` consecutive sorted records against one probe record and
// writes a 0/1 hit flag per candidate; returns the number of hits. Branch-free, so it vectorises; compiled twice (AVX2 and
// baseline x86-64) and picked at load time. Both clones do the same IEEE operations (no FMA:
// -ffp-contract=off), so the flags are identical.
struct Probe {
  float x, y, z, r, pz, window;
  std::uint32_t body;
  std::int32_t a0, b0, a, b;
};
struct SortedColumns {
  const float* x;
  const float* y;
  const float* z;
  const float* r;
  const float* pz;
  const std::uint32_t* body;
  const std::int32_t* a0;
  const std::int32_t* b0;
};

__attribute__((target_clones("avx2", "default"))) std::uint32_t testCandidates(const SortedColumns& c, std::uint32_t base,
                                                                    std::uint32_t len, const Probe& me,
                                                                    std::uint32_t* __restrict hits) {
  const float* __restrict cx = c.x + base;
  const float* __restrict cy = c.y + base;
  const float* __restrict cz = c.z + base;
  const float* __restrict cr = c.r + base;
  const float* __restrict cpz = c.pz + base;
  const std::uint32_t* __restrict cb = c.body + base;
  const std::int32_t* __restrict ca0 = c.a0 + base;
  const std::int32_t* __restrict cb0 = c.b0 + base;
  std::uint32_t numHits = 0;
  for (std::uint32_t t = 0; t < len; ++t) {
    const bool hit = (cpz[t] - me.pz < me.window) & (cb[t] != me.body) & (std::max(me.a0, ca0[t]) == me.a) &
                     (std::max(me.b0, cb0[t]) == me.b) & spheresOverlap(me.x, me.y, me.z, me.r, cx[t], cy[t], cz[t], cr[t]);
    hits[t] = hit;
    numHits += hit;
  }
  return numHits;
}

}  // namespace

void Broadphase::computeFrame(const BroadphaseInput& in, const BroadphaseParams& params) {
  const Bounds b = computeBounds(in);
  if (b.firstBad != std::numeric_limits<std::uint32_t>::max())
    throw SimulationError("particle " + std::to_string(b.firstBad) + " has a non-finite position or radius");

  if (m_runsSinceAxis < 0 || m_runsSinceAxis >= std::max(1, params.pcaEvery)) {
    m_axis = principalAxis(in);
    m_runsSinceAxis = 0;
  }
  ++m_runsSinceAxis;

  SweepFrame& f = m_frame;
  f.lz = m_axis;
  // l_p ⟂ l_z from a cross product with the coordinate axis least aligned with l_z.
  const double az[3] = {m_axis.x, m_axis.y, m_axis.z};
  int least = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(az[k]) < std::abs(az[least])) least = k;
  double e[3] = {0, 0, 0};
  e[least] = 1.0;
  double p[3] = {az[1] * e[2] - az[2] * e[1], az[2] * e[0] - az[0] * e[2], az[0] * e[1] - az[1] * e[0]};
  const double pn = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  for (double& c : p) c /= pn;
  const double q[3] = {az[1] * p[2] - az[2] * p[1], az[2] * p[0] - az[0] * p[2], az[0] * p[1] - az[1] * p[0]};
  f.lp = {float(p[0]), float(p[1]), float(p[2])};
  f.lq = {float(q[0]), float(q[1]), float(q[2])};

  double half[3];
  float c[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = static_cast<float>(0.5 * (double(b.lo[k]) + double(b.hi[k])));
    half[k] = std::max(double(b.hi[k]) - c[k], double(c[k]) - b.lo[k]);
  }
  f.center = {c[0], c[1], c[2]};
  const double u = std::ldexp(1.0, -24);
  const double slack = 32.0 * u * (half[0] + half[1] + half[2]) + 1e-30;
  f.slack = static_cast<float>(slack);
  const double ep = std::abs(p[0]) * half[0] + std::abs(p[1]) * half[1] + std::abs(p[2]) * half[2];
  const double eq = std::abs(q[0]) * half[0] + std::abs(q[1]) * half[1] + std::abs(q[2]) * half[2];
  const double reach = double(in.maxRadius) + 4.0 * slack;

  double m = params.cellSize > 0.0f ? params.cellSize : 4.0 * in.maxRadius;
  for (;;) {
    const double na = std::floor((ep + reach) / m) - std::floor(-(ep + reach) / m) + 3.0;
    const double nb = std::floor((eq + reach) / m) - std::floor(-(eq + reach) / m) + 3.0;
    if (na * nb < 2147483648.0) {
      f.cellSize = static_cast<float>(m);
      f.invCellSize = static_cast<float>(1.0 / m);
      f.aMin = static_cast<std::int32_t>(std::floor(-(ep + reach) / m)) - 1;
      f.bMin = static_cast<std::int32_t>(std::floor(-(eq + reach) / m)) - 1;
      f.numA = static_cast<std::uint32_t>(na);
      f.numB = static_cast<std::uint32_t>(nb);
      break;
    }
    m *= std::sqrt(na * nb / 1073741824.0) * 1.01;  // too many cells: coarser grid (speed only)
  }
  const std::uint64_t cells = std::uint64_t(f.numA) * f.numB;
  m_cellBits = cells > 1 ? std::bit_width(cells - 1) : 0;
}

void Broadphase::run(const BroadphaseInput& in, const BroadphaseParams& params, double* seconds) {
  const std::uint32_t n = in.n;
  auto t0 = Clock::now();
  m_numRecords = 0;
  m_numEntries = 0;
  tumble::detail::grow(recFirst, n + 1);
  if (n == 0) {
    recFirst[0] = 0;
    tumble::detail::grow(nbrOffsets, 1)[0] = 0;
    return;
  }
  computeFrame(in, params);
  const SweepFrame f = m_frame;
  seconds[int(Phase::Axis)] += since(t0);

  // Keys: count records per particle, scan, emit (key, unsorted record number).
  t0 = Clock::now();
  ParticleRow* prow = tumble::detail::grow(m_prow, n);
  std::uint32_t* counts = tumble::detail::grow(m_counts, n + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kChunk), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
      const Projected pr = project(f, Vec3f{in.x[i], in.y[i], in.z[i]});
      const CellRange cr = cellRange(f, pr, in.r[i]);
      prow[i] = ParticleRow{in.x[i], in.y[i], in.z[i], in.r[i], pr.z, in.body[i], cr.a0, cr.b0};
      counts[i] = tumble::numRecords(cr);
    }
  });
  counts[n] = 0;
  std::uint32_t* first = recFirst.data();
  std::size_t tempBytes = 0;
  exclusiveSum<std::uint32_t>(nullptr, tempBytes, counts, first, n + 1);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, counts, first, n + 1);
  const std::uint32_t numRec = first[n];
  m_numRecords = numRec;
  std::uint64_t* keys = tumble::detail::grow(m_keys, numRec);
  std::uint32_t* vals = tumble::detail::grow(m_vals, numRec);
  std::uint32_t* recParticle = tumble::detail::grow(m_recParticle, numRec);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kChunk), [&](const auto& rg) {
    for (std::uint32_t i = rg.begin(); i != rg.end(); ++i) {
      std::uint32_t r = first[i];
      const ParticleRow& pi = prow[i];
      if (counts[i] == 1) {
        keys[r] = sweepKey(cellNumber(f, pi.a0, pi.b0), pi.pz);
        vals[r] = r;
        recParticle[r] = i;
        continue;
      }
      const CellRange cr = cellRange(f, project(f, Vec3f{in.x[i], in.y[i], in.z[i]}), in.r[i]);
      for (std::int32_t a = cr.a0; a <= cr.a1; ++a)
        for (std::int32_t b = cr.b0; b <= cr.b1; ++b, ++r) {
          keys[r] = sweepKey(cellNumber(f, a, b), pi.pz);
          vals[r] = r;
          recParticle[r] = i;
        }
    }
  });
  seconds[int(Phase::Keys)] += since(t0);

  // Sort records by (cell, z).
  t0 = Clock::now();
  std::uint64_t* skeys = tumble::detail::grow(m_sortedKeys, numRec);
  std::uint32_t* svals = tumble::detail::grow(m_sortedVals, numRec);
  const int endBit = 32 + m_cellBits;
  radixSortPairs<std::uint64_t, std::uint32_t>(nullptr, tempBytes, keys, skeys, vals, svals, numRec, 0, endBit);
  radixSortPairs<std::uint64_t, std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, keys, skeys,
                                               vals, svals, numRec, 0, endBit);
  seconds[int(Phase::Sort)] += since(t0);

  // Sweep: gather sorted columns, then walk each record's cell both ways.
  t0 = Clock::now();
  std::uint32_t* invp = tumble::detail::grow(inv, numRec);
  float* sx = tumble::detail::grow(m_sx, numRec);
  float* sy = tumble::detail::grow(m_sy, numRec);
  float* sz = tumble::detail::grow(m_sz, numRec);
  float* sr = tumble::detail::grow(m_sr, numRec);
  float* spz = tumble::detail::grow(m_spz, numRec);
  std::uint32_t* sp = tumble::detail::grow(m_sp, numRec);
  std::uint32_t* sbody = tumble::detail::grow(m_sbody, numRec);
  std::int32_t* sa0 = tumble::detail::grow(m_sa0, numRec);
  std::int32_t* sb0 = tumble::detail::grow(m_sb0, numRec);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, numRec, kChunk), [&](const auto& rg) {
    for (std::uint32_t s = rg.begin(); s != rg.end(); ++s) {
      const std::uint32_t r = svals[s];
      const std::uint32_t i = recParticle[r];
      const ParticleRow pi = prow[i];
      invp[r] = s;
      sp[s] = i;
      sx[s] = pi.x;
      sy[s] = pi.y;
      sz[s] = pi.z;
      sr[s] = pi.r;
      spz[s] = pi.pz;
      sbody[s] = pi.body;
      sa0[s] = pi.a0;
      sb0[s] = pi.b0;
    }
  });
  const std::uint32_t numChunks = (numRec + kSweepChunk - 1) / kSweepChunk;
  if (m_chunkNbr.size() < numChunks) m_chunkNbr.resize(numChunks);
  std::uint32_t* nbrCount = tumble::detail::grow(m_nbrCount, numRec + 1);
  const float reachR = in.maxRadius + 2.0f * f.slack;
  const float maxWindow = 2.0f * reachR;  // ≥ every record's window r_s + reachR
  const SortedColumns cols{sx, sy, sz, sr, spz, sbody, sa0, sb0};
  tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
    auto& out = m_chunkNbr[c];
    out.clear();
    std::vector<std::uint32_t> cand;
    const std::uint32_t end = std::min(numRec, (c + 1) * kSweepChunk);
    std::uint32_t e = c * kSweepChunk + 1;  // two pointers: end of the widest possible window
    for (std::uint32_t s = c * kSweepChunk; s < end; ++s) {
      const std::uint32_t cell = static_cast<std::uint32_t>(skeys[s] >> 32);
      const float zs = spz[s];
      if (e <= s) e = s + 1;
      while (e < numRec && static_cast<std::uint32_t>(skeys[e] >> 32) == cell && spz[e] - zs < maxWindow) ++e;
      const std::int32_t a = static_cast<std::int32_t>(cell / f.numB) + f.aMin;
      const std::int32_t b = static_cast<std::int32_t>(cell % f.numB) + f.bMin;
      const Probe me{sx[s], sy[s], sz[s], sr[s], zs, sr[s] + reachR, sbody[s], sa0[s], sb0[s], a, b};
      const std::uint32_t len = e - s - 1;
      if (cand.size() < len) cand.resize(len);
      const std::uint32_t base = s + 1;
      const std::uint32_t k = testCandidates(cols, base, len, me, cand.data());
      if (k > 0) {  // most records have no contact at all
        const std::uint32_t* hits = cand.data();
        for (std::uint32_t t = 0; t < len; ++t)
          if (hits[t]) out.push_back(sp[base + t]);
      }
      nbrCount[s] = k;
    }
  });
  nbrCount[numRec] = 0;
  std::uint32_t* offs = tumble::detail::grow(nbrOffsets, numRec + 1);
  exclusiveSum<std::uint32_t>(nullptr, tempBytes, nbrCount, offs, numRec + 1);
  exclusiveSum<std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, nbrCount, offs, numRec + 1);
  m_numEntries = offs[numRec];
  const std::uint32_t numEntries = static_cast<std::uint32_t>(m_numEntries);
  std::uint32_t* nb = tumble::detail::grow(nbr, numEntries);
  std::uint32_t* owner = tumble::detail::grow(m_owner, numEntries);
  tbb::parallel_for(std::uint32_t{0}, numChunks, [&](std::uint32_t c) {
    const auto& src = m_chunkNbr[c];
    std::copy(src.begin(), src.end(), nb + offs[c * kSweepChunk]);
    const std::uint32_t end = std::min(numRec, (c + 1) * kSweepChunk);
    for (std::uint32_t s = c * kSweepChunk; s < end; ++s)
      std::fill(owner + offs[s], owner + offs[s + 1], sp[s]);
  });
  // Transpose: stable sort of (other, owner) by other gives each particle its backward list.
  std::uint32_t* bkeys = tumble::detail::grow(m_backKeys, numEntries);
  std::uint32_t* bvals = tumble::detail::grow(back, numEntries);
  const int nBits = std::max(1, static_cast<int>(std::bit_width(n - 1)));
  radixSortPairs<std::uint32_t, std::uint32_t>(nullptr, tempBytes, nb, bkeys, owner, bvals, numEntries, 0, nBits);
  radixSortPairs<std::uint32_t, std::uint32_t>(tumble::detail::grow(m_temp, tempBytes), tempBytes, nb, bkeys, owner,
                                               bvals, numEntries, 0, nBits);
  // Offsets from the sorted keys: entry k starts particle i's list for every i in
  // (key[k−1], key[k]]; one writer per offset.
  std::uint32_t* boffs = tumble::detail::grow(backOffsets, n + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, numEntries + 1, kChunk), [&](const auto& rg) {
    for (std::uint32_t k = rg.begin(); k != rg.end(); ++k) {
      const std::uint32_t lo = k == 0 ? 0 : bkeys[k - 1] + 1;
      const std::uint32_t hi = k == numEntries ? n : bkeys[k];
      for (std::uint32_t i = lo; i <= hi; ++i) boffs[i] = k;
    }
  });
  seconds[int(Phase::Sweep)] += since(t0);
}

std::vector<Pair> Broadphase::sortedPairs(std::uint32_t n) const {
  std::vector<Pair> out;
  out.reserve(m_numEntries);
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t r = recFirst[i]; r < recFirst[i + 1]; ++r) {
      const std::uint32_t s = inv[r];
      for (std::uint32_t e = nbrOffsets[s]; e < nbrOffsets[s + 1]; ++e)
        out.push_back({std::min(i, nbr[e]), std::max(i, nbr[e])});
    }
  std::sort(out.begin(), out.end());  // keys are unique, so the order is unique
  return out;
}

}  // namespace tumble::cpu::detail
