// SPDX-License-Identifier: MIT
/// @file output_file.hpp
/// How every tumble output reaches its path (docs/recording.md#outputs): never half-written,
/// never in place of something that is not a file.
///
/// - The target is the path with its symbolic links followed (up to 40), so a link to a file
///   keeps pointing at it and its target is what gets replaced.
/// - An existing target that is not a regular file (a device such as /dev/null, a FIFO) is
///   written directly: it is never replaced. /dev/stdout, /dev/stderr, /dev/fd/N and
///   /proc/self/fd/N are written through a duplicate of that descriptor (a pipe, or a file the
///   shell opened for appending, gets the bytes as set up).
/// - Otherwise the bytes go to a new temporary next to the target, `TARGET.part-XXXXXX` with an
///   unpredictable suffix, created exclusively (mkstemp: O_CREAT | O_EXCL, so no existing file
///   or planted link is ever opened), and commit() renames it over the target, with the
///   target's permission bits when it existed (else 0666 less the umask; never set-id bits). Until then the target
///   is untouched; abandon() (or the destructor) removes the temporary.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tumble {

/// `path` with its symbolic links followed; a dangling link gives the path it names. Throws
/// tumble::Error for a loop (more than 40 links).
std::string outputTarget(const std::string& path);

/// Asks writes to give up instead of restarting when a signal interrupts them. Async-signal-safe:
/// a stop handler calls it (tumble run's first Ctrl-C), so that a write blocked on a pipe nobody
/// reads ends once a later signal interrupts it (EINTR) instead of blocking the stop forever.
void requestWriteStop() noexcept;
/// Clears the request (a new stop handler, or the handler's end).
void clearWriteStop() noexcept;
bool writeStopRequested() noexcept;

/// Writes all `size` bytes of `data` to `file`, continuing after a short write and after a signal
/// (EINTR) unless writeStopRequested(). Returns false on an error, errno telling which (EINTR
/// once a stop was requested).
bool writeFully(std::FILE* file, const void* data, std::size_t size);

/// What appendWhole() did.
enum class Appended { Whole, CutBack, Torn };
/// Appends one record of a file made of records (a recording's frames, a time series' rows) to
/// `out`'s file, which must be unbuffered (setvbuf _IONBF), and flushes it: Whole, and `complete`
/// (the bytes of the whole records) grows by `size`; or, when the write fails (a full disk), the
/// temporary is cut back to `complete` bytes and CutBack says it keeps every whole record; Torn
/// when even that failed, or when `out` writes to its target directly (OutputFile::direct(): a
/// descriptor's file may hold what others wrote, and is never cut). `error` receives errno of
/// the failed write.
class OutputFile;
Appended appendWhole(const OutputFile& out, const void* data, std::size_t size, std::uint64_t& complete, int& error);

/// Whether `path` names a descriptor of this process (/dev/stdout, /dev/stderr, /dev/fd/N,
/// /proc/self/fd/N), which OutputFile writes through.
bool namesDescriptor(const std::string& path);

/// Whether `a` and `b` are one regular file, or would become one (the same path, links followed,
/// that does not exist yet): two outputs of one command that would overwrite each other, or an
/// output over an input. Devices and FIFOs are never "the same" (--record /dev/null twice is fine).
bool sameFile(const std::string& a, const std::string& b);

class OutputFile {
 public:
  /// Where the bytes wait for commit(). Private: `TARGET.part-XXXXXX` (above). Live: the fixed,
  /// documented name `TARGET.part`, readable as the target will be (a time series followed while
  /// it is written: `tail -f`, `tumble plot`); created exclusively too (O_EXCL, O_NOFOLLOW), so a
  /// second writer of the same target, or a live file a killed run left, is refused with a message
  /// saying so and nothing else is touched.
  enum class Temporary { Private, Live };
  /// Opens the temporary (or the non-regular target) for writing. Throws tumble::Error naming
  /// the path and the reason. A FIFO is waited for until a reader opens it, or until a stop is
  /// requested (requestWriteStop(): "stopped while waiting for a reader of the FIFO").
  explicit OutputFile(const std::string& path, Temporary temporary = Temporary::Private);
  ~OutputFile();  ///< abandon() unless committed or kept
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* file() const { return m_file; }
  /// The path the bytes go to now: the temporary, or the target when written directly.
  const std::string& writingTo() const { return m_writing; }
  /// The path the caller named.
  const std::string& path() const { return m_path; }
  /// Written through a descriptor the process already had (/dev/stdout, /dev/fd/N, …): its
  /// offset is shared with whoever opened it, so the writer must not seek.
  bool throughDescriptor() const { return m_descriptor; }
  /// Written to the target itself, with no temporary (a device, a FIFO, a descriptor): what is
  /// there is not the writer's alone, so it must not be cut back (appendWhole).
  bool direct() const { return m_direct; }
  /// Closes and renames into place (or just closes a direct target). Throws tumble::Error with
  /// the reason (the temporary is removed then).
  void commit();
  /// Closes and removes the temporary. Never throws.
  void abandon() noexcept;
  /// Closes and leaves the temporary where it is (what a crash would leave: a recording's
  /// complete frames stay readable there). Returns its path.
  std::string keep() noexcept;

 private:
  std::string m_path, m_target, m_writing;
  std::FILE* m_file = nullptr;
  bool m_direct = false;
  bool m_descriptor = false;
  bool m_existed = false;
  unsigned m_mode = 0;
};

}  // namespace tumble
