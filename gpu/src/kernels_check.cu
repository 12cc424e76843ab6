// SPDX-License-Identifier: MIT
// Compile-only check: every shared per-element kernel header of core/ built by nvcc, with each
// function instantiated in a __global__ wrapper, so host-only constructs fail CI at once.
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/math.hpp"
#include "tumble/soa.hpp"

namespace tumble {

__global__ void kernelsCheckKernel(SweepFrame f, const float* x, float* out, std::uint64_t* keys, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const Vec3f p{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
  const Projected pr = project(f, p);
  const CellRange cr = cellRange(f, pr, 0.5f);
  keys[i] = sweepKey(cellNumber(f, cr.a0, cr.b0), pr.z) + numRecords(cr) +
            (ownsPair(cr.a0, cr.b0, cr.a0, cr.b0, cr.a1, cr.b1) ? 1u : 0u);
  const bool ov = spheresOverlap(p.x, p.y, p.z, 0.5f, 0.0f, 0.0f, 0.0f, 0.5f);
  const ContactForces cf = contactForces(p, p, p, 0.5f, Vec3f{0, 0, 0}, p, p, 0.5f, ov, ContactCoeffs{1, 1, 1});
  float tx = 0.0f, ty = 0.0f;
  const GroundForces gf = groundForces(p, p, p, 0.5f, 1.0f, GroundCoeffs{0, 1, 1, 0.5f}, 1e-3f, &tx, &ty);
  const Vec3f ext = externalForce(p, 1.0f, Vec3f{0, 0, -9.81f}, 1, 1, 1, 7u, p);
  Vec3f X = p, V = p, L = p, xo, vo;
  Quatf q{1, 0, 0, 0};
  const Sym3f inv{1, 1, 1, 0, 0, 0};
  integrateTranslation(total(cf), 1.0f, 1e-3f, &X, &V);
  const Vec3f om = integrateRotation(gf.normal + gf.friction + ext, inv, 1e-3f, &L, &q) +
                   integrateRotationSplitting(gf.lever, inv, 1e-3f, &L, &q);
  particleFromBody(X, V, q, om, p, &xo, &vo);
  out[i] = xo.x + vo.y + fromOrderedBits(orderedBits(q.w));
}

}  // namespace tumble
