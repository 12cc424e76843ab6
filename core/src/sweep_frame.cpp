// SPDX-License-Identifier: MIT
// The host-side pieces of the broadphase and of load() that both pipelines call, written once so
// that both give the same bits (sweep_frame.hpp): the bounds and covariance combined in chunk
// order, the PCA axis (Eigen), the frame and cell grid, the sweep window, the detection's totals,
// the Morton grid, the initial rows and the sorted pair list. Compiled by the host compiler with
// the project's flags; the CUDA pipeline copies its chunk partials back and calls the same code.
#include "tumble/sweep_frame.hpp"
#include "tumble/error.hpp"
#include "tumble/memory.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "tumble/kernels/integrate.hpp"

namespace tumble::detail {

BoundsPartial combineBounds(const BoundsPartial* part, std::uint32_t numChunks) {
  BoundsPartial b = emptyBounds();
  for (std::uint32_t c = 0; c < numChunks; ++c) mergeBounds(b, part[c]);
  return b;
}

// Both broadphases' axis from their chunk partials (addCovariance).
Vec3f principalAxisFromPartials(const CovariancePartial* part, std::uint32_t numChunks, std::uint32_t n) {
  if (n < 2) return {0.0f, 0.0f, 1.0f};
  std::array<double, 9> s{};
  for (std::uint32_t c = 0; c < numChunks; ++c)
    for (int k = 0; k < 9; ++k) s[k] += part[c].a[k];
  const double nd = n;
  const double mx = s[0] / nd, my = s[1] / nd, mz = s[2] / nd;
  Eigen::Matrix3d cov;
  cov(0, 0) = s[3] / nd - mx * mx;
  cov(1, 1) = s[4] / nd - my * my;
  cov(2, 2) = s[5] / nd - mz * mz;
  cov(0, 1) = cov(1, 0) = s[6] / nd - mx * my;
  cov(0, 2) = cov(2, 0) = s[7] / nd - mx * mz;
  cov(1, 2) = cov(2, 1) = s[8] / nd - my * mz;
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

// Both broadphases' frame, after the bounds check and the axis.
int computeFrame(const BoundsPartial& b, Vec3f axis, float maxRadius, float cellRadius, const BroadphaseParams& params,
                 SweepFrame* outFrame) {
  SweepFrame& f = *outFrame;
  f.lz = axis;
  // l_p ⟂ l_z from a cross product with the coordinate axis least aligned with l_z.
  const double az[3] = {axis.x, axis.y, axis.z};
  double p[3], q[3];
  tumble::perpendicularPair(az, p, q);
  f.lp = {float(p[0]), float(p[1]), float(p[2])};
  f.lq = {float(q[0]), float(q[1]), float(q[2])};

  double half[3];
  float c[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = static_cast<float>(0.5 * (double(b.lo[k]) + double(b.hi[k])));
    half[k] = std::max(double(b.hi[k]) - c[k], double(c[k]) - b.lo[k]);
  }
  f.center = {c[0], c[1], c[2]};
  // Projected coordinates (and their differences in the sweep) must stay finite floats: beyond
  // this, a pair's test would compare inf − inf and drop it. Refused instead (found by review
  // with the particle CSV fuzz target: clouds at ±2.5e38).
  if (!(half[0] + half[1] + half[2] + double(maxRadius) <= kSweepRange)) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "the particles are spread over more than single precision can sweep (half-extents "
                  "%.3g, %.3g, %.3g m, and the largest radius grown by half the skin %.3g m; at most %.0e in all); "
                  "bring them closer together, or use a smaller skin",
                  half[0], half[1], half[2], double(maxRadius), kSweepRange);
    throw Error(buf);
  }
  const double u = std::ldexp(1.0, -24);
  const double slack = 32.0 * u * (half[0] + half[1] + half[2]) + 1e-30;
  f.slack = static_cast<float>(slack);
  const double ep = std::abs(p[0]) * half[0] + std::abs(p[1]) * half[1] + std::abs(p[2]) * half[2];
  const double eq = std::abs(q[0]) * half[0] + std::abs(q[1]) * half[1] + std::abs(q[2]) * half[2];
  const double reach = double(maxRadius) + 4.0 * slack;

