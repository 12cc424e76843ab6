// SPDX-License-Identifier: MIT
// The estimate of a run's peak memory (tumble/run_memory.hpp), buffer by buffer.
//
// What it counts: everything `tumble run` holds once the first rebuild of the contact list has
// sized the pipeline's scratch, which is where its peak is (massif, heaptrack: the load's copies
// are all still held then, the guard's first detection has been given back). Each line below
// names its buffers: the scene's bodies (the scene read, Run's Pouring and its World), the two
// worlds (Run's, and the CpuPipeline's copy in its integration frame), the pipeline's rows and
// its grow-only scratch (cpu/src/cpu_pipeline_impl.hpp), the detection's (cpu::detail::Broadphase,
// cpu/include/tumble/cpu/broadphase.hpp), the candidate and near lists, the histories, the
// guard's copies (RunGuard, tumble/guard.hpp) and Run's state for the outputs (--state-out,
// recordings, checkpoints).
// What it leaves out: the program itself and its libraries (some 11 MB for `tumble run`), the
// threads' stacks, the ghosts of periodic boundaries (the particles within reach of a periodic
// side), the mesh lists of the particles near a mesh wall, recording buffers of one frame.
// Scratch that `grow()` (cpu/src/grow.hpp) sizes holds 25 % more rows than asked: kGrow.
#include "tumble/run_memory.hpp"

#include <algorithm>
#include <limits>

#include "tumble/kernels/contact_sums.hpp"
#include "tumble/kernels/records.hpp"
#include "tumble/mesh.hpp"
#include "tumble/soa.hpp"
#include "tumble/world.hpp"

