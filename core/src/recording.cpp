// SPDX-License-Identifier: MIT
// The recording format of docs/recording.md: writer and validating reader.
//
// Design notes
// - Byte order. Every value is encoded little-endian with explicit shifts (floats through
//   std::bit_cast), so files are identical on any host and the reader never depends on
//   alignment or on the host's endianness.
// - Crash safety. The writer appends to a temporary next to `path` (OutputFile), unbuffered, so a
//   crashed run leaves a temporary that holds every frame written so far. The header's frame count
//   stays at the sentinel kUnfinished until close() patches it (and the header checksum) and
//   renames the file to `path`. std::rename replaces `path` atomically on POSIX, so `path` is
//   either the previous file or the finished new one, never a torn one. There is no fsync:
//   the guarantee covers a crashed process, not a power loss.
// - Never NaN. writeFrame() checks every value before it encodes anything; a rejected frame
//   leaves the file exactly as it was. The reader checks finiteness again, so a player can
//   trust whatever read() returns.
// - Hostile input. read() treats the file as untrusted: every count is multiplied out in
//   64-bit arithmetic and compared with the bytes left in the file *before* anything is
//   allocated or read, so a corrupt count cannot cause a huge allocation, and every block is
//   covered by a checksum. Decoding runs only on buffers whose size was checked first, and the
//   decoder checks its bounds again anyway.
// - Checksum. FNV-1a, 32 bit, per block (binary_io.hpp, shared with the checkpoint format).
// - Contact forces (version 3, flag bit 3). A block after the debug block: the contacts with
//   their forces, the same set as the debug block's pairs when both are there (one count, so a
//   frame's size is its bodies' and particles' bytes plus a fixed number per contact).
// - Walls (version 2). One block between the particle table and the frames, so the frames keep
//   their fixed size and arithmetic index. The writer records what sceneWallSurfaces() draws
//   from the world's scene and bodiesExtent, both of which a resumed run has too, so a continued
//   recording has the same wall bytes as the uninterrupted one. Version 1 has no block.
#include "tumble/recording.hpp"

#include <unistd.h>

#include <memory>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/wall_geometry.hpp"