  // 3 diameters: measured best (docs/performance.md), of the typical radius; at least 1/32 of the
  // largest diameter, which bounds the records of the largest sphere; and at least 8 slacks, or
  // the margin alone spans many cells (radii below the slack's 1e-30 floor, or coordinates
  // spread over far more than 10^5 radii). A cell size the user gives is raised to 8 slacks too
  // (speed only): one particle 2e7 m from 258 others made the slack 19 m, each particle cover
  // 4000 cells of 0.6 m and the sweep test every pair in each (found by the particle CSV fuzz
  // target; 0.36 s and 130 MB, against 0.02 s with the automatic cells).
  const double typical = cellRadius > 0.0f ? double(cellRadius) : double(maxRadius);
  double m = std::max(params.cellSize > 0.0f ? double(params.cellSize)
                                             : std::max(6.0 * typical, 2.0 * double(maxRadius) / 32.0),
                      8.0 * double(f.slack));
  for (;;) {
    const double na = std::floor((ep + reach) / m) - std::floor(-(ep + reach) / m) + 3.0;
    const double nb = std::floor((eq + reach) / m) - std::floor(-(eq + reach) / m) + 3.0;
    const double nbPow2 = nb <= 1.0 ? 1.0 : std::exp2(std::ceil(std::log2(nb)));
    if (na * nbPow2 < 2147483648.0) {
      f.cellSize = static_cast<float>(m);
      f.invCellSize = static_cast<float>(1.0 / m);
      f.aMin = static_cast<std::int32_t>(std::floor(-(ep + reach) / m)) - 1;
      f.bMin = static_cast<std::int32_t>(std::floor(-(eq + reach) / m)) - 1;
      f.numA = static_cast<std::uint32_t>(na);
      f.numB = static_cast<std::uint32_t>(nb);
      f.bShift = f.numB > 1 ? static_cast<std::uint32_t>(std::bit_width(f.numB - 1)) : 0u;
      break;
    }
    m *= std::sqrt(na * nbPow2 / 1073741824.0) * 1.01;  // too many cells: coarser grid (speed only)
  }
  const std::uint64_t cells = std::uint64_t(f.numA) << f.bShift;
  return cells > 1 ? static_cast<int>(std::bit_width(cells - 1)) : 0;
}

MortonGrid mortonGridOf(const BoundsPartial& b) {
  float lo[3], extent = 0.0f;
  for (int a = 0; a < 3; ++a) {
    const bool any = b.lo[a] <= b.hi[a];  // false when no centre is finite
    lo[a] = any ? b.lo[a] : 0.0f;
    if (any) extent = std::max(extent, b.hi[a] - b.lo[a]);
  }
  return MortonGrid{Vec3f{lo[0], lo[1], lo[2]}, extent > 0.0f ? 1023.0f / extent : 0.0f};
}

void initialRows(const World& w, std::vector<BodyRow>* outBodies, std::vector<BodyStatic>* outStatic,
                 std::vector<OwnRow>* outOwn) {
  const std::uint32_t nb = w.numBodies(), n = w.numParticles();
  const std::vector<Vec3f> omega = initialOmega(w);
  const BodyState& s = w.state;
  outBodies->resize(nb);
  outStatic->resize(nb);
  for (std::uint32_t k = 0; k < nb; ++k) {
    BodyRow& b = (*outBodies)[k];
    b = BodyRow{};
    b.x = Vec3f{s.px[k], s.py[k], s.pz[k]};
    b.v = Vec3f{s.vx[k], s.vy[k], s.vz[k]};
    b.q = Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]};
    b.l = Vec3f{s.lx[k], s.ly[k], s.lz[k]};
    b.omega = omega[k];
    b.rot = rotationMatrix(b.q);
    b.invMass = w.invMass[k];
    b.first = w.first[k];
    b.count = w.numParticlesOf[k];
    b.orig = k;
    b.image[0] = s.imageX.empty() ? 0 : s.imageX[k];
    b.image[1] = s.imageY.empty() ? 0 : s.imageY[k];
    float reach = 0.0f;
    for (std::uint32_t i = w.first[k], e = i + w.numParticlesOf[k]; i < e; ++i)
      reach = std::max(reach, std::sqrt(w.ux[i] * w.ux[i] + w.uy[i] * w.uy[i] + w.uz[i] * w.uz[i]));
    (*outStatic)[k] = BodyStatic{w.invInertia[k], w.bodyMass[k], reach * (1.0f + 0x1p-20f)};
  }
  outOwn->resize(n);
  for (std::uint32_t i = 0; i < n; ++i) (*outOwn)[i] = OwnRow{Vec3f{w.ux[i], w.uy[i], w.uz[i]}, w.groundDamping[i]};
}

std::vector<Vec3f> initialOmega(const World& world) {
  const BodyState& s = world.state;
  std::vector<Vec3f> omega(world.numBodies(), Vec3f{0, 0, 0});
  for (std::uint32_t k = 0; k < world.numBodies(); ++k)
    // Single-sphere bodies rotate only under a law that turns them; otherwise Ω stays 0.
    if (world.bodyRotates(k))
      omega[k] = angularVelocity(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}, world.invInertia[k],
                               Vec3f{s.lx[k], s.ly[k], s.lz[k]});
  return omega;
}

