// SPDX-License-Identifier: MIT
// The checkpoint format of docs/checkpoint.md: writer and validating reader.
//
// Design notes
// - Exactness. The state is stored as the pipeline integrates it: positions in the run's local
//   frame (whose origin is stored too, as doubles), the simulated time as the double the
//   pipeline accumulated. Loading it back gives the pipeline the same bits it had.
// - Identity. Two fingerprints tie a checkpoint to its run: the static bodies and particles
//   (a different scene cannot be resumed) and the physical parameters (a different dt or
//   stiffness may be resumed, with a warning: the continuation is then another run).
// - Safety. Written to a temporary next to `path` and renamed (OutputFile; atomic on POSIX); read as untrusted input, with
//   every size checked against the file before anything is allocated, FNV-1a checksums over the
//   header and the state, and finiteness checks. Encoding and checks: binary_io.hpp.
#include "tumble/checkpoint.hpp"

#include "tumble/output_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/mesh.hpp"

namespace tumble {
namespace {

using namespace tumble::detail;  // binary_io.hpp

constexpr char kMagic[8] = {'T', 'U', 'M', 'B', 'L', 'E', 'C', 'K'};
constexpr std::uint32_t kFlagGroundSprings = 1u;
// Periodic boundaries: the image counters of x, of y follow the histories (optional blocks).
constexpr std::uint32_t kFlagImageX = 2u, kFlagImageY = 4u;
constexpr std::uint32_t kKnownFlags = kFlagGroundSprings | kFlagImageX | kFlagImageY;
constexpr std::uint64_t kHeaderBytes = 92;  // through the header checksum (version 1; 96 in version 2)
constexpr std::uint64_t kOffVersion = 8, kOffFlags = 12, kOffNumParticles = 16, kOffNumBodies = 20;

/// 64-bit FNV-1a over the bytes of values.
class Fingerprint {
 public:
  template <class T>
  void add(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    for (std::size_t k = 0; k < sizeof v; ++k) {
      m_h ^= p[k];
      m_h *= 1099511628211ull;
    }
  }
  template <class T>
  void addAll(const std::vector<T>& v) {
    add(std::uint64_t(v.size()));
    for (const T& x : v) add(x);
  }
  std::uint64_t value() const { return m_h; }

 private:
  std::uint64_t m_h = 1469598103934665603ull;
};

std::vector<const std::vector<float>*> bodyColumns(const BodyState& s) {
  return {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz};
}
std::vector<std::vector<float>*> bodyColumns(BodyState& s) {
  return {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz};
}
const char* const kColumnNames[13] = {"px", "py", "pz", "vx", "vy", "vz", "qw",
                                      "qx", "qy", "qz", "lx", "ly", "lz"};

// The histories (ContactHistory: i, j; MeshContactHistory: particle, triangle) are records of
// two u32 indices a, b and ξ as 3 × f32, sorted by (a, b).
template <class H>
void writeHistories(Encoder& e, const std::vector<H>& hs, std::uint32_t H::*a, std::uint32_t H::*b) {
  for (const H& h : hs) {
    e.u32(h.*a);
    e.u32(h.*b);
    e.f32(h.x);
    e.f32(h.y);
    e.f32(h.z);
  }
}

// Reads n of them, refusing one that does not follow the previous in (a, b) order (or, for
// pairs, whose a is not below its b), or that is not finite; `what` and `order` name them.
template <class H>
void readHistories(Decoder& d, const InFile& in, std::size_t n, std::uint32_t H::*a, std::uint32_t H::*b, bool pairs,
                   const std::string& what, const std::string& order, std::vector<H>& out) {
  out.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t at = d.fileOffset();
    H& h = out[k];
    h.*a = d.u32();
    h.*b = d.u32();
    h.x = d.f32();
    h.y = d.f32();
    h.z = d.f32();
    const H* p = k > 0 ? &out[k - 1] : nullptr;
    if ((pairs && !(h.*a < h.*b)) || (p && !(p->*a < h.*a || (p->*a == h.*a && p->*b < h.*b))))
      in.fail(at, what + " " + std::to_string(k) + ": expected " + order);
    if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z))
      in.fail(at, what + " " + std::to_string(k) + " is not finite");
  }
}

}  // namespace

