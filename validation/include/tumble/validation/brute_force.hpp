// SPDX-License-Identifier: MIT
/// @file brute_force.hpp
/// The O(N²) reference pair finder: the oracle every broadphase is checked against.
#pragma once
#include <vector>

#include "tumble/mesh.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::validation {

/// Every pair i < j of particles of different bodies with spheresOverlap() true, sorted by
/// (i, j); with periodic boundaries (cloud.periodic) its minimum-image form (kernels/periodic.hpp).
/// Uses the same predicate as the pipelines, so boundary cases agree by construction.
/// Parallel over i (TBB); output is deterministic.
std::vector<Pair> bruteForcePairs(const ParticleCloud& cloud);

/// Every mesh contact of spheres at positions x (3 floats per particle, the mesh's frame) with
/// radii r, by brute force: each particle against each triangle, with the kernels' own nearest
/// point (nearestOnTriangle(), so that contacts exactly at the boundary agree) and the counting
/// rule of kernels/mesh.hpp written plainly, without the mesh's adjacency: a face point always
/// counts; an edge or vertex point counts when every triangle that has that edge's two
/// vertices (or that vertex), found by comparing all triangles' vertex indices, has its nearest
/// point on the same edge (vertex), and then for the lowest of them. Sorted by (particle,
/// triangle). Parallel over particles (TBB); the output is deterministic.
std::vector<MeshContact> bruteForceMeshContacts(const KernelMesh& mesh, const std::vector<float>& x,
                                                const std::vector<float>& radius);

/// The particle cloud of a world at its current body state (x = X + R u).
ParticleCloud cloudOf(const World& world, const BodyState& state);

}  // namespace tumble::validation
