// SPDX-License-Identifier: MIT
// The validation study's impact cases: sphere–ground restitution and contact duration, and
// sphere–sphere restitution through η with momentum (docs/validation.md).
#include "study_physics_common.hpp"

namespace tumble::validation::study::physics {

// ---------------------------------------------------------------------------------------------
// Sphere–ground restitution and contact duration.

namespace {

struct Bounce {
  double e = kNaN, duration = kNaN, wallPerSim = kNaN;
};

/// A sphere (no gravity) hits the ground at v_in; returns v_out / v_in and the time between the
/// crossings of z = r, interpolated linearly inside the step (exact for the drift X += V dt).
Bounce groundBounce(Backend b, double e, double k, double m, double r, double vin, double dt, RotationScheme rs,
                    double phase = 0.0) {
  Scene s = groundScene({0, 0, 0}, k, sphereShape(r, m, e), dt, rs);
  const double tc = kPi * std::sqrt(m / k);
  const double gap = 0.25 * vin * tc + phase * vin * dt;
  BodyDef bd;
  bd.position = {0, 0, float(r + gap)};
  bd.velocity = {0, 0, float(-vin)};
  s.bodies = {bd};
  Sim sim(s, b);
  const double rf = asFloat(r), dtf = asFloat(dt);
  double zPrev = sim.st.pz[0], tIn = -1.0;
  const auto maxSteps = static_cast<std::uint64_t>((gap / vin + 4 * tc) / dt) + 10;
  Bounce out;
  for (std::uint64_t n = 0; n < maxSteps; ++n) {
    sim.step();
    sim.read();
    const double z = sim.st.pz[0], t = sim.time();
    if (!std::isfinite(z)) return out;
    if (tIn < 0 && zPrev >= rf && z < rf) tIn = t - dtf + (zPrev - rf) / (zPrev - z) * dtf;
    if (tIn >= 0 && zPrev < rf && z >= rf) {
      const double tOut = t - dtf + (rf - zPrev) / (z - zPrev) * dtf;
      out.e = sim.st.vz[0] / vin;
      out.duration = tOut - tIn;
      out.wallPerSim = sim.wallPerSimSecond();
      return out;
    }
    zPrev = z;
  }
  return out;
}

}  // namespace

CaseResult groundRestitution(const CaseContext& ctx) {
  CaseResult r;
  r.id = "ground_restitution";
  r.title = "Sphere–ground restitution and contact duration";
  const double k = 1.0e6, m = 1.0, rad = 0.1, vin = 1.0;
  const double tc0 = kPi * std::sqrt(m / k);
  const double dt = tc0 / 200.0;
  Table t{"restitution",
          {"e", "zeta", "e_measured", "e_discrete_map", "rel_error", "tolerance", "duration_s", "duration_analytic_s",
           "duration_rel_error", "duration_tolerance"},
          {}};
  for (int i = 1; i <= 10; ++i) {
    const double e = 0.1 * i;
    const double c = dampingForRestitution(e, k, m);
    const double zeta = c / (2 * std::sqrt(k * m));
    const Bounce bo = groundBounce(ctx.backend, e, k, m, rad, vin, dt, RotationScheme::Report);
    const DiscreteOscillator dm = discreteOscillator(k, c, m, dt);
    const double tol = restitutionTolerance(dm, e, k, c, m, dt);
    const double tcA = contactDuration(k, c, m);
    const double tolT = (std::abs(dm.tc - tcA) + dt) / tcA;
    r.checks.push_back(relCheck(fmt("restitution e=%.1f", e),
                                "v_out/v_in vs e (unclamped linear spring-dashpot, c = 2ζ√(km))", bo.e, e, tol));
    r.checks.push_back(relCheck(fmt("contact duration e=%.1f", e), "π/ω_d, ω_d = √(k/m − (c/2m)²)", bo.duration,
                                tcA, tolT));
    t.rows.push_back({e, zeta, bo.e, dm.e, std::abs(bo.e - e) / e, tol, bo.duration, tcA,
                      std::abs(bo.duration - tcA) / tcA, tolT});
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"restitution", "Ground restitution: measured against configured e", "restitution", "e",
                         "configured e", "restitution", {"e", "e_measured"}, false, false, ""});
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const double eS = 0.5;
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    return phaseAverage([&](double ph) {
      const Bounce bo = groundBounce(ctx.backend, eS, k, m, rad, vin, d, rs, ph);
      return Measured{std::abs(bo.e - eS) / eS, bo.wallPerSim};
    });
  });
  const std::string div = addSweep(r, rows, "|e_meas − e| / e (e = 0.5), mean of 8 entry phases", "tc");
  r.summary =
      "A sphere (r = 0.1 m, m = 1 kg) meets the ground (k_g = 1e6 N/m) at 1 m/s with gravity off, so that the "
      "linear spring-dashpot formula is exact for the model: the ground force f_n = k_g δ − c v_z is **not clamped** "
      "at zero, the contact ends when δ returns to 0, and c = 2ζ√(k m) with ζ = −ln e/√(π² + ln² e) gives "
      "e = exp(−πζ/√(1−ζ²)) and the duration t_c = π/ω_d, ω_d = √(k/m − (c/2m)²). Checks at dt = t_c0/200 "
      "(t_c0 = π√(m/k) = 3.14 ms). The tolerance is the error of the discrete leapfrog map of the oscillator "
      "(column e_discrete_map: amplitude factor √(1 − c dt/m) per step, phase θ with cos θ = (2 − c dt/m − k dt²/m)/"
      "(2√(1 − c dt/m))) plus the bound c dt/m + k dt²/m on the last step's force sample; for the duration, the "
      "map's half period plus one dt. The velocity-dependent damping is sampled at the start of the step, so the "
      "error is first order in dt (sweep plots). Single spheres do not rotate: both rotation schemes give the same "
      "numbers. Float suffices: the error floor at t_c/100 (≈ 1e-3) is four orders above float's 6e-8 relative "
      "rounding of v. With gravity, e would be lowered by about g t_c / v_in (0.3 % here); the sphere-on-ground "
      "test in physics_test.cpp covers that configuration."
      + kImpactSweepNote + div;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Sphere–sphere restitution through η, and momentum.