std::uint64_t sceneFingerprint(const World& w) {
  Fingerprint f;
  f.add(w.numBodies());
  f.add(w.numParticles());
  for (const auto* c : {&w.radius, &w.mass, &w.elasticity, &w.ux, &w.uy, &w.uz, &w.bodyMass}) f.addAll(*c);
  f.addAll(w.body);
  if (!w.material.empty()) f.addAll(w.material);  // hertz-mindlin only: other scenes keep their fingerprints
  for (const Sym3f& i : w.invInertia) f.add(i);
  f.add(static_cast<std::uint32_t>(w.params.integrator.rotation));
  const PeriodicParams& p = w.params.periodic;
  if (p.any())  // the frame and the image counters depend on the box; scenes without one keep their fingerprints
    for (int a = 0; a < 2; ++a) {
      f.add(p.on[a]);
      f.add(p.lo[a]);
      f.add(p.hi[a]);
    }
  return f.value();
}

std::uint64_t physicsFingerprint(const Scene& s) {
  Fingerprint f;
  f.add(s.dt);
  f.add(s.gravity);
  f.add(s.contact.stiffness);
  f.add(s.contact.damping);
  f.add(s.contact.shear);
  if (s.contact.law != ContactLaw::Report) {  // the report's law keeps its fingerprints
    f.add(static_cast<std::uint32_t>(s.contact.law));
    f.add(s.contact.tangentialStiffness);
    f.add(s.contact.gammaN);
    f.add(s.contact.gammaT);
    f.add(s.contact.friction);
    f.add(s.contact.rollingFriction);
    f.add(s.groundRollingFriction());
  }
  if (s.contact.usesMaterials()) {  // the materials (the particles' own are in sceneFingerprint)
    f.add(static_cast<std::uint32_t>(s.materials.size()));
    for (const MaterialDef& m : s.materials)
      for (float v : {m.youngsModulus, m.poissonRatio, m.restitution, m.friction, m.rollingFriction}) f.add(v);
    f.add(static_cast<std::uint32_t>(s.ground.material + 1));
    f.add(s.ground.frictionOverride);
    f.add(s.ground.rollingFriction);
  }
  if (s.contact.cohesion != Cohesion::None) {  // scenes without cohesion keep their fingerprints
    f.add(static_cast<std::uint32_t>(s.contact.cohesion));
    f.add(s.contact.cohesionValue);
    for (const MaterialDef& m : s.materials) f.add(m.cohesion);
    f.add(s.ground.cohesion);
    for (const WallDef& w : s.walls) f.add(w.contact.cohesion);
  }
  f.add(s.ground.enabled);
  f.add(s.ground.height);
  f.add(s.ground.stiffness);
  f.add(s.ground.friction);
  f.add(s.ground.tangentialStiffness);
  f.add(s.pulls.x);
  f.add(s.pulls.y);
  f.add(s.pulls.swirl);
  f.add(static_cast<std::uint32_t>(s.integrator.rotation));
  if (!s.walls.empty()) {  // scenes without walls keep their fingerprints
    f.add(static_cast<std::uint32_t>(s.walls.size()));
    for (const WallDef& w : s.walls) {
      f.add(w.point);
      f.add(w.normal);
      for (float v : {w.contact.stiffness, w.contact.friction, w.contact.tangentialStiffness, w.contact.rollingFriction,
                      w.contact.frictionOverride})
        f.add(v);
      f.add(static_cast<std::uint32_t>(w.contact.material + 1));
      if (w.shape != WallDef::Shape::Plane || w.moves()) {  // plane walls that do not move keep their fingerprints
        f.add(static_cast<std::uint32_t>(w.shape));
        for (float v : {w.length, w.radius0, w.radius1, w.angularVelocity}) f.add(v);
        f.add(w.velocity);
        f.add(w.start);
        f.add(w.stop);
      }
      if (w.shape == WallDef::Shape::Mesh && w.mesh) {  // its placement and its triangles
        f.add(w.scale);
        f.add(w.orientation);
        f.addAll(w.mesh->vertices);
        f.addAll(w.mesh->triangles);
        if (w.moves()) {  // its rotation (meshes that stand still keep their fingerprints)
          f.add(w.meshAngularVelocity);
          f.add(w.meshPivot());
        }
      }
    }
  }
  if (!s.pours.empty()) {  // scenes without pours keep their fingerprints
    for (const PourDef& p : s.pours) {
      f.add(static_cast<std::uint32_t>(p.region.kind));
      for (const Vec3f& v : {p.region.min, p.region.max, p.region.point, p.region.axis}) f.add(v);
      f.add(p.region.radius);
      f.add(static_cast<std::uint64_t>(p.region.wall));
      for (double v : {p.start, p.rate, p.interval}) f.add(v);
      for (std::uint64_t v : {p.count, p.seed, p.attempts}) f.add(v);
    }
    for (const PourBody& b : s.pourBodies) {  // what each body brings in
      f.add(b.body.shape);
      f.add(b.body.velocity);
      f.add(b.body.orientation);
      f.add(b.body.angularVelocity);
    }
  }
  return f.value();
}

