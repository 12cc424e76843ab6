// SPDX-License-Identifier: MIT
/// @file guard.hpp
/// Run-time guards (docs/model.md#guards): between steps, check that the state is finite, that
/// the mechanical energy has not grown beyond what the scene can supply, and that no two
/// particles (or a particle and the ground) overlap by more than a fraction of the radius. On a
/// trip, the caller stops before writing anything from the bad state; the message names the
/// step, the body and a dt to use.
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "tumble/mesh.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/thermo.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// Steps between two checks of `tumble run` when it writes nothing in between (it also checks
/// before every frame, checkpoint and the final state). A check reads the whole state and walks
/// the contacts, about half a step's work on the 2-core development machine at 960k particles
/// (docs/performance.md#guards): every 50 steps that is about 1 % of the run.
inline constexpr std::uint64_t kDefaultGuardEvery = 50;

/// The initial overlap, as a fraction of the smaller radius, beyond which RunGuard warns at
/// the start (a pile at rest on the ground overlaps by a few percent).
inline constexpr double kInitialOverlapWarning = 0.1;

struct GuardParams {
  /// Trip when the energy has grown by more than this fraction of the energy scale (see
  /// RunGuard) beyond what the pulls did on the bodies. A stable run with dt ≤ t_c/10 gains a
  /// few percent in a collision at most; a diverging one grows without bound.
  double energyGrowth = 0.5;
  /// Trip when an overlap (r_i + r_j − d, or the depth below the ground) exceeds this fraction
  /// of the smaller radius, and also exceeds the largest overlap of the initial state + 0.05.
  /// At 1 the smaller sphere's centre has reached the other's surface (or the ground plane): a
  /// little further and the contact normal of two spheres flips (tunnelling). Soft scenes reach
  /// 0.7 without harm (molecules.toml, under impacts of the falling pile).
  double maxOverlap = 1.0;
};

/// Why a guard tripped.
struct GuardTrip {
  enum class Kind { NonFinite, Energy, Overlap };
  Kind kind = Kind::NonFinite;
  std::uint64_t step = 0;    ///< the pipeline's stepCount(): steps since the start of the run
  std::uint32_t body = 0;    ///< the body named in the message
  double suggestedDt = 0.0;  ///< s
  std::string message;       ///< one line: step, time, body, what, dt to use
};

/// Checks a pipeline's state against the guards. It reads the state in the pipeline's own frame
/// (Pipeline::readLocalState), so a scene far from the origin is judged as precisely as one at
/// it. Contacts are those of pipeline.pairs(), the contacts at the start of the last step (a
/// contact that formed during that step is seen at the next check), their terms summed by
/// Pipeline::contactSumsPerBody() where the pipeline has it, from pairs() otherwise. Construct
/// after load() (it records the initial energy and overlaps); call check() whenever the caller
/// is about to use the state (each recorded frame, or every few steps).
///
/// Energy: E = kinetic + gravity (−M g·X, X unwrapped across periodic boundaries) + the potentials of the x/y pulls that are on
/// (½ m κ x²) + contact springs (½ k δ² for every pair and ground contact). Without the swirl
/// pull, E can only fall (damping, friction); the swirl's work W = ∫ Σ f·v dt is added to the
/// budget (trapezoid rule between checks). The guard trips when E − E₀ − W exceeds
/// energyGrowth × S, with S the energy the initial state can release (kinetic + contact springs
/// + |pull potential| + gravity down to the ground or the lowest body, at least Σ M |g| r_max)
/// plus the swirl's work W, plus the error
/// that float-rounded positions put into E₀ and E (negligible near the origin; far from it the
/// positions handed out are rounded to ulp(|X|), which a stiff contact turns into joules).
class RunGuard {
 public:
  /// Measures the initial state; its contacts come from pipeline.findPairs() when the pipeline
  /// has not stepped yet (pairs() is empty before the first step).
  RunGuard(const World& world, Pipeline& pipeline, GuardParams params = {});

  /// Returns the trip, or nothing when every guard holds. Reads the pipeline's state and pairs.
  std::optional<GuardTrip> check(const Pipeline& pipeline);

  /// The dt the guard suggests: t_c/20 of the shortest contact, or half the current dt if the
  /// current one is already smaller.
  double suggestedDt() const;

