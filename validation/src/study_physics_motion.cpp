// SPDX-License-Identifier: MIT
// The validation study's cases of motion on the ground: free fall, resting penetration mg/k,
// block sliding to rest, a body on a slope and a sphere rolling or sliding on one.
#include "study_physics_common.hpp"

namespace tumble::validation::study::physics {

// ---------------------------------------------------------------------------------------------
// Free fall.

namespace {

struct Fall {
  double z = kNaN, zDiscrete = kNaN, zCont = kNaN, tolRound = kNaN, wallPerSim = kNaN;
};

Fall freeFall(Backend b, double T, double dt, RotationScheme rs) {
  Scene s;
  s.gravity = {0, 0, float(-kG)};
  s.shapes = {sphereShape(0.1, 1.0, 0.5)};
  s.integrator.rotation = rs;
  s.dt = float(dt);
  s.bodies = {BodyDef{}};
  Sim sim(s, b);
  const std::uint64_t n = stepsFor(T, dt);
  sim.step(n);
  sim.read();
  Fall f;
  const double dtf = asFloat(dt);
  const double dv = asFloat(asFloat(kG) * dtf);  // the per-step kick as the kernel computes it (1/M = 1)
  const double t = double(n) * dtf;
  f.z = sim.st.pz[0];
  f.zDiscrete = -dv * dtf * double(n) * double(n + 1) / 2.0;
  f.zCont = -0.5 * asFloat(kG) * t * t;
  // Rounding bound: each drift rounds z by ≤ ½ ulp(z), each kick v by ≤ ½ ulp(v) (which then
  // drifts for the rest of the run: ≤ n t/2 · ½ ulp(v)).
  f.tolRound = double(n) * 0.5 * ulpf(f.zDiscrete) + double(n) * t / 2 * 0.5 * ulpf(dv * double(n));
  f.wallPerSim = sim.wallPerSimSecond();
  return f;
}

}  // namespace

CaseResult freeFallCase(const CaseContext& ctx) {
  CaseResult r;
  r.id = "free_fall";
  r.title = "Free fall";
  const double T = 1.0, dt = 1.0e-3;
  const Fall f = freeFall(ctx.backend, T, dt, RotationScheme::Report);
  r.checks.push_back(absCheck("position vs discrete leapfrog formula", "z_n = −g dt² n(n+1)/2 (kick-drift, exact)",
                              f.z, f.zDiscrete, f.tolRound, "m"));
  r.checks.push_back(absCheck("position vs continuous formula", "z(t) = −½ g t²; leapfrog offset −½ g t dt",
                              f.z, f.zCont, 0.5 * kG * T * dt + f.tolRound, "m"));
  std::vector<double> dts = ctx.depth == Depth::Quick ? std::vector<double>{1e-2, 1e-3}
                                                       : std::vector<double>{2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4};
  Table t{"offset", {"dt", "z", "z_discrete", "z_continuous", "offset_measured", "offset_predicted"}, {}};
  const auto rows = sweep(dts, 1.0, [&](double d, RotationScheme rs) {
    const Fall x = freeFall(ctx.backend, T, d, rs);
    if (rs == RotationScheme::Report && (t.rows.empty() || t.rows.back()[0] != d))  // once per dt (timing repeats)
      t.rows.push_back({d, x.z, x.zDiscrete, x.zCont, x.z - x.zCont, -0.5 * asFloat(kG) * T * asFloat(d)});
    return Measured{std::abs(x.z - x.zCont), x.wallPerSim};
  });
  r.tables.push_back(t);
  const std::string div = addSweep(r, rows, "|z − (−½ g t²)| at t = 1 s [m]", "s");
  r.summary =
      "A sphere falls from rest for 1 s (no ground). Translation is the leapfrog kick-drift V ← V + g dt, "
      "X ← X + V dt, which with a constant force gives exactly z_n = −g dt² n(n+1)/2 = −½ g t_n² − ½ g t_n dt: the "
      "continuous parabola shifted by half a step of velocity. The first check compares with that discrete formula "
      "(tolerance: the float rounding bound n·½ ulp(z) + n t/2·½ ulp(v)); the second with the continuous one "
      "(tolerance: the O(dt) offset ½ g t dt plus rounding). The sweep shows the error against the continuous "
      "formula, first order in dt, at a cost ∝ 1/dt; there is no stability limit (no stiffness). Float suffices: "
      "the rounding bound (~1e-4 m at dt = 1e-3 s, typically far less) is below the O(dt) offset at every swept dt. " +
      div;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Resting penetration mg/k.

namespace {

struct Rest {
  double delta = kNaN, wallPerSim = kNaN;
};

Rest restingPenetration(Backend b, double k, double dt, double T, RotationScheme rs) {
  const double r = 0.1, m = 1.0;
  Scene s = groundScene({0, 0, float(-kG)}, k, sphereShape(r, m, 0.5), dt, rs);
  BodyDef bd;
  bd.position = {0, 0, float(r)};
  s.bodies = {bd};
  Sim sim(s, b);
  // Settle, then average δ over the last 200 steps: at rest z may cycle over a few ulp.
  const std::uint64_t n = stepsFor(T, dt);
  sim.step(n > 200 ? n - 200 : 0);
  double sum = 0.0;
  for (int i = 0; i < 200; ++i) {
    sim.step();
    sim.read();
    sum += asFloat(r) - double(sim.st.pz[0]);
  }
  return {sum / 200.0, sim.wallPerSimSecond()};
}

}  // namespace

CaseResult restingCase(const CaseContext& ctx) {
  CaseResult r;
  r.id = "resting_penetration";
  r.title = "Resting penetration mg/k";
  const double m = 1.0, rad = 0.1, e = 0.5;
  const double le = std::log(e), zeta = -le / std::sqrt(kPi * kPi + le * le);
  Table t{"stiffness", {"k", "delta_expected", "delta_measured", "rel_error", "ulp_r_over_delta", "tolerance"}, {}};
  for (double k : {1e4, 1e5, 1e6, 1e7}) {
    const double tc = kPi * std::sqrt(m / k), w0 = std::sqrt(k / m);
    const double T = 60 * tc;
    const Rest x = restingPenetration(ctx.backend, k, tc / 50, T, RotationScheme::Report);
    const double expected = m * asFloat(kG) / asFloat(k);
    // z is a float near r: it resolves δ only to ulp(r). And the float state stops moving as
    // soon as |v dt| < ½ ulp(z), so v may stay at up to ulp(r)/(2 dt) with the dashpot c v
    // balancing a spring residual: |δ − mg/k| ≤ ulp(r) (1 + c/(2 k dt)). Plus what is left of
    // the initial oscillation (amplitude δ, decaying as exp(−ζ ω0 t)).
    const double c = dampingForRestitution(e, k, m), dtk = tc / 50;
    const double tol = ulpf(rad) * (1 + c / (2 * k * dtk)) / expected + std::exp(-zeta * w0 * T);
    r.checks.push_back(relCheck(fmt("resting penetration k=%.0e", k), "δ = r − z (mean of the last 200 steps of 60 t_c) vs m g / k_g",
                                x.delta, expected, tol));
    t.rows.push_back({k, expected, x.delta, std::abs(x.delta - expected) / expected, ulpf(rad) / expected, tol});
  }
  r.tables.push_back(t);
  const double k = 1e5, tc0 = kPi * std::sqrt(m / k);
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    const Rest x = restingPenetration(ctx.backend, k, d, 60 * tc0, rs);
    const double ex = m * asFloat(kG) / asFloat(k);
    return Measured{std::abs(x.delta - ex) / ex, x.wallPerSim};
  });
  const std::string div = addSweep(r, rows, "|δ − mg/k| / (mg/k), k = 1e5", "tc");
  r.summary =
      "A sphere (r = 0.1 m, m = 1 kg, e = 0.5) is released touching the ground and settles for 60 contact times. "
      "At rest the leapfrog fixed point is exactly k_g δ = m g (the force is zero), for any stable dt, so the only "
      "error is float resolution: z ≈ r is a float, and δ = r − z is known to ulp(r) = 7.5e-9 m. The tolerance is "
      "2 ulp(r)/δ plus the decayed initial oscillation exp(−ζ ω0 T); δ is averaged over the last 200 steps because the float fixed point can become a cycle over a few ulp. This is the case where float precision shows: "
      "at k_g = 1e7 N/m (δ ≈ 1 µm) the relative resolution is 0.8 %; double would resolve it to 1e-10. For the "
      "stiffnesses tumble scenes use (δ/r ≥ 1e-4), float resolves δ to better than 1e-3 of itself. The sweep "
      "(k = 1e5) is flat at that floor while dt is stable: dt does not matter at rest. At dt = 0.6 t_c0, beyond the "
      "damped leapfrog limit ω0 dt < 2(√(1+ζ²) − ζ) (0.51 t_c0 at e = 0.5), the oscillation grows instead of "
      "settling and the error is O(100). " +
      div;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Block sliding to rest.

namespace {

struct Slide {
  double distance = kNaN, stopTime = kNaN, wallPerSim = kNaN;
};

Slide blockSlide(Backend b, double v0, double mu, double dt, double T, RotationScheme rs) {
  const double r = 0.05, mi = 0.1, k = 1e5;
  Scene s = groundScene({0, 0, float(-kG)}, k, plateShape(r, mi, 0.3), dt, rs);
  s.ground.friction = float(mu);
  BodyDef bd;
  bd.position = {0, 0, float(r - mi * kG / k)};
  bd.velocity = {float(v0), 0, 0};
  s.bodies = {bd};
  Sim sim(s, b);
  const double x0 = sim.st.px[0];
  const std::uint64_t n = stepsFor(T, dt);
  Slide out;
  for (std::uint64_t i = 0; i < n; ++i) {
    sim.step();
    if (std::isnan(out.stopTime)) {
      sim.read();
      if (sim.st.vx[0] <= 0.0f) out.stopTime = sim.time();
    }
  }
  sim.read();
  out.distance = sim.st.px[0] - x0;
  out.wallPerSim = sim.wallPerSimSecond();
  return out;
}

}  // namespace

CaseResult blockSliding(const CaseContext& ctx) {
  CaseResult r;
  r.id = "block_sliding";
  r.title = "Block sliding to rest (Coulomb friction)";
  const double mu = 0.5, mi = 0.1, k = 1e5, kt = k * 2.0 / 7.0;
  const double tc0 = kPi * std::sqrt(mi / k);
  const double dt = tc0 / 100;
  Table t{"stopping", {"v0", "distance", "distance_coulomb", "rel_error", "tolerance", "stop_time", "stop_time_coulomb"}, {}};
  const std::vector<double> v0s = ctx.depth == Depth::Quick ? std::vector<double>{1.0} : std::vector<double>{0.5, 1.0, 2.0};
  for (double v0 : v0s) {
    const double d = v0 * v0 / (2 * mu * kG), ts = v0 / (mu * kG);
    const Slide x = blockSlide(ctx.backend, v0, mu, dt, ts + 0.2, RotationScheme::Report);
    // The stick spring springs back by its stretch at the stop, μ m_i g / k_t,g; leapfrog with a
    // constant deceleration stops within v0 dt of the continuous distance. Factor 2 for the
    // plate's slight pitching and the damping transient at the start.
    const double tolAbs = 2 * (mu * mi * kG / kt + v0 * dt);
    r.checks.push_back(relCheck(fmt("stopping distance v0=%.1f", v0), "d = v0² / (2 μ g)", x.distance, d, tolAbs / d));
    t.rows.push_back({v0, x.distance, d, std::abs(x.distance - d) / d, tolAbs / d, x.stopTime, ts});
  }
  r.tables.push_back(t);
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const double d1 = 1.0 / (2 * mu * kG);
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    const Slide x = blockSlide(ctx.backend, 1.0, mu, d, 1.0 / (mu * kG) + 0.2, rs);
    return Measured{std::abs(x.distance - d1) / d1, x.wallPerSim};
  });
  const std::string div = addSweep(r, rows, "|d − v0²/(2μg)| / d (v0 = 1 m/s)", "tc");
  r.summary =
      "A flat 3×3 clump (spheres r = 0.05 m, m = 0.1 kg; k_g = 1e5 N/m, μ = 0.5) starts at its resting "
      "penetration sliding at v0 and decelerates at μ g: d = v0²/(2μg), t = v0/(μg). Ground friction is a "
      "Cundall–Strack stick spring (k_t,g = 2/7 k_g) capped at μ max(f_n, 0); while sliding the cap holds, so the "
      "deceleration is exactly μ g. At the stop the spring holds its stretch μ m_i g/k_t,g = 1.7e-5 m and springs "
      "back by it. Tolerance: 2 (μ m_i g/k_t,g + v0 dt), at dt = t_c/100. Float suffices: positions ~0.1 m carry "
      "ulp 7e-9 m, far below the 1.7e-5 m spring-back. " +
      div;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Body on a slope: stick below the friction angle, slide above it.

