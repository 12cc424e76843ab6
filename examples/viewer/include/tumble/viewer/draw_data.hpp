// SPDX-License-Identifier: MIT
/// @file draw_data.hpp
/// What the renderer draws, computed on the CPU without OpenGL: sphere instances (centre,
/// radius, colour), force lines and the ground, from a recording frame or a live body state.
#pragma once
#include <cstdint>
#include <vector>

#include "tumble/recording.hpp"
#include "tumble/viewer/camera.hpp"
#include "tumble/viewer/controls.hpp"
#include "tumble/world.hpp"

namespace tumble::viewer {

/// The static particle table of a recording or a world.
struct ParticleTable {
  std::vector<float> radius, mass, elasticity;
  std::vector<std::uint32_t> body;
  std::vector<float> ux, uy, uz;
  static ParticleTable from(const Recording& rec);
  static ParticleTable from(const World& world);
  std::size_t size() const { return radius.size(); }
  float maxRadius() const;
};

/// Everything one image shows.
struct DrawData {
  std::vector<float> spheres;  ///< x, y, z, radius per particle
  std::vector<float> colors;   ///< r, g, b per particle
  std::vector<float> lines;    ///< x, y, z, r, g, b per line end (two per line)
  bool groundEnabled = false;
  float groundHeight = 0.0f;
  std::uint32_t pulls = 0;     ///< colours the ground (groundColor)
  std::size_t numSpheres() const { return spheres.size() / 4; }
};

/// Particle colours for a colouring mode: plain gives every body its own colour from a fixed
/// palette; mass and elasticity map the particle's value from the table's range to a colour
/// ramp (light = smallest, dark = largest; mass in warm, elasticity in cool colours).
std::vector<float> particleColors(const ParticleTable& table, ColorMode mode);
/// The colour ramp of the mass and elasticity modes at t in [0, 1] (0: the smallest value, light;
/// 1: the largest, dark): cream to dark red for mass, ice blue to navy for elasticity.
Rgb rampColor(ColorMode mode, float t);

/// Particle centres x = X + R(Q) u from per-body columns (writes x, y, z, radius per particle).
void particleSpheres(const ParticleTable& table, const float* px, const float* py, const float* pz,
                     const float* qw, const float* qx, const float* qy, const float* qz, std::vector<float>& out);

/// One line per particle from its centre along each shown force kind (show[k]), one scale for
/// all: the 90th percentile of the frame's non-zero magnitudes (over the shown kinds) is drawn
/// 2.5 × the largest radius long, and no line is longer than 6 largest radii.
void forceLines(const ParticleTable& table, const std::vector<float>& spheres, const ParticleDebug& debug,
                const bool show[kNumForces], std::vector<float>& outLines);

/// What the camera frames (for a video or the player): over every frame, the box of the bulk of
/// the particles (robustBounds), and the ground (the box starts no lower than the ground). One
/// pass over the file, one frame in memory; `times`, when given, gets each frame's simulated time
/// and `perFrame` each frame's own box (cut at the ground in the same way).
Bounds recordingBounds(RecordingReader& rec, const ParticleTable& table, std::vector<double>* times = nullptr,
                       std::vector<Bounds>* perFrame = nullptr);
/// The bulk of the given spheres (x, y, z, r per particle): per axis from the 1st to the 99th
/// percentile of the sphere extents, so that a few escaping bodies do not shrink the rest (all
/// of them below 100 spheres).
Bounds robustBounds(const std::vector<float>& spheres);
/// Bounds of the given spheres (x, y, z, r per particle).
Bounds sphereBounds(const std::vector<float>& spheres);

}  // namespace tumble::viewer
