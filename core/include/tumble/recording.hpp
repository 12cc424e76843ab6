// SPDX-License-Identifier: MIT
/// @file recording.hpp
/// The versioned binary recording format (docs/recording.md): a header, the static particle
/// table, the walls as triangles with their motion (version 2), then one frame per
/// `stepsPerFrame` steps with each body's X and Q; optionally a debug block per frame
/// (velocities, the five forces per particle, the contact pairs) and a block of the contacts
/// with their forces (version 3).
#pragma once
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "tumble/output_file.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/wall_geometry.hpp"
#include "tumble/world.hpp"

namespace tumble {

/// The version the writer writes; the reader reads it and versions 1 (no walls) and 2 (no
/// contact forces).
inline constexpr std::uint32_t kRecordingVersion = 3;

/// Scene-level facts a player needs.
struct RecordingInfo {
  std::uint32_t version = kRecordingVersion;
  std::uint32_t numParticles = 0;
  std::uint32_t numBodies = 0;
  std::uint32_t stepsPerFrame = 10;
  float dt = 0.0f;
  float fps = 60.0f;
  bool debug = false;
  bool groundEnabled = false;
  /// Bodies enter during the run ([[pour]]): the table holds every body that may, and each frame
  /// the first RecordedFrame::numBodies() of them, those present (flag bit 2).
  bool grows = false;
  /// Each frame holds the contacts of the step before it with their forces
  /// (RecordedFrame::debug.contactForces; version 3).
  bool contactForces = false;
  float groundHeight = 0.0f;
  Vec3f gravity{0, 0, 0};
  std::string sceneName;
};

/// One recorded frame.
struct RecordedFrame {
  std::uint64_t step = 0;
  double time = 0.0;
  std::uint32_t pulls = 0;                  ///< PullBits on during this frame
  std::vector<float> px, py, pz;            ///< per body present: the first numBodies() of the table
  std::vector<float> qw, qx, qy, qz;        ///< per body
  /// In a debug recording: v, force and contacts (the particles present); in one with contact
  /// forces: contactForces. Empty otherwise.
  ParticleDebug debug;
  /// Bodies in this frame: all of the table's, or in a recording that grows the first so many.
  std::size_t numBodies() const { return px.size(); }
};

/// A whole recording in memory.
struct Recording {
  RecordingInfo info;
  // Static particle table.
  std::vector<float> radius, mass, elasticity;
  std::vector<std::uint32_t> body;
  std::vector<float> ux, uy, uz;
  /// The scene's walls besides the ground as drawn (sceneWallSurfaces(): one per Scene::walls
  /// entry, a box's faces each), with their motion; empty in a version 1 recording.
  std::vector<WallSurface> walls;
  std::vector<RecordedFrame> frames;
  /// The particles of the first `bodies` bodies (particles follow their bodies): those a frame of
  /// that many bodies shows.
  std::size_t particlesOf(std::size_t bodies) const;

  /// Reads a whole recording: RecordingReader, then every frame. Throws what RecordingReader
  /// and RecordingReader::readFrame throw. Memory: the whole recording (about the file size, plus
  /// some 400 bytes per frame); players and the renderer read frame by frame instead.
  static Recording read(const std::string& path);
};

/// Reads a recording one frame at a time: memory is the particle table and one frame, whatever
/// the file's length (plus 8 bytes per frame for a debug recording's index).
///
/// The constructor checks the header and the particle table (checksums, counts, finite values)
/// and indexes the frames: in a plain recording every frame has the same size, so the index is
/// arithmetic; a debug recording's frames are walked by their size fields. readFrame() checks the
/// frame it reads (size, checksum, finite values, contact pairs). Errors are tumble::InputError
/// naming the file and the byte offset; bad bytes never crash it, and every count is checked
/// against the file size before anything is allocated. A `.part` file left by a crashed writer
/// reads as the complete frames it holds (a torn last frame is an error).
/// Not thread-safe (one file position); separate readers of one file are fine.
class RecordingReader {
 public:
  /// What a torn end does: Refuse (an error naming the frame and the byte, and `tumble repair`),
  /// or KeepWholeFrames: the frames before it are the recording (numFrames()), and torn() says
  /// where it was cut; a frame count in the header that disagrees is then not an error either.
  enum class TornEnd { Refuse, KeepWholeFrames };
  explicit RecordingReader(const std::string& path, TornEnd tornEnd = TornEnd::Refuse);
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  /// The header and the particle table; its `frames` is empty.
  const Recording& header() const { return m_header; }
  const RecordingInfo& info() const { return m_header.info; }
  std::size_t numFrames() const { return m_numFrames; }
  /// Reads frame `k` (< numFrames()) into `out`, reusing its storage.
  void readFrame(std::size_t k, RecordedFrame& out);
  /// Under TornEnd::KeepWholeFrames: why the file ends before its frames do (empty when it does
  /// not): "frame 22 truncated: needs 4812 bytes, only 1200 left", with its byte.
  const std::string& torn() const { return m_torn; }

