// SPDX-License-Identifier: MIT
/// @file world.hpp
/// Host-owned SoA state of a scene: the static particle and body tables and the body state.
/// Pipelines copy it in at load() and write the body state back on demand.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tumble/kernels/contact.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/kernels/wall.hpp"
#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/soa.hpp"
#include "tumble/wall_geometry.hpp"

namespace tumble {

/// Everything that carries from one step to the next: the integrated state of every body (one
/// column per component, scene order) and the contact history of every particle.
/// The tangential history of one touching contact (contact laws with a history): the sliding
/// displacement ξ of particle i relative to particle j (scene indices, i < j); that of j
/// relative to i is −ξ exactly.
struct ContactHistory {
  std::uint32_t i, j;
  float x, y, z;
};

/// A sphere in contact with a mesh wall's triangle: the particle (scene index) and the
/// triangle (meshTriangleCount()'s numbering, tumble/mesh.hpp), as counted by the rule of
/// kernels/mesh.hpp (once per local minimum of the distance).
struct MeshContact {
  std::uint32_t particle, triangle;
  friend bool operator==(const MeshContact& a, const MeshContact& b) {
    return a.particle == b.particle && a.triangle == b.triangle;
  }
  friend bool operator<(const MeshContact& a, const MeshContact& b) {
    return a.particle != b.particle ? a.particle < b.particle : a.triangle < b.triangle;
  }
};

/// The stick spring of a particle on a mesh triangle (docs/model.md#mesh-walls): the
/// elongation ξ as a vector in the frame the run integrates in (world axes), projected on the
/// contact's tangent plane each step.
struct MeshContactHistory {
  std::uint32_t particle, triangle;
  float x, y, z;
};

struct BodyState {
  std::vector<float> px, py, pz;      ///< centre of mass X
  std::vector<float> vx, vy, vz;      ///< V
  std::vector<float> qw, qx, qy, qz;  ///< orientation Q
  std::vector<float> lx, ly, lz;      ///< angular momentum L (world frame)
  /// Per plane and particle (scene order), plane-major (plane k's at k n + i; the planes of
  /// Scene::planes(), the ground first): the stick spring's elongation ξ in the plane's frame
  /// (along t1, t2; for the ground x, y), +0 out of contact (a held JKR neck of zero spring: y
  /// is −0, heldPlaneSpring()). Empty in a scene without planes, or (on input) for zero
  /// everywhere.
  std::vector<float> groundSpringX, groundSpringY;
  /// Laws with a history (ContactParams::hasHistory): the contacts whose ξ is not all zero bits
  /// (isZeroSpring(): a JKR neck that holds keeps a negative zero), sorted by (i, j). Empty
  /// otherwise, or (on input) for no history.
  std::vector<ContactHistory> contacts;
  /// Periodic boundaries (Scene::periodic): per body, the periods its centre has crossed on x
  /// and on y, +1 each time it left the box through its upper end, so that X + n L is where it
  /// would be without the boundary (unwrappedPosition()). Empty for an axis that is not
  /// periodic, or (on input) for zero everywhere.
  std::vector<std::int32_t> imageX, imageY;
  /// Mesh walls: the springs ξ that are not all zero bits, per (particle, triangle), sorted. Empty
  /// without meshes, or (on input) for none.
  std::vector<MeshContactHistory> meshContacts;
  /// Resizes the body columns to n bodies (the particle columns and the image counters are left
  /// alone).
  void resize(std::size_t n);
  std::size_t size() const { return px.size(); }
};

struct World;

/// The frame a pipeline integrates in (docs/model.md#precision). Positions are float, and far
/// from the origin their spacing swallows small motions (ulp(10⁵ m) = 7.8 mm: a body moving
/// 1 m/s with dt = 10⁻⁴ s would not move at all). A scene lying far from the origin compared with
/// its own size is therefore moved, at load, into a local frame centred on its bodies' bounding
/// box; the pipelines give positions back in the world frame (rounded to float there).
struct LocalFrame {
  double x = 0.0, y = 0.0, z = 0.0;  ///< the local origin in world coordinates (a float value)
  bool active() const { return x != 0.0 || y != 0.0 || z != 0.0; }