namespace tumble {
namespace {

using namespace tumble::detail;  // binary_io.hpp

constexpr char kMagic[8] = {'T', 'U', 'M', 'B', 'L', 'R', 'E', 'C'};
constexpr std::uint64_t kUnfinished = std::numeric_limits<std::uint64_t>::max();
constexpr std::uint32_t kFlagDebug = 1u;
constexpr std::uint32_t kFlagGround = 2u;
constexpr std::uint32_t kFlagGrows = 4u;  // version 2: bodies enter during the run
constexpr std::uint32_t kFlagContactForces = 8u;  // version 3: each frame's contacts with their forces
constexpr std::uint32_t kKnownFlags = kFlagDebug | kFlagGround | kFlagGrows | kFlagContactForces;
constexpr std::uint32_t kMaxNameBytes = 65535;

// Header layout (offsets from the start of the file); L = scene name length.
constexpr std::uint64_t kOffVersion = 8;
constexpr std::uint64_t kOffHeaderBytes = 12;
constexpr std::uint64_t kOffNumParticles = 16;
constexpr std::uint64_t kOffNumBodies = 20;
constexpr std::uint64_t kOffStepsPerFrame = 24;
constexpr std::uint64_t kOffDt = 28;
constexpr std::uint64_t kOffFps = 32;
constexpr std::uint64_t kOffFlags = 36;
constexpr std::uint64_t kOffGroundHeight = 40;
constexpr std::uint64_t kOffGravity = 44;
constexpr std::uint64_t kOffNameLength = 56;
constexpr std::uint64_t kOffName = 60;
constexpr std::uint64_t kFixedHeaderBytes = 72;  // header size without the name: H = 72 + L
static_assert(kOffNumBodies == kOffNumParticles + 4 && kOffName == kOffNameLength + 4 &&
                  kFixedHeaderBytes == kOffName + 8 + 4,
              "header layout of docs/recording.md");

constexpr std::uint64_t kParticleBytes = 28;       // radius, mass, elasticity, body, ux, uy, uz
constexpr std::uint64_t kBodyBytes = 28;           // px, py, pz, qw, qx, qy, qz
constexpr std::uint64_t kFramePrefixBytes = 20;    // step u64, time f64, pulls u32
constexpr std::uint64_t kDebugParticleBytes = 72;  // v and five forces, 3 × f32 each
constexpr std::uint64_t kContactBytes = 8;         // i, j
constexpr std::uint64_t kContactForceBytes = 40;   // i, j, n (3 × f32), fn, tangential (3 × f32), overlap
// The wall block (version 2): W and S, then W records of 60 + 36 T bytes, then a checksum.
constexpr std::uint64_t kWallHeadBytes = 8;        // W, S
constexpr std::uint64_t kWallRecordBytes = 60;     // kind, v, ω, pivot (3 × f32 each), start, stop (f64), T
constexpr std::uint64_t kTriangleBytes = 36;       // 3 corners × 3 f32

const char* const kForceNames[5] = {"repulsion", "damping", "shear", "ground", "friction"};

// A frame's payload bytes: `min` without its contacts (nb bodies, np particles present), and
// `perContact` more per contact (its pair in a debug frame, its record in one with contact forces).
struct FrameSizes {
  std::uint64_t min, perContact;
};
FrameSizes frameSizes(const RecordingInfo& info, std::uint64_t nb, std::uint64_t np) {
  return {kFramePrefixBytes + (info.grows ? 4 : 0) + kBodyBytes * nb +
              (info.debug ? kDebugParticleBytes * np + 4 : 0) + (info.contactForces ? 4 : 0),
          (info.debug ? kContactBytes : 0) + (info.contactForces ? kContactForceBytes : 0)};
}

// Whether a contact force's normal is a unit vector (within 10⁻³ in its square: the capture's is, to
// a few float roundings); the writer writes and the reader takes no other.
bool unitNormal(const ContactForce& x) {
  return std::fabs(x.n.x * x.n.x + x.n.y * x.n.y + x.n.z * x.n.z - 1.0f) < 1e-3f;
}

// Whether frames differ in size (and are indexed by walking their size fields).
bool variableFrames(const RecordingInfo& info) { return info.debug || info.grows || info.contactForces; }

bool allFinite(const std::vector<float>& v, std::size_t count, std::size_t* bad) {
  for (std::size_t k = 0; k < count; ++k) {
    if (!std::isfinite(v[k])) {
      *bad = k;
      return false;
    }
  }
  return true;
}

// The wall block's bytes (docs/recording.md): W, S, the records, the checksum. Throws
// tumble::Error (after `where`) for a wall that cannot be recorded: an unknown kind, a
// non-finite value, stop before start, or a block beyond the format's u32 sizes.
std::vector<std::uint8_t> encodeWalls(const std::vector<WallSurface>& walls, const std::string& where) {
  std::uint64_t bytes = 0;
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const WallSurface& w = walls[k];
    const std::string wall = where + "wall " + std::to_string(k) + " (" + toString(w.kind) + ") ";
    const WallMotion& m = w.motion;
    if (static_cast<std::uint32_t>(w.kind) >= kNumWallKinds) throw Error(wall + "has an unknown kind");
    if (w.triangles.size() % 9 != 0) throw Error(wall + "has a triangle list that is not 9 floats per triangle");
    std::size_t bad = 0;
    const std::vector<float> motion = {m.velocity.x, m.velocity.y, m.velocity.z, m.angularVelocity.x,
                                       m.angularVelocity.y, m.angularVelocity.z, m.pivot.x, m.pivot.y, m.pivot.z};
    if (!allFinite(motion, motion.size(), &bad) || !std::isfinite(m.start) || !(m.stop >= m.start))
      throw Error(wall + "has a non-finite motion, or stops before it starts");
    if (!allFinite(w.triangles, w.triangles.size(), &bad))
      throw Error(wall + "has a non-finite corner in triangle " + std::to_string(bad / 9));
    bytes += kWallRecordBytes + 4 * static_cast<std::uint64_t>(w.triangles.size());
  }
  if (walls.size() > std::numeric_limits<std::uint32_t>::max() || bytes > std::numeric_limits<std::uint32_t>::max() - 16)
    throw Error(where + "the walls' triangles are too many for the format");
  std::vector<std::uint8_t> out;
  out.reserve(static_cast<std::size_t>(bytes) + 12);
  Encoder e(out);
  e.u32(static_cast<std::uint32_t>(walls.size()));
  e.u32(static_cast<std::uint32_t>(bytes));
  for (const WallSurface& w : walls) {
    const WallMotion& m = w.motion;
    e.u32(static_cast<std::uint32_t>(w.kind));
    for (const Vec3f& v : {m.velocity, m.angularVelocity, m.pivot}) {
      e.f32(v.x);
      e.f32(v.y);
      e.f32(v.z);
    }
    e.f64(m.start);
    e.f64(m.stop);
    e.u32(static_cast<std::uint32_t>(w.numTriangles()));
    e.f32s(w.triangles, w.triangles.size());
  }
  e.u32(fnv1a(out.data(), out.size()));
  return out;
}

// Reads the wall block at the file's position into `out` (buf: scratch); the position ends
// after its checksum, where the frames begin.
void readWalls(InFile& in, std::vector<std::uint8_t>& buf, std::vector<WallSurface>& out) {
  const std::uint64_t blockOffset = in.offset();
  if (in.remaining() < kWallHeadBytes + 4)
    in.fail(blockOffset, "wall block truncated: needs at least 12 bytes, only " + std::to_string(in.remaining()) +
                             " left");
  buf.clear();
  in.read(buf, kWallHeadBytes, "wall block");
  const std::uint64_t numWalls = getU32(buf.data()), recordBytes = getU32(buf.data() + 4);
  if (recordBytes + 4 > in.remaining())
    in.fail(blockOffset + 4, "wall block truncated: its " + std::to_string(recordBytes) + " bytes of walls and checksum need " +
                                 std::to_string(recordBytes + 4) + ", only " + std::to_string(in.remaining()) + " left");
  if (numWalls > recordBytes / kWallRecordBytes)
    in.fail(blockOffset, "wall count " + std::to_string(numWalls) + " does not fit the block's " +
                             std::to_string(recordBytes) + " bytes (60 at least per wall)");
  in.read(buf, recordBytes + 4, "wall block");
  checkChecksum(in, buf, 0, static_cast<std::size_t>(kWallHeadBytes + recordBytes),
                blockOffset + kWallHeadBytes + recordBytes, "wall block");
  const std::uint64_t end = blockOffset + kWallHeadBytes + recordBytes;
  Decoder d(in, buf, blockOffset, kWallHeadBytes);
  out.assign(static_cast<std::size_t>(numWalls), WallSurface{});
  for (std::size_t k = 0; k < out.size(); ++k) {
    WallSurface& w = out[k];
    const std::string name = "wall " + std::to_string(k);
    const std::uint64_t at = d.fileOffset();
    if (end - at < kWallRecordBytes)
      in.fail(at, name + " truncated: needs 60 bytes, the block has " + std::to_string(end - at) + " left");
    const std::uint32_t kind = d.u32();
    if (kind >= kNumWallKinds)
      in.fail(at, name + " has unknown kind " + std::to_string(kind) + " (0 plane, 1 cylinder, 2 cone, 3 disk, 4 mesh)");
    w.kind = static_cast<WallKind>(kind);
    for (Vec3f* v : {&w.motion.velocity, &w.motion.angularVelocity, &w.motion.pivot}) {
      const char* what = v == &w.motion.velocity ? " velocity" : v == &w.motion.pivot ? " pivot" : " angular velocity";
      v->x = d.finite(name + what);
      v->y = d.finite(name + what);
      v->z = d.finite(name + what);
    }
    const std::uint64_t timesAt = d.fileOffset();
    w.motion.start = d.f64();
    w.motion.stop = d.f64();
    if (!std::isfinite(w.motion.start) || !(w.motion.stop >= w.motion.start))
      in.fail(timesAt, name + " start and stop must be finite and in order (stop may be infinite: never)");
    const std::uint64_t countAt = d.fileOffset();
    const std::uint64_t numTriangles = d.u32();
    if (numTriangles > (end - d.fileOffset()) / kTriangleBytes)
      in.fail(countAt, name + " has " + std::to_string(numTriangles) + " triangles, the block has room for " +
                           std::to_string((end - d.fileOffset()) / kTriangleBytes));
    d.finiteColumn(w.triangles, static_cast<std::size_t>(9 * numTriangles), name + " triangle corner");
  }
  if (d.fileOffset() != end)
    in.fail(d.fileOffset(), "wall block holds " + std::to_string(end - d.fileOffset()) + " bytes after its last wall");
}

}  // namespace

// ---- RecordingReader -----------------------------------------------------------------------

