// SPDX-License-Identifier: MIT
// The CUDA pipeline's detection in a periodic box, written once over the execution layer
// (exec/exec.hpp): the count → scan → fill steps of kernels/periodic_images.hpp, whose
// per-element functions the CPU pipeline calls too (cpu/src/periodic_images.cpp), so that the
// images, the ghosts' numbering and every row are the same bits. Internal to tumble::gpu.
//
// Host round trips per rebuild: the ghosts' total, the rows' room and the rows' total.
#pragma once
#include <cstdint>

#include "exec/exec.hpp"
#include "tumble/kernels/contact_list.hpp"
#include "tumble/kernels/periodic_images.hpp"

namespace tumble::gpu::detail {
inline namespace TUMBLE_EXEC_ABI {  // one copy per compiler (exec.hpp)

// Element n writes the trailing zero of the counts.
struct WrapImageFn {
  BroadphaseInput in;
  PeriodicBox box;
  float reach;
  float *x, *y, *z, *r;
  std::uint32_t* body;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    count[i] = i < in.n ? wrapImage(in, box, reach, i, x, y, z, r, body) : 0u;
  }
};

struct WriteGhostsFn {
  PeriodicBox box;
  float reach;
  std::uint32_t n;
  const std::uint32_t* ghostFirst;
  float *x, *y, *z, *r;
  std::uint32_t* body;
  std::uint32_t* ghostOf;
  TUMBLE_HD void operator()(std::uint32_t i) const { writeGhosts(box, reach, n, i, ghostFirst, x, y, z, r, body, ghostOf); }
};

// Element n writes the trailing zero of the counts.
struct PeriodicRowBoundFn {
  SweepListView s;
  PeriodicImagesView v;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const { count[i] = i < v.n ? periodicRowBound(s, v, i) : 0u; }
};

// Writes each row at its room and its length over the room's count (count[n] stays 0).
struct PeriodicRowFillFn {
  SweepListView s;
  PeriodicImagesView v;
  const std::uint32_t* orig;
  const std::uint32_t* room;
  std::uint32_t* rows;
  std::uint32_t* key;
  std::uint32_t* count;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    count[i] = fillPeriodicRow(s, v, orig, i, rows + room[i], key + room[i]);
  }
};

struct CompactRowFn {
  const std::uint32_t* room;
  const std::uint32_t* rows;
  const std::uint32_t* offsets;
  std::uint32_t* cand;
  TUMBLE_HD void operator()(std::uint32_t i) const {
    for (std::uint32_t e = offsets[i], a = room[i]; e < offsets[i + 1]; ++e, ++a) cand[e] = rows[a];
  }
};

/// The images of a periodic detection and the rows built from the sweep over them (as
/// cpu::detail::PeriodicImages and CpuPipeline::buildPeriodicList).
template <class Exec>
class PeriodicImages {
 public:
  using Stream = typename Exec::Stream;
  template <class T>
  using Buffer = typename Exec::template Buffer<T>;

  /// Builds the images of in's particles (radii and maxRadius as the sweep is to use them).
  /// wrapImage() writes the particles' columns; where their ghosts need more room than the
  /// columns have, the columns grow (which discards them) and the count runs again: once the
  /// sizes have settled, it never does.
  void build(const BroadphaseInput& in, const PeriodicBox& box, float reach, const Stream& s) {
    const std::uint32_t n = in.n;
    m_n = n;
    std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
    std::uint32_t* first = m_ghostFirst.grow(std::size_t(n) + 1);
    const auto wrap = [&](std::size_t size) {
      for (auto* c : {&m_x, &m_y, &m_z, &m_r}) c->grow(size);
      m_body.grow(size);
      Exec::forEach(s, std::uint64_t(n) + 1,
                    WrapImageFn{in, box, reach, m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(), count},
                    "wrapImage");
    };
    wrap(n);
    Exec::exclusiveSum(s, m_temp, count, first, n + 1);
    std::uint32_t numGhosts = 0;
    Exec::copyToHost(s, &numGhosts, first + n, 1);
    s.synchronize();
    const std::size_t total = std::size_t(n) + numGhosts;
    if (m_x.capacity() < total || m_body.capacity() < total) wrap(total);
    for (auto* c : {&m_x, &m_y, &m_z, &m_r}) c->grow(total);  // within their room: the contents stay
    m_body.grow(total);
    Exec::forEach(s, n,
                  WriteGhostsFn{box, reach, n, first, m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(),
                                m_ghostOf.grow(numGhosts)},
                  "writeGhosts");
    m_in = BroadphaseInput{m_x.data(), m_y.data(), m_z.data(), m_r.data(), m_body.data(),
                           static_cast<std::uint32_t>(total), in.maxRadius, in.cellRadius};
  }

  /// The sweep's input over the images.
  const BroadphaseInput& input() const { return m_in; }
  PeriodicImagesView view() const { return {m_n, m_ghostFirst.data(), m_ghostOf.data()}; }

  /// The candidate list from the sweep over the images: each particle's row (fillPeriodicRow(),
  /// sorted by orig, each partner once) at offsets (n + 1) in cand; key is scratch. Returns the
  /// list's length.
  std::uint32_t rows(const SweepListView& sweep, const std::uint32_t* orig, Buffer<std::uint32_t>& offsets,
                     Buffer<std::uint32_t>& cand, Buffer<std::uint32_t>& key, const Stream& s) {
    const std::uint32_t n = m_n;
    const PeriodicImagesView v = view();
    std::uint32_t* count = m_count.grow(std::size_t(n) + 1);
    std::uint32_t* room = m_room.grow(std::size_t(n) + 1);
    Exec::forEach(s, std::uint64_t(n) + 1, PeriodicRowBoundFn{sweep, v, count}, "periodicRowBound");
    Exec::exclusiveSum(s, m_temp, count, room, n + 1);
    std::uint32_t roomTotal = 0;
    Exec::copyToHost(s, &roomTotal, room + n, 1);
    s.synchronize();
    std::uint32_t* rows = m_rows.grow(roomTotal);
    Exec::forEach(s, n, PeriodicRowFillFn{sweep, v, orig, room, rows, key.grow(roomTotal), count}, "periodicRowFill");
    std::uint32_t* at = offsets.grow(std::size_t(n) + 1);
    Exec::exclusiveSum(s, m_temp, count, at, n + 1);
    std::uint32_t total = 0;
    Exec::copyToHost(s, &total, at + n, 1);
    s.synchronize();
    Exec::forEach(s, n, CompactRowFn{room, rows, at, cand.grow(total)}, "compactRow");
    return total;
  }

 private:
  std::uint32_t m_n = 0;
  BroadphaseInput m_in{};
  Buffer<float> m_x, m_y, m_z, m_r;
  Buffer<std::uint32_t> m_body, m_count, m_ghostFirst, m_ghostOf, m_room, m_rows;
  Buffer<unsigned char> m_temp;
};

}  // namespace TUMBLE_EXEC_ABI
}  // namespace tumble::gpu::detail