  /// Per axis a: c_a, the centre of the bodies' bounding box rounded to float, when
  /// |c_a| > 4 × max(largest extent of the box, 2 × largest radius); otherwise 0 (that axis stays).
  /// The box also holds what the bodies move towards: the ground height (z), when the ground is
  /// on, and the world origin on the axes of the pulls that are on at load. On a periodic axis
  /// (Scene::periodic) c_a is always the centre of the periodic box rounded to float, so that the
  /// box is [−h, h) in the frame (kernelPeriodic()).
  static LocalFrame of(const World& world);
};

/// Bodies, particles and parameters of one run, on the host.
struct World {
  Scene params;  ///< the scene it was built from (parameters; bodies/shapes kept for reference)

  // Static particle table; particles of one body are contiguous, bodies in creation order.
  /// groundDamping: c of the first plane (the ground's, when there is one) from each
  /// particle's elasticity; the other planes' in planeDamping.
  std::vector<float> radius, mass, elasticity, groundDamping;
  /// c of plane k ≥ 1 (Scene::planes()) for particle i at (k − 1) n + i; empty with one plane
  /// or none.
  std::vector<float> planeDamping;
  /// hertz-mindlin: the coefficients of material a on plane k at planeHertz[k M + a] (the
  /// ground's are materialPairs' b = M); empty under the other laws.
  std::vector<HertzPair> planeHertz;
  std::vector<std::uint32_t> body;
  /// hertz-mindlin: each particle's material (index into params.materials), and the
  /// coefficients of every pair of materials a, b at materialPairs[a (M + 1) + b], the ground's
  /// at b = M (materialPair()). Empty under the other laws.
  std::vector<std::uint16_t> material;
  std::vector<HertzPair> materialPairs;
  std::vector<float> ux, uy, uz;

  // Static body table.
  std::vector<float> bodyMass, invMass;
  std::vector<Sym3f> invInertia;  ///< body frame, about the centre of mass
  std::vector<Sym3f> inertia;     ///< I0 itself (for energies and diagnostics)
  std::vector<std::uint32_t> first, numParticlesOf;
  /// Per body, the rotation from the frame the pipelines integrate (the "body frame") to the
  /// shape frame of the scene file. Identity, except with [integrator] rotation = "splitting",
  /// which needs the principal axes: then the body frame is the principal frame, the offsets u
  /// and the inertia are expressed in it, and BodyState::q is the principal frame's orientation.
  std::vector<Quatf> bodyToShape;

  BodyState state;
  /// Step number and simulated time of `state`: 0 for a scene, the checkpoint's on a resume.
  std::uint64_t step = 0;
  double time = 0.0;
  /// Set on a resume (Checkpoint): the frame the run integrates in, chosen at its start;
  /// `state`'s positions are then already in it. Unset: load() chooses LocalFrame::of().
  std::optional<LocalFrame> frame;

  /// The bodies where the scene creates them, in the world frame (sceneBodiesExtent(), kept
  /// when params.bodies is cleared, and on a resume; toLocal() leaves it): what the walls are
  /// drawn around (RecordingWriter, tumble view).
  Extent bodiesExtent;

  bool hasClumps = false;  ///< some body has more than one particle
  /// Whether body k rotates: a clump, or any body under a law that turns spheres.
  bool bodyRotates(std::size_t k) const { return numParticlesOf[k] > 1 || params.contact.rotatesSpheres(); }
  float maxRadius = 0.0f;
  /// The largest extent of a body's spheres about its centre of mass (shapeExtent), m.
  double maxExtent = 0.0;
  /// The 99th percentile of the radii (detail::sizingRadius): what the automatic skin and cell
  /// size are sized from, so that a few large spheres do not set them for all the small ones.
  float sizingRadius = 0.0f;

