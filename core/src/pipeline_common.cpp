// SPDX-License-Identifier: MIT
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/sweep_frame.hpp"

namespace tumble {

const char* toString(Backend b) {
  switch (b) {
    case Backend::Cpu: return "cpu";
    case Backend::Cuda: return "cuda";
    case Backend::CudaHost: return "cuda-host";
  }
  return "?";
}

Backend backendFromString(const std::string& s) {
  for (Backend b : {Backend::Cpu, Backend::Cuda, Backend::CudaHost})
    if (s == toString(b)) return b;
  throw Error("unknown pipeline '" + s + "' (expected cpu, cuda or cuda-host)");
}

bool cudaRequired() {
  const char* env = std::getenv("TUMBLE_REQUIRE_CUDA");
  return env != nullptr && std::strcmp(env, "1") == 0;
}

void requireReady(const CudaStatus& s) {
  if (s.state != CudaState::Ready) throw Error("the CUDA pipeline cannot run: " + s.message + "; use --pipeline cpu");
}

std::vector<ContactForce> capturedContacts(const ContactForce* capture, std::size_t entries) {
  std::vector<ContactForce> out;
  for (std::size_t e = 0; e < entries; ++e)
    if (capture[e].i != kNoContact && capture[e].i < capture[e].j) out.push_back(capture[e]);
  std::sort(out.begin(), out.end());  // the keys are unique
  return out;
}

std::array<double, 3> contactBranch(const ContactForce& c, float ri, float rj) {
  const double length = (double(ri) + rj) - c.overlap;
  return {c.n.x * length, c.n.y * length, c.n.z * length};
}

const char* toString(Phase p) {
  switch (p) {
    case Phase::Reorder: return "reorder";
    case Phase::State: return "state";
    case Phase::Axis: return "axis";
    case Phase::Keys: return "keys";
    case Phase::Sort: return "sort";
    case Phase::Sweep: return "sweep";
    case Phase::List: return "list";
    case Phase::Forces: return "forces";
    case Phase::Integrate: return "integrate";
    default: return "?";
  }
}

float checkCloud(const ParticleCloud& cloud) {
  const std::size_t n = cloud.size();
  if (cloud.y.size() != n || cloud.z.size() != n || cloud.r.size() != n || cloud.body.size() != n)
    throw Error("particle cloud columns differ in length");
  if (n >= (std::size_t{1} << 31)) throw Error("too many particles (limit 2^31)");
  float maxR = 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(cloud.r[i] > 0.0f) || !std::isfinite(cloud.r[i]))
      throw Error("particle " + std::to_string(i) + ": radius must be a positive finite number");
    maxR = std::max(maxR, cloud.r[i]);
  }
  return maxR;
}

float effectiveSkin(const World& world) {
  const float skin = world.params.broadphase.skin;
  // Half the skin grows every radius the detection sees: beyond the sweep's range on its own, no
  // spread of the particles could be swept (the sweep's own message would blame the spread).
  if (!(0.5 * double(skin) + double(world.maxRadius) <= detail::kSweepRange)) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "[broadphase] skin = %g m is beyond single precision's range for the contact "
                  "detection: half of it is added to every radius, and radii, skin and the particles' spread together "
                  "must stay within %.0e m; use a skin of the order of the particles' radius (automatic: %g m)",
                  double(skin), detail::kSweepRange, double(effectiveSkin(-1.0f, world.sizingRadius, world.maxRadius)));
    throw Error(buf);
  }
  return effectiveSkin(skin, world.sizingRadius, world.maxRadius);
}

float neckReach(const World& world) {
  if (world.params.contact.cohesion != Cohesion::Jkr) return 0.0f;
  const double pi = 3.14159265358979323846, reff = 0.5 * double(world.maxRadius);
  double reach = 0.0;
  for (const HertzPair& p : world.materialPairs) {
    if (!(p.cohesion > 0.0f && p.ystar > 0.0f)) continue;
    const double c = std::sqrt(2.0 * pi * double(p.cohesion) / double(p.ystar));
    reach = std::max(reach, 0.75 * c * std::cbrt(0.25 * c * reff));
  }
  return static_cast<float>(reach * (1.0 + 1e-3));
}

float effectiveSkin(float skin, float sizingRadius, float maxRadius) {
  return skin >= 0.0f ? skin : kAutoSkinPerRadius * (sizingRadius > 0.0f ? sizingRadius : maxRadius);
}

double StepStats::totalSeconds() const {
  double t = 0.0;
  for (double s : seconds) t += s;
  return t;
}

void StepStats::add(const StepStats& later) {
  const StepStats before = *this;
  *this = later;
  steps += before.steps;
  for (int p = 0; p < kNumPhases; ++p) seconds[p] += before.seconds[p];
  numRebuilds += before.numRebuilds;
  numNearRefreshes += before.numNearRefreshes;
  energy += before.energy;
}

}  // namespace tumble
