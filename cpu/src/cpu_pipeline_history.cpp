// SPDX-License-Identifier: MIT
// The CPU pipeline's contact histories kept across a rebuild (or from the load) and read back,
// for sphere pairs and sphere–triangle contacts.
#include "cpu_pipeline_impl.hpp"

namespace tumble::cpu::impl {

// keyOf(e): the key of entry e of the rows offsets[i] .. offsets[i+1] (internal numbering);
// count → scan → fill by scene index (kernels/history.hpp, as the CUDA pipeline).
template <class KeyOf>
void CpuPipeline::keepRows(const std::vector<std::uint32_t>& offsets, const std::vector<Vec3f>& hist, const KeyOf& keyOf,
                           KeptHistories& out) {
  const std::uint32_t n = m_world.numParticles();
  std::uint32_t* count = tumble::detail::grow(out.count, std::size_t(n) + 1);
  forEach(n, kGrain, [&](std::uint32_t i) {
    count[m_orig[i]] = takenCount(offsets.data(), hist.data(), keyOf, TakeAll{}, i, m_orig[i]);
  });
  count[n] = 0;
  out.offsets.resize(std::size_t(n) + 1);
  scanCounts(count, std::size_t(n) + 1, out.offsets.data());
  out.key.resize(out.offsets[n]);
  out.hist.resize(out.offsets[n]);
  forEach(n, kGrain, [&](std::uint32_t i) {
    takeRow(offsets.data(), hist.data(), keyOf, TakeAll{}, i, m_orig[i], out.offsets[m_orig[i]], out.key.data(),
            out.hist.data());
  });
}

template <class KeyOf>
void CpuPipeline::restoreRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets, const KeyOf& keyOf,
                              std::vector<Vec3f>& hist) {
  const std::uint32_t n = m_world.numParticles();
  hist.resize(offsets[n]);
  const KeptView k{kept.offsets.data(), kept.key.data(), kept.hist.data()};
  forEach(n, kGrain, [&](std::uint32_t i) { restoreRow(k, m_orig[i], offsets.data(), keyOf, i, hist.data()); });
}

// The entries with a key and a non-zero ξ that `take` accepts, as make(scene index, key, ξ),
// sorted by (scene index, key): taken out of the rows of a list (count → scan → fill by scene
// index, kernels/history.hpp, as the CUDA pipeline), or before the first rebuild (loaded, not
// stepped) from the kept histories.
template <class Out, class KeyOf, class Take, class Make>
std::vector<Out> CpuPipeline::readRows(const KeptHistories& kept, const std::vector<std::uint32_t>& offsets,
                                       const std::vector<Vec3f>& hist, const KeyOf& keyOf, const Take& take, const Make& make) const {
  const std::uint32_t n = m_world.numParticles();
  if (!m_listBuilt)
    return tumble::detail::readRows<Out>(n, kept.offsets.data(), kept.key.data(), kept.hist.data(), take, make);
  std::vector<std::uint32_t> at(std::size_t(n) + 1, 0u);
  m_arena.execute([&] {
    forEach(n, kGrain, [&](std::uint32_t i) {
      at[m_orig[i] + 1] = takenCount(offsets.data(), hist.data(), keyOf, take, i, m_orig[i]);
    });
  });
  for (std::uint32_t o = 0; o < n; ++o) at[o + 1] += at[o];
  std::vector<std::uint32_t> key(at[n]);
  std::vector<Vec3f> taken(at[n]);
  m_arena.execute([&] {
    forEach(n, kGrain, [&](std::uint32_t i) {
      takeRow(offsets.data(), hist.data(), keyOf, take, i, m_orig[i], at[m_orig[i]], key.data(), taken.data());
    });
  });
  return tumble::detail::readRows<Out>(n, at.data(), key.data(), taken.data(), TakeAll{}, make);
}

void CpuPipeline::keepHistory() { keepRows(m_candOffsets, m_hist, PartnerKey{m_orig.data(), m_cand.data()}, m_keep); }

void CpuPipeline::restoreHistory() { restoreRows(m_keep, m_candOffsets, PartnerKey{m_orig.data(), m_cand.data()}, m_hist); }

// The histories of a loaded state (BodyState::contacts, i < j sorted) in the kept form.
void CpuPipeline::keepLoadedHistory(const std::vector<ContactHistory>& contacts) {
  static_cast<tumble::detail::KeptRows&>(m_keep) = tumble::detail::keptOfContacts(m_world.numParticles(), contacts);
}

// BodyState::contacts: the non-zero ξ of the pairs i < j (scene indices), sorted.
void CpuPipeline::readHistory(std::vector<ContactHistory>& out) const {
  out.clear();
  if (!m_history) return;
  out = readRows<ContactHistory>(m_keep, m_candOffsets, m_hist, PartnerKey{m_orig.data(), m_cand.data()}, TakeAbove{},
                                 tumble::detail::MakeContact{});
}

// The mesh springs: kept and restored by triangle; a loaded state's (BodyState::meshContacts,
// sorted by (particle, triangle)) in the kept form.
void CpuPipeline::keepMeshHistory() { keepRows(m_meshOffsets, m_meshHist, TriangleKey{m_meshTri.data()}, m_meshKeep); }

void CpuPipeline::restoreMeshHistory() { restoreRows(m_meshKeep, m_meshOffsets, TriangleKey{m_meshTri.data()}, m_meshHist); }

void CpuPipeline::keepLoadedMeshHistory(const std::vector<MeshContactHistory>& contacts) {
  static_cast<tumble::detail::KeptRows&>(m_meshKeep) =
      tumble::detail::keptOfMeshContacts(m_world.numParticles(), contacts);
}

void CpuPipeline::readMeshHistory(std::vector<MeshContactHistory>& out) const {
  out.clear();
  if (!m_hasMesh) return;
  out = readRows<MeshContactHistory>(m_meshKeep, m_meshOffsets, m_meshHist, TriangleKey{m_meshTri.data()}, TakeAll{},
                                     tumble::detail::MakeMeshContact{});
}

}  // namespace tumble::cpu::impl