namespace tumble {

namespace {

constexpr double kGrow = 1.25;  // cpu/src/grow.hpp: n + n/4 rows

constexpr double kU32 = sizeof(std::uint32_t), kF32 = sizeof(float), kU64 = sizeof(std::uint64_t);

}  // namespace

RunSize runSizeOf(const Scene& scene, std::uint64_t bodies, std::uint64_t pouredBodies, std::uint64_t particles) {
  RunSize s;
  s.bodies = bodies;
  s.pouredBodies = pouredBodies;
  s.particles = particles;
  s.planes = scene.planes().size();
  s.meshTriangles = meshTriangleCount(scene);
  s.history = scene.contact.hasHistory();
  s.materialColumn = scene.contact.usesMaterials();
  s.pipelineMaterials = s.materialColumn && scene.materials.size() > 1;
  s.periodic = scene.periodic.any();
  float r = 0.0f;
  for (const ShapeDef& shape : scene.shapes)
    for (const SphereDef& sphere : shape.spheres) r = std::max(r, sphere.radius);
  // The detection's cells are columns of side m across the sweep axis; a sphere of (grown)
  // radius r covers (1 + 2r/m)² of them on average. Automatic cells are 6 radii wide: 16/9.
  if (scene.broadphase.cellSize > 0.0f) {
    const double across = 1.0 + 2.0 * double(r) / double(scene.broadphase.cellSize);
    s.recordsPerParticle = std::max(16.0 / 9.0, across * across);
  }
  if (scene.broadphase.skin > 0.0f && r > 0.0f) {  // a given skin (negative: the automatic 0.5 r)
    const double shell = (2.0 * double(r) + double(scene.broadphase.skin)) / (2.5 * double(r));
    s.pairsFactor = std::max(1.0, shell * shell * shell);
  }
  return s;
}

std::vector<MemoryItem> runMemoryItems(const RunSize& s) {
  const double n = double(s.particles), nb = double(s.allBodies());
  // Plane 0's damping lives in the own rows (OwnRow::groundDamping), the others' in columns.
  const double planes = double(s.planes), walls = s.planes > 0 ? double(s.planes - 1) : 0.0;
  // Each pair found once by the sweep; at most every pair of particles (a skin beyond the scene).
  const double pairs = std::min(kCandidatePairsPerParticle * s.pairsFactor, std::max(0.0, 0.5 * (n - 1.0))) * n;
  const double entries = 2.0 * pairs;                   // the candidate list holds both directions
  const double contacts = kContactsPerParticle * n;
  const double records = s.recordsPerParticle * n;
  // The skin test's reference per body where bodies hold two particles or more on average
  // (CpuPipeline::load, m_perBody), else per particle.
  const bool perBody = n >= 2.0 * nb;
  std::vector<MemoryItem> v;
  const auto add = [&v](const char* what, double count, double bytes) {
    if (count > 0.0 && bytes > 0.0) v.push_back(MemoryItem{what, count, bytes});
  };

  // The scene's bodies: the scene read (held by the caller), Run's Pouring copy, and World::fromScene's
  // copy of the scene, whose bodies it clears but whose capacity stays.
  add("BodyDef of the scene, Pouring's copy, World::params (capacity)", double(s.bodies), 3.0 * sizeof(BodyDef));
  // A pour's bodies stay in the parameters of both worlds too (Run's, the pipeline's).
  add("PourBody of the scene, Pouring's copy, both worlds' params", double(s.pouredBodies), 4.0 * sizeof(PourBody));

  // The two worlds: Run's (World::fromScene) and the pipeline's copy in its integration frame
  // (localWorld(), toLocal()).
  add("World particle table ×2: radius, mass, elasticity, groundDamping, ux, uy, uz, body", n, 2.0 * (7 * kF32 + kU32));
  if (s.materialColumn) add("World::material ×2 (hertz-mindlin)", n, 2.0 * sizeof(std::uint16_t));
  add("World::planeDamping ×2: a float per plane but the first and particle", n * walls, 2.0 * kF32);
  add("World body table ×2: bodyMass, invMass, first, numParticlesOf, invInertia, inertia, bodyToShape", nb,
      2.0 * (2 * kF32 + 2 * kU32 + 2 * sizeof(Sym3f) + sizeof(Quatf)));
  // BodyState: X, V, Q, L (13 floats) per body, in the two worlds, the guard's copy
  // (readLocalState each check) and Run's (--state-out, recordings, checkpoints).
  add("BodyState ×4: the worlds', the guard's, Run's (13 floats a body)", nb, 4.0 * 13 * kF32);
  // The plane springs (groundSpringX, groundSpringY: a float each per plane and particle) exist
  // in the states the pipeline writes: its world's (localWorld()), the guard's and Run's.
  add("BodyState plane springs ×3: two floats per plane and particle", n * planes, 3.0 * 2 * kF32);
  if (s.periodic) add("BodyState::imageX, imageY ×4 (periodic)", nb, 4.0 * 2 * sizeof(std::int32_t));

  // The pipeline's rows (CpuPipeline), in pairs where reorder() renumbers into a second buffer
  // and swaps: m_bodies and m_bodiesNext, m_bodyStatic and m_bodyStaticTmp, and so on.
  add("CpuPipeline m_bodies, m_bodiesNext (BodyRow)", nb, 2.0 * sizeof(BodyRow));
  add("CpuPipeline m_bodyStatic and its reorder copy (BodyStatic)", nb, 2.0 * sizeof(BodyStatic));
  add("CpuPipeline m_own and its reorder copy (OwnRow)", n, 2.0 * sizeof(OwnRow));
  add("CpuPipeline m_radius, m_mass, m_orig, m_bodyOf and their reorder copies", n, 2.0 * (2 * kF32 + 2 * kU32));
  if (s.pipelineMaterials) add("CpuPipeline m_material and its reorder copy", n, 2.0 * sizeof(std::uint16_t));
  add("CpuPipeline m_gtx, m_gty and their reorder copies: per plane and particle", n * planes, 2.0 * 2 * kF32);
  add("CpuPipeline m_planeDamping and its reorder copy: per plane but the first and particle", n * walls, 2.0 * kF32);
  add("CpuPipeline m_pos[2], m_rebuildPos (PosRow)", n, 3.0 * sizeof(PosRow));
  if (perBody)
    add("CpuPipeline m_bodyRef: the skin test's reference per body (BodyRef)", nb, double(sizeof(BodyRef)));
  else
    add("CpuPipeline m_buildPos: the skin test's reference per particle (PosRow)", n, double(sizeof(PosRow)));
  // Offsets of the per-particle lists (n + 1 each): the candidate list, the mesh list and the
  // mesh springs kept across a rebuild; the near list's; the contact histories kept across a
  // rebuild with their count (grown) under the laws with history.
  add("CpuPipeline m_candOffsets, m_meshOffsets, m_meshKeep.offsets, m_nearOffsets, m_touching", n, 4 * kU32 + 1);
  if (s.history) add("CpuPipeline m_keep.offsets, m_keep.count (grown)", n, kU32 + kGrow * kU32);
  // Grow-only scratch: the detection's input (positions and grown radii), the counts of every
  // scan; per body the reordering's Morton keys, values, sorted keys, permutation and new first
  // particles, and its radix sort's temp (the keys and values again, and about a byte a body
  // of block histograms).
  add("CpuPipeline m_bx, m_by, m_bz, m_br, m_count (grown)", n, kGrow * (4 * kF32 + kU32));
  add("CpuPipeline m_mKeys, m_mVals, m_mSortedKeys, m_perm, m_first, m_temp (grown)", nb, kGrow * (5 * kU32 + 2 * kU32 + 1));

  // The detection (Broadphase, kept between rebuilds; grown). Per particle: its record range,
  // counts and backward-list offsets, and its ParticleRow.
  add("Broadphase recFirst, m_counts, backOffsets, m_prow (ParticleRow)", n, kGrow * (3 * kU32 + sizeof(ParticleRow)));
  // Per cell record: the 64-bit keys unsorted and sorted; the values, record → particle,
  // unsorted → sorted, the sorted particle and body, the neighbour counts and offsets; the
  // sorted columns x, y, z, r, the projected z, and the cell coordinates a0, b0.
  add("Broadphase m_keys, m_sortedKeys, 8 uint32 and 7 float/int32 columns per record", records,
      kGrow * (2 * kU64 + 8 * kU32 + 5 * kF32 + 2 * sizeof(std::int32_t)));
  // Per candidate pair (found once): the forward list, its owners, the transpose's keys and the
  // backward list; the sweep's per-chunk hit buffers (push_back: about half again as many).
  add("Broadphase nbr, m_owner, m_backKeys, back (grown) and the sweep's chunk buffers", pairs,
      kGrow * 4 * kU32 + 1.5 * kU32);
  // The radix sorts' temp (the larger sort: records by cell, or the transpose of the pairs),
  // keys and values again plus about a byte per element of block histograms.
  add("Broadphase m_temp: the larger radix sort's keys, values and histograms (grown)", 1.0,
      kGrow * std::max(records * (kU64 + kU32 + 1), pairs * (2 * kU32 + 1)));

  // The candidate list (both directions) and its sort keys.
  add("CpuPipeline m_cand, m_candKey (grown): per candidate-list entry", entries, kU32 + kGrow * kU32);
  // The near list, first at the candidate rows' offsets (grown), then compact with each entry's
  // particle (m_owner); it holds about the touching pairs. Under a law with history each of its
  // entries also has its candidate entry (m_nearSlot, and its room).
  const double nearBytes = s.history ? 2.0 : 1.0;
  add("CpuPipeline m_nearRoom (and m_nearSlotRoom) (grown): per candidate-list entry", entries, nearBytes * kGrow * kU32);
  add("CpuPipeline m_near, m_owner (and m_nearSlot): per near-list entry (both directions of a contact)", 2.0 * contacts,
      (nearBytes + 1.0) * kU32);
  if (s.history) {
    // ξ per candidate-list entry; the histories kept across a rebuild (the non-zero ones: both
    // directions of each contact, key and ξ); the guard's and Run's read-outs (ContactHistory
    // per contact) and readRows()'s scratch (key and ξ per contact, offsets per particle).
    add("CpuPipeline m_hist: ξ per candidate-list entry (Vec3f)", entries, double(sizeof(Vec3f)));
    add("CpuPipeline m_keep.key, m_keep.hist: both directions of each contact", 2.0 * contacts, kU32 + sizeof(Vec3f));
    add("BodyState::contacts ×2 (the guard's, Run's) and readRows() scratch: per contact", contacts,
        2.0 * sizeof(ContactHistory) + kU32 + sizeof(Vec3f));
    add("readRows() offsets", n, kU32);
  }

  // The guard (RunGuard): the particle positions, each body's rounding on two axes, and its
  // contact sums.
  add("RunGuard m_x (3 floats a particle)", n, 3 * kF32);
  add("RunGuard m_err, m_errZ (double), m_contacts (ContactSums)", nb, 2 * sizeof(double) + sizeof(ContactSums));

  if (s.periodic) {
    // The detection's particles and images (x, y, z, r, body; grown), the images' counts and
    // first ghosts; the periodic list's rows before compaction (offsets, and room grown).
    add("PeriodicImages m_x, m_y, m_z, m_r, m_body (grown), m_count, m_ghostFirst", n, kGrow * 5 * kF32 + 2 * kU32);
    add("CpuPipeline m_roomOffsets", n, kU32);
    add("CpuPipeline m_roomCand (grown): per candidate-list entry", entries, kGrow * kU32);
  }

  if (s.meshTriangles > 0) {
    // KernelMesh (kernelMesh(), mesh.cpp), one in the pipeline and one in the guard, each per
    // triangle: its MeshTriangle; its corners (3 uint32, push_back: half again on average) and
    // edges (3); the triangles of each edge (3 entries, 1.5 edge offsets) and of each vertex (3
    // entries, 0.5 vertex offsets: a mesh has about half as many vertices as triangles); its
    // vertices (0.5 Vec3f); its BVH (leaves of 3 or 4 triangles: about 2/3 of a node per
    // triangle, grown by resize: one) and its place in it.
    const double kernelMesh = sizeof(MeshTriangle) + 1.5 * 3 * kU32 + 3 * kU32 + (3 + 1.5) * kU32 +
                              (3 + 0.5) * kU32 + 0.5 * sizeof(Vec3f) + sizeof(MeshBvhNode) + kU32;
    // While the guard builds its copy: each triangle's wall and file index, its normal (double),
    // its edges' keys (3 × 3 uint32) and its centre (double) for the BVH.
    const double building = 2 * kU32 + 3 * sizeof(double) + 9 * kU32 + 3 * sizeof(double);
    // The mesh as read (TriangleMesh: corners, source lines, half a vertex grown by push_back)
    // and the reader's vertex index (an unordered_map node of 32 bytes and a bucket of 8 per
    // vertex), whose pages the process keeps.
    const double read = 3 * kU32 + kU64 + 0.75 * sizeof(Vec3f) + 0.5 * (32 + 8);
    add("KernelMesh ×2 (pipeline, guard), the guard's construction and the mesh as read: per triangle",
        double(s.meshTriangles), 2.0 * kernelMesh + building + read);
  }

  if (s.pouredBodies > 0) {
    // Each pour reloads the pipeline (Run::reload): the world before it and the state now are
    // copied while the pipeline builds its world of the new bodies.
    add("Run::reload's world copies (previous, back): the particle and body tables and states", 1.0,
        2.0 * (n * (7 * kF32 + kU32 + 2 * kF32 * planes) + nb * (2 * kF32 + 2 * kU32 + 2 * sizeof(Sym3f) +
                                                                     sizeof(Quatf) + 13 * kF32)));
  }
  return v;
}

std::uint64_t runMemoryEstimate(const RunSize& size) {
  double total = 0.0;
  for (const MemoryItem& item : runMemoryItems(size)) total += item.count * item.bytes;
  constexpr std::uint64_t kMost = std::numeric_limits<std::uint64_t>::max();
  return total >= 1.8e19 ? kMost : static_cast<std::uint64_t>(total);
}

}  // namespace tumble