struct RecordingReader::File {
  InFile in;
  FrameSizes sizes;  // of a frame of all the bodies
  // Where frame k starts: framesOffset + k * frameBytes in a plain recording (all frames have
  // the same size), frameOffsets[k] in one of variableFrames().
  std::uint64_t framesOffset = 0, frameBytes = 0;
  std::vector<std::uint64_t> frameOffsets;
  std::vector<std::uint32_t> firstParticle;  // a recording that grows: of each body, and N
  std::uint64_t frameCountOffset = 0;         // the header's frame count (a u64, then the header's checksum)
  std::uint64_t framesEnd = 0;                // where the whole frames end
  explicit File(const std::string& path) : in(path, "recording") {}
};

RecordingReader::RecordingReader(const std::string& path, TornEnd tornEnd) : m_file(std::make_unique<File>(path)) {
  InFile& in = m_file->in;
  Recording& rec = m_header;
  RecordingInfo& info = rec.info;
  std::vector<std::uint8_t>& buf = m_buffer;
  // Magic, version and header size. A wrong magic is reported before a short file, so any
  // non-recording says so; the version is checked before the checksum, so a newer file gets
  // "unsupported version" rather than "corrupt".
  in.read(buf, std::min<std::uint64_t>(in.size(), kOffNumParticles), "header");
  if (!buf.empty() && std::memcmp(buf.data(), kMagic, std::min<std::size_t>(buf.size(), 8)) != 0) {
    in.fail(0, "not a tumble recording (bad magic; expected \"TUMBLREC\")");
  }
  if (buf.size() < kOffNumParticles) {
    in.fail(buf.size(),
            "header truncated: the file is only " + std::to_string(in.size()) + " bytes");
  }
  info.version = getU32(buf.data() + kOffVersion);
  if (info.version < 1 || info.version > kRecordingVersion) {
    in.fail(kOffVersion, "unsupported recording version " + std::to_string(info.version) +
                             " (this build of tumble reads versions 1 to " + std::to_string(kRecordingVersion) + ")");
  }
  const std::uint64_t headerBytes = getU32(buf.data() + kOffHeaderBytes);
  if (headerBytes < kFixedHeaderBytes || headerBytes > kFixedHeaderBytes + kMaxNameBytes) {
    in.fail(kOffHeaderBytes, "invalid header size " + std::to_string(headerBytes) +
                                 " (must be 72 + scene name length, at most " +
                                 std::to_string(kFixedHeaderBytes + kMaxNameBytes) + ")");
  }
  if (headerBytes > in.size()) {
    in.fail(kOffHeaderBytes, "header truncated: header size " + std::to_string(headerBytes) +
                                 " exceeds the file size " + std::to_string(in.size()));
  }
  in.read(buf, headerBytes - kOffNumParticles, "header");
  checkChecksum(in, buf, 0, headerBytes - 4, headerBytes - 4, "header");

  Decoder hd(in, buf, 0, kOffNumParticles);
  info.numParticles = hd.u32();
  info.numBodies = hd.u32();
  info.stepsPerFrame = hd.u32();
  info.dt = hd.f32();
  info.fps = hd.f32();
  const std::uint32_t flags = hd.u32();
  info.groundHeight = hd.f32();
  info.gravity.x = hd.f32();
  info.gravity.y = hd.f32();
  info.gravity.z = hd.f32();
  const std::uint32_t nameBytes = hd.u32();
  if (nameBytes != headerBytes - kFixedHeaderBytes) {
    in.fail(kOffNameLength, "scene name length " + std::to_string(nameBytes) +
                                " does not match header size " + std::to_string(headerBytes));
  }
  const std::uint8_t* name = hd.take(nameBytes);
  info.sceneName.assign(reinterpret_cast<const char*>(name), nameBytes);
  const std::uint64_t frameCountOffset = hd.fileOffset();
  m_file->frameCountOffset = frameCountOffset;
  const std::uint64_t headerFrameCount = hd.u64();

  if (info.stepsPerFrame == 0) in.fail(kOffStepsPerFrame, "steps per frame is 0");
  if (!std::isfinite(info.dt) || info.dt <= 0.0f) in.fail(kOffDt, "dt is not a positive number");
  if (!std::isfinite(info.fps) || info.fps <= 0.0f) {
    in.fail(kOffFps, "frames per second is not a positive number");
  }
  const std::uint32_t known = info.version < 2   ? kFlagDebug | kFlagGround
                              : info.version < 3 ? kFlagDebug | kFlagGround | kFlagGrows
                                                 : kKnownFlags;
  if ((flags & ~known) != 0) {
    in.fail(kOffFlags, "unknown flag bits " + hex32(flags & ~known) + " for version " + std::to_string(info.version) +
                           " (version 1 defines bit 0 debug, bit 1 ground; version 2 also bit 2 bodies entering; "
                           "version 3 also bit 3 contact forces)");
  }
  info.debug = (flags & kFlagDebug) != 0;
  info.groundEnabled = (flags & kFlagGround) != 0;
  info.grows = (flags & kFlagGrows) != 0;
  info.contactForces = (flags & kFlagContactForces) != 0;
  if (!std::isfinite(info.groundHeight)) in.fail(kOffGroundHeight, "ground height is not finite");
  if (!std::isfinite(info.gravity.x) || !std::isfinite(info.gravity.y) ||
      !std::isfinite(info.gravity.z)) {
    in.fail(kOffGravity, "gravity is not finite");
  }

  // Static particle table: seven column blocks, then a checksum.
  const std::uint64_t numParticles = info.numParticles;
  const std::uint64_t numBodies = info.numBodies;
  const std::uint64_t tableOffset = in.offset();
  const std::uint64_t tableBytes = kParticleBytes * numParticles;
  if (tableBytes + 4 > in.remaining()) {
    in.fail(tableOffset, "particle table truncated: " + std::to_string(numParticles) +
                             " particles need " + std::to_string(tableBytes + 4) + " bytes, only " +
                             std::to_string(in.remaining()) + " left");
  }
  buf.clear();
  in.read(buf, tableBytes + 4, "particle table");
  checkChecksum(in, buf, 0, static_cast<std::size_t>(tableBytes), tableOffset + tableBytes,
                "particle table");
  {
    const std::size_t n = static_cast<std::size_t>(numParticles);
    Decoder td(in, buf, tableOffset);
    td.finiteColumn(rec.radius, n, "radius");
    td.finiteColumn(rec.mass, n, "mass");
    td.finiteColumn(rec.elasticity, n, "elasticity");
    rec.body.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint64_t at = td.fileOffset();
      rec.body[k] = td.u32();
      if (rec.body[k] >= numBodies) {
        in.fail(at, "particle " + std::to_string(k) + " belongs to body " +
                        std::to_string(rec.body[k]) + " but there are " +
                        std::to_string(numBodies) + " bodies");
      }
    }
    td.finiteColumn(rec.ux, n, "ux");
    td.finiteColumn(rec.uy, n, "uy");
    td.finiteColumn(rec.uz, n, "uz");
    if (info.grows) {  // its frames hold a prefix of the bodies: the particles must follow them
      std::vector<std::uint32_t>& first = m_file->firstParticle;
      first.assign(static_cast<std::size_t>(numBodies) + 1, static_cast<std::uint32_t>(n));
      for (std::size_t k = n; k-- > 0;) {
        if (k + 1 < n && rec.body[k] > rec.body[k + 1])
          in.fail(tableOffset + 12 * numParticles + 4 * k, "particle " + std::to_string(k) + " of body " +
                                                               std::to_string(rec.body[k]) + " comes before one of body " +
                                                               std::to_string(rec.body[k + 1]) +
                                                               ": a recording that grows needs the particles in body order");
        first[rec.body[k]] = static_cast<std::uint32_t>(k);
      }
      for (std::size_t b = numBodies; b-- > 0;) first[b] = std::min(first[b], first[b + 1]);
    }
  }

  // Version 2: the walls.
  if (info.version >= 2) readWalls(in, buf, rec.walls);

  // The frame index. Frame k starts with its payload size; the frame is size + 8 bytes.
  const FrameSizes sizes = frameSizes(info, numBodies, numParticles);
  m_file->sizes = sizes;
  // A torn end: refused (with the way out), or where the kept frames end.
  const bool keep = tornEnd == TornEnd::KeepWholeFrames;
  bool cut = false;
  const auto torn = [&](std::uint64_t at, const std::string& problem) {
    if (!keep) in.fail(at, problem + " (tumble repair " + m_file->in.path() + " keeps the whole frames before it)");
    m_torn = "byte " + std::to_string(at) + ": " + problem;
    cut = true;
  };
  const auto truncated = [&](std::uint64_t k, std::uint64_t at, std::uint64_t needs) {
    torn(at, "frame " + std::to_string(k) + " truncated: needs " + std::to_string(needs) + " bytes, only " +
                 std::to_string(in.size() - at) + " left");
  };
  // A finished file cut at a frame's end: its header's count says what is missing.
  const auto countAgrees = [&](std::uint64_t held) {
    if (headerFrameCount != kUnfinished && headerFrameCount != held)
      torn(frameCountOffset, "header says " + std::to_string(headerFrameCount) + " frames but the file holds " +
                                 std::to_string(held));
  };
  const std::uint64_t framesOffset = in.offset();
  if (!variableFrames(info)) {
    const std::uint64_t frameBytes = sizes.min + 8;
    const std::uint64_t whole = (in.size() - framesOffset) / frameBytes;
    const std::uint64_t tail = framesOffset + whole * frameBytes;
    if (tail < in.size()) truncated(whole, tail, in.size() - tail < 4 ? 4 : frameBytes);
    if (!cut) countAgrees(whole);
    m_numFrames = static_cast<std::size_t>(whole);
    m_file->framesOffset = framesOffset;
    m_file->frameBytes = frameBytes;
    m_file->framesEnd = tail;
  } else {
    std::uint64_t at = framesOffset;
    for (std::uint64_t k = 0; at < in.size() && !cut; ++k) {
      if (in.size() - at < 4) {
        truncated(k, at, 4);
        break;
      }
      in.seek(at);
      buf.clear();
      in.read(buf, 4, "frame size");
      const std::uint64_t payloadBytes = getU32(buf.data());
      // (A frame of a recording that grows is sized by its number of bodies: readFrame checks it.)
      if (info.grows && payloadBytes < kFramePrefixBytes + 4)
        torn(at, "frame " + std::to_string(k) + " has payload size " + std::to_string(payloadBytes) +
                     ", less than the " + std::to_string(kFramePrefixBytes + 4) + " bytes before its bodies");
      else if (!info.grows && (payloadBytes < sizes.min || (payloadBytes - sizes.min) % sizes.perContact != 0))
        torn(at, "frame " + std::to_string(k) + " has payload size " + std::to_string(payloadBytes) + ", expected " +
                     std::to_string(sizes.min) + " + " + std::to_string(sizes.perContact) + " per contact");
      else if (payloadBytes + 8 > in.size() - at)
        truncated(k, at, payloadBytes + 8);
      if (cut) break;
      m_file->frameOffsets.push_back(at);
      at += payloadBytes + 8;
    }
    m_numFrames = m_file->frameOffsets.size();
    m_file->framesEnd = at;
    if (!cut) countAgrees(m_numFrames);
  }
}

