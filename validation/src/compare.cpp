// SPDX-License-Identifier: MIT
#include "tumble/validation/compare.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <memory>

#include "tumble/factory.hpp"
#include "tumble/random.hpp"
#include "tumble/validation/brute_force.hpp"
#include "tumble/validation/scenes.hpp"

namespace tumble::validation {
namespace {

std::string firstDifference(const std::vector<Pair>& got, const std::vector<Pair>& want) {
  std::vector<Pair> missing, extra;
  std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
  std::set_difference(got.begin(), got.end(), want.begin(), want.end(), std::back_inserter(extra));
  if (missing.empty() && extra.empty()) return {};
  std::string s = std::to_string(missing.size()) + " missing, " + std::to_string(extra.size()) + " extra";
  if (!missing.empty()) s += ", e.g. (" + std::to_string(missing[0].i) + "," + std::to_string(missing[0].j) + ") missing";
  if (!extra.empty()) s += ", e.g. (" + std::to_string(extra[0].i) + "," + std::to_string(extra[0].j) + ") extra";
  return s;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The first difference of two history lists (ContactHistory, MeshContactHistory: indices a, b
// and ξ), named by names: the count, a, b, and ξ (its component appended).
template <class H>
std::optional<StateDifference> firstHistoryDifference(const std::vector<H>& x, const std::vector<H>& y,
                                                      std::uint32_t H::*a, std::uint32_t H::*b,
                                                      const std::array<const char*, 4>& names) {
  if (x.size() != y.size()) return StateDifference{names[0], 0, float(x.size()), float(y.size())};
  for (std::size_t k = 0; k < x.size(); ++k) {
    const H &hx = x[k], &hy = y[k];
    const auto at = static_cast<std::uint32_t>(k);
    if (hx.*a != hy.*a) return StateDifference{names[1], at, float(hx.*a), float(hy.*a)};
    if (hx.*b != hy.*b) return StateDifference{names[2], at, float(hx.*b), float(hy.*b)};
    if (!sameBits(hx.x, hy.x)) return StateDifference{std::string(names[3]) + " x", at, hx.x, hy.x};
    if (!sameBits(hx.y, hy.y)) return StateDifference{std::string(names[3]) + " y", at, hx.y, hy.y};
    if (!sameBits(hx.z, hy.z)) return StateDifference{std::string(names[3]) + " z", at, hx.z, hy.z};
  }
  return std::nullopt;
}

}  // namespace

std::vector<PairCase> comparePairSets(const std::vector<Backend>& pipelines, std::uint64_t seed, int numRandom) {
  std::vector<NamedCloud> cases = hardCases(seed);
  Rng rng(seed);
  for (int k = 0; k < numRandom; ++k) {
    const std::uint64_t s = seed + static_cast<std::uint64_t>(k);
    const std::uint32_t n = 100 + rng.below(20000);
    const float rmin = rng.uniform(0.02f, 0.5f);
    cases.push_back({"random seed " + std::to_string(s) + " n " + std::to_string(n),
                     randomCloud(n, s, rng.uniform(2.0f, 80.0f), rmin, rmin * rng.uniform(1.0f, 10.0f),
                                 1 + rng.below(8))});
  }
  std::vector<std::unique_ptr<Pipeline>> ps;
  for (Backend b : pipelines) ps.push_back(makePipeline(b));
  std::vector<PairCase> out;
  for (const auto& c : cases) {
    PairCase pc;
    pc.name = c.name;
    const auto want = bruteForcePairs(c.cloud);
    pc.oraclePairs = want.size();
    for (auto& p : ps) {
      const auto got = p->findPairs(c.cloud, BroadphaseParams{});
      const std::string d = firstDifference(got, want);
      pc.matches.push_back(d.empty());
      pc.detail.push_back(d);
    }
    out.push_back(std::move(pc));
  }
  return out;
}

std::string StateDifference::describe() const {
  char buf[200];
  const bool spring = quantity.rfind("ground", 0) == 0, contact = quantity.rfind("contact", 0) == 0;
  std::snprintf(buf, sizeof buf, "%s of %s %u: %.9g vs %.9g", quantity.c_str(),
                spring ? "plane spring (plane k, particle i at k × particles + i)" : contact ? "entry" : "body", index,
                a, b);
  return buf;
}

std::optional<StateDifference> firstDifference(const BodyState& a, const BodyState& b) {
  const std::vector<float> BodyState::*cols[] = {&BodyState::px, &BodyState::py, &BodyState::pz, &BodyState::vx,
                                                 &BodyState::vy, &BodyState::vz, &BodyState::qw, &BodyState::qx,
                                                 &BodyState::qy, &BodyState::qz, &BodyState::lx, &BodyState::ly,
                                                 &BodyState::lz, &BodyState::groundSpringX, &BodyState::groundSpringY};
  const char* names[] = {"px", "py", "pz", "vx", "vy", "vz", "qw", "qx",
                         "qy", "qz", "lx", "ly", "lz", "groundSpringX", "groundSpringY"};
  for (int c = 0; c < 15; ++c) {
    const std::vector<float>& ca = a.*cols[c];
    const std::vector<float>& cb = b.*cols[c];
    if (ca.size() != cb.size()) return StateDifference{std::string(names[c]) + " (length)", 0, float(ca.size()), float(cb.size())};
    for (std::size_t k = 0; k < ca.size(); ++k)
      if (!sameBits(ca[k], cb[k])) return StateDifference{names[c], static_cast<std::uint32_t>(k), ca[k], cb[k]};
  }
  // Image counters of the periodic boundaries (index: the body).
  for (const auto& [col, name] : {std::pair<const std::vector<std::int32_t> BodyState::*, const char*>{&BodyState::imageX, "imageX"},
                                  {&BodyState::imageY, "imageY"}}) {
    const std::vector<std::int32_t>& ca = a.*col;
    const std::vector<std::int32_t>& cb = b.*col;
    if (ca.size() != cb.size()) return StateDifference{std::string(name) + " (length)", 0, float(ca.size()), float(cb.size())};
    for (std::size_t k = 0; k < ca.size(); ++k)
      if (ca[k] != cb[k]) return StateDifference{name, static_cast<std::uint32_t>(k), float(ca[k]), float(cb[k])};
  }
  // Contact histories and mesh springs: the same pairs with the same bits (index: the entry).
  if (auto d = firstHistoryDifference(a.contacts, b.contacts, &ContactHistory::i, &ContactHistory::j,
                                      {"contacts (count)", "contact i", "contact j", "contact history"}))
    return d;
  return firstHistoryDifference(a.meshContacts, b.meshContacts, &MeshContactHistory::particle,
                                &MeshContactHistory::triangle,
                                {"contact (mesh) count", "contact (mesh) particle", "contact (mesh) triangle",
                                 "contact (mesh) spring"});
}

BodyState stateAfter(Backend backend, const World& world, std::uint64_t steps, const PipelineOptions& options) {
  auto p = makePipeline(backend, options);
  p->load(world);
  p->step(steps);
  BodyState s;
  p->readState(s);
  return s;
}

std::optional<StepDifference> firstStepDifference(Pipeline& a, const World& worldA, Pipeline& b, const World& worldB,
                                                  std::uint64_t steps, bool debug, const Pouring* pouring) {
  World wa = worldA, wb = worldB;  // grown by the pours
  a.load(wa);
  b.load(wb);
  a.setDebugCapture(debug);
  b.setDebugCapture(debug);
  BodyState sa, sb;
  ParticleDebug da, db;
  for (std::uint64_t s = 1; s <= steps; ++s) {
    if (pouring != nullptr) {
      pouring->step(a, wa, 1, nullptr);
      pouring->step(b, wb, 1, nullptr);
      if (wa.numBodies() != wb.numBodies())
        return StepDifference{s, "step " + std::to_string(s) + ": the pours brought " +
                                     std::to_string(wa.numBodies()) + " vs " + std::to_string(wb.numBodies()) +
                                     " bodies"};
    } else {
      a.step(1);
      b.step(1);
    }
    const std::string at = "step " + std::to_string(s) + ": ";
    if (const std::string d = firstDifference(a.pairs(), b.pairs()); !d.empty())
      return StepDifference{s, at + "pairs: " + d + " (of the second against the first)"};
    if (const std::vector<MeshContact> ma = a.meshContacts(), mb = b.meshContacts(); ma != mb) {
      std::size_t k = 0;
      while (k < ma.size() && k < mb.size() && ma[k] == mb[k]) ++k;
      return StepDifference{s, at + "mesh contacts: " + std::to_string(ma.size()) + " vs " + std::to_string(mb.size()) +
                                   ", the first difference at entry " + std::to_string(k)};
    }
    a.readState(sa);
    b.readState(sb);
    if (const auto d = firstDifference(sa, sb)) return StepDifference{s, at + d->describe()};
    if (!debug) continue;
    a.readDebug(da);
    b.readDebug(db);
    for (int k = -1; k < 5; ++k) {
      const std::vector<float>& va = k < 0 ? da.v : da.force[k];
      const std::vector<float>& vb = k < 0 ? db.v : db.force[k];
      const std::string name = std::string("debug ") + (k < 0 ? "v" : kDebugForceNames[k]);
      if (va.size() != vb.size()) return StepDifference{s, at + name + ": lengths differ"};
      for (std::size_t e = 0; e < va.size(); ++e)
        if (!sameBits(va[e], vb[e])) {
          char buf[200];
          std::snprintf(buf, sizeof buf, "%s %c of particle %zu: %.9g vs %.9g", name.c_str(), "xyz"[e % 3], e / 3,
                        va[e], vb[e]);
          return StepDifference{s, at + buf};
        }
    }
    if (da.contactForces.size() != db.contactForces.size())
      return StepDifference{s, at + "debug contact forces: " + std::to_string(da.contactForces.size()) + " vs " +
                                   std::to_string(db.contactForces.size())};
    for (std::size_t c = 0; c < da.contactForces.size(); ++c) {
      const ContactForce &x = da.contactForces[c], &y = db.contactForces[c];
      const float vx[8] = {x.n.x, x.n.y, x.n.z, x.fn, x.tangential.x, x.tangential.y, x.tangential.z, x.overlap};
      const float vy[8] = {y.n.x, y.n.y, y.n.z, y.fn, y.tangential.x, y.tangential.y, y.tangential.z, y.overlap};
      bool same = x.i == y.i && x.j == y.j;
      for (int k = 0; k < 8; ++k) same = same && sameBits(vx[k], vy[k]);
      if (!same)
        return StepDifference{s, at + "debug contact force " + std::to_string(c) + " (" + std::to_string(x.i) + ", " +
                                     std::to_string(x.j) + ") differs"};
    }
  }
  return std::nullopt;
}

TrajectoryResult compareTrajectories(Pipeline& a, Pipeline& b, const World& world, std::uint64_t steps,
                                     const TrajectoryTolerance& tol) {
  TrajectoryResult r;
  a.load(world);
  b.load(world);
  const float rmin = *std::min_element(world.radius.begin(), world.radius.end());
  BodyState sa, sb;
  for (std::uint64_t s = 1; s <= steps; ++s) {
    a.step(1);
    b.step(1);
    a.readState(sa);
    b.readState(sb);
    r.steps = s;
    if (r.pairsIdentical && (a.pairs() != b.pairs() || a.meshContacts() != b.meshContacts())) {
      r.pairsIdentical = false;
      r.firstPairMismatchStep = s;
    }

    for (std::uint32_t k = 0; k < sa.size(); ++k) {
      const float* ca[] = {&sa.px[k], &sa.py[k], &sa.pz[k], &sa.vx[k], &sa.vy[k], &sa.vz[k], &sa.qw[k],
                           &sa.qx[k], &sa.qy[k], &sa.qz[k], &sa.lx[k], &sa.ly[k], &sa.lz[k]};
      const float* cb[] = {&sb.px[k], &sb.py[k], &sb.pz[k], &sb.vx[k], &sb.vy[k], &sb.vz[k], &sb.qw[k],
                           &sb.qx[k], &sb.qy[k], &sb.qz[k], &sb.lx[k], &sb.ly[k], &sb.lz[k]};
      bool same = true;
      for (int c = 0; c < 13; ++c) same = same && sameBits(*ca[c], *cb[c]);
      if (!same && r.bitwiseIdentical) {
        r.bitwiseIdentical = false;
        r.firstDifferentStep = s;
        r.firstDifferentBody = k;
      }
      if (same) continue;
      const double dx = double(sa.px[k]) - sb.px[k], dy = double(sa.py[k]) - sb.py[k],
                   dz = double(sa.pz[k]) - sb.pz[k];
      const double dpos = std::sqrt(dx * dx + dy * dy + dz * dz) / rmin;
      const double dot = double(sa.qw[k]) * sb.qw[k] + double(sa.qx[k]) * sb.qx[k] + double(sa.qy[k]) * sb.qy[k] +
                         double(sa.qz[k]) * sb.qz[k];
      const double sign = dot < 0 ? -1.0 : 1.0;  // q and −q are the same rotation
      const double qw = sa.qw[k] - sign * sb.qw[k], qx = sa.qx[k] - sign * sb.qx[k],
                   qy = sa.qy[k] - sign * sb.qy[k], qz = sa.qz[k] - sign * sb.qz[k];
      const double dq = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
      if (s <= tol.horizon) {
        r.maxPositionDev = std::max(r.maxPositionDev, dpos);
        r.maxOrientationDev = std::max(r.maxOrientationDev, dq);
        if (r.firstOutOfTolStep == 0 && (!(dpos <= tol.positionTol) || !(dq <= tol.orientationTol))) {
          r.firstOutOfTolStep = s;
          r.firstOutOfTolBody = k;
        }
      }
    }
    if (r.bitwiseIdentical && firstDifference(sa, sb)) {  // the bodies agree, the contact history does not
      r.bitwiseIdentical = false;
      r.firstDifferentStep = s;
    }
  }
  return r;
}

}  // namespace tumble::validation