namespace {

struct PairImpact {
  double e = kNaN, dP = kNaN, pScale = kNaN, tolP = kNaN, wallPerSim = kNaN;
  std::uint64_t contactSteps = 0;
};

/// Two single spheres (m1 = 1, m2 = 2, r = 0.1), no gravity, closing at 1.5 m/s along x with
/// impact parameter `offsetY`. Returns the normal restitution (head-on) and the momentum change.
PairImpact pairImpact(Backend b, double eta, double k, double shear, double offsetY, double dt, RotationScheme rs,
                      double phase = 0.0) {
  const double r = 0.1, m1 = 1.0, m2 = 2.0, v1 = 1.0, v2 = -0.5;
  const double meff = m1 * m2 / (m1 + m2);
  const double tc = kPi * std::sqrt(meff / k);
  Scene s;
  s.gravity = {0, 0, 0};
  s.contact = {float(k), float(eta), float(shear)};
  s.shapes = {sphereShape(r, m1, 0.5), sphereShape(r, m2, 0.5)};
  s.integrator.rotation = rs;
  s.dt = float(dt);
  const double gap = 0.25 * (v1 - v2) * tc + phase * (v1 - v2) * dt;
  const double cx = std::sqrt(std::max(0.0, 4 * r * r - offsetY * offsetY)) + gap;
  BodyDef a, c;
  a.position = {float(-cx / 2), 0, 0};
  a.velocity = {float(v1), 0, 0};
  c.shape = 1;
  c.position = {float(cx / 2), float(offsetY), 0};
  c.velocity = {float(v2), 0, 0};
  s.bodies = {a, c};
  Sim sim(s, b);
  auto momentum = [&](double P[3]) {
    P[0] = m1 * sim.st.vx[0] + m2 * sim.st.vx[1];
    P[1] = m1 * sim.st.vy[0] + m2 * sim.st.vy[1];
    P[2] = m1 * sim.st.vz[0] + m2 * sim.st.vz[1];
  };
  double P0[3];
  momentum(P0);
  PairImpact out;
  out.pScale = m1 * std::abs(v1) + m2 * std::abs(v2);
  const auto maxSteps = static_cast<std::uint64_t>((gap / (v1 - v2) + 6 * tc) / dt) + 10;
  double vmax = std::max(std::abs(v1), std::abs(v2));
  bool touched = false;
  for (std::uint64_t n = 0; n < maxSteps; ++n) {
    sim.step();
    sim.read();
    if (!std::isfinite(sim.st.px[0])) return out;
    vmax = std::max({vmax, double(std::abs(sim.st.vx[0])), double(std::abs(sim.st.vx[1]))});
    if (sim.p->stats().numPairs > 0) {
      ++out.contactSteps;
      touched = true;
    } else if (touched) {
      break;
    }
  }
  double P1[3];
  momentum(P1);
  out.dP = std::sqrt((P1[0] - P0[0]) * (P1[0] - P0[0]) + (P1[1] - P0[1]) * (P1[1] - P0[1]) +
                     (P1[2] - P0[2]) * (P1[2] - P0[2]));
  // Forces are exact negations; only V += F dt/M rounds: ≤ ½ ulp(|v|) per component, body, step.
  out.tolP = std::sqrt(3.0) * double(out.contactSteps + 1) * 0.5 * (m1 + m2) * ulpf(vmax);
  out.e = (sim.st.vx[1] - sim.st.vx[0]) / (v1 - v2);
  out.wallPerSim = sim.wallPerSimSecond();
  return out;
}

}  // namespace