RecordingReader::~RecordingReader() = default;

void RecordingReader::readFrame(std::size_t k, RecordedFrame& f) {
  if (k >= m_numFrames) {
    throw Error("recording frame " + std::to_string(k) + " requested, the file has " +
                std::to_string(m_numFrames));
  }
  InFile& in = m_file->in;
  const RecordingInfo& info = m_header.info;
  std::vector<std::uint8_t>& buf = m_buffer;
  FrameSizes sizes = m_file->sizes;
  std::uint64_t numParticles = info.numParticles;
  std::size_t nb = info.numBodies;
  const std::string frameName = "frame " + std::to_string(k);
  const std::uint64_t frameOffset =
      variableFrames(info) ? m_file->frameOffsets[k] : m_file->framesOffset + k * m_file->frameBytes;
  in.seek(frameOffset);
  buf.clear();
  in.read(buf, 4, "frame size");
  const std::uint64_t payloadBytes = getU32(buf.data());
  // The index checked a variable frame's size and that every frame fits; a plain frame's size
  // field is checked here (that of a frame of a recording that grows once its size is read).
  if (!variableFrames(info) && payloadBytes != sizes.min) {
    in.fail(frameOffset, frameName + " has payload size " + std::to_string(payloadBytes) +
                             ", expected " + std::to_string(sizes.min));
  }
  const std::uint64_t payloadOffset = in.offset();
  buf.clear();
  in.read(buf, payloadBytes + 4, "frame");
  checkChecksum(in, buf, 0, static_cast<std::size_t>(payloadBytes), payloadOffset + payloadBytes,
                frameName);
  Decoder fd(in, buf, payloadOffset);
  f.step = fd.u64();
  {
    const std::uint64_t at = fd.fileOffset();
    f.time = fd.f64();
    if (!std::isfinite(f.time)) in.fail(at, frameName + " time is not finite");
  }
  f.pulls = fd.u32();
  if (info.grows) {  // the bodies present, then the sizes that follow from them
    const std::uint64_t at = fd.fileOffset();
    const std::uint64_t present = fd.u32();
    if (present > nb)
      in.fail(at, frameName + " holds " + std::to_string(present) + " bodies, the recording " + std::to_string(nb));
    nb = static_cast<std::size_t>(present);
    numParticles = m_file->firstParticle[nb];
    sizes = frameSizes(info, nb, numParticles);
    if (sizes.perContact != 0 ? payloadBytes < sizes.min || (payloadBytes - sizes.min) % sizes.perContact != 0
                              : payloadBytes != sizes.min)
      in.fail(frameOffset, frameName + " has payload size " + std::to_string(payloadBytes) + ", expected " +
                               std::to_string(sizes.min) +
                               (sizes.perContact != 0 ? " + " + std::to_string(sizes.perContact) + " per contact" : "") +
                               " for its " + std::to_string(nb) + " bodies");
  }
  // Every contact block holds the same count (the debug pairs and the contact forces: the same contacts).
  const std::uint64_t numContacts = sizes.perContact != 0 ? (payloadBytes - sizes.min) / sizes.perContact : 0;
  const auto checkCount = [&](const char* block) {
    const std::uint64_t at = fd.fileOffset();
    if (const std::uint32_t count = fd.u32(); count != numContacts)
      in.fail(at, frameName + " " + block + " count " + std::to_string(count) + " does not match its payload size " +
                      std::to_string(payloadBytes) + " (" + std::to_string(numContacts) + " contacts)");
  };
  const std::size_t n3 = 3 * static_cast<std::size_t>(numParticles);
  fd.finiteColumn(f.px, nb, frameName + " px");
  fd.finiteColumn(f.py, nb, frameName + " py");
  fd.finiteColumn(f.pz, nb, frameName + " pz");
  fd.finiteColumn(f.qw, nb, frameName + " qw");
  fd.finiteColumn(f.qx, nb, frameName + " qx");
  fd.finiteColumn(f.qy, nb, frameName + " qy");
  fd.finiteColumn(f.qz, nb, frameName + " qz");
  if (info.debug) {
    fd.finiteColumn(f.debug.v, n3, frameName + " v");
    for (int c = 0; c < 5; ++c) {
      fd.finiteColumn(f.debug.force[c], n3, frameName + " " + kForceNames[c] + " force");
    }
    checkCount("contact");
    f.debug.contacts.resize(static_cast<std::size_t>(numContacts));
    for (Pair& p : f.debug.contacts) {
      const std::uint64_t at = fd.fileOffset();
      p.i = fd.u32();
      p.j = fd.u32();
      if (!(p.i < p.j && p.j < numParticles)) {
        in.fail(at, frameName + " contact (" + std::to_string(p.i) + ", " + std::to_string(p.j) +
                        ") is not a pair i < j < " + std::to_string(numParticles));
      }
    }
  }
  if (info.contactForces) {
    checkCount("contact force");
    std::vector<ContactForce>& cf = f.debug.contactForces;
    cf.resize(static_cast<std::size_t>(numContacts));
    for (std::size_t c = 0; c < cf.size(); ++c) {
      ContactForce& x = cf[c];
      const std::uint64_t at = fd.fileOffset();
      x.i = fd.u32();
      x.j = fd.u32();
      if (!(x.i < x.j && x.j < numParticles) || (c > 0 && !(cf[c - 1] < x)))
        in.fail(at, frameName + " contact force (" + std::to_string(x.i) + ", " + std::to_string(x.j) +
                        ") is not a pair i < j < " + std::to_string(numParticles) + " after the one before it");
      if (info.debug && (f.debug.contacts[c].i != x.i || f.debug.contacts[c].j != x.j))
        in.fail(at, frameName + " contact force " + std::to_string(c) + " is not for the debug block's contact " +
                        std::to_string(c));
      const auto what = [&] {  // (the message only: not a string per contact read)
        return frameName + " contact force (" + std::to_string(x.i) + ", " + std::to_string(x.j) + ")";
      };
      for (float* v : {&x.n.x, &x.n.y, &x.n.z, &x.fn, &x.tangential.x, &x.tangential.y, &x.tangential.z, &x.overlap}) {
        const std::uint64_t valueAt = fd.fileOffset();
        *v = fd.f32();
        if (!std::isfinite(*v)) in.fail(valueAt, what() + " is not finite");
      }
      if (!unitNormal(x)) in.fail(at, what() + ": its normal is not a unit vector");
    }
  } else {
    f.debug.contactForces.clear();
  }
}

