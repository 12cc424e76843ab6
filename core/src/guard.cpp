// SPDX-License-Identifier: MIT
#include "tumble/guard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <tbb/parallel_for.h>

#include "tumble/exact_range.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/mesh.hpp"

namespace tumble {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// The duration of a Hertz contact F = K δ^{3/2} of effective mass m whose deepest overlap is δ:
// the impact speed v that reaches it, ½ m v² = ⅖ K δ^{5/2}, then t_c = 2.94 δ / v (Johnson 1985).
double hertzTimeAtOverlap(double K, double m, double delta) {
  const double v = std::sqrt(0.8 * K * delta * delta * std::sqrt(delta) / m);
  return v > 0.0 ? 2.94 * delta / v : std::numeric_limits<double>::infinity();
}

double dtToUse(const World& w) {
  const double tc = shortestContactTime(w);
  const double dt = w.params.dt;
  if (std::isfinite(tc) && tc / 20.0 < dt) return tc / 20.0;
  return 0.5 * dt;
}

std::string dtAdvice(const World& w) {
  const double tc = shortestContactTime(w);
  const double use = dtToUse(w);
  if (!std::isfinite(tc)) {
    // No contact can form: what is left to go wrong is the integration of free motion.
    std::string a = format("the scene has no contacts to resolve; try dt = %.3g s", use);
    if (w.hasClumps && w.params.integrator.rotation == RotationScheme::Report)
      a += ", or [integrator] rotation = \"splitting\" (the report's rotation scheme gains energy on fast-spinning "
           "clumps; the splitting keeps it bounded)";
    return a;
  }
  if (std::isfinite(tc) && tc / 20.0 < w.params.dt)
    return format("the shortest contact lasts %.3g s; use dt <= %.3g s (t_c / 20, now %g s)", tc, use, w.params.dt);
  return format("dt = %g s already resolves the shortest contact (%.3g s); try dt = %.3g s", w.params.dt, tc, use);
}

/// Reduces body(begin, end, acc) over fixed chunks of n elements in parallel, merging the
/// chunks' accumulators in chunk order: the same result for any thread count.
template <class Acc, class Body, class Merge>
Acc chunkedSum(std::size_t n, Body&& body, Merge&& merge) {
  constexpr std::size_t kChunk = 4096;
  const std::size_t numChunks = (n + kChunk - 1) / kChunk;
  std::vector<Acc> part(numChunks);
  tbb::parallel_for(std::size_t{0}, numChunks, [&](std::size_t c) {
    body(c * kChunk, std::min(n, (c + 1) * kChunk), part[c]);
  });
  Acc total;
  for (const Acc& a : part) merge(total, a);
  return total;
}

bool finiteRow(const BodyState& s, std::size_t k) {
  for (const auto* c : {&s.px, &s.py, &s.pz, &s.vx, &s.vy, &s.vz, &s.qw, &s.qx, &s.qy, &s.qz, &s.lx, &s.ly, &s.lz})
    if (!std::isfinite((*c)[k])) return false;
  return true;
}

// The position within the range whose contacts single precision decides right (exact_range.hpp;
// the frame's origin added: the state is the local one).
bool inRangeRow(const BodyState& s, std::size_t k, const LocalFrame& f) {
  return withinExactRange(f.x + double(s.px[k])) && withinExactRange(f.y + double(s.py[k])) &&
         withinExactRange(f.z + double(s.pz[k]));
}

}  // namespace

SpringLaw springLawOf(const World& w) {
  SpringLaw law;
  law.k = w.params.contact.stiffness;
  if (w.params.contact.hasHistory()) {
    law.cohesion = w.params.contact.cohesion;
    law.cohesionValue = w.params.contact.cohesionValue;
  }
  if (w.params.contact.usesMaterials()) {
    law.hertz = w.materialPairs.data();
    law.material = w.params.materials.size() > 1 ? w.material.data() : nullptr;
    law.numMaterials = static_cast<std::uint32_t>(w.params.materials.size());
  }
  return law;
}