CaseResult sphereSphere(const CaseContext& ctx) {
  CaseResult r;
  r.id = "sphere_sphere";
  r.title = "Sphere–sphere restitution through η, and momentum";
  const double k = 1.0e6, meff = 2.0 / 3.0;
  const double tc0 = kPi * std::sqrt(meff / k);
  const double dt = tc0 / 200.0;
  Table t{"restitution", {"e", "eta", "e_measured", "e_discrete_map", "rel_error", "tolerance", "dP_rel", "dP_tol_rel"}, {}};
  for (double e : {0.1, 0.3, 0.5, 0.7, 0.9, 1.0}) {
    const double eta = e < 1.0 ? dampingForRestitution(e, k, meff) : 0.0;
    const PairImpact pi = pairImpact(ctx.backend, eta, k, 5.0, 0.0, dt, RotationScheme::Report);
    const DiscreteOscillator dm = discreteOscillator(k, eta, meff, dt);
    const double tol = restitutionTolerance(dm, e, k, eta, meff, dt);
    r.checks.push_back(relCheck(fmt("restitution e=%.1f", e),
                                "(v2'−v1')/(v1−v2) vs e, η = 2ζ√(k m_eff), m_eff = m1 m2/(m1+m2)", pi.e, e, tol));
    r.checks.push_back(boundCheck(fmt("momentum head-on e=%.1f", e), "|ΔP| / Σ m|v| (float rounding bound)",
                                  pi.dP / pi.pScale, pi.tolP / pi.pScale, "relative"));
    t.rows.push_back({e, eta, pi.e, dm.e, std::abs(pi.e - e) / e, tol, pi.dP / pi.pScale, pi.tolP / pi.pScale});
  }
  r.tables.push_back(t);
  {
    const double eta = dampingForRestitution(0.5, k, meff);
    const PairImpact pi = pairImpact(ctx.backend, eta, k, 50.0, 0.1, dt, RotationScheme::Report);
    r.checks.push_back(boundCheck("momentum oblique (b = r, k_t = 50)", "|ΔP| / Σ m|v| (float rounding bound)",
                                  pi.dP / pi.pScale, pi.tolP / pi.pScale, "relative"));
  }
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const double etaS = dampingForRestitution(0.5, k, meff);
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    return phaseAverage([&](double ph) {
      const PairImpact pi = pairImpact(ctx.backend, etaS, k, 5.0, 0.0, d, rs, ph);
      return Measured{std::abs(pi.e - 0.5) / 0.5, pi.wallPerSim};
    });
  });
  const std::string div = addSweep(r, rows, "|e_meas − e| / e (e = 0.5), mean of 8 entry phases", "tc");
  r.summary =
      "Two single spheres (r = 0.1 m, m1 = 1 kg, m2 = 2 kg, k_s = 1e6 N/m) collide head-on at a closing speed of "
      "1.5 m/s without gravity. The damping force is η w with w the *full* relative velocity, so along the normal "
      "it is a dashpot of coefficient η on the relative coordinate, whose mass is m_eff = m1 m2/(m1 + m2): "
      "ζ = η/(2√(k_s m_eff)) and e = exp(−πζ/√(1−ζ²)) (unclamped, exact for the model). η is chosen from e with "
      "tumble::dampingForRestitution(e, k_s, m_eff). (Tangentially the damping adds to the shear: the tangential "
      "viscosity is η + k_t.) Tolerance as for the ground case: the discrete map's error plus η dt/m_eff + "
      "k dt²/m_eff, at dt = t_c0/200. Momentum: the pair forces are exact bitwise negations, so only the rounding "
      "of V += F dt/M changes Σ m v; the bound is √3 (contact steps + 1) · ½ (m1 + m2) ulp(v_max). The oblique run "
      "(impact parameter 0.1 m, k_t = 50) exercises damping and shear off the normal. Float suffices: momentum is "
      "conserved to rounding (~1e-7) and the restitution error floor is the O(dt) discretisation."
      + kImpactSweepNote + div;
  return r;
}

}  // namespace tumble::validation::study::physics