// ---- Recording::read -----------------------------------------------------------------------

std::size_t Recording::particlesOf(std::size_t bodies) const {
  // Particles follow their bodies: the first whose body is not among the first `bodies`.
  return static_cast<std::size_t>(std::partition_point(body.begin(), body.end(),
                                                       [&](std::uint32_t b) { return b < bodies; }) -
                                  body.begin());
}

Recording Recording::read(const std::string& path) {
  RecordingReader reader(path);
  Recording rec = reader.header();
  rec.frames.resize(reader.numFrames());
  for (std::size_t k = 0; k < rec.frames.size(); ++k) reader.readFrame(k, rec.frames[k]);
  return rec;
}

// ---- RecordingWriter -----------------------------------------------------------------------

RecordingWriter::RecordingWriter(const std::string& path, const World& world, bool debug,
                                 int stepsPerFrame, float fps, bool grows, bool contactForces)
    : m_path(path),
      m_numParticles(world.numParticles()),
      m_numBodies(world.numBodies()),
      m_grows(grows),
      m_debug(debug),
      m_contactForces(contactForces) {
  const std::string where = "recording '" + path + "': ";
  const Scene& params = world.params;
  if (stepsPerFrame < 1) throw Error(where + "steps per frame must be at least 1");
  if (!std::isfinite(fps) || fps <= 0.0f) throw Error(where + "frames per second must be > 0");
  if (!std::isfinite(params.dt) || params.dt <= 0.0f) throw Error(where + "dt must be > 0");
  if (!std::isfinite(params.ground.height) || !std::isfinite(params.gravity.x) ||
      !std::isfinite(params.gravity.y) || !std::isfinite(params.gravity.z)) {
    throw Error(where + "gravity and ground height must be finite");
  }
  if (params.name.size() > kMaxNameBytes) {
    throw Error(where + "scene name longer than " + std::to_string(kMaxNameBytes) + " bytes");
  }
  const std::size_t n = m_numParticles;
  if (world.mass.size() != n || world.elasticity.size() != n || world.body.size() != n ||
      world.ux.size() != n || world.uy.size() != n || world.uz.size() != n) {
    throw Error(where + "the world's particle columns have different sizes");
  }
  for (const auto* column :
       {&world.radius, &world.mass, &world.elasticity, &world.ux, &world.uy, &world.uz}) {
    std::size_t bad = 0;
    if (!allFinite(*column, n, &bad)) {
      throw Error(where + "particle " + std::to_string(bad) + " has a non-finite static value");
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (world.body[k] >= m_numBodies) {
      throw Error(where + "particle " + std::to_string(k) + " belongs to body " +
                  std::to_string(world.body[k]) + " of " + std::to_string(m_numBodies));
    }
  }
  if (grows) {  // the particles of the bodies present are a prefix of the table
    m_firstParticle.assign(world.first.begin(), world.first.end());
    m_firstParticle.push_back(static_cast<std::uint32_t>(n));
  }
  // Payloads are sized by a u32: refuse worlds whose frames could not be described.
  if (frameSizes(contents(), m_numBodies, n).min > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(where + "too many bodies or particles for one frame of the format");
  }

  const std::vector<std::uint8_t> walls = encodeWalls(sceneWallSurfaces(params, world.bodiesExtent), where);

  // Header (docs/recording.md), with the frame count at the sentinel until close().
  const std::uint32_t flags = (debug ? kFlagDebug : 0u) | (params.ground.enabled ? kFlagGround : 0u) |
                              (grows ? kFlagGrows : 0u) | (contactForces ? kFlagContactForces : 0u);
  Encoder h(m_header);
  h.bytes(kMagic, sizeof kMagic);
  h.u32(kRecordingVersion);
  h.u32(static_cast<std::uint32_t>(kFixedHeaderBytes + params.name.size()));
  h.u32(m_numParticles);
  h.u32(m_numBodies);
  h.u32(static_cast<std::uint32_t>(stepsPerFrame));
  h.f32(params.dt);
  h.f32(fps);
  h.u32(flags);
  h.f32(params.ground.height);
  h.f32(params.gravity.x);
  h.f32(params.gravity.y);
  h.f32(params.gravity.z);
  h.u32(static_cast<std::uint32_t>(params.name.size()));
  h.bytes(params.name.data(), params.name.size());
  m_frameCountOffset = static_cast<long>(m_header.size());
  h.u64(kUnfinished);
  h.u32(fnv1a(m_header.data(), m_header.size()));

  // Particle table as column blocks.
  Encoder t(m_buffer);
  t.f32s(world.radius, n);
  t.f32s(world.mass, n);
  t.f32s(world.elasticity, n);
  for (std::size_t k = 0; k < n; ++k) t.u32(world.body[k]);
  t.f32s(world.ux, n);
  t.f32s(world.uy, n);
  t.f32s(world.uz, n);
  t.u32(fnv1a(m_buffer.data(), m_buffer.size()));

  m_out = std::make_unique<OutputFile>(path);  // throws naming the path and the reason
  m_file = m_out->file();
  m_partPath = m_out->writingTo();
  std::setvbuf(m_file, nullptr, _IONBF, 0);  // each frame is one write; a failed one leaves nothing buffered
  try {
    writeBytes(m_header.data(), m_header.size(), "header");
    writeBytes(m_buffer.data(), m_buffer.size(), "particle table");
    writeBytes(walls.data(), walls.size(), "walls");
    if (std::fflush(m_file) != 0) {
      throw Error("cannot write recording file '" + m_partPath + "': " + errnoText(errno));
    }
  } catch (...) {
    m_file = nullptr;
    m_out->abandon();
    throw;
  }
  m_complete = m_header.size() + m_buffer.size() + walls.size();
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; the temporary (or the error) is all we can leave behind.
  }
}