Checkpoint Checkpoint::of(const World& world, const Pipeline& pipeline) {
  Checkpoint c;
  c.step = pipeline.stepCount();
  c.time = pipeline.time();
  c.pulls = pipeline.pulls();
  c.frame = pipeline.frame();
  pipeline.readLocalState(c.state);
  c.sceneFingerprint = tumble::sceneFingerprint(world);
  c.physicsFingerprint = tumble::physicsFingerprint(world.params);
  return c;
}

void Checkpoint::write(const std::string& path) const {
  const std::size_t nb = state.size(), np = state.groundSpringX.size();
  if (state.groundSpringY.size() != np) throw Error("checkpoint " + path + ": ground spring columns differ in length");
  for (const auto* c : bodyColumns(state))
    if (c->size() != nb) throw Error("checkpoint " + path + ": body columns differ in length");
  // read() refuses non-finite values, so a diverged state (a run with --no-guard) is not
  // written: the file at `path` stays as it was.
  const auto cols = bodyColumns(state);
  for (std::size_t k = 0; k < nb; ++k)
    for (int c = 0; c < 13; ++c)
      if (!std::isfinite((*cols[c])[k]))
        throw SimulationError("checkpoint " + path + " not written: body " + std::to_string(k) + "'s " +
                                  kColumnNames[c] + " is not finite (the run diverged; run it with the guard, "
                                  "without --no-guard, to see where)");
  if (state.contacts.size() > 0xFFFFFFFFu || state.meshContacts.size() > 0xFFFFFFFFu)
    throw Error("checkpoint " + path + ": too many contact histories");
  for (const MeshContactHistory& h : state.meshContacts)
    if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z))
      throw SimulationError("checkpoint " + path + " not written: the mesh spring of particle " + std::to_string(h.particle) +
                                " on triangle " + std::to_string(h.triangle) + " is not finite (the run diverged)",
                            static_cast<std::int64_t>(h.particle));
  for (const auto* c : {&state.imageX, &state.imageY})
    if (!c->empty() && c->size() != nb) throw Error("checkpoint " + path + ": image counters differ in length");
  for (const ContactHistory& h : state.contacts)
    if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z))
      throw SimulationError("checkpoint " + path + " not written: the contact history of particles " +
                            std::to_string(h.i) + " and " + std::to_string(h.j) + " is not finite (the run diverged)",
                            static_cast<std::int64_t>(h.i));
  for (std::size_t i = 0; i < np; ++i)
    if (!std::isfinite(state.groundSpringX[i]) || !std::isfinite(state.groundSpringY[i]))
      throw SimulationError("checkpoint " + path + " not written: the plane spring " + std::to_string(i) +
                            " (plane-major) is not finite (the run diverged)",
                            static_cast<std::int64_t>(i));
  std::vector<std::uint8_t> buf;
  Encoder e(buf);
  // Version 1 unless there are mesh springs: the checkpoints of scenes without them keep their bytes.
  const std::uint32_t version = state.meshContacts.empty() ? 1u : kCheckpointVersion;
  e.bytes(kMagic, 8);
  e.u32(version);
  e.u32((np > 0 ? kFlagGroundSprings : 0u) | (state.imageX.empty() ? 0u : kFlagImageX) |
        (state.imageY.empty() ? 0u : kFlagImageY));
  e.u32(static_cast<std::uint32_t>(np));
  e.u32(static_cast<std::uint32_t>(nb));
  e.u64(step);
  e.f64(time);
  e.u32(pulls);
  e.u32(static_cast<std::uint32_t>(state.contacts.size()));
  e.f64(frame.x);
  e.f64(frame.y);
  e.f64(frame.z);
  e.u64(sceneFingerprint);
  e.u64(physicsFingerprint);
  if (version >= 2) e.u32(static_cast<std::uint32_t>(state.meshContacts.size()));
  e.u32(fnv1a(buf.data(), buf.size()));
  const std::size_t stateStart = buf.size();
  for (const auto* c : bodyColumns(state)) e.f32s(*c, nb);
  e.f32s(state.groundSpringX, np);
  e.f32s(state.groundSpringY, np);
  writeHistories(e, state.contacts, &ContactHistory::i, &ContactHistory::j);
  writeHistories(e, state.meshContacts, &MeshContactHistory::particle, &MeshContactHistory::triangle);
  for (const auto* c : {&state.imageX, &state.imageY})
    for (std::int32_t n : *c) e.u32(static_cast<std::uint32_t>(n));
  e.u32(fnv1a(buf.data() + stateStart, buf.size() - stateStart));

  OutputFile out(path);  // a temporary renamed into place (output_file.hpp)
  if (std::fwrite(buf.data(), 1, buf.size(), out.file()) != buf.size())
    throw Error("cannot write checkpoint " + path + ": " + errnoText(errno));  // the temporary is removed
  out.commit();
}

