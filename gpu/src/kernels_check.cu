// SPDX-License-Identifier: MIT
// Compile-only check: every shared per-element kernel header of core/ built by nvcc, with the
// functions the pipelines do not already instantiate called from a __global__ wrapper, so
// host-only constructs fail CI at once (cuda_pipeline.cu and broadphase.cu instantiate the rest).
#include "tumble/kernels/cell_key.hpp"
#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/kernels/mesh.hpp"
#include "tumble/kernels/overlap.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/kernels/step.hpp"
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
            (ownsPair(cr.a0, cr.b0, cr.a0, cr.b0, cr.a1, cr.b1) ? 1u : 0u) + mortonKey(MortonGrid{p, 1.0f}, p);
  const bool ov = spheresOverlap(p.x, p.y, p.z, 0.5f, 0.0f, 0.0f, 0.0f, 0.5f);
  const ContactSide side{p, p, p};
  const ContactForces cf = contactForces<true>(p, 0.25f, 0.5f, 0.5f, side, side, ov, ContactCoeffs{1, 1, 1});
  float tx = 0.0f, ty = 0.0f;
  const GroundForces gf = groundForces<true>(p, 0.5f, side, 1.0f, GroundCoeffs{0, 1, 1, 0.5f, 0.0f}, 1e-3f, &tx, &ty);
  const Vec3f pull = pullForce(p, 1.0f, 1, 1, 1, 7u, p);
  Vec3f X = p, V = p, L = p;
  Quatf q{1, 0, 0, 0};
  Mat3f R;
  const Sym3f inv{1, 1, 1, 0, 0, 0};
  integrateTranslation(total(cf), 1.0f, 1e-3f, &X, &V);
  const Vec3f om = integrateRotation(gf.normal + gf.friction + pull, inv, 1e-3f, &L, &q, &R) +
                   integrateRotationSplitting(gf.arm, inv, 1e-3f, &L, &q, &R);
  const Vec3f xo = particlePosition(X, R, pointVelocity(V, om, p));
  out[i] = xo.x + fromOrderedBits(orderedBits(q.w)) + rotate(q, p).y + tx;
}

// The walls with moving meshes: the posed mesh contacts and the posed candidate query (the CUDA
// pipeline instantiates them too, under its launch configuration; kept here as a direct check).
__global__ void movingMeshCheckKernel(StepView v, ForceParams fp, std::uint32_t* count) {
  const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= v.numParticles) return;
  const PosRow pi = v.pos[i];
  const Vec3f x{pi.x, pi.y, pi.z};
  ParticleForce f{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0u};
  GroundForces gf{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {}};
  wallContacts<true, ContactLaw::HookeHistory, true>(v, fp, v.bodies[v.bodyOf[i]], i, x, pi.r, &f, &gf, false, nullptr);
  std::uint32_t c = 0;
  forPosedTrianglesNear(v.mesh, x, pi.r, [&](std::uint32_t) { ++c; });
  count[i] = c + f.contacts;
}

// The CPU's body batch (bodyForces(), one body per thread here; the report's law and one with
// history), which the CUDA pipeline does
// not instantiate (stepBody<…, kBodyBatch = false>), and the particle pass's debug and history
// paths.
__global__ void bodyBatchCheckKernel(StepView v, ForceParams fp, DebugForcesView dbg, Vec3f* out) {
  const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= v.numBodies) return;
  Vec3f F{0.0f, 0.0f, 0.0f}, T{0.0f, 0.0f, 0.0f};
  const std::uint32_t n = bodyForces<true, ContactLaw::Report, false, false>(v, fp, dbg, v.bodies[k], &F, &T) +
                          bodyForces<true, ContactLaw::HookeHistory, false, false>(v, fp, dbg, v.bodies[k], &F, &T);
  const BodyRow& b = v.bodies[k];
  const ParticleForce h = particleForce<true, true, ContactLaw::HertzMindlin>(v, fp, dbg, b, b.first);
  out[k] = F + T + h.f + Vec3f{float(n), 0.0f, 0.0f};
}

}  // namespace tumble
