// SPDX-License-Identifier: MIT
// One step of the CPU pipeline: the decision between rebuild, refresh and neither, and the
// per-body pass (forces, integration, next rows, skin test) instantiated per law and option.
#include "cpu_pipeline_impl.hpp"

namespace tumble::cpu::impl {

// After a step's skin test (the drift of every particle since the reference of the list the
// step read): whether the next step rebuilds the candidate list or refreshes the near list.
// `next` is the time the next step starts at: moving meshes add their motion since the
// rebuild up to it.
void CpuPipeline::decideList(const Drift& drift, double next) {
  const float closure = closureFor(drift);
  const double meshes = m_meshMotion.any() ? m_meshMotion.closure(m_rebuildTime, next) : 0.0;
  m_needRebuild = !(m_closed + double(closure) + meshes < double(m_fullLimit));
  // The near list holds sphere pairs only: their closure is enough for it (closureOf(), which
  // a common motion does not use up, where the walls' bound is 2 max |dx|).
  const float pairClosure = m_hasMesh ? closureOf(drift) : closure;
  m_needRefresh = m_nearSkin > 0.0f && !(pairClosure < m_nearLimit);
  m_lastClosure = closure;
}

void CpuPipeline::stepOnce() {
  double* sec = m_stats.seconds;
  if (m_wallsMove)
    setWallMotion(m_planes, m_world.params, m_time, m_meshPoses.empty() ? nullptr : m_meshPoses.data());
  if (m_needRebuild)
    rebuild();
  else if (m_needRefresh)
    refreshNear();

  const auto t0 = Clock::now();
  StepTotals tot;
  if (m_debug) {
    for (auto& d : m_dbg) tumble::detail::grow(d, 3 * std::size_t(m_world.numParticles()));
    tumble::detail::grow(m_dbgVel, 3 * std::size_t(m_world.numParticles()));
    tumble::detail::grow(m_dbgContact, contactListView().begin[m_world.numParticles()]);  // an entry each (compact)
    tot = advanceAs<true>();
  } else {
    tot = m_tallyOn ? advanceAs<true>() : advanceAs<false>();  // the tally: the debug pass, no capture
  }
  m_hasDebug = m_debug;  // readDebug() reads the last step's capture, or refuses
  m_hasFlows = m_tallyOn;
  if (m_tallyOn) tallyStep();
  m_cur = 1 - m_cur;
  m_bodies.swap(m_bodiesNext);
  decideList(tot.drift, m_time + m_world.params.dt);
  sec[int(Phase::Forces)] += since(t0);

  ++m_steps;
  m_time += m_world.params.dt;
  ++m_stats.steps;
  m_stats.numPairs = tot.contacts / 2;  // each contact is seen from both sides
}

// advance() instantiated for the scene's law, bodies, periodic boundaries and moving meshes
// (a periodic scene has no mesh).
template <bool kDebug>
StepTotals CpuPipeline::advanceAs() {
  if (m_periodic.axes != 0) return advanceLaw<kDebug, true, false>();
  return m_meshPoses.empty() ? advanceLaw<kDebug, false, false>() : advanceLaw<kDebug, false, true>();
}

template <bool kDebug, bool kPeriodic, bool kPosedMesh>
StepTotals CpuPipeline::advanceLaw() {
  switch (m_law) {
    case ContactLaw::HookeHistory: return advance<kDebug, true, ContactLaw::HookeHistory, kPeriodic, kPosedMesh>();
    case ContactLaw::HertzMindlin: return advance<kDebug, true, ContactLaw::HertzMindlin, kPeriodic, kPosedMesh>();
    default:
      return m_clumps ? advance<kDebug, true, ContactLaw::Report, kPeriodic, kPosedMesh>()
                      : advance<kDebug, false, ContactLaw::Report, kPeriodic, kPosedMesh>();
  }
}

// Stages 3–7 and the next step's stage 1, one pass over the bodies (see the design notes).
template <bool kDebug, bool kClumps, ContactLaw kLaw, bool kPeriodic, bool kPosedMesh>
StepTotals CpuPipeline::advance() {
  StepView v = stepView();
  const ForceParams fp = makeForceParams(m_world.params, m_pulls);
  DebugForcesView dbg{{nullptr, nullptr, nullptr, nullptr, nullptr}, nullptr, nullptr};
  if constexpr (kDebug) {
    if (m_debug) {  // else the energy tally's pass alone
      for (int k = 0; k < 5; ++k) dbg.f[k] = m_dbg[k].data();
      dbg.v = m_dbgVel.data();
      dbg.contact = m_dbgContact.data();
    }
    if (m_tallyOn) {
      m_bodyFlows.resize(m_bodies.size());
      v.bodyFlows = m_bodyFlows.data();
    }
  }
  const float dt = m_world.params.dt;
  const Vec3f g = m_world.params.gravity;
  const RotationScheme scheme = m_world.params.integrator.rotation;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::uint32_t>(0, v.numBodies, kBodyGrain), StepTotals{},
      [&](const auto& rg, StepTotals acc) {
        for (std::uint32_t k = rg.begin(); k != rg.end(); ++k)
          acc.contacts +=
              stepBody<kDebug, kClumps, kLaw, kPeriodic, kPosedMesh, true>(v, fp, dbg, g, dt, scheme, k, &acc.drift);
        return acc;
      },
      [](StepTotals x, const StepTotals& y) {
        mergeDrift(x.drift, y.drift);
        x.contacts += y.contacts;
        return x;
      });
}

