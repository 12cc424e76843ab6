// SPDX-License-Identifier: MIT
/// @file decomposition.hpp
/// Which rank owns which body, and which bodies each rank holds as ghosts (docs/mpi.md). Plain
/// functions of the body centres and particle positions, the same on every rank (each computes
/// the whole decomposition from the same gathered state); they decide only who computes what,
/// never a bit of the result.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tumble/math.hpp"

namespace tumble::mpi {

/// How the domain is cut.
enum class Decomposition {
  Rcb,    ///< recursive coordinate bisection: each cut across the longest extent of its part
  Slabs,  ///< slabs across the longest extent of the whole
};

/// "rcb" / "slabs".
const char* toString(Decomposition d);
/// Parses "rcb" / "slabs"; throws tumble::Error otherwise.
Decomposition decompositionFromString(const std::string& s);

/// The owner (0 .. ranks − 1) of each body, from the bodies' centres and particle counts.
/// Recursive bisection: a part given k ranks is sorted along its longest extent (Slabs: the
/// whole's), ties by body index, and cut where the particles on each side are closest to their
/// share (⌊k/2⌋ ranks below the cut, the rest above); a part given one rank is owned by it.
/// Deterministic (a total order, integer arithmetic). A rank gets no body when there are fewer
/// bodies than ranks in its part. Precondition: finite centres, ranks ≥ 1.
std::vector<int> decompose(const std::vector<Vec3f>& centres, const std::vector<std::uint32_t>& particles, int ranks,
                           Decomposition how);

/// The halo skin s over the run's skin (the MPI pipeline's design notes): redistributions rarer
/// than the local pipelines' own rebuilds.
inline constexpr float kHaloSkinPerSkin = 2.0f;

/// The reach of ghostsOf() for a halo skin s: 2 r_max + s, and a margin for the rounding of the
/// positions compared (1e-3 of that, and 1e-6 of the largest |coordinate|).
double haloReach(float maxRadius, float haloSkin, double largestCoordinate);

/// The ghosts of each rank: per rank, in ascending body index, every body it does not own with a
/// particle inside the bounding box of its own particles grown by `reach` on each side. With
/// reach ≥ 2 r_max + s (plus rounding), every particle that comes within touching distance of a
/// rank's particle before any two particles have closed in by s is its own or a ghost's.
/// positions: 3 floats per particle; particles of body k: first[k] .. first[k] + count[k] − 1.
/// Costs O(ranks × particles).
std::vector<std::vector<std::uint32_t>> ghostsOf(const std::vector<int>& owner, const std::vector<float>& positions,
                                                 const std::vector<std::uint32_t>& first,
                                                 const std::vector<std::uint32_t>& count, int ranks, double reach);

}  // namespace tumble::mpi
