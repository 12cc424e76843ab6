// SPDX-License-Identifier: MIT
/// @file draw_data.hpp
/// What the renderer draws, computed on the CPU without OpenGL: sphere instances (centre,
/// radius, colour), force lines, the ground and the walls, from a recording frame or a live
/// body state.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tumble/recording.hpp"
#include "tumble/wall_geometry.hpp"
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

/// Background (sky) colour of every image unless --background says otherwise.
inline constexpr Rgb kSkyColor{0.13f, 0.15f, 0.19f};

/// How the background and the ground are drawn: `--background` and `--ground` of view, play and
/// render (parseLook, applyLook).
struct Look {
  Rgb background = kSkyColor;
  bool ground = true;              ///< draw the scene's ground (where it has one)
  std::optional<Rgb> groundColor;  ///< one colour instead of the pulls' (groundColor())
};
/// A colour by name (black, white, grey or gray) or as #RRGGBB (hex digits, either case);
/// nothing for any other text.
std::optional<Rgb> rgbFromString(const std::string& text);
/// The values of --background and --ground: the background `default` (kSkyColor) or a colour
/// (rgbFromString); the ground `on` (the pulls' colours), `off` (no ground, no shadows) or a
/// colour. Throws tumble::Error naming the option, the value and what is accepted.
Look parseLook(const std::string& background, const std::string& ground);

/// Everything one image shows.
struct DrawData {
  std::vector<float> spheres;  ///< x, y, z, radius per particle
  std::vector<float> colors;   ///< r, g, b per particle
  std::vector<float> lines;    ///< x, y, z, r, g, b per line end (two per line)
  bool groundEnabled = false;
  float groundHeight = 0.0f;
  std::uint32_t pulls = 0;     ///< colours the ground (groundColor)
  double time = 0.0;           ///< simulated time [s]: poses the walls (WallMotion)
  bool wallsShown = true;      ///< draw the walls given to Renderer::setWalls
  Rgb background = kSkyColor;  ///< the clear colour, into which the ground fades
  std::optional<Rgb> groundColor;  ///< the ground's colour whatever the pulls; by default groundColor(pulls)
  std::size_t numSpheres() const { return spheres.size() / 4; }
};

/// Applies a Look to what is drawn: its background and ground colour, and no ground when it is
/// off (`d.groundEnabled` is left as the scene has it otherwise).
void applyLook(const Look& look, DrawData& d);

/// A wall as the renderer draws it (wallMeshes()).
struct WallMesh {
  /// x, y, z, nx, ny, nz per corner, three corners per triangle, at the pose of t ≤ start; the
  /// normal points to the wall's inner side (WallSurface) and is averaged over the triangles
  /// that share the corner's position and meet at less than 30°: a cylinder is shaded round, a
  /// box's edges stay sharp.
  std::vector<float> vertices;
  /// x, y, z per line end, two per line: the outline, where the surface ends or folds by more
  /// than 30° (a box face's rectangle, a drum's rims).
  std::vector<float> outline;
  Rgb color{0.6f, 0.7f, 0.8f};
  WallMotion motion;
  Bounds bounds;  ///< of the vertices, at rest
  std::size_t numVertices() const { return vertices.size() / 6; }
};

/// The colour of a wall of this kind: light steel tones, a little apart per kind.
Rgb wallColor(WallKind kind);
/// The walls of a recording or a scene as the renderer draws them (normals, outlines, colours).
std::vector<WallMesh> wallMeshes(const std::vector<WallSurface>& walls);
/// What the camera frames with walls: `bodies` grown to hold each wall of finite extent (not a
/// plane: a drum, a silo, a hopper) whose box's diagonal is at most 4 times that of `bodies`, so
/// that a wall around the bodies is seen whole and a huge one does not make them small. Planes
/// never count (a lone plane is as large as the drawing makes it). `bodies` empty: unchanged.
Bounds framedWithWalls(const Bounds& bodies, const std::vector<WallSurface>& walls);