namespace {

struct SlopeRun {
  double v1 = kNaN, v2 = kNaN, x1 = kNaN, x2 = kNaN, vmax = 0.0, wallPerSim = kNaN;
  std::uint64_t steps = 0;
};

/// A body on a slope of angle θ (gravity tilted in x–z) from rest at its resting penetration;
/// velocity and position along the slope at t1 and t2.
SlopeRun slopeRun(Backend b, const ShapeDef& shape, double rLow, double mLow, double k, double mu, double thetaDeg,
                  double dt, double t1, double t2, RotationScheme rs, Vec3f* omegaOut = nullptr) {
  const double th = thetaDeg * kPi / 180.0;
  Scene s = groundScene({float(kG * std::sin(th)), 0.0f, float(-kG * std::cos(th))}, k, shape, dt, rs);
  s.ground.friction = float(mu);
  BodyDef bd;
  bd.position = {0, 0, float(rLow - mLow * kG * std::cos(th) / k)};
  s.bodies = {bd};
  Sim sim(s, b);
  SlopeRun out;
  const std::uint64_t n1 = stepsFor(t1, dt);
  const std::uint64_t n2 = stepsFor(t2, dt);
  sim.step(n1);
  sim.read();
  out.v1 = sim.st.vx[0];
  out.x1 = sim.st.px[0];
  sim.step(n2 - n1);
  sim.read();
  out.v2 = sim.st.vx[0];
  out.x2 = sim.st.px[0];
  out.vmax = std::max(std::abs(out.v1), std::abs(out.v2));
  out.steps = n2 - n1;
  out.wallPerSim = sim.wallPerSimSecond();
  if (omegaOut) *omegaOut = sim.omega();
  return out;
}

/// Relative tolerance of an acceleration measured as (v2 − v1)/(t2 − t1): rounding of v over the
/// steps (≤ ½ ulp(v) per step) plus 1e-3 for the stick-spring and pitching transients.
double accelTolerance(const SlopeRun& x, double a, double dt) {
  return double(x.steps) * 0.5 * ulpf(x.vmax) / (std::abs(a) * double(x.steps) * dt) + 1e-3;
}

}  // namespace

