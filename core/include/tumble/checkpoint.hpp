// SPDX-License-Identifier: MIT
/// @file checkpoint.hpp
/// Checkpoints (docs/checkpoint.md): everything that carries a run from one step to the next,
/// written to a versioned binary file so that the run can stop and continue bit for bit, on
/// either pipeline. The candidate list is not part of it: the contacts do not depend on how
/// they were found, so a resumed run rebuilds the list and gives the same bits.
#pragma once
#include <cstdint>
#include <string>

#include "tumble/pipeline.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// How far from 1 the length of an orientation a run can have may be (a checkpoint's, one set
/// with Run::setBodies): float roundings of a normalised quaternion are a few 1e-7.
inline constexpr double kUnitQuaternionTolerance = 1e-4;

/// The newest format (docs/checkpoint.md): version 2 adds the mesh springs. A state without
/// them is written as version 1, byte for byte as before, and both are read.
inline constexpr std::uint32_t kCheckpointVersion = 2;

/// The state of a run between two steps.
struct Checkpoint {
  std::uint64_t step = 0;   ///< steps since the start of the run
  double time = 0.0;        ///< simulated time (s), exactly as the pipeline accumulated it
  std::uint32_t pulls = 0;  ///< PullBits on
  LocalFrame frame;         ///< the frame the run integrates in (chosen at its start)
  BodyState state;          ///< in that frame (Pipeline::readLocalState), scene order
  std::uint64_t sceneFingerprint = 0;    ///< of the bodies and particles (sceneFingerprint())
  std::uint64_t physicsFingerprint = 0;  ///< of the parameters that set the motion (physicsFingerprint())

  /// The pipeline's state now. `world` is the one the run was loaded with.
  static Checkpoint of(const World& world, const Pipeline& pipeline);

  /// Writes the checkpoint to a temporary next to `path` and renames it (OutputFile), so that `path` is
  /// either the previous file or the complete new one. Throws tumble::Error naming the file and
  /// the system's reason.
  void write(const std::string& path) const;

  /// Reads a checkpoint. Throws tumble::InputError ("FILE: byte OFFSET: problem") on a missing,
  /// truncated or corrupt file, an unsupported version or a non-finite value; never crashes on
  /// bad bytes (every size is checked against the file before anything is allocated).
  static Checkpoint read(const std::string& path);

  /// The world to load() to continue: `world` (built from the same scene) with this state,
  /// step, time and frame. Throws tumble::Error when `world` has other bodies or particles
  /// than the checkpoint's run (naming what differs). When the physical parameters differ
  /// (dt, contact, ground, gravity, pulls, integrator), `*warning` receives a line saying so:
  /// the continuation is then not the uninterrupted run.
  World resume(const World& world, std::string* warning) const;
};

/// 64-bit FNV-1a of the static bodies and particles of a world: counts, radius, mass,
/// elasticity, body of each particle, the offsets u in the body frame (so the rotation scheme's
/// body frame), mass properties, and the periodic box when there is one (the frame and the image
/// counters depend on it).
std::uint64_t sceneFingerprint(const World& world);

/// 64-bit FNV-1a of the parameters that set the motion: dt, gravity, contact, ground, pulls'
/// strengths, rotation scheme (not the detection settings, which change no bit).
std::uint64_t physicsFingerprint(const Scene& scene);

}  // namespace tumble