Checkpoint Checkpoint::read(const std::string& path) {
  InFile in(path, "checkpoint");
  std::vector<std::uint8_t> buf;
  in.read(buf, std::min<std::uint64_t>(in.size(), kHeaderBytes), "header");
  if (!buf.empty() && std::memcmp(buf.data(), kMagic, std::min<std::size_t>(buf.size(), 8)) != 0)
    in.fail(0, "not a tumble checkpoint (bad magic; expected \"TUMBLECK\")");
  if (buf.size() < kOffFlags) in.fail(buf.size(), "header truncated: the file is only " + std::to_string(in.size()) + " bytes");
  const std::uint32_t version = getU32(buf.data() + kOffVersion);
  if (version < 1 || version > kCheckpointVersion)
    in.fail(kOffVersion, "unsupported checkpoint version " + std::to_string(version) +
                             " (this build of tumble reads versions 1 to " + std::to_string(kCheckpointVersion) + ")");
  const std::uint64_t headerBytes = version == 1 ? kHeaderBytes : kHeaderBytes + 4;  // version 2: + M
  if (buf.size() < kHeaderBytes) in.fail(buf.size(), "header truncated: the file is only " + std::to_string(in.size()) + " bytes");
  if (headerBytes > kHeaderBytes) {  // appends its last field
    in.read(buf, std::min<std::uint64_t>(in.remaining(), headerBytes - kHeaderBytes), "header");
    if (buf.size() < headerBytes) in.fail(buf.size(), "header truncated: the file is only " + std::to_string(in.size()) + " bytes");
  }
  checkChecksum(in, buf, 0, static_cast<std::size_t>(headerBytes - 4), headerBytes - 4, "header");
  Decoder d(in, buf, 0, kOffFlags);
  const std::uint32_t flags = d.u32();
  if ((flags & ~kKnownFlags) != 0) in.fail(kOffFlags, "unknown flag bits " + hex32(flags & ~kKnownFlags));
  const std::uint64_t imageColumns = ((flags & kFlagImageX) ? 1 : 0) + ((flags & kFlagImageY) ? 1 : 0);
  const std::uint64_t np = d.u32(), nb = d.u32();
  if (((flags & kFlagGroundSprings) != 0) != (np > 0))
    in.fail(kOffNumParticles, "the plane-spring flag does not match the plane-spring count " + std::to_string(np));
  Checkpoint c;
  c.step = d.u64();
  const std::uint64_t timeAt = d.fileOffset();
  c.time = d.f64();
  if (!std::isfinite(c.time) || c.time < 0.0) in.fail(timeAt, "the simulated time is not a finite number >= 0");
  c.pulls = d.u32();
  if (c.pulls > 7u) in.fail(timeAt + 8, "unknown pull bits " + hex32(c.pulls));
  const std::uint64_t nc = d.u32();  // contact histories
  const std::uint64_t frameAt = d.fileOffset();
  c.frame.x = d.f64();
  c.frame.y = d.f64();
  c.frame.z = d.f64();
  if (!std::isfinite(c.frame.x) || !std::isfinite(c.frame.y) || !std::isfinite(c.frame.z))
    in.fail(frameAt, "the frame origin is not finite");
  c.sceneFingerprint = d.u64();
  c.physicsFingerprint = d.u64();
  const std::uint64_t nm = version >= 2 ? d.u32() : 0;  // mesh springs
  if (version >= 2 && nm == 0) in.fail(kHeaderBytes - 4, "a version 2 checkpoint holds mesh springs (its count is 0: a version 1 file has none)");
  if (nb == 0) in.fail(kOffNumBodies, "the checkpoint holds no bodies");

  // The state block: its size follows from the counts; checked before anything is read.
  const std::uint64_t stateAt = in.offset();
  const std::uint64_t stateBytes = 4 * (13 * nb + 2 * np) + 20 * nc + 20 * nm + 4 * imageColumns * nb;
  if (stateBytes + 4 != in.remaining())
    in.fail(stateAt, "state block of " + std::to_string(nb) + " bodies, " + std::to_string(np) + " plane springs, " +
                         std::to_string(nc) + " contact histories, " + std::to_string(nm) + " mesh springs and " +
                         std::to_string(imageColumns) + " columns of image counters needs " +
                         std::to_string(stateBytes + 4) + " bytes, the file has " + std::to_string(in.remaining()) +
                         " left");
  buf.clear();
  in.read(buf, stateBytes + 4, "state");
  checkChecksum(in, buf, 0, static_cast<std::size_t>(stateBytes), stateAt + stateBytes, "state");
  Decoder sd(in, buf, stateAt);
  auto cols = bodyColumns(c.state);
  for (int k = 0; k < 13; ++k) sd.finiteColumn(*cols[k], static_cast<std::size_t>(nb), kColumnNames[k]);
  // Values a run can have, as the scene reader checks them: positions in the world (the frame's
  // origin plus the local one) within ±2^60 m (exact_range.hpp), and unit orientations (the pipelines
  // keep them to a few float roundings; a crafted zero or huge one is refused).
  const auto entry = [&](int column, std::uint64_t body) { return stateAt + 4 * (std::uint64_t(column) * nb + body); };
  const double frameAxis[3] = {c.frame.x, c.frame.y, c.frame.z};
  for (std::uint64_t b = 0; b < nb; ++b) {
    for (int a = 0; a < 3; ++a) {
      const double x = frameAxis[a] + double((*cols[a])[b]);
      if (!withinExactRange(x))
        in.fail(entry(a, b), "body " + std::to_string(b) + "'s position " + "xyz"[a] + " (the frame origin's " +
                                 std::to_string(frameAxis[a]) + " plus " + kColumnNames[a] +
                                 ") is beyond +-2^60 m, the range whose contacts single precision decides right");
    }
    const double w = c.state.qw[b], x = c.state.qx[b], y = c.state.qy[b], z = c.state.qz[b];
    const double length = std::sqrt(w * w + x * x + y * y + z * z);
    if (!(std::fabs(length - 1.0) <= kUnitQuaternionTolerance))
      in.fail(entry(6, b), "body " + std::to_string(b) + "'s orientation is not a unit quaternion (its length is " +
                               std::to_string(length) + ")");
  }
  sd.finiteColumn(c.state.groundSpringX, static_cast<std::size_t>(np), "groundSpringX");
  sd.finiteColumn(c.state.groundSpringY, static_cast<std::size_t>(np), "groundSpringY");
  readHistories(sd, in, static_cast<std::size_t>(nc), &ContactHistory::i, &ContactHistory::j, true, "contact history",
                "pairs i < j sorted by (i, j)", c.state.contacts);
  readHistories(sd, in, static_cast<std::size_t>(nm), &MeshContactHistory::particle, &MeshContactHistory::triangle, false,
                "mesh spring", "(particle, triangle) sorted and each once", c.state.meshContacts);
  for (const auto& [flag, column] : {std::pair<std::uint32_t, std::vector<std::int32_t>*>{kFlagImageX, &c.state.imageX},
                                     {kFlagImageY, &c.state.imageY}})
    if (flags & flag) {
      column->resize(static_cast<std::size_t>(nb));
      for (std::int32_t& n : *column) n = static_cast<std::int32_t>(sd.u32());
    }
  return c;
}