void RecordingWriter::writeBytes(const std::uint8_t* data, std::size_t size, const char* what) {
  if (!writeFully(m_file, data, size)) {
    m_failed = true;
    throw Error("cannot write " + std::string(what) + " to recording file '" + m_partPath +
                "': " + errnoText(errno));
  }
}

RecordingInfo RecordingWriter::contents() const {
  RecordingInfo i;
  i.debug = m_debug;
  i.grows = m_grows;
  i.contactForces = m_contactForces;
  return i;
}

std::unique_ptr<RecordingWriter> RecordingWriter::continueAt(const std::string& path, const World& world, bool debug,
                                                             int stepsPerFrame, std::uint64_t step, float fps,
                                                             bool grows, bool contactForces) {
  // Nothing to continue where there is no file, where the target is a device or a FIFO, or
  // where it is a descriptor the process was given (`--record /dev/stdout > rec.bin`: the shell
  // has emptied the file, or appends to it; either way the output is a stream of its own).
  std::error_code ec;
  if (namesDescriptor(path) || !std::filesystem::is_regular_file(path, ec))
    return std::make_unique<RecordingWriter>(path, world, debug, stepsPerFrame, fps, grows, contactForces);
  RecordingReader reader(path);
  const Recording& old = reader.header();
  const RecordingInfo& i = old.info;
  const Scene& p = world.params;
  const auto differs = [&](const char* what) {
    throw Error("recording '" + path + "' is not this run's (" + what +
                " differ); to continue it, resume with the settings it was made with, or record to another file");
  };
  if (i.numParticles != world.numParticles() || i.numBodies != world.numBodies() || i.sceneName != p.name)
    differs("the scene name, bodies or particles");
  if (i.stepsPerFrame != std::uint32_t(stepsPerFrame) || i.dt != p.dt || i.fps != fps || i.debug != debug ||
      i.grows != grows || i.contactForces != contactForces)
    differs("the steps per frame, dt, frame rate, debug or contact-force setting or bodies entering");
  if (i.groundEnabled != p.ground.enabled || i.groundHeight != p.ground.height || i.gravity.x != p.gravity.x ||
      i.gravity.y != p.gravity.y || i.gravity.z != p.gravity.z)
    differs("the ground or gravity");
  if (old.radius != world.radius || old.mass != world.mass || old.elasticity != world.elasticity ||
      old.body != world.body || old.ux != world.ux || old.uy != world.uy || old.uz != world.uz)
    differs("the particle tables");
  if (i.version >= 2 && encodeWalls(old.walls, "") != encodeWalls(sceneWallSurfaces(p, world.bodiesExtent), ""))
    differs("the walls");
  auto w = std::make_unique<RecordingWriter>(path, world, debug, stepsPerFrame, fps, grows, contactForces);
  BodyState s;
  RecordedFrame f;
  w->m_copyOf = reader.numFrames();  // a failed write says that `path` keeps these
  try {
    for (std::size_t k = 0; k < reader.numFrames(); ++k) {
      reader.readFrame(k, f);
      if (f.step > step) break;
      s.px = f.px; s.py = f.py; s.pz = f.pz;
      s.qw = f.qw; s.qx = f.qx; s.qy = f.qy; s.qz = f.qz;
      w->writeFrame(f.step, f.time, f.pulls, s, debug || contactForces ? &f.debug : nullptr);
    }
  } catch (...) {
    w->abandon();  // a copy cut short (a full disk) must not replace the recording it copies
    throw;
  }
  w->m_copyOf = 0;
  return w;
}