CaseResult slopeCase(const CaseContext& ctx) {
  CaseResult r;
  r.id = "slope";
  r.title = "Body on a slope: stick below the friction angle, slide above";
  const double mu = 0.5, rad = 0.05, mi = 0.1, k = 1e5, kt = k * 2.0 / 7.0;
  const double tc0 = kPi * std::sqrt(mi / k), dt = tc0 / 50;
  const bool quick = ctx.depth == Depth::Quick;
  const double t1 = quick ? 0.5 : 1.0, t2 = quick ? 1.0 : 2.0;
  const ShapeDef plate = plateShape(rad, mi, 0.3);
  const double frictionAngle = std::atan(mu) * 180.0 / kPi;
  Table t{"angles", {"theta_deg", "tan_theta", "sticks_expected", "accel_measured", "accel_expected", "dx_dt_m_per_s"}, {}};
  const std::vector<double> angles = quick ? std::vector<double>{20, 35} : std::vector<double>{10, 20, 25, 30, 35, 45, 60};
  for (double th : angles) {
    const SlopeRun x = slopeRun(ctx.backend, plate, rad, mi, k, mu, th, dt, t1, t2, RotationScheme::Report);
    const double thr = th * kPi / 180;
    const double a = (x.v2 - x.v1) / (t2 - t1);
    const double creep = (x.x2 - x.x1) / (t2 - t1);
    const bool sticks = std::tan(thr) <= mu;
    const double aExp = sticks ? 0.0 : kG * (std::sin(thr) - mu * std::cos(thr));
    if (sticks) {
      // A stuck body sits at the stick spring's equilibrium; what may remain is float-level
      // jitter of X. Bound: 1e-3 of the spring's stretch m g sinθ / k_t,g per second.
      const double bound = 1e-3 * mi * kG * std::sin(thr) / kt;
      r.checks.push_back(boundCheck(fmt("creep at %.0f deg (below %.1f deg)", th, frictionAngle),
                                    "|Δx|/Δt over [t1, t2]: sticks (elastic stick spring)", creep, bound, "m/s"));
    } else {
      r.checks.push_back(relCheck(fmt("acceleration at %.0f deg", th), "g (sin θ − μ cos θ)", a, aExp,
                                  accelTolerance(x, aExp, dt)));
    }
    t.rows.push_back({th, std::tan(thr), sticks ? 1.0 : 0.0, a, aExp, creep});
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"accel", "Plate on a slope (μ = 0.5): acceleration", "angles", "theta_deg", "slope angle [deg]",
                         "acceleration along the slope [m/s²]", {"accel_measured", "accel_expected"}, false, false, ""});
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const double th = 35.0 * kPi / 180, aS = kG * (std::sin(th) - mu * std::cos(th));
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    const SlopeRun x = slopeRun(ctx.backend, plate, rad, mi, k, mu, 35.0, d, 0.2, 0.7, rs);
    return Measured{std::abs((x.v2 - x.v1) / 0.5 - aS) / aS, x.wallPerSim};
  });
  const std::string div = addSweep(r, rows, "|a − g(sin θ − μ cos θ)| / a at 35°", "tc");
  r.summary =
      "The 3×3 plate of the sliding case on a slope (gravity tilted), μ = 0.5, friction angle 26.6°, from rest. "
      "Above the friction angle the acceleration over [t1, t2] (1–2 s; quick 0.5–1 s) is compared with "
      "g(sin θ − μ cos θ); tolerance: float rounding of v over the steps plus 1e-3 for transients. Below it the "
      "model sticks: the stick spring (k_t,g = 2/7 k_g) stretches by m g sin θ/k_t,g (≈ 1e-5 m) and holds; the "
      "creep per second over [t1, t2] is reported and bounded by 1e-3 of that stretch per second. dt = t_c/50. "
      "Float suffices: the acceleration is a difference of velocities of order 1 m/s (ulp 1e-7) over 1 s. " +
      div;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Sphere on a slope: roll or slide.

