// SPDX-License-Identifier: MIT
// The contact laws' parameters of a World: the materials' Hertz pairs, the damping for a
// coefficient of restitution (and back), and the shortest contact time (SPEC §2.4).
#include "tumble/world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "tumble/error.hpp"

namespace tumble {

const char* toString(RotationScheme s) { return s == RotationScheme::Report ? "report" : "splitting"; }
const char* toString(ContactLaw law) {
  switch (law) {
    case ContactLaw::HookeHistory: return "hooke-history";
    case ContactLaw::HertzMindlin: return "hertz-mindlin";
    default: return "report";
  }
}

const char* toString(Cohesion model) {
  switch (model) {
    case Cohesion::Sjkr: return "sjkr";
    case Cohesion::Dmt: return "dmt";
    case Cohesion::Jkr: return "jkr";
    default: return "none";
  }
}

const char* cohesionKey(Cohesion model) {
  switch (model) {
    case Cohesion::Sjkr: return "cohesion_energy_density";
    case Cohesion::Dmt:
    case Cohesion::Jkr: return "surface_energy";
    default: return "";
  }
}

std::string materialOutOfRange(const MaterialDef& m) {
  // Y* and G* of the material against itself and against a rigid ground (the largest it can meet).
  for (const HertzPair& p : {materialPair(m, &m), materialPair(m, nullptr)}) {
    if (!(std::isfinite(p.ystar) && std::isfinite(p.gstar) && p.ystar > 0.0f && p.gstar > 0.0f)) {
      // Too large overflows Y* = E / (1 − ν²)...; too small rounds it to 0 in single precision.
      const bool tooSmall = std::isfinite(p.ystar) && std::isfinite(p.gstar);
      char buf[200];
      std::snprintf(buf, sizeof buf, "its youngs_modulus %g gives an effective modulus %s single precision; use %s",
                    double(m.youngsModulus), tooSmall ? "too small for" : "beyond",
                    tooSmall ? "a larger one (real materials: 1e5 to 1e12 Pa)" : "a smaller one");
      return buf;
    }
  }
  return {};
}

HertzPair planePair(const Scene& scene, const GroundParams& plane, std::size_t a) {
  HertzPair p = materialPair(scene.materials[a], plane.material >= 0 ? &scene.materials[plane.material] : nullptr);
  if (plane.frictionOverride >= 0.0f) p.mu = plane.frictionOverride;
  if (plane.rollingFriction >= 0.0f) p.muR = plane.rollingFriction;
  if (plane.cohesion >= 0.0f) p.cohesion = plane.cohesion;
  return p;
}

HertzPair materialPair(const MaterialDef& a, const MaterialDef* b) {
  const auto compliance = [](const MaterialDef& m) {
    const double e = m.youngsModulus, nu = m.poissonRatio;
    return std::pair<double, double>{(1.0 - nu * nu) / e, 2.0 * (2.0 - nu) * (1.0 + nu) / e};
  };
  auto [y, g] = compliance(a);
  double e = a.restitution, mu = a.friction, muR = a.rollingFriction, coh = a.cohesion;
  if (b != nullptr) {
    coh = std::sqrt(coh * b->cohesion);  // the geometric mean (a material with itself: its own)
    const auto [yb, gb] = compliance(*b);
    y += yb;
    g += gb;
    e = std::min(e, double(b->restitution));
    mu = std::min(mu, double(b->friction));
    muR = std::min(muR, double(b->rollingFriction));
  }
  const double pi = 3.14159265358979323846, le = std::log(e);
  const double beta = le / std::sqrt(le * le + pi * pi);
  return HertzPair{static_cast<float>(1.0 / y), static_cast<float>(1.0 / g),
                   static_cast<float>(-2.0 * std::sqrt(5.0 / 6.0) * beta), static_cast<float>(mu),
                   static_cast<float>(muR), static_cast<float>(coh)};
}

double dampingForRestitution(double e, double k, double m) {
  if (!(e > 0.0) || e > 1.0) throw Error("elasticity must be in (0, 1], got " + std::to_string(e));
  const double le = std::log(e);
  const double pi = 3.14159265358979323846;
  const double zeta = -le / std::sqrt(pi * pi + le * le);
  return 2.0 * zeta * std::sqrt(k * m);
}

std::string groundDampingOutOfRange(const SphereDef& sphere, const GroundParams& ground, const std::string& where) {
  if (!ground.enabled) return {};
  const double c = dampingForRestitution(sphere.elasticity, ground.stiffness, sphere.mass);
  if (c <= double(std::numeric_limits<float>::max())) return {};
  const bool isGround = where == "[ground]";
  char buf[400];
  std::snprintf(buf, sizeof buf, "its %s damping (elasticity %g, mass %.3g kg, %s stiffness %.3g N/m) is "
                "%.3g N s/m, beyond single precision; use a smaller mass or %s%s", isGround ? "ground" : "wall",
                double(sphere.elasticity), double(sphere.mass), isGround ? "ground" : where.c_str(),
                double(ground.stiffness), c, isGround ? "[ground] stiffness" : "a smaller stiffness of ",
                isGround ? "" : where.c_str());
  return buf;
}

double restitutionForDamping(double c, double k, double m) {
  const double zeta = c / (2.0 * std::sqrt(k * m));
  if (zeta >= 1.0) return 0.0;
  const double pi = 3.14159265358979323846;
  return std::exp(-zeta * pi / std::sqrt(1.0 - zeta * zeta));
}

namespace {

// hertz-mindlin: the shortest Hertz contact time t_c = 2.87 (m*² / (R* Y*² v))^{1/5} of the scene,
// for the lightest mass and the largest radius of each material against each other and every plane (the
// ground, the walls), at
// the fastest impact its start suggests: v = max(1 m/s, |V|max + √(2 |g| H) + the fastest
// moving wall's approach, wallApproachSpeed()), H the largest height of a body above the ground
// (without one, the bodies' vertical extent).
double hertzContactTime(const World& w) {
  const std::size_t m = w.params.materials.size();
  // t_c grows with m*^{2/5} and falls with R*^{1/5}: the lightest mass with the largest radius.
  std::vector<double> mMin(m, std::numeric_limits<double>::infinity()), rMax(m, 0.0);
  for (std::size_t i = 0; i < w.radius.size(); ++i) {
    mMin[w.material[i]] = std::min(mMin[w.material[i]], double(w.mass[i]));
    rMax[w.material[i]] = std::max(rMax[w.material[i]], double(w.radius[i]));
  }
  const BodyState& s = w.state;
  double vmax = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < s.size(); ++k) {
    vmax = std::max(vmax, std::sqrt(double(s.vx[k]) * s.vx[k] + double(s.vy[k]) * s.vy[k] + double(s.vz[k]) * s.vz[k]));
    lo = std::min(lo, double(s.pz[k]));
    hi = std::max(hi, double(s.pz[k]));
  }
  if (w.params.ground.enabled) lo = std::min(lo, double(w.params.ground.height));
  const Vec3f g = w.params.gravity;
  const double gz = std::sqrt(double(g.x) * g.x + double(g.y) * g.y + double(g.z) * g.z);
  double walls = 0.0;
  for (const WallDef& d : w.params.walls) walls = std::max(walls, wallApproachSpeed(d));
  const double v = std::max(1.0, vmax + std::sqrt(2.0 * gz * std::max(0.0, hi - lo)) + walls);
  double tc = std::numeric_limits<double>::infinity();
  const auto contact = [&](double meff, double reff, double ystar) {
    tc = std::min(tc, 2.87 * std::pow(meff * meff / (reff * ystar * ystar * v), 0.2));
  };
  for (std::size_t a = 0; a < m; ++a) {
    if (!std::isfinite(mMin[a])) continue;
    for (std::size_t b = a; b < m; ++b)
      if (std::isfinite(mMin[b]) && (a != b || w.numBodies() > 1))
        contact(mMin[a] * mMin[b] / (mMin[a] + mMin[b]), rMax[a] * rMax[b] / (rMax[a] + rMax[b]),
                w.materialPairs[materialPairIndex(a, b, m)].ystar);
    for (std::size_t q = 0; q * m < w.planeHertz.size(); ++q) contact(mMin[a], rMax[a], w.planeHertz[q * m + a].ystar);
  }
  return tc;
}

}  // namespace

double shortestContactTime(const World& w) {
  const double pi = 3.14159265358979323846;
  double tc = std::numeric_limits<double>::infinity();
  if (w.radius.empty()) return tc;
  if (w.params.contact.usesMaterials()) return hertzContactTime(w);
  const double mMin = *std::min_element(w.mass.begin(), w.mass.end());
  if (w.numBodies() > 1 && w.params.contact.stiffness > 0.0f)
    tc = std::min(tc, pi * std::sqrt(0.5 * mMin / double(w.params.contact.stiffness)));
  for (const WallDef& p : w.params.planes())  // the ground and the walls
    if (p.contact.stiffness > 0.0f) tc = std::min(tc, pi * std::sqrt(mMin / double(p.contact.stiffness)));
  return tc;
}

}  // namespace tumble
