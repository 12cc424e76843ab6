// SPDX-License-Identifier: MIT
/// @file fields.hpp
/// Continuum fields of a recording by coarse-graining (docs/fields.md): the density, packing
/// fraction, momentum, velocity, granular temperature and stress of the particles, smoothed by a
/// kernel of a chosen width, on a grid of points or along an axis, averaged over frames
/// (Goldhirsch 2010, "Stress, stress asymmetry and couple stress"; Weinhart, Thornton, Luding &
/// Bokhove 2012, "From discrete particles to continuum fields near a boundary"; as MercuryDPM's
/// MercuryCG computes them).
///
/// With φ the kernel and per particle i its mass m_i, volume V_i = 4/3 π r_i³, position x_i and
/// velocity v_i, per point r:
///   density ρ = Σ m_i φ(r − x_i), packing fraction ν = Σ V_i φ(r − x_i),
///   momentum p = Σ m_i v_i φ(r − x_i), velocity V = p / ρ,
///   kinetic stress σᵏ = Σ m_i v'_i ⊗ v'_i φ(r − x_i) with v'_i = v_i − V(r),
///   contact stress σᶜ = Σ_contacts f_ij ⊗ l_ij ∫₀¹ φ(r − x_i + s l_ij) ds,
///   with f_ij the force on i from j and l_ij = x_i − x_j,
///   granular temperature T = tr σᵏ / (3 ρ).
/// Stresses are positive in compression (a pressure), so that a column at rest carries
/// σ_zz(z) = ∫_z^∞ ρ g dz (the momentum balance ∂_t p + ∇·(p ⊗ V) = −∇·σ + ρ g).
/// The kernel is Lucy's polynomial (Lucy 1977; one of MercuryCG's), φ(r) = 105 / (16 π c³)
/// (1 + 3r/c)(1 − r/c)³ for r < c: it integrates to one, so each particle puts exactly its mass,
/// volume and momentum into the fields, and it is smooth to its second derivative at c, so a
/// lattice's fields come out flat (a Gaussian cut off at 3 standard deviations has a step there
/// that shows a lattice's planes: 0.3 % in the packing fraction of an FCC crystal at a width of
/// 0.8 cells, 0.01 % with Lucy's). The width w is its standard deviation along each axis,
/// c = √12 w. Along an axis the kernel is its marginal (φ integrated over the plane across the
/// axis, a polynomial in |z| / c) divided by the area of the box across it: the 3-D fields
/// averaged over the box's cross-section (a profile).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tumble/recording.hpp"
#include "tumble/soa.hpp"

