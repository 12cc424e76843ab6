// SPDX-License-Identifier: MIT
/// @file soa.hpp
/// Views: trivially copyable structs of raw column pointers plus a count. Both the CPU
/// pipeline (std::vector columns) and the CUDA pipeline (device buffers) hand kernels the
/// same views, passed by value.
#pragma once
#include <cstdint>

#include "tumble/math.hpp"

namespace tumble {

/// Static particle table (never changes during a run).
struct ParticleStaticView {
  const float* radius;
  const float* mass;
  const float* elasticity;     ///< coefficient of restitution of a lone sphere on the ground
  const float* groundDamping;  ///< c_i of the ground spring-dashpot, derived from elasticity
  const std::uint32_t* body;   ///< owning body of each particle
  const float* ux;             ///< offset from the body's centre of mass, body frame
  const float* uy;
  const float* uz;
  std::uint32_t count;
};

/// Per-step particle state, rebuilt from the bodies at the start of each step.
struct ParticleStateView {
  float* x; float* y; float* z;     ///< world position
  float* vx; float* vy; float* vz;  ///< world velocity
  float* rx; float* ry; float* rz;  ///< R(Q) u: lever arm from the body centre
  float* fx; float* fy; float* fz;  ///< total force of the step
  float* tx; float* ty;             ///< ground tangential spring elongation (history)
  std::uint32_t count;
};

/// Body table: static mass properties plus the integrated state.
struct BodiesView {
  const float* invMass;
  const Sym3f* invInertia;          ///< body-frame I0⁻¹ about the centre of mass
  const std::uint32_t* first;       ///< first particle of each body (particles are contiguous)
  const std::uint32_t* numParticles;
  float* px; float* py; float* pz;  ///< centre of mass X
  float* vx; float* vy; float* vz;  ///< V
  float* qw; float* qx; float* qy; float* qz;  ///< orientation Q
  float* lx; float* ly; float* lz;  ///< angular momentum L, world frame
  std::uint32_t count;
};

}  // namespace tumble
