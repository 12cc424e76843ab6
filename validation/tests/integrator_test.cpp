// SPDX-License-Identifier: MIT
// The two rotation schemes ([integrator] rotation, docs/model.md#rotation): the report's
// exponential map and the symplectic splitting. Free rotation of an asymmetric clump against
// its invariants (|L|, kinetic energy), the two schemes against each other at a small dt, and
// the principal-frame bookkeeping of the splitting scheme (same particles, same shape frame).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "tumble_test/cuda_gate.hpp"
#include "tumble/factory.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/world.hpp"

using namespace tumble;

namespace {

class IntegratorTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    TUMBLE_NEED_BACKEND(GetParam());
  }
};

// An asymmetric clump (three distinct principal moments, axes not aligned with the shape frame).
ShapeDef oddShape() {
  return ShapeDef{"odd",
                  {SphereDef{{0, 0, 0}, 0.3f, 2.0f, 0.5f}, SphereDef{{0.5f, 0, 0}, 0.2f, 1.0f, 0.5f},
                   SphereDef{{0, 0.35f, 0.1f}, 0.15f, 0.5f, 0.5f}, SphereDef{{-0.2f, -0.1f, 0.4f}, 0.25f, 1.5f, 0.5f}}};
}

Scene freeSpin(RotationScheme scheme, float dt) {
  Scene s;
  s.gravity = {0, 0, 0};
  s.shapes = {oddShape()};
  s.dt = dt;
  s.integrator.rotation = scheme;
  BodyDef b;
  b.position = {1.0f, -2.0f, 0.5f};
  b.orientation = normalized(Quatf{0.9f, 0.1f, -0.3f, 0.2f});
  b.angularVelocity = {0.5f, 6.0f, 0.3f};  // near an intermediate axis: it tumbles
  s.bodies = {b};
  return s;
}

double norm3(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

// World positions of every particle (double), from the body state and the world's offsets.
std::vector<double> particlePositions(const World& w, const BodyState& s) {
  std::vector<double> out;
  for (std::uint32_t i = 0; i < w.numParticles(); ++i) {
    const std::uint32_t k = w.body[i];
    const Vec3f ru = rotate(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}, Vec3f{w.ux[i], w.uy[i], w.uz[i]});
    out.push_back(double(s.px[k]) + ru.x);
    out.push_back(double(s.py[k]) + ru.y);
    out.push_back(double(s.pz[k]) + ru.z);
  }
  return out;
}

struct SpinRun {
  double l0, l1, maxDrift, finalDrift;
};

SpinRun spin(Backend backend, RotationScheme scheme, float dt, int checks, int stepsPerCheck) {
  const World w = World::fromScene(freeSpin(scheme, dt));
  auto p = makePipeline(backend);
  p->load(w);
  BodyState st;
  p->readState(st);
  SpinRun r{};
  r.l0 = norm3(st.lx[0], st.ly[0], st.lz[0]);
  const double e0 = kineticEnergy(w, st);
  for (int i = 0; i < checks; ++i) {
    p->step(static_cast<std::uint64_t>(stepsPerCheck));
    p->readState(st);
    r.finalDrift = (kineticEnergy(w, st) - e0) / e0;
    r.maxDrift = std::max(r.maxDrift, std::abs(r.finalDrift));
  }
  r.l1 = norm3(st.lx[0], st.ly[0], st.lz[0]);
  return r;
}

}  // namespace

// The splitting scheme's body frame is the principal frame, but the particles, L and the shape
// orientation it reports are those of the scene.
TEST_P(IntegratorTest, SplittingUsesPrincipalFrameWithoutChangingTheBody) {
  const World a = World::fromScene(freeSpin(RotationScheme::Report, 1e-4f));
  const World b = World::fromScene(freeSpin(RotationScheme::Splitting, 1e-4f));
  // Principal frame: the inertia is diagonal, the same moments (trace) as the shape frame's.
  EXPECT_EQ(b.invInertia[0].xy, 0.0f);
  EXPECT_EQ(b.invInertia[0].xz, 0.0f);
  EXPECT_EQ(b.invInertia[0].yz, 0.0f);
  EXPECT_NE(a.inertia[0].xy, 0.0f) << "the test shape must not already be principal";
  const double ta = double(a.inertia[0].xx) + a.inertia[0].yy + a.inertia[0].zz;
  const double tb = double(b.inertia[0].xx) + b.inertia[0].yy + b.inertia[0].zz;
  EXPECT_NEAR(ta, tb, 1e-6 * ta);
  const auto xa = particlePositions(a, a.state), xb = particlePositions(b, b.state);
  for (std::size_t i = 0; i < xa.size(); ++i) EXPECT_NEAR(xa[i], xb[i], 1e-6) << "coordinate " << i;
  for (auto c : {&BodyState::lx, &BodyState::ly, &BodyState::lz})
    EXPECT_NEAR((a.state.*c)[0], (b.state.*c)[0], 1e-5 * std::abs((a.state.*c)[0]) + 1e-7);
  const Quatf qa = shapeOrientation(a, a.state, 0), qb = shapeOrientation(b, b.state, 0);
  const double d = std::abs(double(qa.w) * qb.w + double(qa.x) * qb.x + double(qa.y) * qb.y + double(qa.z) * qb.z);
  EXPECT_NEAR(d, 1.0, 1e-6) << "shape orientation must round-trip through the principal frame";
  // Report scheme: the body frame is the shape frame, bit for bit.
  EXPECT_EQ(shapeOrientation(a, a.state, 0).w, a.state.qw[0]);
}