void RecordingWriter::writeFrame(std::uint64_t step, double time, std::uint32_t pulls,
                                 const BodyState& state, const ParticleDebug* debug) {
  const std::string where = "recording '" + m_path + "', step " + std::to_string(step) + ": ";
  if (m_file == nullptr) throw Error(where + "the recording is closed");
  if (m_failed) throw Error(where + "an earlier write failed");
  if ((debug != nullptr) != (m_debug || m_contactForces)) {
    throw Error(where + (debug == nullptr ? "a debug or contact-force recording needs debug data for every frame"
                                          : "debug data given to a recording opened without debug or contact forces"));
  }
  // The bodies present: all of them, or in a recording that grows a prefix.
  const std::size_t nb = m_grows ? std::min<std::size_t>(state.size(), m_numBodies) : m_numBodies;
  const std::size_t np = m_grows ? m_firstParticle[nb] : m_numParticles;
  const std::size_t n3 = 3 * np;
  const std::vector<float>* columns[7] = {&state.px, &state.py, &state.pz, &state.qw,
                                          &state.qx, &state.qy, &state.qz};
  static const char* const kColumnNames[7] = {"px", "py", "pz", "qw", "qx", "qy", "qz"};
  for (int c = 0; c < 7; ++c) {
    if (columns[c]->size() != nb) {  // (a growing run's: nb is capped at the table's bodies)
      throw Error(where + "body state has " + std::to_string(columns[c]->size()) + " " +
                  kColumnNames[c] + " values for " + std::to_string(nb) + " bodies");
    }
  }
  // Validate everything before encoding anything: a rejected frame leaves the file unchanged.
  if (!std::isfinite(time)) throw Error(where + "time is not finite; frame not written");
  for (int c = 0; c < 7; ++c) {
    std::size_t bad = 0;
    if (!allFinite(*columns[c], nb, &bad)) {
      throw Error(where + "body " + std::to_string(bad) + " " + kColumnNames[c] +
                  " is not finite (NaN is never recorded); frame not written");
    }
  }
  if (m_debug) {
    const std::vector<float>* dcols[6] = {&debug->v,        &debug->force[0], &debug->force[1],
                                          &debug->force[2], &debug->force[3], &debug->force[4]};
    for (int c = 0; c < 6; ++c) {
      const std::string name =
          c == 0 ? std::string("velocity") : kForceNames[c - 1] + std::string(" force");
      if (dcols[c]->size() != n3) {
        throw Error(where + "debug " + name + " has " + std::to_string(dcols[c]->size()) +
                    " values, expected 3 per particle (" + std::to_string(n3) + ")");
      }
      std::size_t bad = 0;
      if (!allFinite(*dcols[c], n3, &bad)) {
        throw Error(where + "debug " + name + " of particle " + std::to_string(bad / 3) +
                    " is not finite (NaN is never recorded); frame not written");
      }
    }
    for (const Pair& p : debug->contacts) {
      if (!(p.i < p.j && p.j < np)) {
        throw Error(where + "contact (" + std::to_string(p.i) + ", " + std::to_string(p.j) +
                    ") is not a pair i < j < " + std::to_string(np));
      }
    }
  }
  if (m_contactForces) {
    const std::vector<ContactForce>& cf = debug->contactForces;
    for (std::size_t c = 0; c < cf.size(); ++c) {
      const ContactForce& x = cf[c];
      const auto name = [&] { return where + "contact force (" + std::to_string(x.i) + ", " + std::to_string(x.j) + ")"; };
      if (!(x.i < x.j && x.j < np) || (c > 0 && !(cf[c - 1] < x)))
        throw Error(name() + " is not a pair i < j < " + std::to_string(np) + " after the one before it");
      if (m_debug && (c >= debug->contacts.size() || debug->contacts[c].i != x.i || debug->contacts[c].j != x.j))
        throw Error(name() + " is not the debug data's contact " + std::to_string(c));
      for (const float v : {x.n.x, x.n.y, x.n.z, x.fn, x.tangential.x, x.tangential.y, x.tangential.z, x.overlap})
        if (!std::isfinite(v)) throw Error(name() + " is not finite (NaN is never recorded); frame not written");
      if (!unitNormal(x)) throw Error(name() + ": its normal is not a unit vector; frame not written");
    }
    if (m_debug && cf.size() != debug->contacts.size())
      throw Error(where + "the debug data has " + std::to_string(debug->contacts.size()) + " contacts and " +
                  std::to_string(cf.size()) + " contact forces");
  }
  const FrameSizes sizes = frameSizes(contents(), nb, np);
  const std::size_t numContacts =
      m_contactForces ? debug->contactForces.size() : m_debug ? debug->contacts.size() : 0;
  const std::uint64_t payloadBytes = sizes.min + sizes.perContact * numContacts;
  if (payloadBytes > std::numeric_limits<std::uint32_t>::max() || numContacts > std::numeric_limits<std::uint32_t>::max()) {
    throw Error(where + "frame of " + std::to_string(payloadBytes) +
                " bytes is too large for the format");
  }

  m_buffer.clear();
  m_buffer.reserve(static_cast<std::size_t>(payloadBytes) + 8);
  Encoder e(m_buffer);
  e.u32(static_cast<std::uint32_t>(payloadBytes));
  e.u64(step);
  e.f64(time);
  e.u32(pulls);
  if (m_grows) e.u32(static_cast<std::uint32_t>(nb));
  for (int c = 0; c < 7; ++c) e.f32s(*columns[c], nb);
  if (m_debug) {
    e.f32s(debug->v, n3);
    for (int c = 0; c < 5; ++c) e.f32s(debug->force[c], n3);
    e.u32(static_cast<std::uint32_t>(debug->contacts.size()));
    for (const Pair& p : debug->contacts) {
      e.u32(p.i);
      e.u32(p.j);
    }
  }
  if (m_contactForces) {
    e.u32(static_cast<std::uint32_t>(debug->contactForces.size()));
    for (const ContactForce& x : debug->contactForces) {
      e.u32(x.i);
      e.u32(x.j);
      for (const float v : {x.n.x, x.n.y, x.n.z, x.fn, x.tangential.x, x.tangential.y, x.tangential.z, x.overlap})
        e.f32(v);
    }
  }
  e.u32(fnv1a(m_buffer.data() + 4, m_buffer.size() - 4));

  // Flush every frame so that a crashed run leaves all its complete frames in the temporary.
  // A frame that cannot be written whole (a full disk) is cut off again: the file keeps every
  // complete frame, and close() still finishes it.
  // A signal that interrupts the write (a pipe nobody reads) restarts it, unless a stop was
  // requested (writeFully, output_file.hpp).
  int error = 0;
  if (const Appended a = appendWhole(*m_out, m_buffer.data(), m_buffer.size(), m_complete, error);
      a != Appended::Whole) {
    const std::string why = errnoText(error);
    m_failed = a == Appended::Torn;
    if (m_copyOf > 0)  // continueAt's copy: abandoned, so the recording stays as it was
      throw Error("cannot continue recording '" + m_path + "': copying its frames failed at step " +
                  std::to_string(step) + ": " + why + "; it is left as it was, with its " + std::to_string(m_copyOf) +
                  " frames (free some space, or record the resumed run to another file)");
    throw Error(m_failed ? "cannot write frame to recording file '" + m_partPath + "': " + why
                         : "cannot write frame to recording '" + m_path + "': " + why + "; it keeps the " +
                               std::to_string(m_numFrames) + " complete frames written before");
  }
  ++m_numFrames;
  m_lastStep = step;
}

