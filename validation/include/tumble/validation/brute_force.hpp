// SPDX-License-Identifier: MIT
/// @file brute_force.hpp
/// The O(N²) reference pair finder: the oracle every broadphase is checked against.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "tumble/mesh.hpp"
#include "tumble/pipeline.hpp"

namespace tumble::validation {

/// Every pair i < j of particles of different bodies with spheresOverlap() true, sorted by
/// (i, j); with periodic boundaries (cloud.periodic) its minimum-image form (kernels/periodic.hpp).
/// Uses the same predicate as the pipelines, so boundary cases agree by construction.
/// Parallel over i (TBB); output is deterministic.
std::vector<Pair> bruteForcePairs(const ParticleCloud& cloud);

/// An oracle independent of the shared predicate (issue 34, item 7): the pairs of different
/// bodies whose distance squared, |x_i − x_j|² computed in double from the float inputs (exact
/// to 2^-52), is below (r_i + r_j)² by more than a relative `band`, in `sure`; those within the
/// band (where the float predicate may round either way) in `unsure`. Both sorted by (i, j).
/// No periodic boundaries; O(N²), for clouds of a few thousand.
struct DoublePairs {
  std::vector<Pair> sure, unsure;
};
DoublePairs doublePrecisionPairs(const ParticleCloud& cloud, double band);

/// Every mesh contact of spheres at positions x (3 floats per particle, the mesh's frame) with
/// radii r, by brute force: each particle against each triangle, with the kernels' own nearest
/// point (nearestOnTriangle(), so that contacts exactly at the boundary agree) and the counting
/// rule of kernels/mesh.hpp written plainly, without the mesh's adjacency: a face point always
/// counts; an edge or vertex point counts when every triangle that has that edge's two
/// vertices (or that vertex), found by comparing all triangles' vertex indices, has its nearest
/// point on the same edge (vertex), and then for the lowest of them. Sorted by (particle,
/// triangle). Parallel over particles (TBB); the output is deterministic. With `poses` (one per
/// plane, setWallMotion(); empty: every mesh where it was given) each triangle meets the centre
/// taken into its wall's frame by the kernels' transform (meshPoint(), the pose the pipeline
/// uses), so that contacts exactly at the boundary agree.
std::vector<MeshContact> bruteForceMeshContacts(const KernelMesh& mesh, const std::vector<float>& x,
                                                const std::vector<float>& radius,
                                                const std::vector<MeshPose>& poses = {});

/// The point of triangle abc nearest p, in double (Ericson, Real-Time Collision Detection,
/// 5.1.5): the kernels' nearestOnTriangle() is checked against it.
std::array<double, 3> nearestPointDouble(const double a[3], const double b[3], const double c[3], const double p[3]);

/// A run checked against bruteForceMeshContacts() at every step (meshOracleRun()).
struct MeshOracleRun {
  std::uint64_t steps = 0, contacts = 0, rebuilds = 0;  ///< steps that agreed, their contacts, the list's rebuilds
  std::vector<std::size_t> perStep;                     ///< contacts per step
  std::string difference;                               ///< the first disagreement; empty: none
  /// Moving meshes: the largest difference between a contact's distance as the kernels measure
  /// it (the centre taken into the mesh's frame) and the distance in double from the centre to
  /// the triangle posed in double from the WallDef (a quaternion, not the kernels' matrix) [m].
  double worstPoseGap = 0.0;
};

/// Steps `world` on a CPU pipeline `steps` times, comparing after each step its mesh contacts
/// (Pipeline::meshContacts(), decided on the positions and the poses at the step's start) with
/// the oracle's on the same positions, the meshes posed at the same time (setWallMotion());
/// stops at the first difference. With moving meshes each contact's distance is also measured
/// with the triangle posed in double (worstPoseGap).
MeshOracleRun meshOracleRun(const World& world, std::uint64_t steps, const PipelineOptions& options = {});

/// The particle cloud of a world at its current body state (x = X + R u).
ParticleCloud cloudOf(const World& world, const BodyState& state);

}  // namespace tumble::validation