/// Particle colours for a colouring mode: plain gives every body its own colour from a fixed
/// palette, shape every shape (bodyShapes); mass and elasticity map the particle's value from
/// the table's range to a colour ramp (light = smallest, dark = largest; mass in warm,
/// elasticity in cool colours). Speed and height change from frame to frame: here every particle
/// gets the ramp's light end, and frameValues and rampColors give a frame's colours; so does
/// user (rampColors of ColorFile::particleValues gives its colours).
std::vector<float> particleColors(const ParticleTable& table, ColorMode mode);
/// The colour ramp of a mode with a ramp (hasRamp) at t in [0, 1] (0: the smallest value,
/// light; 1: the largest, dark): cream to dark red for mass, ice blue to navy for elasticity,
/// pale to dark green for speed, lilac to deep purple for height, yellow over teal to dark purple
/// for a user's values (viridis, reversed).
Rgb rampColor(ColorMode mode, float t);
/// The shape of each body (indexed by body), numbered from 0 in the order of the bodies: bodies
/// whose particles have the same offsets, radii, masses and elasticities, in the same order,
/// have the same shape (the scene's [[shape]] it was made of).
std::vector<std::uint32_t> bodyShapes(const ParticleTable& table);

/// The speed of each body of frame `f` [m/s]: how far it moved between `f` and `other` (a
/// neighbouring frame: the one before, or the one after for the first frame) over the time
/// between them; 0 for a body `other` lacks (it entered later) and for frames of one time. A body
/// that leaves a periodic box on one side and comes in on the other looks fast for that frame.
std::vector<float> bodySpeeds(const RecordedFrame& f, const RecordedFrame& other);
/// The values a per-frame colouring maps, one per particle of `spheres` (x, y, z, r each): speed,
/// the particle's body's (`speeds` from bodySpeeds); height, the particle's centre z [m].
void frameValues(ColorMode mode, const ParticleTable& table, const std::vector<float>& spheres,
                 const std::vector<float>& speeds, std::vector<float>& out);
/// Colours (r, g, b per value) on the mode's ramp: `lo` light, `hi` dark, clamped outside.
void rampColors(ColorMode mode, const std::vector<float>& values, float lo, float hi, std::vector<float>& out);
/// The `q`-quantile (0 to 1) of `v`, taken by nth_element (`v` is reordered); 0 when empty.
float quantile(std::vector<float>& v, double q);

/// Particle centres x = X + R(Q) u from per-body columns (writes x, y, z, radius per particle),
/// for the first `count` particles of the table (a frame of a recording that grows holds the
/// bodies present: Recording::particlesOf()); all of them by default.
void particleSpheres(const ParticleTable& table, const float* px, const float* py, const float* pz,
                     const float* qw, const float* qx, const float* qy, const float* qz, std::vector<float>& out,
                     std::size_t count = SIZE_MAX);

/// One line per particle from its centre along each shown force kind (show[k]), one scale for
/// all: the 90th percentile of the frame's non-zero magnitudes (over the shown kinds) is drawn
/// 2.5 × the largest radius long, and no line is longer than 6 largest radii.
void forceLines(const ParticleTable& table, const std::vector<float>& spheres, const ParticleDebug& debug,
                const bool show[kNumForces], std::vector<float>& outLines);

/// What the camera frames (for a video or the player): over every frame, the box of the bulk of
/// the particles (robustBounds), and the ground (the box starts no lower than the ground), with
/// the recording's finite walls (framedWithWalls). One pass over the file, one frame in memory;
/// `times`, when given, gets each frame's simulated time and `perFrame` each frame's own box of
/// the bodies (cut at the ground in the same way; no walls).
/// `visit`, when given, is called with each frame and its spheres in order, as read. Only frames
/// `first` to `last` (clamped to the recording) are read and framed, and `times` and `perFrame`
/// hold theirs, from `first` on.
Bounds recordingBounds(RecordingReader& rec, const ParticleTable& table, std::vector<double>* times = nullptr,
                       std::vector<Bounds>* perFrame = nullptr,
                       const std::function<void(const RecordedFrame&, const std::vector<float>&)>& visit = {},
                       std::size_t first = 0, std::size_t last = SIZE_MAX);
/// The bulk of the given spheres (x, y, z, r per particle): per axis from the 1st to the 99th
/// percentile of the sphere extents, so that a few escaping bodies do not shrink the rest (all
/// of them below 100 spheres).
Bounds robustBounds(const std::vector<float>& spheres);
/// Bounds of the given spheres (x, y, z, r per particle).
Bounds sphereBounds(const std::vector<float>& spheres);

}  // namespace tumble::viewer