void contactSumsOfPairs(const World& world, const std::vector<Pair>& pairs, const std::vector<float>& x,
                        const std::vector<double>& bodyErr, const SpringLaw& law, std::vector<ContactSums>& out,
                        const PeriodicBox& box) {
  out.assign(world.numBodies(), ContactSums{});
  for (const Pair& p : pairs) {
    const float* a = &x[3 * std::size_t(p.i)];
    const float* b = &x[3 * std::size_t(p.j)];
    addContactSum(out[world.body[p.i]], a[0], a[1], a[2], world.radius[p.i], b[0], b[1], b[2], world.radius[p.j],
                  bodyErr[world.body[p.i]], bodyErr[world.body[p.j]], law, p.i, p.j, box);
  }
}

std::string divergenceMessage(const World& world, std::uint64_t step, std::uint32_t particle) {
  const std::uint32_t body = particle < world.body.size() ? world.body[particle] : 0;
  return "step " + std::to_string(step) + ": particle " + std::to_string(particle) + " (body " + std::to_string(body) +
         ") has a non-finite position: the simulation diverged; " + dtAdvice(world);
}

RunGuard::RunGuard(const World& world, Pipeline& pipeline, GuardParams params) : m_world(world), m_params(params) {
  m_mesh = kernelMesh(world.params, pipeline.frame());  // as the pipeline's (its frame is chosen at load)
  m_mask = pipeline.pulls();
  const Snapshot s = measure(pipeline, m_mask, pipeline.stats().steps == 0 ? &pipeline : nullptr);
  m_reference = s.energy;
  m_referenceSlack = s.slack;
  m_lastEnergy = s.energy;
  m_lastPower = s.swirlPower;
  m_lastTime = pipeline.time();
  m_initialOverlap = s.maxOverlap;
  m_scale = s.available;
  m_sample = s.sample;
  m_sample.step = pipeline.stepCount();
  m_sample.time = pipeline.time();
  m_sample.finite = s.nonFiniteBody < 0;
  // The contacts of the state at construction: those just measured (findPairs) before the first
  // step, else those of the last step.
  m_sample.contacts = s.foundPairs >= 0 ? static_cast<std::uint64_t>(s.foundPairs) : pipeline.stats().numPairs;
  if (s.maxOverlap > kInitialOverlapWarning) {
    const std::string held =  // the springs' own energy (the cohesive potential, ≤ 0, apart)
        format(" (the contact springs hold %.3g J, released as motion when the run starts); ", s.springs + s.bound);
    m_initialWarning =
        s.groundOverlap
            ? "body " + std::to_string(s.overlapBody) +
                  format(" starts %.0f%% of its radius ", 100.0 * s.maxOverlap) +
                  (s.overlapPlane == "the ground" ? "below" : "inside") + " " + s.overlapPlane + held +
                  (s.overlapPlane == "the ground" ? "raise" : "move") + " it unless it is meant to start pressed into " +
                  s.overlapPlane
            : "bodies " + std::to_string(s.overlapBody) + " and " + std::to_string(s.overlapOther) +
                  format(" start overlapping by %.0f%% of the smaller radius", 100.0 * s.maxOverlap) + held +
                  "separate them unless they are meant to start pressed together";
  }

}

double RunGuard::suggestedDt() const { return dtToUse(m_world); }

