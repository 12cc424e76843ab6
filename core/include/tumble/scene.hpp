// SPDX-License-Identifier: MIT
/// @file scene.hpp
/// Scene description: physical parameters, the bodies to create, and run settings. Read from
/// TOML by readSceneFile() (docs/scenes.md) or built in code (validation/scenes.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tumble/kernels/cohesion.hpp"
#include "tumble/math.hpp"

namespace tumble {

struct TriangleMesh;

/// The particle–particle contact law of a scene (docs/model.md#contact-laws).
enum class ContactLaw : std::uint8_t {
  /// The report's (SPEC §2.3): f_s = k_s δ n, f_d = η w, f_t = k_t (w − (w·n) n); no memory,
  /// and single-sphere bodies do not rotate.
  Report,
  /// LAMMPS gran/hooke/history: normal spring k_n δ and dashpot m_eff γ_n w_n, tangential spring
  /// k_t ξ on the sliding displacement ξ carried while the pair touches (Cundall–Strack) and
  /// dashpot m_eff γ_t w_t, Coulomb limit μ |F_n|. Every body rotates.
  HookeHistory,
  /// Hertz–Mindlin as LIGGGHTS defines `hertz` with tangential history: Hertz normal and Mindlin
  /// tangential stiffness from each pair's materials (Young's modulus, Poisson's ratio), damping
  /// from their coefficient of restitution, the same history and Coulomb limit as hooke-history.
  /// Every body rotates.
  HertzMindlin,
};

/// "report" / "hooke-history" / "hertz-mindlin".
const char* toString(ContactLaw law);
/// "none" / "sjkr" / "dmt".
const char* toString(Cohesion model);
/// The scene key of a model's coefficient: "cohesion_energy_density" (sjkr, k_c) or
/// "surface_energy" (dmt, γ); "" for none.
const char* cohesionKey(Cohesion model);

/// Particle–particle contact (SPEC §2.3 for the report's law; docs/model.md for the others).
struct ContactParams {
  float stiffness = 2.0e4f;  ///< k_s (report) or k_n (hooke-history) [N/m]
  float damping = 10.0f;     ///< report: η [N s/m]
  float shear = 5.0f;        ///< report: k_t [N s/m]
  ContactLaw law = ContactLaw::Report;
  float tangentialStiffness = 0.0f;  ///< hooke-history: k_t [N/m]; 0 = 2/7 k_n
  float gammaN = 0.0f;               ///< hooke-history: γ_n [1/s]
  float gammaT = -1.0f;              ///< hooke-history: γ_t [1/s]; negative = γ_n / 2
  float friction = 0.5f;             ///< hooke-history: Coulomb μ between particles
  float rollingFriction = 0.0f;      ///< hooke-history: rolling resistance μ_r (0 = none)
  /// Cohesion of the contacts (laws with history; docs/model.md#cohesion) and, under
  /// hooke-history, its coefficient for every pair: k_c [J/m³] (sjkr) or γ [J/m²] (dmt).
  Cohesion cohesion = Cohesion::None;
  float cohesionValue = 0.0f;
  /// Whether the law has forces that turn a sphere (then single-sphere bodies rotate too).
  bool rotatesSpheres() const { return law != ContactLaw::Report; }
  /// Whether the law keeps a tangential history per contact.
  bool hasHistory() const { return law != ContactLaw::Report; }
  /// Whether the law takes its parameters from the spheres' materials (Scene::materials).
  bool usesMaterials() const { return law == ContactLaw::HertzMindlin; }
};

/// A material (`[[material]]`, docs/scenes.md): what hertz-mindlin reads of a sphere, and the
/// density that gives a sphere its mass under any law. A pair of materials is mixed as
/// materialPair() says (docs/model.md#materials).
struct MaterialDef {
  std::string name;
  float density = 0.0f;         ///< kg/m³; 0 = none (the spheres give their mass)
  float youngsModulus = 0.0f;   ///< E [Pa]
  float poissonRatio = 0.0f;    ///< ν, in [0, 0.5)
  float restitution = 0.5f;     ///< e, in (0, 1]
  float friction = 0.5f;        ///< Coulomb μ
  float rollingFriction = 0.0f; ///< rolling resistance μ_r (0 = none)
  float cohesion = 0.0f;        ///< k_c or γ under [contact] cohesion (0 = none; pairs mix by the geometric mean)
};

/// Ground plane z = height with normal +z (SPEC §2.4).
struct GroundParams {
  bool enabled = false;
  float height = 0.0f;
  float stiffness = 2.0e4f;          ///< normal spring k_g [N/m]
  float friction = 0.5f;             ///< Coulomb μ (static = kinetic)
  float tangentialStiffness = 0.0f;  ///< stick spring k_t,g [N/m]; 0 = 2/7 k_g
  float rollingFriction = -1.0f;     ///< rolling resistance μ_r; negative = the contact's (laws that turn spheres)
  /// hertz-mindlin: the ground's material (index into Scene::materials); negative = a rigid
  /// ground (E = ∞) with each sphere's own restitution and friction.
  int material = -1;
  /// hertz-mindlin: μ of every sphere–ground pair instead of the mixed one (negative: mixed);
  /// rollingFriction likewise replaces the mixed μ_r when not negative.
  float frictionOverride = -1.0f;
  /// Under [contact] cohesion: k_c or γ of every sphere–plane pair; negative = the contact's
  /// (hooke-history) or the pair's of the sphere's and the plane's materials (hertz-mindlin).
  float cohesion = -1.0f;
};

/// A wall (`[[wall]]`, docs/scenes.md#wall-walls), with its own contact parameters: `contact`
/// is read as a [ground] table (enabled and height unused). A sphere meets a wall as it meets
/// the ground (SPEC §2.4, or hertzGroundForces under hertz-mindlin), in the frame of the
/// wall's surface at the nearest point. The ground is the plane through (0, 0, height) with
/// normal +z (Scene::planes()).
///
/// Plane: the spheres live on the side its normal points to (a half-space). Revolved (a
/// cylinder, a cone, a disk or a ring): the segment from (0, radius0) to (length, radius1) in
/// (s, ρ), s along the axis from `point` and ρ the distance from the axis, turned about the
/// axis: a thin surface that a sphere meets from either side. Mesh: the triangles of `mesh`
/// (a file's, tumble/mesh.hpp) scaled, turned and placed, position + R(orientation) (scale ⊙ v)
/// with position = `point`: thin surfaces met from either side (kernels/mesh.hpp).
struct WallDef {
  Vec3f point{0.0f, 0.0f, 0.0f};   ///< plane: a point of it; revolved: the axis's start; mesh: its position [m]
  /// plane: the normal towards the spheres; revolved: the axis's direction; any length but 0
  /// (kernelWalls() normalises it in double)
  Vec3f normal{0.0f, 0.0f, 1.0f};
  GroundParams contact;
  std::string where;               ///< "[[wall]] #k (file:line)" for messages; empty in code
  enum class Shape : std::uint8_t { Plane, Revolved, Mesh };
  Shape shape = Shape::Plane;
  float length = 0.0f;             ///< revolved: the segment's extent along the axis [m] (0: a disk or ring)
  float radius0 = 0.0f, radius1 = 0.0f;  ///< revolved: its distances from the axis at s = 0 and s = length [m]
  /// The wall moves while start ≤ t < stop [s]: it translates rigidly with `velocity` [m/s]
  /// (at time t it lies where it was given, shifted by velocity τ, τ = clamp(t − start, 0,
  /// stop − start)), and a revolved wall turns about its axis at `angularVelocity` [rad/s]
  /// (right-handed about `normal`; a drum). For a plane only the part of the velocity along its
  /// normal moves the plane (a piston); the part in the plane moves its surface alone (a belt).
  /// A turning revolved wall keeps its shape and place: its surface moves.
  ///
  /// A mesh moves as a rigid body: at time t a point y of it as given (at τ = 0) lies at
  /// pivot + velocity τ + R(τ) (y − pivot), R(τ) the rotation by |ω| τ about ω =
  /// `meshAngularVelocity` (right-handed): it turns about the pivot first, and the pivot moves
  /// with the translation (docs/scenes.md#mesh-walls).
  Vec3f velocity{0.0f, 0.0f, 0.0f};
  float angularVelocity = 0.0f;
  /// mesh: its angular velocity ω as a vector [rad/s]: the rotation's axis and rate
  /// (`angular_velocity = [x, y, z]`), about `pivot`.
  Vec3f meshAngularVelocity{0.0f, 0.0f, 0.0f};
  /// mesh: a point of its rotation's axis where it was given [m] (`pivot`); none: its position,
  /// `point` (meshPivot()).
  std::optional<Vec3f> pivot;
  /// A face of a `[[wall]] type = "box"` (drawing: the faces of a moving box travel together).
  bool boxFace = false;
  double start = 0.0, stop = std::numeric_limits<double>::infinity();
  /// mesh: the triangles as read (shared, never changed), the scale of the file's coordinates
  /// (per axis, > 0) and the orientation applied after it (a unit quaternion, or any non-zero
  /// one: normalised in double)
  std::shared_ptr<const TriangleMesh> mesh;
  std::string meshFile;  ///< mesh: the file it was read from (as opened); empty when made in code
  Vec3f scale{1.0f, 1.0f, 1.0f};
  Quatf orientation{1.0f, 0.0f, 0.0f, 0.0f};
  bool moves() const {
    const Vec3f& w = meshAngularVelocity;
    return velocity.x != 0.0f || velocity.y != 0.0f || velocity.z != 0.0f || angularVelocity != 0.0f || w.x != 0.0f ||
           w.y != 0.0f || w.z != 0.0f;
  }
  /// mesh: the point its rotation turns about where it was given: `pivot`, or its position.
  Vec3f meshPivot() const { return pivot ? *pivot : point; }
};

/// A plane wall built in code: through `point`, `normal` towards the spheres, the ground's
/// default contact (WallDef).
inline WallDef planeWall(Vec3f point, Vec3f normal) {
  WallDef w;
  w.point = point;
  w.normal = normal;
  w.contact.enabled = true;
  return w;
}

/// A revolved wall built in code: the segment (0, radius0)–(length, radius1) about the axis from
/// `point` along `axis` (a cylinder, a cone; a disk or ring with length 0, `axis` its normal).
inline WallDef revolvedWall(Vec3f point, Vec3f axis, float length, float radius0, float radius1) {
  WallDef w;
  w.shape = WallDef::Shape::Revolved;
  w.point = point;
  w.normal = axis;
  w.length = length;
  w.radius0 = radius0;
  w.radius1 = radius1;
  w.contact.enabled = true;
  return w;
}

/// Bits of PullParams::active / Pipeline::setPulls().
enum PullBits : std::uint32_t { kPullX = 1u, kPullY = 2u, kPullSwirl = 4u };

/// The report's user forces (SPEC §2.5), per particle, proportional to its mass:
/// x: f = −m κx x ex; y: f = −m κy y ey; swirl: f = m κs (−y, x, 0), with x, y measured from the
/// world origin. They add.
struct PullParams {
  float x = 2.0f;        ///< κx [1/s²]
  float y = 2.0f;        ///< κy [1/s²]
  float swirl = 2.0f;    ///< κs [1/s²]
  std::uint32_t active = 0;  ///< PullBits that are on
  /// Where the pulls pull to, in the coordinates the pipeline integrates in: the world origin,
  /// i.e. (0, 0, 0), except in a local frame (LocalFrame, set by toLocal(); not in scene files).
  Vec3f centre{0.0f, 0.0f, 0.0f};
};

/// Periodic boundaries (`[periodic]`, docs/scenes.md#periodic-periodic-boundaries): on x and/or
/// y the scene repeats with period L = hi − lo. A body's centre of mass is kept in [lo, hi), its
/// crossings counted (BodyState::imageX, imageY), and two particles meet through their nearest
/// images (docs/model.md#periodic-boundaries). World coordinates.
struct PeriodicParams {
  bool on[2] = {false, false};                  ///< x, y periodic
  float lo[2] = {0.0f, 0.0f}, hi[2] = {0.0f, 0.0f};  ///< the box [lo, hi) on each periodic axis [m]
  bool any() const { return on[0] || on[1]; }
  /// The PullBits that pull along a periodic axis (their potential has no period): the x pull
  /// and the swirl with x periodic, the y pull and the swirl with y periodic.
  std::uint32_t conflictingPulls() const {
    return (on[0] ? (kPullX | kPullSwirl) : 0u) | (on[1] ? (kPullY | kPullSwirl) : 0u);
  }
};

/// One sphere of a shape, in the shape's own frame.
struct SphereDef {
  Vec3f offset{0, 0, 0};
  float radius = 0.5f;
  float mass = 1.0f;
  float elasticity = 0.5f;
  std::uint32_t material = 0;  ///< index into Scene::materials (read only when it has some)
};

/// The mass properties of a shape that has its own (a solid: `[[shape]]` with `mass`,
/// `centre_of_mass` and `inertia`, as `tumble clump` writes them from a mesh), in the shape's
/// frame: the body's mass, centre of mass and inertia are these instead of its spheres' sums.
/// The spheres then give the contacts, and each its share of the mass by volume (its `mass`)
/// for what is per particle (the ground's damping, the pulls).
struct ShapeSolid {
  double mass = 0.0;                                           ///< kg
  std::array<double, 3> centre{0.0, 0.0, 0.0};                 ///< m
  std::array<double, 6> inertia{0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; ///< kg m², about the centre: xx, yy, zz, xy, xz, yz (tensor entries, I_xy = −∫ x y dm)
  /// The same solid `factor` times as large (a fill's or pour's size): mass × f³, centre × f,
  /// inertia × f⁵.
  ShapeSolid scaled(double factor) const {
    ShapeSolid s = *this;
    const double f3 = factor * factor * factor;
    s.mass *= f3;
    for (double& c : s.centre) c *= factor;
    for (double& i : s.inertia) i *= f3 * factor * factor;
    return s;
  }
};

/// A rigid body shape: one or more spheres, and the mass properties of a solid where it has its own.
struct ShapeDef {
  std::string name;
  std::vector<SphereDef> spheres;
  std::optional<ShapeSolid> solid{};
  std::string meshFile{};  ///< a shape made from a mesh: the file it was read from (an input of the run)
};

/// A shape's mass (kg), centre of mass (m) and inertia about it (kg m², xx, yy, zz, xy, xz, yz),
/// in its frame and in double: its solid's where it has one, else its spheres' (each a solid
/// sphere: Σ m, Σ m u / M, Σ m (0.4 r² + |u − c|²) 1 − m (u − c)(u − c)ᵀ).
ShapeSolid shapeMassProperties(const ShapeDef& shape);

/// A solid shape's spheres given their shares of its mass, by volume: m_i = M r_i³ / Σ r³ (what
/// is per particle: the ground's damping, the pulls). Nothing for a shape without a solid.
void shareMassByVolume(ShapeDef& shape);

/// One body to create: shape index, centre-of-mass position, velocities, orientation.
struct BodyDef {
  std::uint32_t shape = 0;
  Vec3f position{0, 0, 0};
  Vec3f velocity{0, 0, 0};
  Quatf orientation{1, 0, 0, 0};
  Vec3f angularVelocity{0, 0, 0};  ///< world frame
};

/// Where a `[[fill]]` or a `[[pour]]` puts bodies: a box, a cylinder or the inside of a closed
/// mesh wall.
struct FillRegion {
  enum class Kind : std::uint8_t { Box, Cylinder, Mesh };
  Kind kind = Kind::Box;
  std::size_t wall = 0;              ///< mesh: the index of the mesh wall in Scene::walls
  Vec3f min{0, 0, 0}, max{0, 0, 0};  ///< box: its corners
  Vec3f point{0, 0, 0};              ///< cylinder: the start of its axis
  Vec3f axis{0, 0, 1};               ///< cylinder: from point to the far end (its length is the cylinder's)
  float radius = 0.0f;               ///< cylinder
};

/// A `[[pour]]` (docs/scenes.md, tumble/pour.hpp): bodies that enter the run in its region
/// at `rate` bodies per second from `start`, each placed where it overlaps nothing.
struct PourDef {
  FillRegion region;
  double start = 0.0;     ///< s
  double rate = 0.0;      ///< bodies per second
  double interval = 0.0;  ///< s between two batches (0: every step)
  std::uint64_t count = 0;
  std::uint64_t seed = 0;
  std::uint64_t attempts = 100;  ///< positions drawn per body and batch
  std::string where;             ///< "[[pour]] #k (file:line)" for messages
};

/// A body a pour will add: its shape (scaled), orientation and velocities drawn when the scene
/// is read; its position is drawn when it enters.
struct PourBody {
  BodyDef body;
  std::uint32_t pour = 0;   ///< index into Scene::pours
  std::uint64_t index = 0;  ///< its place among its pour's bodies
  double time = 0.0;        ///< when it is due: the pour's start + index / rate [s]
};

/// Collision-detection knobs. They change speed only, never the contacts or a bit of the
/// trajectory (the contact list is canonical, kernels/contact_list.hpp).
struct BroadphaseParams {
  float cellSize = 0.0f;   ///< side M of the p–q cells; 0 = automatic (3 diameters of World::sizingRadius, at least 1/32 of the largest diameter and 8 rounding margins); a given size is raised to 8 margins
  int pcaEvery = 10;       ///< recompute the PCA axis every K detections (1 = every one)
  /// Verlet skin s: detection finds the pairs within r_i + r_j + s and the list is kept until two
  /// particles may have closed in by s (about s/2 of motion each); 0 = detect every step (the report's method); negative = automatic
  /// (effectiveSkin()).
  float skin = -1.0f;
};

/// How body orientations advance (SPEC §2.7). Translation is always leapfrog (kick-drift).
enum class RotationScheme : std::uint8_t {
  /// The report's scheme: L += T dt, then Q ← exp(Ω dt) Q with Ω = R I0⁻¹ Rᵀ L held fixed over
  /// the step. Not symplectic: for an asymmetric body the kinetic energy drifts.
  Report,
  /// Symplectic splitting (Dullweber–Leimkuhler–McLachlan 1997): L += T dt, then the free
  /// rotation as five exact rotations about the principal axes (½ h about 1, ½ h about 2, h
  /// about 3, ½ h about 2, ½ h about 1). Keeps |L| exactly and the energy bounded.
  Splitting,
};

/// "report" / "splitting".
const char* toString(RotationScheme s);

struct IntegratorParams {
  RotationScheme rotation = RotationScheme::Report;
};

/// Everything a run needs.
struct Scene {
  std::string name = "scene";
  std::string sourceFile;  ///< the TOML file it came from, if any
  float dt = 1.0e-4f;
  std::uint64_t steps = 1000;
  Vec3f gravity{0.0f, 0.0f, -9.81f};
  ContactParams contact;
  GroundParams ground;
  std::vector<WallDef> walls;  ///< the walls besides the ground (a box gives six planes, or fewer when open)
  PullParams pulls;
  BroadphaseParams broadphase;
  IntegratorParams integrator;
  std::vector<MaterialDef> materials;  ///< hertz-mindlin: at least one; the others: densities only
  std::vector<ShapeDef> shapes;
  std::vector<BodyDef> bodies;
  std::vector<PourDef> pours;
  /// Every body the pours will add, in the order they enter: by the time each is due (then by
  /// pour, then by its index). They enter in this order only: one that finds no place holds
  /// back the ones after it (tumble/pour.hpp).
  std::vector<PourBody> pourBodies;
  // Output settings.
  std::string recordFile;          ///< empty = no recording
  std::uint64_t recordSteps = 0;   ///< 0 = the whole run
  bool recordDebug = false;
  bool recordContacts = false;     ///< [output] contacts: each frame's contacts with their forces
  int stepsPerFrame = 10;
  std::string thermoFile;          ///< time series (docs/thermo.md); empty = none
  /// The ground's rolling resistance as the kernels use it: 0 unless the law turns spheres.
  float groundRollingFriction() const { return rollingFrictionOf(ground); }
  /// A plane's (the ground's or a wall's) rolling resistance as the kernels use it.
  float rollingFrictionOf(const GroundParams& plane) const {
    if (!contact.rotatesSpheres()) return 0.0f;
    return plane.rollingFriction >= 0.0f ? plane.rollingFriction : contact.rollingFriction;
  }
  /// A plane's cohesion coefficient as hooke-history's kernels use it (0 without cohesion).
  float cohesionOf(const GroundParams& plane) const {
    if (contact.cohesion == Cohesion::None) return 0.0f;
    return plane.cohesion >= 0.0f ? plane.cohesion : contact.cohesionValue;
  }
  /// Every wall the spheres touch, in the order the forces sum them: the ground (when enabled)
  /// as the plane through (0, 0, height) with normal +z, then the walls.
  std::vector<WallDef> planes() const;
  /// Some wall's surface moves at some time (WallDef::moves()).
  bool wallsMove() const;
  /// Some wall's surface moves at some step that starts in [t0, t1) (start < t1 and stop > t0).
  bool wallsMoveDuring(double t0, double t1) const;
  std::uint64_t thermoEvery = 100; ///< steps between two rows of the time series
  bool energyBalance = false;      ///< the time series' energy tally (docs/thermo.md#energy-balance)
  PeriodicParams periodic;         ///< periodic boundaries on x and/or y (none by default)
};

}  // namespace tumble
