// SPDX-License-Identifier: MIT
/// @file soa.hpp
/// The rows and views the step's kernels work on. Both pipelines own the same rows (std::vector
/// on the CPU, device buffers on the GPU) and hand kernels the same views, passed by value.
///
/// Numbering. Inside a pipeline, bodies and particles are renumbered by their spatial order at
/// every rebuild of the contact list (a body's particles stay contiguous and in scene order), so
/// that neighbours are near each other in memory. Every row that must reach an output carries
/// its scene index (`orig`), and everything a result depends on is ordered by scene indices, not
/// by this internal numbering: the internal numbering changes speed only, never a bit.
#pragma once
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/kernels/energy.hpp"
#include "tumble/kernels/periodic.hpp"
#include "tumble/math.hpp"

namespace tumble {

struct HertzPair;
struct Wall;

/// One body: its integrated state and what the step reads with it (internal numbering), in two
/// cache lines. The first holds what a touching neighbour reads (V, Ω, R), so that a contact
/// costs one line of the other body.
struct alignas(64) BodyRow {
  Vec3f v;               ///< V
  Vec3f omega;           ///< Ω = R I0⁻¹ Rᵀ L of this state (0 for single-sphere bodies)
  Mat3f rot;             ///< R = rotationMatrix(q): lever arms R u and positions X + R u
  std::uint32_t count;   ///< number of particles
  Vec3f x;               ///< centre of mass X
  std::uint32_t first;   ///< first particle (internal numbering); the body's particles are contiguous
  Quatf q;               ///< orientation Q (body frame → world)
  Vec3f l;               ///< angular momentum L, world frame
  float invMass;
  std::uint32_t orig;    ///< scene index of the body
  std::int32_t image[2]; ///< periodic boundaries: the periods X has crossed on x, y (kernels/periodic.hpp)
};
static_assert(sizeof(BodyRow) == 128, "two cache lines");

/// A body's motion as the integration leaves it: its BodyRow without the pipeline's own fields
/// (numbering, mass). What a domain decomposition copies from a body's owner to its ghosts
/// (HaloPipeline, tumble/pipeline.hpp).
struct BodyMotion {
  Vec3f v, omega;  ///< V, and the Ω of this state
  Mat3f rot;       ///< R = rotationMatrix(q), as the integration computed it
  Vec3f x;
  Quatf q;
  Vec3f l;
  std::int32_t image[2];
};
static_assert(sizeof(BodyMotion) == 108, "27 words a body");

TUMBLE_HD_INLINE BodyMotion motionOf(const BodyRow& b) {
  return BodyMotion{b.v, b.omega, b.rot, b.x, b.q, b.l, {b.image[0], b.image[1]}};
}

TUMBLE_HD_INLINE void setMotion(BodyRow& b, const BodyMotion& m) {
  b.v = m.v;
  b.omega = m.omega;
  b.rot = m.rot;
  b.x = m.x;
  b.q = m.q;
  b.l = m.l;
  b.image[0] = m.image[0];
  b.image[1] = m.image[1];
}

/// A body's static mass properties (internal numbering).
struct alignas(16) BodyStatic {
  Sym3f invInertia;  ///< body-frame I0⁻¹ about the centre of mass
  float mass;        ///< M (the body's weight is M g)
  float reach;       ///< the largest |u| of its particles (the skin test's bound on their motion)
};

/// Where a body was at the skin test's reference (the last rebuild or near-list refresh): its
/// centre and orientation, from which finishBody() bounds the motion of all its particles at
/// once (bodyDrift()).
struct alignas(16) BodyRef {
  Vec3f x;
  Quatf q;
};

/// The hot row of a particle that its neighbours read: position (integration frame) and radius.
struct alignas(16) PosRow {
  float x, y, z, r;
};

/// What only the particle itself reads in a step.
struct alignas(16) OwnRow {
  Vec3f u;              ///< offset from the body's centre of mass, body frame
  float groundDamping;  ///< c of the first plane's spring-dashpot (the ground's; from the particle's elasticity)
};

/// The per-particle contact state that carries from step to step (internal numbering): the
/// stick spring's elongation (Cundall–Strack) on each plane (the ground, the walls), reset to
/// zero out of contact, plane-major: plane k's at k · numParticles + i, in the plane's frame.
struct GroundSpringView {
  float* tx;
  float* ty;
};

/// The candidate list (a Verlet list): particle i's candidates are cand[begin[i] .. end[i]),
/// internal indices, in ascending *scene* index of the candidate. Every particle of another body
/// within r_i + r_j + skin at the last rebuild is listed, in both directions. The near list (a
/// subsequence of each row; on the CPU stored compact, at its own offsets) has the same form.
struct CandidateListView {
  const std::uint32_t* begin;
  const std::uint32_t* end;
  const std::uint32_t* cand;
  /// Under JKR (Cohesion::Jkr), for the readouts of the last step's contacts (pairs(), the
  /// guard's sums, the counts; listedContact()): the entries' springs (entry e's at
  /// heldSlot[e] where heldSlot is not null), whose bits say whether the force stage held the
  /// pair, a neck beyond touching included (kernels/history.hpp). Null otherwise: the exact
  /// predicate decides.
  const Vec3f* held = nullptr;
  const std::uint32_t* heldSlot = nullptr;
};

/// One contact between particles as the debug capture keeps it (Pipeline::readDebug(),
/// ParticleDebug::contactForces): particles i < j (scene indices); the unit normal n = (x_i −
/// x_j) / |x_i − x_j| of the step's positions (+z at coincident centres, the contact law's); the
/// force F the step added to i's force for this contact (j received −F) split along n, fn = F · n
/// (negative: a pull), and across it, `tangential` = F − fn n; and the overlap
/// r_i + r_j − |x_i − x_j|. The branch x_i − x_j is n (r_i + r_j − overlap), across a periodic
/// boundary too (contactBranch()). In the capture itself (per entry of the list the step read)
/// an entry that did not touch has i = kNoContact.
struct ContactForce {
  std::uint32_t i, j;
  Vec3f n;
  float fn;
  Vec3f tangential;
  float overlap;
  /// The normal force on i, fn n.
  TUMBLE_HD_INLINE Vec3f normal() const { return fn * n; }
  /// By (i, j), as Pair: the order of Pipeline::pairs().
  friend bool operator<(const ContactForce& a, const ContactForce& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
};
inline constexpr std::uint32_t kNoContact = 0xffffffffu;

/// The view of a list stored compactly: row i is cand[offsets[i] .. offsets[i+1]).
TUMBLE_HD_INLINE CandidateListView compactList(const std::uint32_t* offsets, const std::uint32_t* cand) {
  return CandidateListView{offsets, offsets + 1, cand};
}

/// One triangle of a mesh wall (kernels/mesh.hpp; built by KernelMesh, tumble/mesh.hpp): its unit normal, the normals of the planes through
/// its three edges (outwards: x is outside edge j when (x − a_j)·m[j] ≥ 0, a_j the edge's
/// lower-indexed vertex; edge j runs from corner j to corner j + 1), its bounding box grown by a
/// bound on the kernels' rounding (the candidate test), and its wall (the plane index k of
/// Scene::planes() whose contact it has).
struct MeshTriangle {
  Vec3f n;
  Vec3f m[3];
  Vec3f lo, hi;
  std::uint32_t wall;
};

/// A node of the bounding-volume hierarchy over the triangles: its box (the union of its
/// triangles' boxes, exact), and either two children at `first` and `first + 1` (count 0) or
/// `count` triangles prims[first .. first + count) (a leaf).
struct MeshBvhNode {
  Vec3f lo, hi;
  std::uint32_t first, count;
};

/// Where a mesh wall is at the start of a step (setWallMotion(), docs/model.md#mesh-walls): a
/// point y of the mesh as it was given (the frame of its KernelMesh: where it lies at τ = 0, in
/// the frame the pipeline integrates in) is at centre + rot (y − pivot); a point x is at
/// pivot + rotᵀ (x − centre) in the mesh's frame (toMeshFrame(), kernels/mesh.hpp). rot, pivot
/// and centre are computed in double from the time and rounded once. `posed` is 0 while the
/// mesh is where it was given (τ = 0, the identity): points are then used as they are.
struct MeshPose {
  Mat3f rot;
  Vec3f pivot, centre;
  std::uint32_t posed;
};

/// Everything the kernels read of the meshes (all the scene's mesh walls, one numbering):
/// vertices in the frame the pipeline integrates in, 3 vertex indices per triangle, the
/// triangles' static data, their edges (3 global edge ids per triangle) and, for each edge and
/// each vertex, the triangles incident to it in ascending order (CSR), and the hierarchy; and
/// when a mesh wall moves, the poses of the walls at the step's start (`poses[k]` for plane k
/// of Scene::planes(), k < numPoses; null when no mesh wall moves: every mesh is where it was
/// given).
struct MeshView {
  const Vec3f* vertices = nullptr;
  const std::uint32_t* triangles = nullptr;
  const MeshTriangle* tri = nullptr;
  const std::uint32_t* triEdges = nullptr;
  const std::uint32_t* edgeTriOffsets = nullptr;
  const std::uint32_t* edgeTris = nullptr;
  const std::uint32_t* vertexTriOffsets = nullptr;
  const std::uint32_t* vertexTris = nullptr;
  const MeshBvhNode* nodes = nullptr;
  const std::uint32_t* prims = nullptr;
  std::uint32_t numTriangles = 0;
  const MeshPose* poses = nullptr;
  std::uint32_t numPoses = 0;
};

/// The mesh candidate list: particle i's candidate triangles are tri[offsets[i] ..
/// offsets[i+1]) in ascending triangle index (internal numbering of the particles), each with
/// the stick spring ξ of that (particle, triangle), zero out of contact (kernels/mesh.hpp).
struct MeshListView {
  const std::uint32_t* offsets = nullptr;
  const std::uint32_t* tri = nullptr;
  Vec3f* hist = nullptr;
};

/// Everything one step reads and writes (internal numbering).
struct StepView {
  const BodyRow* bodies;         ///< the body state at the start of the step (neighbours read it)
  BodyRow* bodiesNext;           ///< written by the integration: the next step's
  const BodyStatic* bodyStatic;
  std::uint32_t numBodies;
  const PosRow* pos;             ///< the particle positions at the start of the step
  PosRow* posNext;               ///< written by the integration: the next step's positions
  const OwnRow* own;
  const float* radius;           ///< particle radii
  const float* mass;             ///< particle masses (read by the pulls only)
  const std::uint32_t* bodyOf;   ///< body of each particle
  const std::uint32_t* orig;     ///< scene index of each particle
  GroundSpringView ground;
  const PosRow* buildPos;        ///< the skin test's reference: positions at the last rebuild of
                                 ///< the list the step reads (on the CPU, of the near list)
  CandidateListView list;
  std::uint8_t* touching;        ///< written by the forces: min(255, contacts) per particle, so that
                                 ///< pairs() need not test the particles that touch nothing
  std::uint32_t numParticles;
  /// Contact laws with a history: ξ of each entry of the candidate list, zero for a pair that
  /// does not touch; nullptr otherwise. Entry e of `list` has its ξ at history[historySlot[e]]
  /// when `list` is the CPU's near list (its candidate entries, fillNear()), else at history[e].
  Vec3f* history = nullptr;
  bool rotateSpheres = false;    ///< single-sphere bodies rotate too (ContactParams::rotatesSpheres)
  /// hertz-mindlin: the coefficients of each pair of materials a, b at hertz[a (M + 1) + b], the
  /// ground's at b = M (World::materialPairs), and the material of each particle; `material` is
  /// nullptr when the scene has one material (every particle's is 0). Unread by the other laws.
  const HertzPair* hertz = nullptr;
  const std::uint16_t* material = nullptr;
  std::uint32_t numMaterials = 0;
  /// The planes (the ground first when there is one, then the walls; World::planes()). Plane k
  /// > 0's damping c of particle i is planeDamping[(k − 1) numParticles + i] (plane 0's is in the
  /// own row); under hertz-mindlin, material a on plane k is planeHertz[k numMaterials + a].
  const Wall* planes = nullptr;
  std::uint32_t numPlanes = 0;
  const float* planeDamping = nullptr;
  const HertzPair* planeHertz = nullptr;
  /// Periodic boundaries (read by the kPeriodic instantiations only): positions are compared
  /// through the minimum image and body centres kept in the box.
  PeriodicBox periodic{};
  /// Mesh walls (their planes are kMeshWall entries of `planes`): the meshes and the candidate
  /// triangles of each particle; mesh.numTriangles is 0 without meshes.
  MeshView mesh;
  MeshListView meshList;
  /// The skin test per body (the CPU pipeline): each body's reference (BodyRef); finishBody()
  /// then bounds its particles' motion from its own (bodyDrift()) instead of measuring each
  /// particle against `buildPos`. nullptr: per particle.
  const BodyRef* bodyRef = nullptr;
  /// When `list` is compact (row i ends where row i + 1 begins), the particle of each of its
  /// entries, so that a body's rows are walked as one run (bodyForces()); nullptr otherwise (the
  /// CUDA pipeline).
  const std::uint32_t* listOwner = nullptr;
  /// See `history`: the candidate entry of each entry of `list`; nullptr when `list` is the
  /// candidate list (the CUDA pipeline's, the CPU's without a near list).
  const std::uint32_t* historySlot = nullptr;
  /// The energy tally (kernels/energy.hpp): each body's EnergyFlows of the step, written by the
  /// debug instantiation of the step (stepBody()); nullptr: not kept.
  EnergyFlows* bodyFlows = nullptr;
};

/// ξ of entry e of v.list (StepView::history, historySlot).
TUMBLE_HD_INLINE Vec3f& historyOf(const StepView& v, std::uint32_t e) {
  return v.history[v.historySlot != nullptr ? v.historySlot[e] : e];
}

}  // namespace tumble