 private:
  friend struct RecordingRepair;
  struct File;
  std::unique_ptr<File> m_file;
  Recording m_header;
  std::size_t m_numFrames = 0;
  std::vector<std::uint8_t> m_buffer;         ///< one frame's bytes
  std::string m_torn;
};

/// What repairRecording() did.
struct RepairResult {
  std::size_t kept = 0;            ///< whole frames written to the output
  std::uint64_t droppedBytes = 0;  ///< of the input, after them
  std::string why;                 ///< what ended the kept frames ("" when the file was whole)
};

/// `tumble repair`: copies the recording at `in` to `out` up to its last frame that reads whole
/// (a crash-left temporary, a file cut short by a full disk or a copy), with the frame count in
/// its header set to what it keeps. `out` is written as every output is (OutputFile: in place
/// only by a rename; `out` may be `in`). Nothing is written when the file is whole (result.why
/// empty), and InputError when not even its header and table can be read (as the reader's) or
/// when not one frame is whole.
RepairResult repairRecording(const std::string& in, const std::string& out);

/// Writes a recording. Frames go to a temporary next to `path` (`path.part-XXXXXX`, OutputFile);
/// close() (or the destructor) writes the frame count and renames it to `path`, so a crash never
/// leaves a half-written `path`. Every frame is written whole and at once: a crash leaves all
/// complete frames in the temporary (readable as a recording), and a frame that cannot be
/// written (a full disk) is cut off again, so the file keeps every complete frame.
/// Not thread-safe: one caller at a time.
/// Determinism: the bytes written depend only on the values given (no timestamps, no padding).
class RecordingWriter {
 public:
  /// Opens the temporary and writes the header, the static particle table of `world`
  /// (radius, mass, elasticity, body, ux, uy, uz; dt, gravity, ground and name from
  /// world.params) and its walls (sceneWallSurfaces(world.params, world.bodiesExtent)). Throws tumble::Error if the
  /// file cannot be opened (naming it and the reason), if stepsPerFrame < 1, fps or dt is not
  /// positive, or the table is inconsistent or non-finite.
  /// `grows`: bodies enter during the run (tumble/pour.hpp): `world` holds every body that may,
  /// and each frame the bodies present, a prefix of them.
  /// `contactForces`: each frame also holds the contacts of the step before it with their forces
  /// (ParticleDebug::contactForces).
  RecordingWriter(const std::string& path, const World& world, bool debug, int stepsPerFrame,
                  float fps = 60.0f, bool grows = false, bool contactForces = false);
  /// Continues the recording at `path` for a run resumed at `step` (tumble run --resume): its
  /// frames up to that step are written again, with the same bytes, to a temporary and
  /// the writer appends from there, so that the finished file equals the uninterrupted run's;
  /// `path` itself is replaced only by close(), and never when the copy fails. When `path` does
  /// not exist, is not a regular file (a device, a FIFO) or names a descriptor (/dev/stdout,
  /// /dev/fd/N: namesDescriptor), this is a new recording, from `step` on. Throws tumble::InputError for an unreadable or corrupt file and tumble::Error
  /// when it records another scene or other settings (its frames would not belong to this run).
  /// A version 1 recording is continued as version 2 (its frames, with this world's walls). A copy
  /// that cannot be written (a full disk) throws tumble::Error saying that `path` is left as it
  /// was, with its frames.
  static std::unique_ptr<RecordingWriter> continueAt(const std::string& path, const World& world, bool debug,
                                                     int stepsPerFrame, std::uint64_t step, float fps = 60.0f,
                                                     bool grows = false, bool contactForces = false);
  /// Calls close(), swallowing its exceptions.
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  /// Appends a frame. `debug` must be given iff the recording was opened with debug or
  /// contactForces (the writer writes the parts the recording has: v, force and contacts, and
  /// contactForces, sorted, the same pairs as contacts in a debug recording). In a recording
  /// that grows, `state` (and `debug`) hold the first bodies (particles) present.
  /// Throws tumble::Error if the state holds a non-finite value (NaN is never recorded), if
  /// sizes do not match the world, or on a write error. Values are checked before anything is
  /// written, so a frame rejected for its values leaves the file unchanged and the writer usable.
  void writeFrame(std::uint64_t step, double time, std::uint32_t pulls, const BodyState& state,
                  const ParticleDebug* debug = nullptr);
  /// Finishes the file and renames it into place. Idempotent. Throws tumble::Error if that
  /// fails. When a failed frame could not be cut off again it only closes, leaving the
  /// temporary in place.
  void close();
  /// Closes and removes the temporary: `path` stays as it was. Idempotent, never throws.
  void abandon() noexcept;
  /// Frames written so far.
  std::uint64_t numFrames() const { return m_numFrames; }
  /// Step of the last frame written (0 before the first).
  std::uint64_t lastStep() const { return m_lastStep; }
  /// The final path.
  const std::string& path() const { return m_path; }
  /// Where the frames go until close(): the temporary (or `path` itself when it is a device or
  /// a FIFO).
  const std::string& writingTo() const { return m_partPath; }

 private:
  std::string m_path;
  std::string m_partPath;
  std::unique_ptr<OutputFile> m_out;
  std::FILE* m_file = nullptr;            ///< m_out's, until close()
  std::uint64_t m_complete = 0;           ///< bytes up to the end of the last complete frame
  std::uint64_t m_numFrames = 0;
  std::uint64_t m_lastStep = 0;
  std::uint32_t m_numParticles = 0;
  std::uint32_t m_numBodies = 0;
  bool m_grows = false;
  std::vector<std::uint32_t> m_firstParticle;  ///< grows: the first particle of each body, and N
  bool m_debug = false;
  bool m_contactForces = false;
  bool m_failed = false;                 ///< a failed frame could not be cut off: close() keeps the temporary
  std::uint64_t m_copyOf = 0;            ///< continueAt() copying: the frames `path` keeps if a write fails
  long m_frameCountOffset = 0;           ///< byte offset of the header's frame count
  std::vector<std::uint8_t> m_header;    ///< header bytes, re-checksummed at close()
  std::vector<std::uint8_t> m_buffer;    ///< one frame, encoded before it is written

  void writeBytes(const std::uint8_t* data, std::size_t size, const char* what);
  /// The frames' contents (debug, grows, contactForces) as a RecordingInfo says them.
  RecordingInfo contents() const;
};

}  // namespace tumble
