// SPDX-License-Identifier: MIT
/// @file compare.hpp
/// Cross-validation of pipelines: pair sets against the brute-force oracle and each other, and
/// trajectories stepped side by side and compared after every step (`tumble validate`).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tumble/pipeline.hpp"
#include "tumble/pour.hpp"

namespace tumble::validation {

/// One pair-set case: the oracle's count and, per pipeline, whether its set was identical.
struct PairCase {
  std::string name;
  std::size_t oraclePairs = 0;
  std::vector<bool> matches;       ///< per pipeline, same order as the pipelines given
  std::vector<std::string> detail; ///< per pipeline: "" or the first difference
};

/// Runs every hard case of SPEC §3 and `numRandom` random clouds (seeds seed, seed+1, …)
/// through each pipeline's findPairs() and the oracle.
std::vector<PairCase> comparePairSets(const std::vector<Backend>& pipelines, std::uint64_t seed, int numRandom);

/// Tolerance of a side-by-side trajectory comparison: positions within `positionTol` × the
/// smallest particle radius, orientations within `orientationTol` (|Δq| of unit quaternions,
/// sign-aligned), for the first `horizon` steps.
struct TrajectoryTolerance {
  double positionTol = 1e-3;
  double orientationTol = 1e-3;
  std::uint64_t horizon = 200;
};

/// Result of stepping two pipelines side by side.
struct TrajectoryResult {
  std::uint64_t steps = 0;            ///< steps compared
  bool bitwiseIdentical = true;       ///< every compared state (bodies, contact history) equal bit for bit
  std::uint64_t firstDifferentStep = 0;  ///< first step whose state differs at all (0 = none)
  std::uint32_t firstDifferentBody = 0;
  std::uint64_t firstOutOfTolStep = 0;   ///< first step beyond tolerance (0 = none)
  std::uint32_t firstOutOfTolBody = 0;
  double maxPositionDev = 0.0;        ///< max |ΔX| / r_min within the horizon
  double maxOrientationDev = 0.0;     ///< max |Δq| within the horizon
  bool pairsIdentical = true;         ///< pair lists equal after every step
  std::uint64_t firstPairMismatchStep = 0;
  bool withinTolerance() const { return firstOutOfTolStep == 0; }
};

/// The first bit-level difference between two states (bodies first, in column order X, V, Q,
/// L, then the plane springs, the periodic image counters, the contact histories): the column's
/// name ("px", …, "groundSpringY", "imageX", …), the body or particle index and both values.
/// Empty when every bit agrees.
struct StateDifference {
  std::string quantity;
  std::uint32_t index = 0;
  float a = 0.0f, b = 0.0f;
  std::string describe() const;  ///< "vz of body 12: 0.125 vs 0.12500001"
};
std::optional<StateDifference> firstDifference(const BodyState& a, const BodyState& b);

/// The state (readState()) of a fresh pipeline of `backend` loaded with `world` after `steps` steps.
BodyState stateAfter(Backend backend, const World& world, std::uint64_t steps, const PipelineOptions& options = {});

/// Where two pipelines stepped side by side first differ: the step (1 = after the first step),
/// the quantity ("pairs", a BodyState column or contact history as firstDifference() names it,
/// "debug v", "debug repulsion", …), the body, particle or entry, and both values.
struct StepDifference {
  std::uint64_t step = 0;
  std::string what;  ///< "step 12: vz of body 3: 0.125 vs 0.12500001"
};

/// Loads a with worldA and b with worldB (the same world, but for the tests of this function) and
/// steps them side by side for `steps` steps, comparing after every step the pair lists, the
/// mesh contacts (Pipeline::meshContacts()), every bit of the state (bodies, plane springs, contact histories: firstDifference()) and, with
/// `debug`, every bit of the per-particle debug velocities and forces and of the contact forces (readDebug()); stops at the
/// first difference. nullopt: identical throughout. With `pouring` (the scene's pours), each
/// pipeline steps through Pouring::step, so that the bodies due enter both at the batch steps.
std::optional<StepDifference> firstStepDifference(Pipeline& a, const World& worldA, Pipeline& b, const World& worldB,
                                                  std::uint64_t steps, bool debug, const Pouring* pouring = nullptr);

/// Steps pipelines a and b from the same world for `steps` steps and compares the body state
/// (and the pair lists) after every step.
TrajectoryResult compareTrajectories(Pipeline& a, Pipeline& b, const World& world, std::uint64_t steps,
                                     const TrajectoryTolerance& tol);

}  // namespace tumble::validation
