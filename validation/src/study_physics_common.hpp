// SPDX-License-Identifier: MIT
// What the analytic physics cases of the validation study share (study_physics.cpp lists them):
// the shapes, the one-scene simulation, the discrete oscillator and the dt sweep; and the cases,
// one file per group (study_physics_*.cpp). Internal: not installed, not API.
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
#include "tumble/kernels/integrate.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/random.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/validation/scenes.hpp"
#include "tumble/validation/study.hpp"
#include "tumble/world.hpp"
#include "study_util.hpp"

namespace tumble::validation::study::physics {

using namespace detail;  // the helpers shared with the stability cases (study_util.hpp)

inline const RotationScheme kSchemes[2] = {RotationScheme::Report, RotationScheme::Splitting};

/// A flat 3×3 clump of spheres (radius r, mass m each, spacing 2r): wide and low, cannot tip.
inline ShapeDef plateShape(double r, double m, double e) {
  ShapeDef s{"plate", {}};
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      s.spheres.push_back(SphereDef{{float(2 * r * i), float(2 * r * j), 0.0f}, float(r), float(m), float(e)});
  return s;
}

/// A "ball": one sphere plus a tiny core sphere at its centre (mass 1e-3 m, radius r/10), so
/// that the body has two particles and rotates (single-sphere bodies do not). Inertia ≈ 2/5 m r².
inline ShapeDef ballShape(double r, double m, double e) {
  return ShapeDef{"ball",
                  {SphereDef{{0, 0, 0}, float(r), float(m), float(e)},
                   SphereDef{{0, 0, 0}, float(r / 10), float(m * 1e-3), float(e)}}};
}

/// A pipeline on one scene; wall time is measured around step() only. One thread: the scenes
/// are a few bodies, and the machine is shared.
struct Sim {
  World world;
  std::unique_ptr<Pipeline> p;
  BodyState st;
  double wall = 0.0;
  Sim(const Scene& s, Backend b) : world(World::fromScene(s)) {
    PipelineOptions o;
    o.threads = 1;
    p = makePipeline(b, o);
    p->load(world);
    p->readState(st);
  }
  void step(std::uint64_t n = 1) {
    const auto t0 = std::chrono::steady_clock::now();
    p->step(n);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  void read() { p->readState(st); }
  double time() const { return p->time(); }
  double wallPerSimSecond() const { return time() > 0 ? wall / time() : kNaN; }
  /// Angular velocity of body 0 (world frame) in the last state read.
  Vec3f omega() const {
    const Quatf q{st.qw[0], st.qx[0], st.qy[0], st.qz[0]};
    return angularVelocity(q, world.invInertia[0], Vec3f{st.lx[0], st.ly[0], st.lz[0]});
  }
};

/// Discrete leapfrog map of a linear spring-dashpot (k, c, m) at step dt: per step the amplitude
/// shrinks by √(1 − c dt/m) and the phase advances by θ, cos θ = (2 − c dt/m − k dt²/m)/(2√(1 − c dt/m)).
/// Restitution and duration of a half oscillation of that map (what the integrator converges from).
struct DiscreteOscillator {
  double e, tc;
};
inline DiscreteOscillator discreteOscillator(double k, double c, double m, double dt) {
  const double a = c * dt / m, w2 = k * dt * dt / m;
  const double ct = (2.0 - a - w2) / (2.0 * std::sqrt(1.0 - a));
  if (!(a < 1.0) || !(std::abs(ct) < 1.0)) return {kNaN, kNaN};
  const double th = std::acos(ct);
  return {std::pow(1.0 - a, kPi / (2.0 * th)), kPi * dt / th};
}

/// Continuous restitution and contact duration of the unclamped linear spring-dashpot.
inline double contactDuration(double k, double c, double m) {
  const double wd2 = k / m - (c / (2 * m)) * (c / (2 * m));
  return kPi / std::sqrt(wd2);
}

/// Tolerance of a restitution measured at dt: the discrete map's own error, plus the last
/// step's force sample (it acts for a whole step although the overlap closes inside it:
/// relative impulse ≤ c dt/m + k dt²/m).
inline double restitutionTolerance(const DiscreteOscillator& dm, double e, double k, double c, double m, double dt) {
  return std::abs(dm.e - e) / e + c * dt / m + k * dt * dt / m;
}

// ---------------------------------------------------------------------------------------------
// Speed against error.

struct SweepRow {
  double dt = 0.0, dtOverTc = 0.0;
  int scheme = 0;
  double wallPerSim = kNaN, error = kNaN;
  bool diverged = false;
};

struct Measured {
  double error;
  double wallPerSim;
};

/// Fractions of the contact time swept: from near the leapfrog stability limit (ω dt = 2 at
/// dt = 0.64 t_c) down to t_c / 100.
inline std::vector<double> sweepFractions(Depth d) {
  if (d == Depth::Quick) return {0.1, 0.01};
  return {0.6, 0.5, 0.3, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005};
}

/// The swept dts: sweepFractions(d) × tc.
inline std::vector<double> sweepDts(Depth d, double tc) {
  std::vector<double> dts;
  for (double f : sweepFractions(d)) dts.push_back(f * tc);
  return dts;
}

/// Mean of f(phase) over 8 phases k/8 of the contact's first step (the contact starts at a
/// different point inside a step): the error of one impact jumps with that phase, the mean is
/// the representative error at a dt.
template <class F>
Measured phaseAverage(F&& f) {
  Measured sum{0.0, 0.0};
  const int n = 8;
  for (int k = 0; k < n; ++k) {
    const Measured m = f(double(k) / n);
    sum.error += m.error / n;
    sum.wallPerSim += m.wallPerSim / n;
  }
  return sum;
}

/// What the summaries of the single-impact cases say about their dt sweep.
inline const std::string kImpactSweepNote =
    "Sweep: dt from 0.6 t_c0 to t_c0/200 (t_c0 = π√(m/k)); the leapfrog map of the damped contact is stable for "
    "ω0 dt < 2(√(1+ζ²) − ζ), i.e. dt < 0.51 t_c0 at e = 0.5 (0.64 t_c0 undamped), so the first point lies beyond "
    "the limit: a single impact does not blow up there, but its error is O(1). The sweep error is the mean over 8 "
    "phases of the contact's start within a step, which otherwise makes single-impact errors jump with dt. ";

/// Runs f(dt, scheme) for every dt and scheme; a run that throws SimulationError or gives a
/// non-finite error is kept as a diverged row.
template <class F>
std::vector<SweepRow> sweep(const std::vector<double>& dts, double tc, F&& f) {
  std::vector<SweepRow> rows;
  for (double dt : dts)
    for (int s = 0; s < 2; ++s) {
      SweepRow r;
      r.dt = dt;
      r.dtOverTc = dt / tc;
      r.scheme = s;
      try {
        // The error is deterministic; the wall time is the fastest of repeated runs (at least
        // 3, until 0.2 s of wall time or 10 runs), as the machine may be shared.
        Measured m = f(dt, kSchemes[s]);
        double best = m.wallPerSim, spent = 0.0;
        for (int rep = 1; rep < 10 && (rep < 3 || spent < 0.2) && std::isfinite(m.error); ++rep) {
          const auto t0 = std::chrono::steady_clock::now();
          best = std::min(best, f(dt, kSchemes[s]).wallPerSim);
          spent += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        r.error = m.error;
        r.wallPerSim = best;
        r.diverged = !std::isfinite(m.error);
      } catch (const SimulationError&) {
        r.diverged = true;
      }
      if (r.diverged) r.error = kNaN;
      rows.push_back(r);
    }
  return rows;
}

/// Adds the sweep table and its two plots (error against wall time per simulated second, and
/// against dt) to a case; returns a markdown sentence on diverged runs for the summary.
inline std::string addSweep(CaseResult& r, const std::vector<SweepRow>& rows, const std::string& errorWhat,
                     const std::string& tcName) {
  Table t{"sweep", {"dt", "dt_over_" + tcName, "scheme", "wall_s_per_sim_s", "error", "diverged"}, {}};
  std::string diverged;
  for (const auto& x : rows) {
    t.rows.push_back({x.dt, x.dtOverTc, double(x.scheme), x.wallPerSim, x.error, x.diverged ? 1.0 : 0.0});
    if (x.diverged) diverged += (diverged.empty() ? "" : ", ") + fmt("dt = %.3g s", x.dt) + " (" + toString(kSchemes[x.scheme]) + ")";
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"speed", r.title + ": error against cost", "sweep", "wall_s_per_sim_s",
                         "wall time per simulated second [s] (1 thread)", errorWhat, {"error"}, true, true, "scheme"});
  r.plots.push_back(Plot{"error_dt", r.title + ": error against dt", "sweep", "dt", "dt [s]", errorWhat, {"error"},
                         true, true, "scheme"});
  return diverged.empty() ? std::string("No sweep run diverged.")
                          : "Diverged (reported as such, error NaN): " + diverged + ".";
}

// The cases, by file.
// study_physics_impact.cpp
CaseResult groundRestitution(const CaseContext& ctx);
CaseResult sphereSphere(const CaseContext& ctx);
// study_physics_motion.cpp
CaseResult freeFallCase(const CaseContext& ctx);
CaseResult restingCase(const CaseContext& ctx);
CaseResult blockSliding(const CaseContext& ctx);
CaseResult slopeCase(const CaseContext& ctx);
CaseResult sphereSlope(const CaseContext& ctx);
// study_physics_spin.cpp
CaseResult torqueFreeCase(const CaseContext& ctx);
// study_physics_oblique.cpp
CaseResult chungOoi(const CaseContext& ctx);
CaseResult hookeOblique(const CaseContext& ctx);
CaseResult hertzChungOoi(const CaseContext& ctx);
// study_physics_granular.cpp
CaseResult angleOfRepose(const CaseContext& ctx);
CaseResult beverloo(const CaseContext& ctx);
CaseResult columnStress(const CaseContext& ctx);
CaseResult janssen(const CaseContext& ctx);
// study_physics_energy.cpp
CaseResult energyBalance(const CaseContext& ctx);
// study_physics_cohesion.cpp
CaseResult jkrSticking(const CaseContext& ctx);

}  // namespace tumble::validation::study::physics
