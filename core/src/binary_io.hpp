// SPDX-License-Identifier: MIT
// Little-endian binary encoding, FNV-1a checksums and a bounds-checked reader of untrusted
// files, shared by the recording (recording.cpp) and checkpoint (checkpoint.cpp) formats.
// Internal to tumble_core.
//
// Checksum: FNV-1a, 32 bit (Fowler, Noll, Vo; http://www.isthe.com/chongo/tech/comp/fnv/ and
// IETF draft-eastlake-fnv): h = 2166136261; for each byte h = (h ^ b) * 16777619 mod 2^32. Each
// step is a bijection of h for a fixed byte (the prime is odd), so any single-byte change is
// always detected; it is an integrity check, not protection against tampering.
#pragma once
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "tumble/error.hpp"
#include "tumble/memory.hpp"

namespace tumble::detail {

inline std::string errnoText(int err) { return std::strerror(err); }

inline std::uint32_t fnv1a(const std::uint8_t* data, std::size_t size) {
  std::uint32_t h = 2166136261u;
  for (std::size_t k = 0; k < size; ++k) {
    h ^= data[k];
    h *= 16777619u;
  }
  return h;
}

inline std::string hex32(std::uint32_t v) {
  static const char* const kDigits = "0123456789abcdef";
  std::string s = "0x00000000";
  for (int k = 0; k < 8; ++k) s[9 - k] = kDigits[(v >> (4 * k)) & 0xFu];
  return s;
}

/// How much of a text or mesh file a reader takes (readWholeFile()).
struct FileLimit {
  const char* name;         ///< "a scene file", for the messages
  std::uint64_t maxBytes;   ///< larger files are refused, saying this limit
  std::uint64_t memoryPerByte;  ///< what reading holds per byte of the file (the bytes and what they become)
  const char* instead;      ///< what to do with a larger input
};

/// The readers' limits. A scene's tables are read into toml++'s tree: a 3.4 MB scene of 60 000
/// [[body]] tables took 55 MB while read (16 bytes per byte of text; 30 leaves room). A mesh holds
/// its welded vertices, triangles, their lines, the check of repeated triangles and then the
/// kernels' copy: 2 million triangles, a binary STL of 100 MB, took 0.9 GB (issue 34's
/// measurement), 9 bytes per byte. A particle list about 3.
inline constexpr FileLimit kSceneFileLimit{"a scene file", std::uint64_t{256} << 20, 30,
                                           "list many bodies with [[group]], [[fill]] or [[pour]] tables instead of one "
                                           "[[body]] table each (docs/scenes.md)"};
inline constexpr FileLimit kMeshFileLimit{"a mesh file", std::uint64_t{1} << 30, 9,
                                          "simplify the mesh (a wall needs its shape, not its scan: meshlab, "
                                          "blender's decimate) or split it into several [[wall]]s"};
inline constexpr FileLimit kParticleFileLimit{"a particle file", std::uint64_t{16} << 30, 3, "split the particle list"};

/// The bytes of the regular file at `path` (a scene, a particle list, a mesh): InputError(path, 0,
/// "cannot open[ WHAT]: reason") when it cannot be opened (a folder included), "cannot read…"
/// when reading fails; refused before a byte is read when it is not a regular file (a device
/// such as /dev/zero, a FIFO: their size is unknown), when it is larger than `limit.maxBytes`,
/// and when `limit.memoryPerByte` times its size would not fit in memory (memoryShortfall()).
inline std::string readWholeFile(const std::string& path, const std::string& what, const FileLimit& limit) {
  const std::string of = what.empty() ? std::string() : " " + what;
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);  // before opening: a FIFO would block
  if (std::filesystem::is_directory(st)) throw InputError(path, 0, "cannot open" + of + ": " + errnoText(EISDIR));
  if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
    throw InputError(path, 0, std::string("not a regular file (a device, a FIFO or a socket): give ") + limit.name +
                                  " as a file; its size must be known before it is read");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError(path, 0, "cannot open" + of + ": " + errnoText(err));
  }
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, 0, "cannot read" + of + ": " + ec.message());
  if (size > limit.maxBytes)
    throw InputError(path, 0, bytesText(size) + ", more than the " + bytesText(limit.maxBytes) + " tumble reads as " +
                                  limit.name + "; " + limit.instead);
  if (const std::string why = memoryShortfall(size * limit.memoryPerByte); !why.empty())
    throw InputError(path, 0, std::string("reading ") + limit.name + " of " + bytesText(size) + " needs " + why);
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (in.bad() || static_cast<std::uint64_t>(in.gcount()) != size) {
    const int err = errno;
    throw InputError(path, 0, "cannot read" + of + ": " + (in.bad() ? errnoText(err) : "the file changed while it was read"));
  }
  return bytes;
}

// ---- encoding ------------------------------------------------------------------------------

class Encoder {
 public:
  explicit Encoder(std::vector<std::uint8_t>& out) : m_out(out) {}
  void u32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) m_out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void u64(std::uint64_t v) {
    for (int k = 0; k < 8; ++k) m_out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    m_out.insert(m_out.end(), p, p + size);
  }
  void f32s(const std::vector<float>& v, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) f32(v[k]);
  }

 private:
  std::vector<std::uint8_t>& m_out;
};