KeptRows keptOfContacts(std::uint32_t n, const std::vector<ContactHistory>& contacts) {
  KeptRows k;
  k.offsets.assign(std::size_t(n) + 1, 0u);
  for (const ContactHistory& c : contacts) {
    ++k.offsets[c.i + 1];
    ++k.offsets[c.j + 1];
  }
  for (std::uint32_t i = 0; i < n; ++i) k.offsets[i + 1] += k.offsets[i];
  k.key.resize(k.offsets[n]);
  k.hist.resize(k.offsets[n]);
  // In (i, j) order, row p receives its partners below p before those above, each ascending.
  std::vector<std::uint32_t> at(k.offsets.begin(), k.offsets.end() - 1);
  for (const ContactHistory& c : contacts) {
    k.key[at[c.i]] = c.j;
    k.hist[at[c.i]++] = Vec3f{c.x, c.y, c.z};
    k.key[at[c.j]] = c.i;
    k.hist[at[c.j]++] = Vec3f{-c.x, -c.y, -c.z};
  }
  return k;
}

KeptRows keptOfMeshContacts(std::uint32_t n, const std::vector<MeshContactHistory>& contacts) {
  KeptRows k;
  k.offsets.assign(std::size_t(n) + 1, 0u);
  for (const MeshContactHistory& c : contacts) ++k.offsets[c.particle + 1];
  for (std::uint32_t i = 0; i < n; ++i) k.offsets[i + 1] += k.offsets[i];
  k.key.resize(contacts.size());
  k.hist.resize(contacts.size());
  for (std::size_t e = 0; e < contacts.size(); ++e) {
    k.key[e] = contacts[e].triangle;
    k.hist[e] = Vec3f{contacts[e].x, contacts[e].y, contacts[e].z};
  }
  return k;
}

// Both broadphases' sorted pairs (Broadphase::sortedPairs).
std::vector<Pair> sortedPairs(std::uint32_t n, const std::uint32_t* recFirst, const std::uint32_t* inv,
                              const std::uint32_t* nbrOffsets, const std::uint32_t* nbr, std::uint64_t numEntries) {
  std::vector<Pair> out;
  out.reserve(numEntries);
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t r = recFirst[i]; r < recFirst[i + 1]; ++r) {
      const std::uint32_t s = inv[r];
      for (std::uint32_t e = nbrOffsets[s]; e < nbrOffsets[s + 1]; ++e)
        out.push_back({std::min(i, nbr[e]), std::max(i, nbr[e])});
    }
  std::sort(out.begin(), out.end());  // keys are unique, so the order is unique
  return out;
}

}  // namespace tumble::detail

namespace tumble::detail {

std::uint64_t recordLimit(std::uint32_t n) {
  return std::min<std::uint64_t>(kMaxEntries, std::max<std::uint64_t>(4096ull * n, 1ull << 24));
}

void checkTotal(std::uint64_t total, std::uint64_t limit, std::uint64_t bytesEach, std::uint64_t held, std::uint32_t n,
                const char* what, const char* cause, bool atLeast) {
  const std::string shortfall =
      total <= limit && !atLeast ? memoryShortfall((total > held ? total - held : 0) * bytesEach) : std::string();
  if (total <= limit && shortfall.empty() && !atLeast) return;
  std::string msg = "detection would need ";
  msg += atLeast ? "more than " : "";
  msg += std::to_string(total);
  msg += " ";
  msg += what;
  msg += " for ";
  msg += std::to_string(n);
  if (total >= limit || (shortfall.empty() && !atLeast)) {
    msg += " particles (at most ";
    msg += std::to_string(limit);
    msg += "): ";
  } else if (atLeast) {
    msg += " particles, whose buffers (" + std::to_string(bytesEach) + " bytes each) would take all of " +
           availableMemoryText() + ": ";
  } else {
    msg += " particles, " + shortfall + ": ";
  }
  msg += cause;
  throw Error(msg);
}

void checkRecordTotal(std::uint64_t total, std::uint32_t n, float cellSize, float maxRadius, std::uint64_t bytesEach,
                      std::uint64_t held) {
  if (total <= recordLimit(n) && total * kRecordBytes < (1u << 30)) return;  // small: no message to build
  char cause[320];
  std::snprintf(cause, sizeof cause,
                "the cell size %g is too small for particles of radius up to %g, or the particles are spread too "
                "far apart; use a larger [broadphase] cell_size or --cell-size (0 = automatic)",
                double(cellSize), double(maxRadius));
  checkTotal(total, recordLimit(n), bytesEach, held, n, "cell records", cause);
}

// The sweep's window (both broadphases).
SweepWindow sweepWindow(float maxRadius, const SweepFrame& f) {
  const float reachR = maxRadius + 2.0f * f.slack;
  const float maxWindow = 2.0f * reachR;  // ≥ every record's window r_s + reachR
  return {reachR, maxWindow};
}

}  // namespace tumble::detail

namespace tumble::detail {

float sizingRadius(const float* radius, std::size_t n) {
  if (n == 0) return 0.0f;
  std::vector<float> r(radius, radius + n);
  const std::size_t k = (n - 1) * 99 / 100;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(k), r.end());
  return r[k];
}

}  // namespace tumble::detail