void RecordingWriter::abandon() noexcept {
  if (m_file == nullptr) return;
  m_file = nullptr;
  m_out->abandon();
}

void RecordingWriter::close() {
  if (m_file == nullptr) return;
  std::FILE* file = std::exchange(m_file, nullptr);
  if (m_failed) {
    // Leave the temporary for inspection; the write error was already reported.
    m_out->keep();
    return;
  }
  const std::size_t at = static_cast<std::size_t>(m_frameCountOffset);
  putU64At(m_header, at, m_numFrames);
  putU32At(m_header, at + 8, fnv1a(m_header.data(), at + 8));
  // A target that cannot seek (a FIFO, a pipe, a descriptor shared with the shell) keeps the
  // header's "unfinished" count, which readers accept.
  const bool seekable = !m_out->throughDescriptor() && std::fseek(file, m_frameCountOffset, SEEK_SET) == 0;
  const bool patched = !seekable || (writeFully(file, m_header.data() + at, 12) && std::fflush(file) == 0);
  if (!patched) {
    const std::string why = errnoText(errno != 0 ? errno : EIO);
    const std::string kept = m_out->keep();
    throw Error("cannot finish recording file '" + kept + "': " + why);
  }
  m_out->commit();  // throws naming the path and the reason
}

// The reader's index, for repairRecording().
struct RecordingRepair {
  static std::uint64_t frameStart(const RecordingReader& r, std::size_t k) {
    const RecordingInfo& info = r.m_header.info;
    return variableFrames(info) ? r.m_file->frameOffsets[k] : r.m_file->framesOffset + k * r.m_file->frameBytes;
  }
  static std::uint64_t framesEnd(const RecordingReader& r) { return r.m_file->framesEnd; }
  static std::uint64_t frameCountOffset(const RecordingReader& r) { return r.m_file->frameCountOffset; }
  static std::uint64_t size(const RecordingReader& r) { return r.m_file->in.size(); }
};

RepairResult repairRecording(const std::string& in, const std::string& out) {
  RecordingReader reader(in, RecordingReader::TornEnd::KeepWholeFrames);
  RepairResult r;
  r.why = reader.torn();
  RecordedFrame frame;
  for (; r.kept < reader.numFrames(); ++r.kept) {  // a frame whose bytes are damaged ends them too
    try {
      reader.readFrame(r.kept, frame);
    } catch (const InputError& e) {
      r.why = e.problem();
      break;
    }
  }
  const std::uint64_t end =
      r.kept < reader.numFrames() ? RecordingRepair::frameStart(reader, r.kept) : RecordingRepair::framesEnd(reader);
  r.droppedBytes = RecordingRepair::size(reader) - end;
  if (r.why.empty()) return r;  // whole: nothing to write
  if (r.kept == 0)  // a recording of no frame is one nothing opens
    throw InputError(in, 0, "no whole frame to keep (" + r.why + "): nothing written");

  // The header up to its checksum, with the frame count of the frames kept, then the rest as is.
  const std::uint64_t at = RecordingRepair::frameCountOffset(reader);
  std::ifstream src(in, std::ios::binary);
  std::vector<std::uint8_t> head(static_cast<std::size_t>(at + 12));
  if (!src.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size())))
    throw InputError(in, 0, "cannot read the header again: " + errnoText(errno));
  putU64At(head, static_cast<std::size_t>(at), r.kept);
  putU32At(head, static_cast<std::size_t>(at + 8), fnv1a(head.data(), static_cast<std::size_t>(at + 8)));
  OutputFile o(out);
  bool ok = writeFully(o.file(), head.data(), head.size());
  std::vector<char> chunk(std::size_t{1} << 20);
  for (std::uint64_t left = end - head.size(); ok && left > 0;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, chunk.size()));
    if (!src.read(chunk.data(), static_cast<std::streamsize>(n)))
      throw InputError(in, 0, "cannot read its frames again: " + errnoText(errno));
    ok = writeFully(o.file(), chunk.data(), n);
    left -= n;
  }
  if (!ok) throw Error("cannot write " + out + ": " + errnoText(errno));
  o.commit();
  return r;
}

}  // namespace tumble