// Free rotation: both schemes keep |L| (the drift leaves L alone); the splitting keeps the
// kinetic energy bounded where the report's scheme drifts. dt = 2e-3 with |ω| ≈ 6 rad/s
// (|ω| dt ≈ 0.012), 20 000 steps = 40 s, several tumbling periods.
TEST_P(IntegratorTest, SplittingKeepsEnergyWhereReportSchemeDrifts) {
  const SpinRun rep = spin(GetParam(), RotationScheme::Report, 2e-3f, 200, 100);
  const SpinRun spl = spin(GetParam(), RotationScheme::Splitting, 2e-3f, 200, 100);
  std::printf("free spin 40 s at dt 2e-3: report |L| rel change %.2e, KE drift max %.3e final %.3e\n",
              (rep.l1 - rep.l0) / rep.l0, rep.maxDrift, rep.finalDrift);
  std::printf("                           splitting |L| rel change %.2e, KE drift max %.3e final %.3e\n",
              (spl.l1 - spl.l0) / spl.l0, spl.maxDrift, spl.finalDrift);
  EXPECT_NEAR(rep.l1, rep.l0, 1e-6 * rep.l0);
  EXPECT_NEAR(spl.l1, spl.l0, 1e-6 * spl.l0);
  EXPECT_LT(spl.maxDrift, 1e-3) << "symplectic splitting: energy error bounded, O(dt²)";
  EXPECT_LT(spl.maxDrift * 10.0, rep.maxDrift) << "the splitting must do clearly better than the report's scheme";
}

// At a small dt both schemes follow the same motion: the particle positions after 1 s agree.
TEST_P(IntegratorTest, SchemesAgreeAtSmallTimeStep) {
  const float dt = 1e-4f;
  std::vector<double> x[2];
  for (int s = 0; s < 2; ++s) {
    const RotationScheme scheme = s == 0 ? RotationScheme::Report : RotationScheme::Splitting;
    const World w = World::fromScene(freeSpin(scheme, dt));
    auto p = makePipeline(GetParam());
    p->load(w);
    p->step(10000);
    BodyState st;
    p->readState(st);
    x[s] = particlePositions(w, st);
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < x[0].size(); ++i) worst = std::max(worst, std::abs(x[0][i] - x[1][i]));
  std::printf("report vs splitting after 1 s at dt 1e-4: max particle distance %.3e m\n", worst);
  EXPECT_LT(worst, 5e-3) << "both are consistent integrators of the same equations";
}

// The splitting step itself: one exact sub-rotation about a principal axis of a body spinning
// about that axis is the exact solution (Q turns by |ω| dt, L and π unchanged).
TEST(IntegratorKernel, SplittingIsExactForSpinAboutAPrincipalAxis) {
  const Sym3f invI{0.5f, 0.25f, 0.125f, 0.0f, 0.0f, 0.0f};
  Vec3f L{0.0f, 0.0f, 8.0f};  // ω = I⁻¹ L = 1 rad/s about z
  Quatf q{1.0f, 0.0f, 0.0f, 0.0f};
  Mat3f R;
  for (int i = 0; i < 1000; ++i) integrateRotationSplitting(Vec3f{0, 0, 0}, invI, 1e-3f, &L, &q, &R);
  // After 1 s: rotated by 1 rad about z.
  EXPECT_NEAR(q.w, std::cos(0.5), 1e-5);
  EXPECT_NEAR(q.z, std::sin(0.5), 1e-5);
  EXPECT_EQ(L.z, 8.0f);
}

INSTANTIATE_TEST_SUITE_P(Backends, IntegratorTest, ::testing::ValuesIn(compiledBackends()),
                         tumble_test::backendName);