World Checkpoint::resume(const World& world, std::string* warning) const {
  if (state.size() != world.numBodies())
    throw Error("the checkpoint holds " + std::to_string(state.size()) + " bodies, the scene has " +
                std::to_string(world.numBodies()) + ": it was written by a run of another scene");
  const std::size_t planes = world.params.planes().size();
  if (!state.groundSpringX.empty() && state.groundSpringX.size() != world.numParticles() * planes)
    throw Error("the checkpoint holds " + std::to_string(state.groundSpringX.size()) + " plane springs, the scene has " +
                std::to_string(world.numParticles()) + " particles on " + std::to_string(planes) +
                " planes (the ground and the walls): it was written by a run of another scene");
  for (const ContactHistory& h : state.contacts)  // sorted by (i, j): the largest j may be anywhere
    if (h.j >= world.numParticles())
      throw Error("the checkpoint's contact histories name particle " + std::to_string(h.j) + ", the scene has " +
                  std::to_string(world.numParticles()) + ": it was written by a run of another scene");
  for (int a = 0; a < 2; ++a)
    if ((a == 0 ? state.imageX : state.imageY).empty() == world.params.periodic.on[a])
      throw Error(std::string("the checkpoint ") + (world.params.periodic.on[a] ? "has no" : "has") +
                  " image counters on " + "xy"[a] + ", and the scene " + (world.params.periodic.on[a] ? "is" : "is not") +
                  " periodic there ([periodic]): it was written by a run of another scene");
  const std::uint32_t triangles = meshTriangleCount(world.params);
  for (const MeshContactHistory& h : state.meshContacts)
    if (h.particle >= world.numParticles() || h.triangle >= triangles)
      throw Error("the checkpoint's mesh springs name particle " + std::to_string(h.particle) + " and triangle " +
                  std::to_string(h.triangle) + ", the scene has " + std::to_string(world.numParticles()) +
                  " particles and " + std::to_string(triangles) + " mesh triangles: it was written by a run of another scene");
  if (sceneFingerprint != tumble::sceneFingerprint(world))
    throw Error("the checkpoint was written by a run of another scene (the same counts, but other shapes, "
                "masses, radii, materials or rotation scheme)");
  if (warning) {
    warning->clear();
    if (physicsFingerprint != tumble::physicsFingerprint(world.params))
      *warning = "the scene's physical parameters (dt, contact, ground, walls, gravity, pulls or integrator) differ from "
                 "those the checkpoint was written with: the continuation is not the uninterrupted run";
  }
  World w = world;
  w.state = state;
  w.step = step;
  w.time = time;
  w.frame = frame;
  w.params.pulls.active = pulls;
  return w;
}

}  // namespace tumble
