// SPDX-License-Identifier: MIT
/// @file brute_force.hpp
/// The O(N²) reference pair finder: the oracle every broadphase is checked against.
#pragma once
#include <vector>

#include "tumble/pipeline.hpp"

namespace tumble::validation {

/// Every pair i < j of particles of different bodies with spheresOverlap() true, sorted by
/// (i, j); with periodic boundaries (cloud.periodic) its minimum-image form (kernels/periodic.hpp).
/// Uses the same predicate as the pipelines, so boundary cases agree by construction.
/// Parallel over i (TBB); output is deterministic.
std::vector<Pair> bruteForcePairs(const ParticleCloud& cloud);

/// The particle cloud of a world at its current body state (x = X + R u).
ParticleCloud cloudOf(const World& world, const BodyState& state);

}  // namespace tumble::validation