CaseResult sphereSlope(const CaseContext& ctx) {
  CaseResult r;
  r.id = "sphere_slope";
  r.title = "Sphere on a slope: rolling or sliding";
  const double mu = 0.2, rad = 0.1, m = 1.0, k = 1e5;
  const double tc0 = kPi * std::sqrt(m / k), dt = tc0 / 50;
  const bool quick = ctx.depth == Depth::Quick;
  const double t1 = 0.3, t2 = quick ? 0.6 : 1.0;
  const ShapeDef sphere = sphereShape(rad, m, 0.3), ball = ballShape(rad, m, 0.3);
  Table t{"angles",
          {"theta_deg", "tan_theta", "solid_sphere_rolls", "accel_solid_sphere", "accel_model", "accel_sphere",
           "accel_ball", "spin_ratio_solid_sphere", "spin_ratio_ball", "omega_ball_rad_s"},
          {}};
  const std::vector<double> angles =
      quick ? std::vector<double>{5, 20, 50} : std::vector<double>{5, 10, 15, 20, 30, 35, 40, 50, 60, 70};
  for (double th : angles) {
    const double thr = th * kPi / 180, s = std::sin(thr), c = std::cos(thr);
    const bool rolls = std::tan(thr) <= 3.5 * mu;
    const bool modelSticks = std::tan(thr) <= mu;
    const double aSolid = rolls ? 5.0 / 7.0 * kG * s : kG * (s - mu * c);
    const double aModel = modelSticks ? 0.0 : kG * (s - mu * c);
    const SlopeRun xs = slopeRun(ctx.backend, sphere, rad, m, k, mu, th, dt, t1, t2, RotationScheme::Report);
    Vec3f om{0, 0, 0};
    const SlopeRun xb = slopeRun(ctx.backend, ball, rad, m, k, mu, th, dt, t1, t2, RotationScheme::Report, &om);
    const double as = (xs.v2 - xs.v1) / (t2 - t1), ab = (xb.v2 - xb.v1) / (t2 - t1);
    // Spin about y (the slope's rolling axis): Ω_y R / V.
    const double spinBall = double(om.y) * rad / xb.v2;
    const double spinSolid = rolls ? 1.0 : 2.5 * mu * c / (s - mu * c);
    const std::string where = fmt("%.0f deg", th);
    const double delta = m * kG * c / k;  // resting overlap; friction acts at lever r − δ/2
    if (modelSticks) {
      r.checks.push_back(boundCheck("sphere sticks at " + where, "tan θ ≤ μ: a sphere that cannot rotate sticks",
                                    (xs.x2 - xs.x1) / (t2 - t1), 1e-3 * m * kG * s / (k * 2 / 7), "m/s"));
    } else {
      r.checks.push_back(relCheck("sphere slides at " + where, "g (sin θ − μ cos θ)", as, aModel,
                                  accelTolerance(xs, aModel, dt)));
    }
    if (rolls) {
      // Rolling without slipping about the contact point at lever r − δ/2:
      // a = g sin θ / (1 + I/(m (r − δ/2)²)), Ω (r − δ/2) = V. Tolerance: δ/r for the lever
      // (and the core sphere's 1e-3 of the mass) plus the acceleration's rounding bound.
      r.checks.push_back(relCheck("ball clump rolls at " + where, "a = (5/7) g sin θ", ab, aSolid,
                                  delta / rad + 1e-3 + accelTolerance(xb, aSolid, dt)));
      r.checks.push_back(relCheck("ball clump rolls without slip at " + where, "Ω R / V = 1", spinBall, 1.0,
                                  delta / rad + 1e-3));
    } else {
      r.checks.push_back(relCheck("ball clump slides at " + where, "g (sin θ − μ cos θ)", ab, aModel,
                                  accelTolerance(xb, aModel, dt)));
      // Sliding regime: the spin comes from the friction torque μ m g cos θ (r − δ/2); tolerance
      // δ/(2r) for the lever plus 2e-3.
      r.checks.push_back(relCheck("ball clump spin at " + where, "Ω R / V = (5/2) μ cos θ / (sin θ − μ cos θ)",
                                  spinBall, spinSolid, delta / (2 * rad) + 2e-3));
    }
    t.rows.push_back({th, std::tan(thr), rolls ? 1.0 : 0.0, aSolid, aModel, as, ab, spinSolid, spinBall, double(om.y)});
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"accel", "Sphere on a slope (μ = 0.2): acceleration", "angles", "theta_deg", "slope angle [deg]",
                         "acceleration along the slope [m/s²]", {"accel_solid_sphere", "accel_model", "accel_sphere", "accel_ball"},
                         false, false, ""});
  const std::vector<double> dts = sweepDts(ctx.depth, tc0);
  const double thS = 50.0 * kPi / 180, aS = kG * (std::sin(thS) - mu * std::cos(thS));
  const auto rows = sweep(dts, tc0, [&](double d, RotationScheme rs) {
    const SlopeRun x = slopeRun(ctx.backend, ball, rad, m, k, mu, 50.0, d, 0.2, 0.5, rs);
    return Measured{std::abs((x.v2 - x.v1) / 0.3 - aS) / aS, x.wallPerSim};
  });
  const std::string div = addSweep(r, rows, "|a − g(sin θ − μ cos θ)| / a, ball clump at 50°", "tc");
  r.summary =
      "A solid sphere on a slope rolls without slipping when tan θ ≤ (7/2) μ, with a = (5/7) g sin θ and Ω R = V; "
      "above that it slides with a = g(sin θ − μ cos θ) while friction spins it up, Ω R/V = (5/2) μ cos θ/(sin θ − "
      "μ cos θ). **What tumble's model does** (μ = 0.2, so μ ↔ 11.3° and 3.5 μ ↔ 35°): (1) single-sphere bodies do "
      "not rotate (the report's model), so a sphere sticks for tan θ ≤ μ and slides with g(sin θ − μ cos θ) above; "
      "it never rolls. (2) A two-particle \"ball\" clump (the sphere plus a tiny core, so that it may rotate) "
      "behaves as the solid sphere: ground friction acts on the velocity of the contact point (V + Ω × lever, "
      "docs/model.md), so below tan θ = 3.5 μ it rolls without slipping at a = (5/7) g sin θ with Ω R = V (checked, "
      "tolerance δ/r for the lever r − δ/2 plus 1e-3), and above it slides with the sliding acceleration and the "
      "spin-up of the friction torque (checked). There is no rolling resistance: a ball rolls down any slope. "
      "dt = t_c/50. Float suffices: the "
      "accelerations are differences of velocities of order 1–10 m/s (ulp ≤ 1e-6) over 0.7 s, and the checks' "
      "errors (≤ 1e-4) are set by the stick-spring transient, not by rounding. " +
      div;
  return r;
}

}  // namespace tumble::validation::study::physics
