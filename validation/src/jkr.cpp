// SPDX-License-Identifier: MIT
#include "tumble/validation/jkr.hpp"

#include <cmath>
#include <cstdio>

#include "tumble/scene_io.hpp"

namespace tumble::validation {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double JkrCurve::delta(double a) const { return a * a / reff - std::sqrt(2.0 * kPi * gamma * a / ystar); }
double JkrCurve::force(double a) const {
  return 4.0 * ystar * a * a * a / (3.0 * reff) - std::sqrt(8.0 * kPi * gamma * ystar * a * a * a);
}
double JkrCurve::dDelta(double a) const { return 2.0 * a / reff - 0.5 * std::sqrt(2.0 * kPi * gamma / (ystar * a)); }
double JkrCurve::aEnd() const { return std::cbrt(kPi * gamma * reff * reff / (8.0 * ystar)); }
double JkrCurve::aTouch() const { return std::cbrt(2.0 * kPi * gamma * reff * reff / ystar); }
double JkrCurve::aPull() const { return std::cbrt(9.0 * kPi * gamma * reff * reff / (8.0 * ystar)); }
double JkrCurve::pullOff() const { return 1.5 * kPi * gamma * reff; }

double JkrCurve::work(double a0, double a1) const {
  const int n = 20000;
  const double h = (a1 - a0) / n;
  double s = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double a = a0 + k * h, w = k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0);
    s += w * force(a) * dDelta(a);
  }
  return s * h / 3.0;
}

double JkrCurve::neckWork() const { return -work(aEnd(), aTouch()); }

double JkrCurve::radiusAt(double f) const {
  double lo = aPull(), hi = 100.0 * aTouch();
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (force(mid) > f ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

double jkrYstar(bool plane) { return 1.0 / ((plane ? 1.0 : 2.0) * (1.0 - kJkrNu * kJkrNu) / kJkrE); }

std::string jkrSceneText(double e, double g, double dt, const std::string& bodies) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "[scene]\nname = \"jkr\"\ndt = %g\nsteps = 1\ngravity = [0, 0, %.17g]\n[contact]\nlaw = \"hertz-mindlin\"\n"
                "cohesion = \"jkr\"\n[[material]]\nname = \"m\"\ndensity = %g\nyoungs_modulus = %g\npoisson_ratio = %g\n"
                "restitution = %g\nfriction = 0.5\nsurface_energy = %g\n[ground]\nheight = %g\n"
                "[[shape]]\nname = \"s\"\n[[shape.sphere]]\nradius = %g\nmaterial = \"m\"\n",
                dt, g, kJkrDensity, kJkrE, kJkrNu, e, kJkrGamma, -kJkrRadius, kJkrRadius);
  return buf + bodies;
}

std::string jkrHeadOnBodies(bool plane, double v) {
  char body[400];
  if (plane)
    std::snprintf(body, sizeof body, "[[body]]\nshape = \"s\"\nposition = [0, 0, 0.00001]\nvelocity = [0, 0, %.17g]\n", -v);
  else
    std::snprintf(body, sizeof body,
                  "[[body]]\nshape = \"s\"\nposition = [-0.00201, 0, 0.01]\nvelocity = [%.17g, 0, 0]\n"
                  "[[body]]\nshape = \"s\"\nposition = [0.00201, 0, 0.01]\nvelocity = [%.17g, 0, 0]\n",
                  0.5 * v, -0.5 * v);
  return body;
}

JkrImpact jkrImpact(Backend backend, bool plane, double v) {
  const Scene scene = parseScene(jkrSceneText(1.0, 0.0, 1e-6, jkrHeadOnBodies(plane, v)), "jkr impact");
  auto p = makePipeline(backend);
  p->load(World::fromScene(scene));
  p->setEnergyTally(true);
  p->step(30000);
  BodyState s;
  p->readState(s);
  const double after = plane ? double(s.vz[0]) : double(s.vx[1]) - double(s.vx[0]);
  const double gap = plane ? double(s.pz[0]) : double(s.px[1]) - double(s.px[0]) - 2.0 * kJkrRadius;
  return JkrImpact{after, gap, p->stats().energy.cohesion};
}

}  // namespace tumble::validation