namespace tumble {

/// Where the fields are computed: the centres of n[0] × n[1] × n[2] equal cells of the box
/// [lo, hi] (points at lo + (k + ½) h, h = (hi − lo) / n), or, when axis ≥ 0, of the n[axis]
/// slices of the box across that axis (a profile; n of the other axes ignored).
struct FieldGrid {
  std::array<double, 3> lo{}, hi{};
  std::array<int, 3> n{1, 1, 1};
  int axis = -1;  ///< 0, 1, 2: a profile along x, y, z; −1: a 3-D grid
  /// A profile: the area its fields are per (> 0), instead of the box's cross-section (a silo's
  /// circle in the square box around it); 0: the box's. Particles and contacts outside the box's
  /// cross-section are left out of a profile either way.
  double area = 0.0;
  /// Points along each axis: n, or 1 across a profile's axis.
  int points(int a) const { return axis < 0 || a == axis ? n[a] : 1; }
  std::size_t size() const { return std::size_t(points(0)) * points(1) * points(2); }
  /// Point k's coordinate along axis a (k < points(a)); the middle of the box across a profile.
  double at(int a, int k) const;
};

/// One frame's particles and contacts, as coarseGrain() reads them: positions x (3 per
/// particle), velocities v (3 per particle, or empty: no momentum, velocity, kinetic stress or
/// temperature), radius and mass per particle, and the contacts with their forces (or none:
/// `contacts` false, no contact stress).
struct FieldFrame {
  const float* x = nullptr;
  const float* v = nullptr;
  const float* radius = nullptr;
  const float* mass = nullptr;
  std::size_t n = 0;
  const ContactForce* contact = nullptr;
  std::size_t numContacts = 0;
  bool contacts = false;
};

/// The fields at every point of a grid, averaged over the frames added (point k = x + nx (y + ny z)).
struct Fields {
  FieldGrid grid;
  double width = 0.0;
  std::size_t frames = 0;
  bool velocities = false;  ///< momentum, velocity, kinetic stress and temperature are there
  bool contacts = false;    ///< the contact stress is there
  std::vector<double> density;          ///< ρ [kg/m³]
  std::vector<double> packing;          ///< ν
  std::vector<double> momentum;         ///< p, 3 per point [kg/(m² s)]
  std::vector<double> velocity;         ///< V = p / ρ (0 where ρ is 0), 3 per point [m/s]
  std::vector<double> temperature;      ///< T [m²/s²]
  std::vector<double> kineticStress;    ///< σᵏ, 6 per point: xx, yy, zz, xy, xz, yz [Pa]
  std::vector<double> contactStress;    ///< σᶜ, 6 per point, as σᵏ [Pa]
};

/// Coarse-grains frames one after the other into their average. Throws tumble::Error for a
/// width that is not positive and finite, a box that is empty or not finite, a grid of no point
/// or more than 2^22 points, or a frame with velocities or contacts where the first had none
/// (or the other way round).
class CoarseGraining {
 public:
  CoarseGraining(const FieldGrid& grid, double width);
  void add(const FieldFrame& frame);
  /// The average over the frames added so far (the velocity and the temperature from the
  /// averaged momentum, density and kinetic stress).
  Fields result() const;

 private:
  Fields m_sum;  ///< the sums over the frames
  double m_cut, m_norm3, m_norm1, m_area;
  template <class F>
  void forPointsNear(const double lo[3], const double hi[3], F&& f) const;
  double kernel(const double d[3]) const;
  bool inCrossSection(const double c[3]) const;
};

/// What `tumble fields` and the Python module ask of a recording.
struct FieldOptions {
  /// Its box: when lo == hi on every axis, the particles' bounds (their spheres) over the frames
  /// used. A count of 0 on an axis: cells about a width wide there (at most 256 per axis and
  /// 2^22 points in all, fewer and wider cells where they would be more).
  FieldGrid grid;
  double width = 0.0;    ///< w, the kernel's standard deviation [m]
  std::size_t first = 0, last = SIZE_MAX, every = 1;  ///< the frames first, first + every, … ≤ last
  std::function<bool()> stop;  ///< polled before each frame: true stops (the frames so far are averaged)
  std::function<void(std::size_t, std::size_t)> progress;  ///< after each frame: (done, of)
};

/// Coarse-grains the chosen frames of a recording: positions from each frame's bodies
/// (x = X + R(Q) u), velocities from its debug block (the velocities at the start of the step
/// before the frame) when it has one, the contact stress from its contact forces when it has them.
/// Throws tumble::Error for a choice of no frame and what CoarseGraining throws; tumble::InputError
/// for a damaged recording. Stopped (options.stop) before the first frame: fields of no frame
/// (Fields::frames 0).
Fields coarseGrainRecording(RecordingReader& reader, const FieldOptions& options);

/// Why `path` is not a name writeFields() takes (its extension neither .vti nor .csv, in any
/// case), or "" when it is.
std::string fieldsOutputProblem(const std::string& path);

/// Writes the fields as VTK XML image data (a name ending in .vti, point data on the grid's
/// points; ParaView) or CSV (.csv: a row per point, x, y, z and the fields). Each file is written
/// whole (OutputFile). Throws tumble::Error (another extension: fieldsOutputProblem()).
void writeFields(const Fields& fields, const std::string& path);

}  // namespace tumble