// The energy tally: the last step's flows of every body added (exact integer sums: any order).
void CpuPipeline::tallyStep() {
  const float dt = m_world.params.dt;
  const EnergyFlows* flows = m_bodyFlows.data();
  m_tally.add(tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, m_bodyFlows.size(), 4096), noLimbs(),
      [&](const auto& rg, EnergyLimbs acc) {
        for (std::size_t k = rg.begin(); k != rg.end(); ++k) addEnergy(acc, flows[k], dt);
        return acc;
      },
      [](EnergyLimbs x, const EnergyLimbs& y) {
        addLimbs(x, y);
        return x;
      }));
  m_stats.energy = m_tally.joules();
}

StepView CpuPipeline::stepView() {
  const int c = m_cur;
  return StepView{m_bodies.data(),
                  m_bodiesNext.data(),
                  m_bodyStatic.data(),
                  static_cast<std::uint32_t>(m_bodies.size()),
                  m_pos[c].data(),
                  m_pos[1 - c].data(),
                  m_own.data(),
                  m_radius.data(),
                  m_mass.data(),
                  m_bodyOf.data(),
                  m_orig.data(),
                  GroundSpringView{m_gtx.data(), m_gty.data()},
                  m_perBody ? nullptr : m_buildPos.data(),  // the skin test per particle, or per body (bodyRef)
                  contactListView(),
                  m_touching.data(),
                  m_world.numParticles(),
                  m_history ? m_hist.data() : nullptr,
                  m_world.params.contact.rotatesSpheres(),
                  m_world.materialPairs.empty() ? nullptr : m_world.materialPairs.data(),
                  m_material.empty() ? nullptr : m_material.data(),
                  static_cast<std::uint32_t>(m_world.params.materials.size()),
                  m_planes.data(),
                  static_cast<std::uint32_t>(m_planes.size()),
                  m_planeDamping.empty() ? nullptr : m_planeDamping.data(),
                  m_planeHertz.empty() ? nullptr : m_planeHertz.data(),
                  m_periodic,
                  m_mesh.view(m_meshPoses),
                  MeshListView{m_meshOffsets.data(), m_meshTri.data(), m_meshHist.data()},
                  m_perBody ? m_bodyRef.data() : nullptr,
                  m_owner.empty() ? nullptr : m_owner.data(),
                  m_history && m_nearSkin > 0.0f ? m_nearSlot.data() : nullptr};
}

// The arrays of the fused pass (advance(): stepBody() per body, the body batch) a step without
// a rebuild or refresh reads and writes, each counted once per read and once per write at its
// size now (docs/performance.md, "The memory floor"). What a step reads only for some
// particles is counted whole where most particles read it (a partner's rows are counted with
// the partner); the scene index (m_orig: coincident centres only) and the masses (pulls only) are
// left out.
std::vector<TrafficLine> CpuPipeline::stepTraffic() const {
  const double n = m_world.numParticles(), nb = double(m_bodies.size());
  const bool nearList = m_nearSkin > 0.0f;
  const double entries = double(nearList ? m_near.size() : m_cand.size());
  const double touching = 2.0 * double(m_stats.numPairs);  // both directions of each contact
  constexpr double kU32 = sizeof(std::uint32_t), kF32 = sizeof(float);
  std::vector<TrafficLine> t;
  const auto add = [&t](const char* what, double bytes) {
    if (bytes > 0.0) t.push_back(TrafficLine{what, bytes});
  };
  add("particle positions (PosRow: this step's read, the next written)", 2.0 * n * sizeof(PosRow));
  add("own rows (OwnRow: body-frame offset, ground damping; read)", n * sizeof(OwnRow));
  add("radii (read for the next positions)", n * kF32);
  if (m_clumps) add("body of each particle (read: the partners' bodies)", n * kU32);
  add("contacts per particle (written)", n * sizeof(std::uint8_t));
  add("the list's row offsets (read)", (n + 1.0) * kU32);
  add(nearList ? "near-list entries (read)" : "candidate-list entries (read)", entries * kU32);
  if (!m_owner.empty()) add("the entries' particles (read: the body batch)", entries * kU32);
  if (m_history) {
    if (nearList) add("the near entries' candidate entries (read: where their xi is)", entries * kU32);
    add("xi of the list's entries (read) and of the contacts (written)", (entries + touching) * sizeof(Vec3f));
  }
  if (!m_material.empty()) add("materials (read)", n * sizeof(std::uint16_t));
  add("body rows (BodyRow: this step's read, the next written)", 2.0 * nb * sizeof(BodyRow));
  add("body static rows (BodyStatic: read)", nb * sizeof(BodyStatic));
  if (m_perBody)
    add("the skin test's reference per body (BodyRef: read)", nb * sizeof(BodyRef));
  else
    add("the skin test's reference positions (PosRow: read)", n * sizeof(PosRow));
  add("plane springs (two floats per plane and particle: read and written)",
      2.0 * double(m_gtx.size() + m_gty.size()) * kF32);
  add("plane damping of the walls (read)", double(m_planeDamping.size()) * kF32);
  if (m_hasMesh)
    add("mesh rows: offsets and triangles (read), springs (read and written)",
        (n + 1.0) * kU32 + double(m_meshTri.size()) * kU32 + 2.0 * double(m_meshHist.size()) * sizeof(Vec3f));
  return t;
}

}  // namespace tumble::cpu::impl