RunGuard::Snapshot RunGuard::measure(const Pipeline& pipeline, std::uint32_t mask, Pipeline* findPairsWith) {
  const World& w = m_world;
  // The state as the pipeline integrates it: far from the origin that is a local frame
  // (LocalFrame), whose positions are not rounded to the world's float spacing.
  const LocalFrame frame = pipeline.frame();
  pipeline.readLocalState(m_state);
  const BodyState& s = m_state;
  const Scene& sc = w.params;
  // The planes as the pipeline uses them (both build them from the world's points and the frame,
  // and pose them at the time of the state).
  const std::vector<WallDef> planeDefs = sc.planes();
  std::vector<Wall> planes = kernelWalls(sc, frame);
  std::vector<MeshPose> meshPoses(meshWallsMove(sc) ? planes.size() : 0, MeshPose{});  // moving meshes: posed too
  setWallMotion(planes, sc, pipeline.time(), meshPoses.empty() ? nullptr : meshPoses.data());
  // Periodic boundaries: contacts through the minimum image, and the bodies' heights and
  // momenta from their unwrapped positions X + n L (a body crossing the box keeps its potential).
  const PeriodicBox box = kernelPeriodic(sc, frame);
  const double groundZ = sc.ground.enabled ? double(planes[0].coeffs.height) : 0.0;
  Snapshot out;
  const std::size_t nb = s.size();
  struct FirstBad {
    std::int64_t body = -1;
    bool beyond = false;  // finite, but beyond the range
  };
  const FirstBad bad = chunkedSum<FirstBad>(nb, [&](std::size_t begin, std::size_t end, FirstBad& a) {
    for (std::size_t k = begin; k < end && a.body < 0; ++k)
      if (!finiteRow(s, k) || !inRangeRow(s, k, frame)) a = FirstBad{static_cast<std::int64_t>(k), finiteRow(s, k)};
  }, [](FirstBad& l, const FirstBad& r) {
    if (l.body < 0) l = r;  // the lowest index
  });
  if (bad.body >= 0) {
    out.nonFiniteBody = bad.body;
    out.beyondRange = bad.beyond;
    return out;
  }

  // Particle positions: the pipeline's own (so that the pairs it reports apply to them).
  const std::uint32_t np = w.numParticles();
  std::vector<float>& x = m_x;  // buffers kept between checks: no allocation per check
  pipeline.readLocalPositions(x);
  // Far from the origin the positions handed out are rounded (pipelines may integrate in a local
  // frame, LocalFrame): every energy term computed from them carries that rounding, which is
  // added to the allowance (slack) instead of counting as growth. Per body: err (largest axis),
  // errZ (z).
  std::vector<double>& err = m_err;
  std::vector<double>& errZ = m_errZ;
  err.resize(nb);
  errZ.resize(nb);
  const Vec3f g = sc.gravity;
  const double gNorm = std::sqrt(double(g.x) * g.x + double(g.y) * g.y + double(g.z) * g.z);
  // Per body (and, with pulls on, per particle), in parallel over fixed chunks combined in chunk
  // order: the same sums for any thread count.
  struct BodySums {
    double slack = 0.0, kinetic = 0.0, rotation = 0.0, gravity = 0.0, pullPotential = 0.0, power = 0.0, hottest = -1.0;
    double lowest = std::numeric_limits<double>::infinity();
    double speed2 = 0.0, p[3] = {0, 0, 0}, l[3] = {0, 0, 0};  // for the time series (ThermoSample)
    std::uint32_t hottestBody = 0;
  };
  const BodySums bs = chunkedSum<BodySums>(nb, [&](std::size_t begin, std::size_t end, BodySums& a) {
    for (std::size_t k = begin; k < end; ++k) {
      const Quatf q{s.qw[k], s.qx[k], s.qy[k], s.qz[k]};
      const Vec3f X{s.px[k], s.py[k], s.pz[k]}, V{s.vx[k], s.vy[k], s.vz[k]};
      double Xu[3];  // X without the periodic boundaries
      unwrappedPosition(s, k, box, Xu);
      const bool rotates = w.bodyRotates(k);
      const Vec3f omega =
          rotates ? angularVelocity(q, w.invInertia[k], Vec3f{s.lx[k], s.ly[k], s.lz[k]}) : Vec3f{0, 0, 0};
      const double m = w.bodyMass[k];
      const double v2 = double(V.x) * V.x + double(V.y) * V.y + double(V.z) * V.z;
      const double er =
          rotates ? 0.5 * (double(omega.x) * s.lx[k] + double(omega.y) * s.ly[k] + double(omega.z) * s.lz[k]) : 0.0;
      const double e = 0.5 * m * v2 + er;
      a.kinetic += e;
      a.rotation += er;
      a.speed2 = std::max(a.speed2, v2);
      const double P[3] = {m * V.x, m * V.y, m * V.z};
      const double Xw[3] = {Xu[0] + frame.x, Xu[1] + frame.y, Xu[2] + frame.z};
      a.p[0] += P[0], a.p[1] += P[1], a.p[2] += P[2];
      a.l[0] += Xw[1] * P[2] - Xw[2] * P[1] + s.lx[k];
      a.l[1] += Xw[2] * P[0] - Xw[0] * P[2] + s.ly[k];
      a.l[2] += Xw[0] * P[1] - Xw[1] * P[0] + s.lz[k];
      if (e > a.hottest) {
        a.hottest = e;
        a.hottestBody = static_cast<std::uint32_t>(k);
      }
      const double h = -(double(g.x) * Xu[0] + double(g.y) * Xu[1] + double(g.z) * Xu[2]);
      a.gravity += m * h;
      const double eX = bodyRounding(X.x, X.y, X.z);
      err[k] = eX;
      errZ[k] = floatRounding(X.z);
      a.slack += m * gNorm * 1.8 * eX;
      a.lowest = std::min(a.lowest, h);
      if (mask == 0) continue;
      for (std::uint32_t i = w.first[k], e1 = i + w.numParticlesOf[k]; i < e1; ++i) {
        const Vec3f xi{x[3 * std::size_t(i)], x[3 * std::size_t(i) + 1], x[3 * std::size_t(i) + 2]};
        const Vec3f vi = rotates ? pointVelocity(V, omega, xi - X) : V;
        const double mi = w.mass[i];
        // The pulls act about the world origin: world coordinates (double) for them.
        const double wx = double(xi.x) + frame.x, wy = double(xi.y) + frame.y;
        if (mask & kPullX) {
          a.pullPotential += 0.5 * mi * sc.pulls.x * wx * wx;
          a.slack += mi * std::abs(sc.pulls.x) * (std::abs(wx) + eX) * eX;
        }
        if (mask & kPullY) {
          a.pullPotential += 0.5 * mi * sc.pulls.y * wy * wy;
          a.slack += mi * std::abs(sc.pulls.y) * (std::abs(wy) + eX) * eX;
        }
        if (mask & kPullSwirl) a.power += mi * sc.pulls.swirl * (-wy * vi.x + wx * vi.y);
      }
    }
  }, [](BodySums& l, const BodySums& r) {
    l.slack += r.slack;
    l.kinetic += r.kinetic;
    l.rotation += r.rotation;
    l.speed2 = std::max(l.speed2, r.speed2);
    for (int c = 0; c < 3; ++c) l.p[c] += r.p[c], l.l[c] += r.l[c];
    l.gravity += r.gravity;
    l.pullPotential += r.pullPotential;
    l.power += r.power;
    l.lowest = std::min(l.lowest, r.lowest);
    if (r.hottest > l.hottest) {  // the lowest index among equals: the serial loop's choice
      l.hottest = r.hottest;
      l.hottestBody = r.hottestBody;
    }
  });
  double slack = bs.slack;
  const double kinetic = bs.kinetic, gravity = bs.gravity, pullPotential = bs.pullPotential, power = bs.power;
  const double lowest = bs.lowest;
  out.hottestBody = bs.hottestBody;

  // Contact springs and overlaps: the contacts of the last step (of the initial state before
  // the first), summed per body, then over fixed chunks of bodies in order.
  double springs = 0.0, bound = 0.0;  // bound: the energy the cohesion holds (springs has its potential)
  const SpringLaw law = springLawOf(w);
  std::vector<ContactSums>& perBody = m_contacts;
  if (findPairsWith) {
    ParticleCloud cloud;
    for (auto* c : {&cloud.x, &cloud.y, &cloud.z, &cloud.r}) c->resize(np);
    for (std::uint32_t i = 0; i < np; ++i) {
      cloud.x[i] = x[3 * std::size_t(i)];
      cloud.y[i] = x[3 * std::size_t(i) + 1];
      cloud.z[i] = x[3 * std::size_t(i) + 2];
      cloud.r[i] = w.radius[i];
    }
    cloud.body = w.body;
    cloud.periodic = box;
    const std::vector<Pair> found = findPairsWith->findPairs(cloud, sc.broadphase);
    out.foundPairs = static_cast<std::int64_t>(found.size());
    contactSumsOfPairs(w, found, x, err, law, perBody, box);
  } else if (!pipeline.contactSumsPerBody(law, perBody)) {
    contactSumsOfPairs(w, pipeline.pairs(), x, err, law, perBody, box);
  }
  const ContactSums ps = chunkedSum<ContactSums>(nb, [&](std::size_t begin, std::size_t end, ContactSums& a) {
    for (std::size_t b = begin; b < end; ++b) mergeContactSums(a, perBody[b]);
  }, [](ContactSums& l, const ContactSums& r) { mergeContactSums(l, r); });
  springs += ps.springs;
  slack += ps.slack;
  bound += ps.bound;
  // JKR's necks (pairs that hold beyond touching, δ < 0: the springs above count δ > 0 only)
  // hold their energy U(δ) > 0 (jkrEnergy()), which the time series counts as dissipated_cohesion
  // and the guard as energy: released when a neck closes again, it is no growth. A neck's pair is
  // one of the state's contacts (a held spring, kernels/history.hpp).
  const bool jkr = sc.contact.cohesion == Cohesion::Jkr;
  double neck = 0.0;
  if (jkr) {
    for (const ContactHistory& c : s.contacts) {
      double d[3];
      for (int a = 0; a < 3; ++a) d[a] = double(x[3 * std::size_t(c.i) + a]) - x[3 * std::size_t(c.j) + a];
      if (box.on(0)) d[0] = minimumImage<double>(d[0], box.half[0], box.length[0]);
      if (box.on(1)) d[1] = minimumImage<double>(d[1], box.half[1], box.length[1]);
      const double ri = w.radius[c.i], rj = w.radius[c.j];
      const double delta = ri + rj - std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (delta >= 0.0) continue;
      const HertzPair& hp = w.materialPairs[materialPairIndex(w.material[c.i], w.material[c.j], law.numMaterials)];
      neck += jkrEnergy(delta, ri * rj / (ri + rj), hp.ystar, hp.cohesion);
    }
  }
  if (ps.maxOverlap > out.maxOverlap) {
    out.maxOverlap = ps.maxOverlap;
    out.overlapBody = w.body[ps.deepestI];
    out.overlapOther = w.body[ps.deepestJ];
    out.groundOverlap = false;
    const double mi = w.mass[ps.deepestI], mj = w.mass[ps.deepestJ], meff = mi * mj / (mi + mj);
    if (law.hertz) {
      const double ri = w.radius[ps.deepestI], rj = w.radius[ps.deepestJ];
      const HertzPair& c =
          w.materialPairs[materialPairIndex(w.material[ps.deepestI], w.material[ps.deepestJ], law.numMaterials)];
      out.overlapContactTime =
          hertzTimeAtOverlap(hertzStiffness(c, ri * rj / (ri + rj)), meff, ps.maxOverlap * std::min(ri, rj));
    } else {
      out.overlapContactTime = kPi * std::sqrt(meff / double(sc.contact.stiffness));
    }
  }
  // The planes (the ground, the walls) and the mesh walls' triangles: a sphere's spring and
  // overlap on plane q at depth delta (e: its rounding), summed into a.
  struct GroundSums {
    double springs = 0.0, slack = 0.0, bound = 0.0, maxOverlap = 0.0, contactTime = 0.0;
    double neck = 0.0;  // JKR's necks on the plane (δ < 0)
    std::uint32_t body = 0, triangle = 0;
  };
  const auto addPlane = [&](GroundSums& a, std::size_t q, std::size_t i, double delta, double e) {
    double K = 0.0;  // Hertz: F = K δ^{3/2}
    const double stiffness = planeDefs[q].contact.stiffness;
    double cohesion = sc.cohesionOf(planeDefs[q].contact), ystar = 0.0;
    if (law.hertz) {
      const HertzPair& c = w.planeHertz[q * law.numMaterials + w.material[i]];
      K = hertzStiffness(c, w.radius[i]);
      a.springs += 0.4 * K * delta * delta * std::sqrt(delta);
      a.slack += K * (delta + e) * std::sqrt(delta + e) * e;
      cohesion = c.cohesion;
      ystar = c.ystar;
    } else {
      a.springs += 0.5 * stiffness * delta * delta;
      a.slack += stiffness * e * (delta + e);
    }
    if (law.cohesion != Cohesion::None)
      addCohesiveSum(&a.springs, &a.slack, &a.bound, law.cohesion, cohesion, delta, e, w.radius[i], 0.0, true, ystar);
    const double frac = delta / w.radius[i];
    if (frac > a.maxOverlap) {
      a.maxOverlap = frac;
      a.body = w.body[i];
      a.contactTime = law.hertz ? hertzTimeAtOverlap(K, w.mass[i], delta) : kPi * std::sqrt(double(w.mass[i]) / stiffness);
      return true;
    }
    return false;
  };
  const auto mergePlanes = [](GroundSums& l, const GroundSums& r) {
    l.springs += r.springs;
    l.slack += r.slack;
    l.bound += r.bound;
    l.neck += r.neck;
    if (r.maxOverlap > l.maxOverlap) {
      l.maxOverlap = r.maxOverlap;
      l.body = r.body;
      l.contactTime = r.contactTime;
      l.triangle = r.triangle;
    }
  };
  const auto addDeepest = [&](const GroundSums& gs, const std::string& where) {
    springs += gs.springs;
    slack += gs.slack;
    bound += gs.bound;
    neck += gs.neck;
    if (gs.maxOverlap > out.maxOverlap) {
      out.maxOverlap = gs.maxOverlap;
      out.overlapBody = gs.body;
      out.groundOverlap = true;
      out.overlapPlane = where;
      out.overlapContactTime = gs.contactTime;
    }
  };
  for (std::size_t q = 0; q < planes.size(); ++q) {
    const Wall& pw = planes[q];
    if (pw.axis == kMeshWall) continue;  // its triangles below
    const GroundSums gs = chunkedSum<GroundSums>(np, [&](std::size_t begin, std::size_t end, GroundSums& a) {
      for (std::size_t i = begin; i < end; ++i) {
        const double xi[3] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
        double delta, e;
        if (pw.axis >= 0) {  // the ground's form: h − (x_a − r), sign-flipped for a −e_a normal
          delta = double(pw.coeffs.height) - (pw.sign * xi[pw.axis] - w.radius[i]);
          e = (pw.axis == 2 ? errZ : err)[w.body[i]] + floatRounding(pw.coeffs.height);
        } else if (pw.axis == kRevolvedWall) {  // the kernels' distance, from the same floats
          const Vec3f xf{x[3 * i], x[3 * i + 1], x[3 * i + 2]};
          delta = w.radius[i] - double(revolvedContact(pw, xf).dist);
          const float size = std::max({std::abs(pw.centre.x), std::abs(pw.centre.y), std::abs(pw.centre.z), pw.length,
                                       pw.radius0, pw.radius1});
          e = 2.0 * err[w.body[i]] + 8.0 * floatRounding(size);
        } else {
          const double d = xi[0] * pw.n.x + xi[1] * pw.n.y + xi[2] * pw.n.z;  // x·n = h on the plane
          delta = w.radius[i] - (d - pw.coeffs.height);
          e = 1.8 * err[w.body[i]] + floatRounding(pw.coeffs.height);
        }
        if (delta > 0.0) {
          addPlane(a, q, i, delta, e);
        } else if (jkr && (q + 1) * np <= s.groundSpringX.size() &&
                   !isZeroPlaneSpring(s.groundSpringX[q * np + i], s.groundSpringY[q * np + i])) {
          const HertzPair& hp = w.planeHertz[q * law.numMaterials + w.material[i]];
          a.neck += jkrEnergy(delta, w.radius[i], hp.ystar, hp.cohesion);
        }
      }
    }, mergePlanes);
    addDeepest(gs, q == 0 && sc.ground.enabled ? "the ground" : planeDefs[q].where);
  }
  // The mesh contacts of the last step (of the initial state before the first: found here),
  // with the kernels' distance to the same triangle at the present positions (and a moving
  // mesh's present pose), in (particle, triangle) order over fixed chunks. The rounding of a
  // distance: the triangle's box growth.
  if (m_mesh.numTriangles() > 0) {
    const MeshView mv = m_mesh.view(meshPoses);
    const std::vector<MeshContact> mc =
        findPairsWith ? findMeshContacts(m_mesh, x, w.radius, meshPoses) : pipeline.meshContacts();
    const GroundSums gs = chunkedSum<GroundSums>(mc.size(), [&](std::size_t begin, std::size_t end, GroundSums& a) {
      for (std::size_t c = begin; c < end; ++c) {
        const std::size_t i = mc[c].particle;
        const std::uint32_t t = mc[c].triangle;
        const Vec3f xf = meshPoint(mv, mv.tri[t].wall, Vec3f{x[3 * i], x[3 * i + 1], x[3 * i + 2]});
        const double delta = w.radius[i] - double(nearestOnTriangle(mv, t, xf).dist);
        const MeshTriangle& tr = mv.tri[t];
        const double size = std::max({double(tr.hi.x) - tr.lo.x, double(tr.hi.y) - tr.lo.y, double(tr.hi.z) - tr.lo.z});
        // A posed mesh's: also the rounding of the centre's transform into its frame.
        const double moved = mv.poses != nullptr && mv.poses[tr.wall].posed != 0u
                                 ? 16.0 * 0x1p-24 * (std::abs(xf.x) + std::abs(xf.y) + std::abs(xf.z))
                                 : 0.0;
        if (delta > 0.0 && addPlane(a, tr.wall, i, delta, 2.0 * err[w.body[i]] + 64.0 * 0x1p-24 * size + moved))
          a.triangle = t;
      }
    }, mergePlanes);
    if (gs.maxOverlap > 0.0)
      addDeepest(gs, meshTriangleWhere(sc, gs.triangle));
  }

  out.energy = kinetic + gravity + pullPotential + springs + neck;  // (the time series: without the necks)
  ThermoSample& ts = out.sample;
  ts.kineticTranslation = kinetic - bs.rotation;
  ts.kineticRotation = bs.rotation;
  ts.pullPotential = pullPotential;
  ts.springs = springs;
  ts.maxOverlap = out.maxOverlap;
  ts.maxSpeed = std::sqrt(bs.speed2);
  for (int c = 0; c < 3; ++c) ts.momentum[c] = bs.p[c], ts.angularMomentum[c] = bs.l[c];
  out.springs = springs;
  out.bound = bound;
  out.slack = slack;
  out.swirlPower = power;
  // What the state can release: motion, springs, the pulls' potential, and gravity down to the
  // lowest body or, with a ground below, down to the ground (the heights above it), at least
  // Σ M |g| r_max.
  struct DropSums {
    double drop = 0.0, mass = 0.0;
  };
  const DropSums ds = chunkedSum<DropSums>(nb, [&](std::size_t begin, std::size_t end, DropSums& a) {
    for (std::size_t k = begin; k < end; ++k) {
      double Xu[3];
      unwrappedPosition(s, k, box, Xu);
      double hk = -(double(g.x) * Xu[0] + double(g.y) * Xu[1] + double(g.z) * Xu[2]) - lowest;
      if (sc.ground.enabled && g.z < 0.0f) hk = std::max(hk, -double(g.z) * (double(s.pz[k]) - groundZ));
      a.drop += w.bodyMass[k] * std::max(0.0, hk);
      a.mass += w.bodyMass[k];
    }
  }, [](DropSums& l, const DropSums& r) {
    l.drop += r.drop;
    l.mass += r.mass;
  });
  const double drop = ds.drop, totalMass = ds.mass;
  // Gravity in world coordinates for the time series: the local frame shifts it by −M g·o.
  ts.gravity = gravity - totalMass * (double(g.x) * frame.x + double(g.y) * frame.y + double(g.z) * frame.z);
  // |pull potential|: an outward pull (κ < 0) has a negative potential, whose size is still the
  // energy scale of the motion it drives.
  out.available =
      kinetic + springs + bound + neck + std::abs(pullPotential) + std::max(0.0, drop) + totalMass * gNorm * w.maxRadius;
  if (!(out.available > 0.0)) out.available = 1e-12;
  return out;
}

