// SPDX-License-Identifier: MIT
// What the stability cases of the validation study share (study_stability.cpp lists them): the
// clock, the finite-state check, the one-scene simulation and the scheme's critical ω dt; and the
// cases, one file each (study_stability_*.cpp). Internal: not installed, not API.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"
#include "tumble/validation/study.hpp"
#include "tumble/world.hpp"
#include "study_util.hpp"

namespace tumble::validation::study::stability {

using namespace detail;  // the helpers shared with study_physics.cpp (study_util.hpp)

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline bool finiteState(const BodyState& s) {
  for (const auto* c : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz})
    for (float v : *c)
      if (!std::isfinite(v)) return false;
  return true;
}

/// A loaded pipeline and its last state.
struct Sim {
  World world;
  std::unique_ptr<Pipeline> pipe;
  BodyState st;
  bool ok = true;  ///< false once a step threw or the state became non-finite
  Sim(const Scene& s, Backend b) : world(World::fromScene(s)), pipe(makePipeline(b)) {
    pipe->load(world);
    pipe->readState(st);
  }
  /// n steps; false (and ok = false) on a SimulationError or a non-finite state.
  bool step(std::uint64_t n = 1) {
    if (!ok) return false;
    try {
      pipe->step(n);
    } catch (const Error&) {
      ok = false;
      return false;
    }
    pipe->readState(st);
    if (!finiteState(st)) ok = false;
    return ok;
  }
};

/// Critical ω dt of the scheme: 2 (√(1 + ζ²) − ζ) (Jury criterion; 2 without damping).
inline double criticalH(double zeta) { return 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta); }

// The cases, by file.
// study_stability_stiff.cpp
CaseResult stiffContactCase(const CaseContext& ctx);
// study_stability_stack.cpp
CaseResult massRatioCase(const CaseContext& ctx);
CaseResult towerCase(const CaseContext& ctx);
// study_stability_tunnel.cpp
CaseResult tunnellingCase(const CaseContext& ctx);
// study_stability_spin.cpp
CaseResult spinCase(const CaseContext& ctx);
// study_stability_coincident.cpp
CaseResult coincidentCase(const CaseContext& ctx);
// study_stability_far.cpp
CaseResult farCase(const CaseContext& ctx);

}  // namespace tumble::validation::study::stability