  /// A warning about the state at construction when something overlaps by more than
  /// kInitialOverlapWarning of the smaller radius (bodies pressed into each other or into the
  /// ground): the deepest pair or body, the depth and the energy the springs hold; empty
  /// otherwise. tumble run prints it at the start of a fresh run.
  const std::string& initialWarning() const { return m_initialWarning; }

  /// Energy E as defined above, at the last check (J).
  double energy() const { return m_lastEnergy; }
  /// Largest overlap at the last check, as a fraction of the smaller radius.
  double maxOverlap() const { return m_lastOverlap; }
  /// Work done by the swirl pull since the last change of the pulls (J), as integrated by the
  /// checks (the guard's budget).
  double pullWork() const { return m_work; }
  /// The quantities of the last check (or of the state at construction), for the time series:
  /// its pullWork is the swirl's work since construction (trapezoid rule between checks).
  const ThermoSample& sample() const { return m_sample; }

 private:
  struct Snapshot {
    double energy = 0.0, swirlPower = 0.0, maxOverlap = 0.0, available = 0.0, springs = 0.0;
    double bound = 0.0;   ///< with cohesion: the energy it holds, −Σ U (springs has U)
    double slack = 0.0;   ///< bound of the energy's error from rounded positions
    std::uint32_t overlapBody = 0, overlapOther = 0;
    bool groundOverlap = false;       ///< the deepest overlap is with a plane (the ground or a wall)
    std::string overlapPlane;         ///< which: "the ground" or the wall's WallDef::where
    double overlapContactTime = 0.0;  ///< t_c of the deepest contact (its own masses and stiffness)
    std::uint32_t hottestBody = 0;  ///< largest kinetic energy
    std::int64_t nonFiniteBody = -1;
    bool beyondRange = false;  ///< that body is finite but beyond ±2^60 m (exact_range.hpp)
    std::int64_t foundPairs = -1;  ///< pairs found with findPairsWith, when given
    ThermoSample sample;           ///< the energies and momenta (step, time, work and contacts: by the caller)
  };
  Snapshot measure(const Pipeline& pipeline, std::uint32_t pullMask, Pipeline* findPairsWith = nullptr);
  GuardTrip trip(GuardTrip::Kind kind, std::uint32_t body, const Pipeline& pipeline, const std::string& what,
                 double contactTime = std::numeric_limits<double>::quiet_NaN()) const;

  const World& m_world;
  GuardParams m_params;
  BodyState m_state;
  std::vector<float> m_x;             ///< particle positions (Pipeline::readLocalPositions), per check
  std::vector<double> m_err, m_errZ;  ///< the rounding of each body's position, per check
  std::vector<ContactSums> m_contacts;  ///< per body, per check
  KernelMesh m_mesh;                    ///< the mesh walls in the pipeline's frame (as the pipeline's)
  double m_reference = 0.0;   ///< E₀ (rebased when the pull mask changes)
  double m_referenceSlack = 0.0;
  double m_scale = 0.0;       ///< S
  double m_work = 0.0;        ///< W
  double m_totalWork = 0.0;   ///< the swirl's work since construction (not reset with the pulls)
  ThermoSample m_sample;
  double m_lastPower = 0.0, m_lastTime = 0.0, m_lastEnergy = 0.0;
  double m_initialOverlap = 0.0, m_lastOverlap = 0.0;
  std::uint32_t m_mask = 0;
  std::string m_initialWarning;
};

/// The guard's contact sums per body (Pipeline::contactSumsPerBody()) from a pair list sorted
/// by (i, j), the particle positions x (3 per particle, scene order) and each body's rounding
/// (bodyRounding of its position): the reference that a pipeline's own sums must equal bit for
/// bit. box: the periodic boundaries of the positions' frame (kernelPeriodic()), if any.
void contactSumsOfPairs(const World& world, const std::vector<Pair>& pairs, const std::vector<float>& x,
                        const std::vector<double>& bodyErr, const SpringLaw& law, std::vector<ContactSums>& out,
                        const PeriodicBox& box = PeriodicBox{});

/// The springs' law of a world's contacts (SpringLaw): Hertz with its material pairs under
/// hertz-mindlin, else linear with [contact] stiffness.
SpringLaw springLawOf(const World& world);

/// The message of a non-finite state found by a pipeline: names the step, the particle's body
/// and the dt to use. Used by the pipelines when they throw SimulationError.
std::string divergenceMessage(const World& world, std::uint64_t step, std::uint32_t particle);

}  // namespace tumble