  std::uint32_t numParticles() const { return static_cast<std::uint32_t>(radius.size()); }
  std::uint32_t numBodies() const { return static_cast<std::uint32_t>(bodyMass.size()); }

  /// Builds the tables from a scene: mass properties (SPEC §1), centres of mass, offsets u,
  /// ground damping from each particle's elasticity, L = R I0 Rᵀ ω. Throws tumble::Error on an
  /// empty scene or invalid values (radius ≤ 0, mass ≤ 0, elasticity outside (0, 1], NaN), and
  /// with `checkPlacement` on a body whose sphere starts behind a plane wall or whose centre
  /// lies outside a periodic box (a pour's worlds are built without: their bodies are where the
  /// run has them, tumble/pour.hpp).
  static World fromScene(const Scene& scene, bool checkPlacement = true);
};

/// The world expressed in frame f: body positions X − o, the ground height h − o_z, the walls'
/// points p − o (a mesh's pivot too) and the pull centre −o (params.pulls.centre). Identity when f is not active.
World toLocal(const World& world, const LocalFrame& f);

/// What a pipeline's load() integrates: the world in its frame (world.frame when set, the
/// positions already in it; otherwise LocalFrame::of(world)), with the particle columns of the
/// contact history sized (zeros where absent). Throws tumble::Error on mismatched sizes.
World localWorld(const World& world, LocalFrame* outFrame);

/// The walls of a scene (Scene::planes(): the ground, then the walls) as the kernels see them,
/// in frame f: the normal (or axis) normalised in double; a plane's h = (p − o)·n in double (an
/// aligned plane's h is ±float(p_a − o_a), as toLocal() moves the ground), a revolved wall's
/// axis start p − o. The pipelines and the guard build them from the world's scene and the
/// run's frame, so that they agree to the bit. None moves (setWallMotion()).
std::vector<Wall> kernelWalls(const Scene& scene, const LocalFrame& f);

/// What is wrong with a wall's motion, or empty: finite velocities, a window 0 ≤ start < stop,
/// a plane does not turn, a revolved wall turns about its own axis (a number), a mesh about a
/// vector and a finite pivot, a pivot only with a rotation. scene_io names the key;
/// kernelWalls() refuses walls built in code.
std::string wallMotionOutOfRange(const WallDef& wall);

/// How long a wall has moved by time t: τ = clamp(t − start, 0, stop − start) [s], in double.
double wallMotionTime(const WallDef& wall, double t);

/// Poses the walls of `scene` (kernelWalls()) for a step that starts at time t: Wall::moving
/// while start ≤ t < stop, and a wall with a velocity shifted by velocity τ from where it was
/// given (WallDef::velocity; a plane along its normal only). A mesh wall's Wall gets the pivot
/// where it is now (`centre`, for its material's velocity, wallVelocity()); with `meshPoses`
/// (one entry per wall of `walls`, plane-indexed) each mesh wall's MeshPose is written there:
/// the rotation by |ω| τ about ω and the pivot moved by velocity τ, computed in double from
/// the time and rounded once, so that time t gives the same bits whatever came before (a
/// resumed run). Entries of other walls are left alone. Returns whether any changed (a
/// pipeline whose walls live on a device uploads them then).
bool setWallMotion(std::vector<Wall>& walls, const Scene& scene, double t, MeshPose* meshPoses = nullptr);

/// Some mesh wall of the scene moves at some time (its poses then enter the contacts).
bool meshWallsMove(const Scene& scene);

/// The periodic box of a scene as the kernels see it in frame f (whose origin on a periodic axis
/// is the box's centre, LocalFrame::of): h = (hi − lo) / 2 rounded to float, L = 2h; the box is
/// [−h, h). axes = 0 without periodic boundaries. Throws tumble::Error when f is not centred on
/// the box (a frame chosen for another scene).
PeriodicBox kernelPeriodic(const Scene& scene, const LocalFrame& f);

/// Body k's centre of mass without the periodic boundaries, X + n L on each periodic axis
/// (BodyState::imageX, imageY; box from kernelPeriodic()), in double, in the frame of `state`.
void unwrappedPosition(const BodyState& state, std::size_t k, const PeriodicBox& box, double out[3]);

/// What the shortest period of a run is made of (docs/model.md#periodic-boundaries): E, the
/// largest extent of a body's spheres about its centre of mass (shapeExtent), r, the largest
/// radius, and the skin the run uses. A period of at most 2 (E + r + skin) could let a body meet
/// its own image, or a pair of particles two images of each other within the skin.
struct PeriodReach {
  double extent = 0.0, radius = 0.0, skin = 0.0;
  double minimum() const { return 2.0 * (extent + radius + skin); }
};

/// The reach of a scene's bodies (the shapes they use) with the scene's skin ([broadphase] skin,
/// or the automatic one of its radii, effectiveSkin()).
PeriodReach periodReach(const Scene& scene);
/// The reach of a world's bodies with the given skin.
PeriodReach periodReach(const World& world, float skin);

/// Why periodic axis `axis` (0: x, 1: y) is too short for this reach (its period hi − lo at most
/// reach.minimum()), as a phrase naming the shortest period allowed and what it is made of; empty
/// when it is long enough or the axis is not periodic.
std::string periodTooShort(const PeriodicParams& periodic, int axis, const PeriodReach& reach);

/// Throws tumble::Error with periodTooShort()'s phrase when a periodic axis of `world` is too
/// short for its bodies with the run's skin (effectiveSkin(world): the skin may be another than
/// the scene's, --skin). What a pipeline checks first in load(), so that a refused world changes
/// nothing of the pipeline.
void requirePeriodsFit(const World& world);

/// Why a wall is not invariant under the periodic translations of a scene, as a phrase; empty
/// when it is. A plane must contain each periodic axis (its normal's component along it is 0;
/// a box's faces across a periodic axis must be open); a revolved wall must be a cylinder whose
/// axis lies along the only periodic axis and reaches half a period beyond each end of the box.
std::string periodicWallProblem(const WallDef& wall, const PeriodicParams& periodic);

/// Why a periodic box [lo, hi) cannot be integrated, as a phrase: its length hi − lo (by which
/// positions wrap) must be a finite single-precision number; empty when it is.
std::string periodicBoxRange(float lo, float hi);

/// Why a body centred at x lies outside the periodic box ([lo, hi) on each periodic axis), as a
/// phrase; empty when inside or without periodic boundaries.
std::string outsidePeriodicBox(const PeriodicParams& periodic, Vec3f x);

/// Why the pulls `active` (PullBits) cannot run with the periodic boundaries (a pull along a
/// periodic axis: its potential has no period), as a phrase naming them; empty when they can.
std::string periodicPullProblem(const PeriodicParams& periodic, std::uint32_t active);

/// Body positions from frame f back to the world frame: X + o, rounded to float.
void toWorld(BodyState& s, const LocalFrame& f);

/// The largest |u| + r of a shape's spheres about its centre of mass (m): how far its particles
/// reach from the body's position.
double shapeExtent(const ShapeDef& shape);

/// Σ m (0.4 r² + |u|²) over a shape's spheres (u about the centre of mass), kg m²: at least its
/// largest principal moment of inertia.
double shapeInertiaBound(const ShapeDef& shape);

/// Why a body of this shape spinning at `omega` rad/s would have an angular momentum beyond
/// single precision (bounded by shapeInertiaBound × omega), as a phrase; empty when it fits.
std::string angularVelocityOutOfRange(const ShapeDef& shape, double omega);

/// Why a shape's derived values cannot be held in single precision (the total mass or its
/// inverse, its weight under `gravity`, the moment of inertia or its inverse, the extent), as a phrase for a message; empty
/// when they can. The scene reader reports it at the shape's line; World::fromScene throws it.
/// spheresRotate: the scene's law turns single spheres (their inertia is then used too).
std::string shapeOutOfRange(const ShapeDef& shape, bool spheresRotate = false, Vec3f gravity = Vec3f{0, 0, 0});

/// Orientation of body k's shape frame (as written in the scene file): q_k ⊗ bodyToShape[k]⁻¹.
Quatf shapeOrientation(const World& world, const BodyState& state, std::size_t k);

/// Damping coefficient c of a linear spring-dashpot k, mass m whose coefficient of restitution
/// is e (0 < e ≤ 1): c = 2 ζ √(k m), ζ = −ln e / √(π² + ln² e). Exact for an unclamped linear
/// spring-dashpot without gravity, contact ending when the overlap returns to zero.
double dampingForRestitution(double e, double k, double m);

/// Why the ground damping of a sphere (dampingForRestitution of its elasticity, its mass and the
/// ground's stiffness) cannot be held in single precision, as a phrase; empty when it can or the
/// ground is off. The scene reader reports it at the sphere's line; World::fromScene throws it.
/// A wall's (Scene::planes()) is the same with its own contact and `where` naming it.
std::string groundDampingOutOfRange(const SphereDef& sphere, const GroundParams& ground,
                                    const std::string& where = "[ground]");

/// The Hertz–Mindlin coefficients of two materials in contact (docs/model.md#materials): Y* and
/// G* from both E and ν, the restitution, friction and rolling friction the smaller of the two
/// (as Chrono's default composition). b = nullptr: a rigid partner (the ground without a
/// material: E = ∞, and a's restitution and friction).
HertzPair materialPair(const MaterialDef& a, const MaterialDef* b);

/// Material a of `scene` on a plane (the ground or a wall): materialPair() with the plane's
/// material (none: rigid), then the plane's friction and rolling friction where it gives them.
HertzPair planePair(const Scene& scene, const GroundParams& plane, std::size_t a);

/// Why a material's effective moduli (materialPair() with itself and with a rigid ground) cannot
/// be held in single precision, as a phrase; empty when they can.
std::string materialOutOfRange(const MaterialDef& m);

/// Restitution of the same model for damping c: e = exp(−ζπ/√(1−ζ²)) (0 when ζ ≥ 1).
double restitutionForDamping(double c, double k, double m);

/// Contact time π √(m_eff / k) of the stiffest, lightest contact the scene can have (two of its
/// lightest particles with k_s; its lightest particle on the ground or a wall with its k), undamped. Under
/// hertz-mindlin, the Hertz contact time 2.87 (m*² / (R* Y*² v))^{1/5} of the lightest mass and
/// the largest radius of each pair of materials (and on every plane) at the fastest impact the
/// initial state suggests, v = max(1 m/s, |V|max + √(2 |g| H) + the fastest moving wall),
/// H the drop to the ground (wallApproachSpeed()).
double shortestContactTime(const World& world);

/// The fastest a wall's surface can run into a body [m/s]: 0 for a wall that does not move; a
/// plane's speed along its normal; a revolved wall's translation (its turn moves its surface
/// along itself); a mesh's translation plus its rate times the largest distance of a vertex from
/// its pivot (a lifter, a blade).
double wallApproachSpeed(const WallDef& wall);

/// Empty when dt resolves the shortest contact with at least 10 steps; otherwise a one-line
/// warning naming the contact time and the dt to use (t_c / 20).
std::string timeStepWarning(const World& world);

/// Kinetic energy Σ ½ M V² + ½ Ω·L of the body state.
double kineticEnergy(const World& world, const BodyState& state);

/// 64-bit FNV-1a hash of every bit of a state: the bodies and the per-particle contact history
/// (determinism tests, goldens, and a quick check that two runs agree bit for bit).
std::uint64_t stateHash(const BodyState& state);

}  // namespace tumble