GuardTrip RunGuard::trip(GuardTrip::Kind kind, std::uint32_t body, const Pipeline& pipeline,
                         const std::string& what, double contactTime) const {
  GuardTrip t;
  t.kind = kind;
  t.step = pipeline.stepCount();
  t.body = body;
  t.suggestedDt = suggestedDt();
  const double dt = m_world.params.dt;
  std::string advice;
  if (kind == GuardTrip::Kind::Overlap && std::isfinite(contactTime) && contactTime / 20.0 >= dt) {
    // A deep overlap at a dt that resolves this very contact is physics, not numerics: halving
    // dt will not help.
    advice = format("; dt = %g s already resolves this contact (t_c = %.3g s) with %.0f steps, so the depth is "
                    "physical: the contact is too soft for this impact (a linear contact sinks to about "
                    "v sqrt(m/k)); make it stiffer or the impact slower",
                    dt, contactTime, contactTime / dt);
  } else {
    advice = "; the integration is unstable or too coarse: " + dtAdvice(m_world);
  }
  t.message = "step " + std::to_string(t.step) + format(" (t = %.6g s): ", pipeline.time()) + what + advice;
  return t;
}

std::optional<GuardTrip> RunGuard::check(const Pipeline& pipeline) {
  const std::uint32_t mask = pipeline.pulls();
  Snapshot s = measure(pipeline, mask);
  const double t = pipeline.time();
  m_totalWork += 0.5 * (m_lastPower + s.swirlPower) * (t - m_lastTime);
  m_sample = s.sample;
  m_sample.step = pipeline.stepCount();
  m_sample.time = t;
  m_sample.pullWork = m_totalWork;
  m_sample.contacts = pipeline.stats().numPairs;
  m_sample.finite = s.nonFiniteBody < 0;
  if (s.nonFiniteBody >= 0) {
    if (s.beyondRange) {  // it flew off: no dt helps
      GuardTrip t = trip(GuardTrip::Kind::NonFinite, static_cast<std::uint32_t>(s.nonFiniteBody), pipeline, "");
      t.message = "step " + std::to_string(t.step) + format(" (t = %.6g s): body ", pipeline.time()) +
                  std::to_string(s.nonFiniteBody) +
                  " left the range +-2^60 m (1.15e18) whose contacts single precision decides right; keep it in "
                  "with a wall, or give it less speed";
      return t;
    }
    return trip(GuardTrip::Kind::NonFinite, static_cast<std::uint32_t>(s.nonFiniteBody), pipeline,
                "body " + std::to_string(s.nonFiniteBody) + " has a non-finite position, velocity or orientation");
  }
  // Moving walls do work the guard does not measure: while one moved since the last check, the
  // energy budget starts afresh at each check (it checks finiteness and overlaps).
  const bool wallsMoved = m_world.params.wallsMoveDuring(m_lastTime, t);
  if (mask != m_mask || wallsMoved) {
    // The pulls changed (their potentials and power change with them), or a wall moved: start
    // the energy budget afresh from the present state (the pulls' potential now counts as
    // available energy).
    m_mask = mask;
    m_reference = s.energy;
    m_referenceSlack = s.slack;
    m_work = 0.0;
    m_scale = std::max(m_scale, s.available);
  } else {
    m_work += 0.5 * (m_lastPower + s.swirlPower) * (t - m_lastTime);
  }
  m_lastPower = s.swirlPower;
  m_lastTime = t;
  m_lastEnergy = s.energy;
  m_lastOverlap = s.maxOverlap;

  const double gained = s.energy - m_reference - m_work;
  // The swirl's work is motion the initial state did not have: it widens the scale as well.
  const double scale = m_scale + std::max(0.0, m_work);
  if (!wallsMoved && gained > m_params.energyGrowth * scale + m_referenceSlack + s.slack) {
    return trip(GuardTrip::Kind::Energy, s.hottestBody, pipeline,
                format("the energy grew by %.3g J, more than %.0f%% of the %.3g J the scene can release", gained,
                       100.0 * m_params.energyGrowth, scale) +
                    " (body " + std::to_string(s.hottestBody) + " moves fastest)");
  }
  const double limit = std::max(m_params.maxOverlap, m_initialOverlap + 0.05);
  if (s.maxOverlap > limit) {
    const std::string who = s.groundOverlap ? "body " + std::to_string(s.overlapBody) + " sinks into " + s.overlapPlane
                                            : "bodies " + std::to_string(s.overlapBody) + " and " +
                                                  std::to_string(s.overlapOther) + " overlap";
    return trip(GuardTrip::Kind::Overlap, s.overlapBody, pipeline,
                who + format(" by %.0f%% of the smaller radius (limit %.0f%%)", 100.0 * s.maxOverlap, 100.0 * limit),
                s.overlapContactTime);
  }
  return std::nullopt;
}

}  // namespace tumble