inline void putU32At(std::vector<std::uint8_t>& buf, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) buf[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
}
inline void putU64At(std::vector<std::uint8_t>& buf, std::size_t at, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) buf[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
}

inline std::uint32_t getU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
inline std::uint64_t getU64(const std::uint8_t* p) {
  return static_cast<std::uint64_t>(getU32(p)) | static_cast<std::uint64_t>(getU32(p + 4)) << 32;
}

// ---- reading -------------------------------------------------------------------------------

/// An open input file with its size and a read position; every error names the byte offset.
class InFile {
 public:
  /// Opens `path`; `kind` names the file in the errors ("cannot open recording: …").
  InFile(const std::string& path, const std::string& kind) : m_path(path) {
    const std::string cannot = "cannot open " + kind + ": ";
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) throw InputError(path, 0, cannot + (ec ? ec.message() : errnoText(ENOENT)));
    if (!std::filesystem::is_regular_file(status)) throw InputError(path, 0, cannot + "not a regular file");
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(path, 0, cannot + ec.message());
    m_size = size;
    m_file = std::fopen(path.c_str(), "rb");
    if (m_file == nullptr) throw InputError(path, 0, cannot + errnoText(errno));
  }
  ~InFile() {
    if (m_file != nullptr) std::fclose(m_file);
  }
  InFile(const InFile&) = delete;
  InFile& operator=(const InFile&) = delete;

  std::uint64_t size() const { return m_size; }
  const std::string& path() const { return m_path; }
  std::uint64_t offset() const { return m_offset; }
  std::uint64_t remaining() const { return m_size - m_offset; }

  [[noreturn]] void fail(std::uint64_t at, const std::string& problem) const {
    throw InputError(m_path, 0, "byte " + std::to_string(at) + ": " + problem);
  }

  /// Moves the read position to `at` (≤ size()).
  void seek(std::uint64_t at) {
    if (at > m_size) fail(at, "offset beyond the end of the file");
    if (fseeko(m_file, static_cast<off_t>(at), SEEK_SET) != 0) fail(at, "cannot seek: " + errnoText(errno));
    m_offset = at;
  }

  /// Appends the next `count` bytes to `out`. Callers check `count` against remaining() first
  /// (with a better message); this check is the last line of defence.
  void read(std::vector<std::uint8_t>& out, std::uint64_t count, const char* what) {
    if (count > remaining()) {
      fail(m_offset, std::string(what) + " truncated: needs " + std::to_string(count) +
                         " bytes, only " + std::to_string(remaining()) + " left");
    }
    if (count == 0) return;
    const std::size_t old = out.size();
    out.resize(old + static_cast<std::size_t>(count));
    const std::size_t got =
        std::fread(out.data() + old, 1, static_cast<std::size_t>(count), m_file);
    if (got != count) {
      fail(m_offset + got, std::string("cannot read ") + what + ": " +
                               (std::ferror(m_file) ? errnoText(errno) : "unexpected end of file"));
    }
    m_offset += count;
  }

 private:
  std::string m_path;
  std::FILE* m_file = nullptr;
  std::uint64_t m_size = 0;
  std::uint64_t m_offset = 0;
};

/// Bounds-checked little-endian cursor over a buffer that starts at file offset `base`.
class Decoder {
 public:
  Decoder(const InFile& in, const std::vector<std::uint8_t>& buf, std::uint64_t base,
          std::size_t pos = 0)
      : m_in(in), m_buf(buf), m_base(base), m_pos(pos) {}

  std::uint64_t fileOffset() const { return m_base + m_pos; }
  std::uint32_t u32() { return getU32(take(4)); }
  std::uint64_t u64() { return getU64(take(8)); }
  float f32() { return std::bit_cast<float>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }
  const std::uint8_t* take(std::size_t n) {
    if (n > m_buf.size() - m_pos) m_in.fail(fileOffset(), "record shorter than its declared size");
    const std::uint8_t* p = m_buf.data() + m_pos;
    m_pos += n;
    return p;
  }
  /// A finite f32; `what` names the value in the error.
  float finite(const std::string& what) {
    const std::uint64_t at = fileOffset();
    const float v = f32();
    if (!std::isfinite(v)) m_in.fail(at, what + " is not finite");
    return v;
  }
  /// `count` finite f32 into `out`.
  void finiteColumn(std::vector<float>& out, std::size_t count, const std::string& what) {
    out.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
      const std::uint64_t at = fileOffset();
      out[k] = f32();
      if (!std::isfinite(out[k])) m_in.fail(at, what + "[" + std::to_string(k) + "] is not finite");
    }
  }

 private:
  const InFile& m_in;
  const std::vector<std::uint8_t>& m_buf;
  std::uint64_t m_base;
  std::size_t m_pos;
};

/// Reads the next u32 checksum after a block and compares it with the block's FNV-1a.
inline void checkChecksum(const InFile& in, const std::vector<std::uint8_t>& buf, std::size_t from,
                   std::size_t to, std::uint64_t checksumOffset, const std::string& what) {
  const std::uint32_t stored = getU32(buf.data() + to);
  const std::uint32_t computed = fnv1a(buf.data() + from, to - from);
  if (stored != computed) {
    in.fail(checksumOffset, what + " checksum mismatch (stored " + hex32(stored) + ", computed " +
                                hex32(computed) + "): the file is corrupt");
  }
}

}  // namespace tumble::detail
