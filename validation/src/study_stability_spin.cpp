// SPDX-License-Identifier: MIT
// The validation study's fast spin: a free body's rotation under both rotation schemes against
// the exact solution in double.
#include "study_stability_common.hpp"

namespace tumble::validation::study::stability {

namespace {

struct Qd {
  double w, x, y, z;
};
Qd qmul(const Qd& a, const Qd& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
Qd qnorm(Qd q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}
/// Rotation angle between two unit quaternions (sign-insensitive).
double qangle(const Qd& a, const Qd& b) {
  const Qd d = qmul(a, Qd{b.w, -b.x, -b.y, -b.z});
  const double v = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return 2.0 * std::atan2(v, std::abs(d.w));
}

/// Inertia of a shape about its centre of mass (double), and its principal axes (Jacobi).
void shapeInertia(const ShapeDef& sh, double I[3][3]) {
  double M = 0, c[3] = {0, 0, 0};
  for (const auto& s : sh.spheres) {
    M += s.mass;
    c[0] += s.mass * double(s.offset.x);
    c[1] += s.mass * double(s.offset.y);
    c[2] += s.mass * double(s.offset.z);
  }
  for (double& v : c) v /= M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) I[i][j] = 0;
  for (const auto& s : sh.spheres) {
    const double u[3] = {s.offset.x - c[0], s.offset.y - c[1], s.offset.z - c[2]};
    const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        I[i][j] += s.mass * ((i == j ? 0.4 * double(s.radius) * s.radius + uu : 0.0) - u[i] * u[j]);
  }
}
void jacobiEigen(const double A0[3][3], double evals[3], double V[3][3]) {
  double A[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      A[i][j] = A0[i][j];
      V[i][j] = i == j ? 1 : 0;
    }
  for (int sweep = 0; sweep < 50; ++sweep) jacobiSweep(A, V);
  for (int i = 0; i < 3; ++i) evals[i] = A[i][i];
}

/// Torque-free rigid body in the shape frame (double, RK4): state L_b (body frame) and q.
struct FreeBody {
  double Iinv[3][3];
  void deriv(const double L[3], const Qd& q, double dL[3], Qd& dq) const {
    double w[3];
    for (int i = 0; i < 3; ++i) w[i] = Iinv[i][0] * L[0] + Iinv[i][1] * L[1] + Iinv[i][2] * L[2];
    // dL_b/dt = L_b × ω_b
    dL[0] = L[1] * w[2] - L[2] * w[1];
    dL[1] = L[2] * w[0] - L[0] * w[2];
    dL[2] = L[0] * w[1] - L[1] * w[0];
    const Qd wq{0, w[0], w[1], w[2]};
    const Qd d = qmul(q, wq);
    dq = {0.5 * d.w, 0.5 * d.x, 0.5 * d.y, 0.5 * d.z};
  }
  void step(double L[3], Qd& q, double h) const {
    double k1[3], k2[3], k3[3], k4[3], Lt[3];
    Qd q1, q2, q3, q4, qt;
    auto axpy = [](const double a[3], const double b[3], double s, double out[3]) {
      for (int i = 0; i < 3; ++i) out[i] = a[i] + s * b[i];
    };
    auto qaxpy = [](const Qd& a, const Qd& b, double s) { return Qd{a.w + s * b.w, a.x + s * b.x, a.y + s * b.y, a.z + s * b.z}; };
    deriv(L, q, k1, q1);
    axpy(L, k1, 0.5 * h, Lt);
    qt = qaxpy(q, q1, 0.5 * h);
    deriv(Lt, qt, k2, q2);
    axpy(L, k2, 0.5 * h, Lt);
    qt = qaxpy(q, q2, 0.5 * h);
    deriv(Lt, qt, k3, q3);
    axpy(L, k3, h, Lt);
    qt = qaxpy(q, q3, h);
    deriv(Lt, qt, k4, q4);
    for (int i = 0; i < 3; ++i) L[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    q = qnorm(Qd{q.w + h / 6 * (q1.w + 2 * q2.w + 2 * q3.w + q4.w), q.x + h / 6 * (q1.x + 2 * q2.x + 2 * q3.x + q4.x),
                 q.y + h / 6 * (q1.y + 2 * q2.y + 2 * q3.y + q4.y), q.z + h / 6 * (q1.z + 2 * q2.z + 2 * q3.z + q4.z)});
  }
};

void inverse3(const double A[3][3], double B[3][3]) {
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  B[0][0] = (A[1][1] * A[2][2] - A[1][2] * A[2][1]) / det;
  B[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) / det;
  B[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) / det;
  B[1][0] = (A[1][2] * A[2][0] - A[1][0] * A[2][2]) / det;
  B[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) / det;
  B[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) / det;
  B[2][0] = (A[1][0] * A[2][1] - A[1][1] * A[2][0]) / det;
  B[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) / det;
  B[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) / det;
}

struct SpinRun {
  double energyDrift = 0;  ///< max |E − E0| / E0
  double energyEnd = 0;    ///< (E_end − E0)/E0
  double lDrift = 0;       ///< max | |L| − |L0| | / |L0|
  double qNorm = 0;        ///< max | |Q| − 1 |
  double angleErr = 0;     ///< orientation error at the end vs the reference [rad]
  std::uint64_t steps = 0;
  bool ok = true;
};

SpinRun runSpin(RotationScheme scheme, const double omega0[3], double dt, std::uint64_t n, Backend backend) {
  Scene sc;
  sc.gravity = {0, 0, 0};
  sc.integrator.rotation = scheme;
  sc.shapes = {oddShape()};
  BodyDef b;
  b.angularVelocity = {float(omega0[0]), float(omega0[1]), float(omega0[2])};
  sc.bodies = {b};
  sc.dt = float(dt);
  Sim sim(sc, backend);
  SpinRun r;
  r.steps = n;
  const double e0 = kineticEnergy(sim.world, sim.st);
  auto lnorm = [](const BodyState& s) { return angularMomentumNorm(s, 0); };
  const double l0 = lnorm(sim.st);
  // Reference: RK4 in the shape frame, from the float L the pipeline starts with.
  double I[3][3];
  shapeInertia(oddShape(), I);
  FreeBody fb;
  inverse3(I, fb.Iinv);
  const Quatf qs0 = shapeOrientation(sim.world, sim.st, 0);
  Qd q{qs0.w, qs0.x, qs0.y, qs0.z};
  const Vec3f Lw{sim.st.lx[0], sim.st.ly[0], sim.st.lz[0]};
  const Vec3f Lb = rotateInv(qs0, Lw);
  double L[3] = {Lb.x, Lb.y, Lb.z};
  const int sub = 20;
  for (std::uint64_t i = 0; i < n; ++i) {
    if (!sim.step()) {
      r.ok = false;
      return r;
    }
    for (int j = 0; j < sub; ++j) fb.step(L, q, double(float(dt)) / sub);
    const double e = kineticEnergy(sim.world, sim.st);
    r.energyDrift = std::max(r.energyDrift, std::abs(e - e0) / e0);
    r.energyEnd = (e - e0) / e0;
    r.lDrift = std::max(r.lDrift, std::abs(lnorm(sim.st) - l0) / l0);
    const BodyState& s = sim.st;
    const double qn = std::sqrt(double(s.qw[0]) * s.qw[0] + double(s.qx[0]) * s.qx[0] + double(s.qy[0]) * s.qy[0] +
                                double(s.qz[0]) * s.qz[0]);
    r.qNorm = std::max(r.qNorm, std::abs(qn - 1.0));
  }
  const Quatf qs = shapeOrientation(sim.world, sim.st, 0);
  r.angleErr = qangle(Qd{qs.w, qs.x, qs.y, qs.z}, q);
  return r;
}

/// Least-squares slope of log y vs log x.
double logSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

CaseResult spinCase(const CaseContext& ctx) {
  const bool full = ctx.depth == Depth::Full;
  CaseResult res;
  res.id = "fast_spin";
  res.title = "Fast-spinning asymmetric clump";
  double I[3][3], ev[3], V[3][3];
  shapeInertia(oddShape(), I);
  jacobiEigen(I, ev, V);
  int iMax = 0, iMin = 0;
  for (int i = 1; i < 3; ++i) {
    if (ev[i] > ev[iMax]) iMax = i;
    if (ev[i] < ev[iMin]) iMin = i;
  }
  const int iMid = 3 - iMax - iMin;
  // ω along the largest axis tilted 25° toward the smallest: L circulates about the largest axis.
  const double tilt = 25.0 * kPi / 180.0;
  double dir[3];
  for (int i = 0; i < 3; ++i) dir[i] = std::cos(tilt) * V[i][iMax] + std::sin(tilt) * V[i][iMin];
  double wb[3] = {std::cos(tilt), std::sin(tilt)};  // components on max/min axes
  const double l2 = ev[iMax] * ev[iMax] * wb[0] * wb[0] + ev[iMin] * ev[iMin] * wb[1] * wb[1];
  const double twoE = ev[iMax] * wb[0] * wb[0] + ev[iMin] * wb[1] * wb[1];
  const double sep = l2 / (twoE * ev[iMid]);  // > 1: circulates about the largest axis
  const double dt = 1.0e-3;
  const double phi = 20.0;  // total rotation angle [rad]: errors stay small enough to be asymptotic
  const std::vector<double> hs =
      full ? std::vector<double>{0.0002, 0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5}
           : std::vector<double>{0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 0.5};
  Table t{"sweep",
          {"scheme", "omega_dt", "steps", "energy_drift", "energy_end", "L_drift", "Q_norm_err", "angle_err",
           "angle_err_per_rad"},
          {}};
  std::vector<double> xs[2], angle[2], edrift[2];
  bool identical = true;
  double lWorst = 0, qWorst = 0;
  bool allOk = true;
  for (int si = 0; si < 2; ++si) {
    const RotationScheme scheme = si == 0 ? RotationScheme::Report : RotationScheme::Splitting;
    for (double h : hs) {
      const double w = h / dt;
      const double om[3] = {w * dir[0], w * dir[1], w * dir[2]};
      const auto n = static_cast<std::uint64_t>(std::llround(phi / h));
      const SpinRun r = runSpin(scheme, om, dt, n, ctx.backend);
      allOk = allOk && r.ok;
      t.rows.push_back({double(si), h, double(n), r.energyDrift, r.energyEnd, r.lDrift, r.qNorm, r.angleErr,
                        r.angleErr / phi});
      lWorst = std::max(lWorst, r.lDrift);
      qWorst = std::max(qWorst, r.qNorm);
      xs[si].push_back(h);
      angle[si].push_back(std::max(r.angleErr, 1e-12));
      edrift[si].push_back(std::max(r.energyDrift, 1e-12));
      if (si == 1) {
        const auto& a = t.rows[t.rows.size() - 1 - hs.size()];
        if (a[3] != r.energyDrift || a[7] != r.angleErr) identical = false;
      }
    }
  }
  // Orders: fit over the points where the error is above the rounding floor and below 0.3 rad.
  // Rounding floor of a run of n steps: up to ~6e-8 rad (½ float ε) per step — the splitting runs
  // at small ω dt, where truncation is negligible, accumulate 7e-9 to 5e-8 per step; a point
  // enters the fit only when its error exceeds 3× that floor.
  auto fitOrder = [&](int si, const std::vector<double>* ys, double lo, double hi) {
    std::vector<double> x, y;
    for (std::size_t i = 0; i < xs[si].size(); ++i) {
      const double floorErr = 3.0 * 6e-8 * (phi / xs[si][i]);
      if (ys[si][i] > std::max(lo, floorErr) && ys[si][i] < hi) {
        x.push_back(xs[si][i]);
        y.push_back(ys[si][i]);
      }
    }
    return x.size() >= 3 ? logSlope(x, y) : kNaN;
  };
  const double orderReport = fitOrder(0, angle, 1e-4, 0.3);
  const double orderSplit = fitOrder(1, angle, 1e-4, 0.3);
  const double eOrderReport = fitOrder(0, edrift, 1e-6, 0.5);
  const double eOrderSplit = fitOrder(1, edrift, 1e-6, 0.5);
  // Where the report's scheme fails: orientation error > 0.1 rad over phi (interpolated).
  double failReport = kNaN, failSplit = kNaN;
  for (int si = 0; si < 2; ++si)
    for (std::size_t i = 1; i < xs[si].size(); ++i)
      if (angle[si][i - 1] <= 0.1 && angle[si][i] > 0.1) {
        const double f = std::log(0.1 / angle[si][i - 1]) / std::log(angle[si][i] / angle[si][i - 1]);
        (si == 0 ? failReport : failSplit) = xs[si][i - 1] * std::pow(xs[si][i] / xs[si][i - 1], f);
        break;
      }
  // Exact case: spin about the largest principal axis (Ω constant): the exponential map is exact,
  // so only rounding remains — over Φ = 20 rad. Over a longer run (Φ_long) the report's scheme
  // amplifies the rounding-level off-axis component (it pumps energy), the splitting does not.
  const double hAxis = 0.5, phiLong = full ? 200.0 : 100.0;
  Table axis{"axis", {"scheme", "phi", "omega_dt", "steps", "angle_err", "energy_drift"}, {}};
  double axisErr[2] = {0, 0}, axisLong[2] = {0, 0}, axisLongE[2] = {0, 0};
  const auto nAxis = static_cast<std::uint64_t>(std::llround(phi / hAxis));
  const auto nLong = static_cast<std::uint64_t>(std::llround(phiLong / hAxis));
  for (int si = 0; si < 2; ++si) {
    const double w = hAxis / dt;
    const double om[3] = {w * V[0][iMax], w * V[1][iMax], w * V[2][iMax]};
    const RotationScheme sch = si == 0 ? RotationScheme::Report : RotationScheme::Splitting;
    const SpinRun a = runSpin(sch, om, dt, nAxis, ctx.backend);
    const SpinRun b = runSpin(sch, om, dt, nLong, ctx.backend);
    axisErr[si] = a.angleErr;
    axisLong[si] = b.angleErr;
    axisLongE[si] = b.energyDrift;
    axis.rows.push_back({double(si), phi, hAxis, double(nAxis), a.angleErr, a.energyDrift});
    axis.rows.push_back({double(si), phiLong, hAxis, double(nLong), b.angleErr, b.energyDrift});
  }
  const double axisTol = double(nAxis) * 32.0 * 6e-8 + phi * 1e-6;
  const double axisTolLong = double(nLong) * 32.0 * 6e-8 + phiLong * 1e-6;
  res.checks.push_back(mkCheck("finite", "no SimulationError, finite state", allOk ? 0 : 1, 0, allOk ? 0 : 1, 0, "flag"));
  res.checks.push_back(boundCheck("|L| conserved (T = 0)", "max | |L| − |L0| | / |L0| (world L untouched when T = 0)",
                                  lWorst, 1e-6, "relative"));
  res.checks.push_back(boundCheck("|Q| = 1", "max | |Q| − 1 | (renormalised every step)", qWorst, 1e-6, "absolute"));
  res.checks.push_back(mkCheck("report: first-order orientation error",
                               "slope of log(angle error) vs log(ω dt), errors in (max(1e-4, 1.8e-7 n), 0.3) rad: 1", orderReport,
                               1.0, std::abs(orderReport - 1.0), 0.3, "absolute"));
  res.checks.push_back(boundCheck("principal-axis spin exact (report)",
                                  "Ω constant: exp map exact; error <= n·32·6e-8 + Φ·1e-6 rad (float rounding)",
                                  axisErr[0], axisTol, "rad"));
  res.checks.push_back(boundCheck("principal-axis spin exact (splitting)", "same bound", axisErr[1], axisTol, "rad"));
  res.checks.push_back(boundCheck("principal-axis spin, long run (splitting)",
                                  "over Φ_long: error <= n·32·6e-8 + Φ_long·1e-6 rad (symplectic: no energy pumping)",
                                  axisLong[1], axisTolLong, "rad"));
  if (!identical) {
    res.checks.push_back(mkCheck("splitting: second-order orientation error",
                                 "slope of log(angle error) vs log(ω dt), errors in (max(1e-4, 1.8e-7 n), 0.3) rad: 2",
                                 orderSplit, 2.0, std::abs(orderSplit - 2.0), 0.4, "absolute"));
    double worstRatio = 0;
    for (std::size_t i = 0; i < hs.size(); ++i)
      if (edrift[0][i] > 1e-5) worstRatio = std::max(worstRatio, edrift[1][i] / edrift[0][i]);
    res.checks.push_back(boundCheck("splitting: energy error below the report's",
                                    "max over ω dt of drift_splitting / drift_report (where report > 1e-5)",
                                    worstRatio, 1.0, "ratio"));
  }
  res.tables = {t, axis};
  res.plots.push_back(Plot{"angle", "Orientation error after Φ rad of rotation vs ω dt", "sweep", "omega_dt", "ω dt",
                           "angle error [rad]", {"angle_err"}, true, true, "scheme"});
  res.plots.push_back(Plot{"energy", "Max kinetic-energy drift vs ω dt", "sweep", "omega_dt", "ω dt",
                           "max |E − E0| / E0", {"energy_drift"}, true, true, "scheme"});
  res.summary = fmt(
      "The asymmetric 4-sphere clump of physics_test (principal moments %.4g, %.4g, %.4g kg m²), no "
      "gravity, no contacts (T = 0), dt = 10⁻³ s, |ω| = (ω dt)/dt up to %.0f rad/s, ω along the largest "
      "axis tilted 25° toward the smallest (L²/(2E I_mid) = %.3f > 1: L circulates about the largest axis, "
      "away from the separatrix). Each run turns Φ = %.0f rad (n = Φ/(ω dt) steps). Reference: RK4 on "
      "Euler's equations and the quaternion in double with 20 substeps per step. scheme 0 = report, "
      "1 = splitting.\n\n"
      "The report's scheme holds Ω fixed over a step: the exponential map is exact for constant Ω (so a "
      "spin about a principal axis must stay exact to rounding at ω dt = 0.5: measured %.2e / %.2e rad, "
      "bound %.2e). Over Φ_long = %.0f rad the report's scheme does *not* keep that spin (error %.3g rad, "
      "energy drift %.3g): its energy pumping amplifies the rounding-level off-axis component; splitting "
      "stays exact (%.2e rad, bound %.2e). For a precessing body the report's scheme commits a local error ~ |dΩ/dt| dt² ~ (ω dt)², i.e. a "
      "first-order global error ∝ Φ·ω dt. Measured orders: orientation %.2f (report), %.2f (splitting); "
      "energy drift %.2f, %.2f. The orientation error reaches 0.1 rad over %.0f rad of rotation at "
      "ω dt ≈ %.3g (report) and %s (splitting). World-frame L is untouched when T = 0, so |L| is conserved "
      "by both to rounding (worst %.1e) — the drift shows in the energy (body-frame L leaves the energy "
      "ellipsoid); for the report's scheme it grows until the spin has moved to the smallest axis (maximum "
      "energy for the given |L|; table `sweep`, energy_drift saturating). %s",
      ev[iMin], ev[iMid], ev[iMax], hs.back() / dt, sep, phi, axisErr[0], axisErr[1], axisTol, phiLong, axisLong[0], axisLongE[0], axisLong[1],
      axisTolLong, orderReport,
      orderSplit, eOrderReport, eOrderSplit, phi, failReport,
      std::isnan(failSplit) ? "not within ω dt ≤ 0.5" : fmt("%.3g", failSplit).c_str(), lWorst,
      identical ? "**The splitting kernel is not active in this build: both schemes gave identical results, so "
                  "the splitting-specific checks (order 2, energy below the report's) were not run.**"
                : "Splitting is symplectic: its energy error stays bounded (no secular drift) and its "
                  "orientation error is second order.");
  return res;
}

// =============================================================================================
// 6. Coincident centres.

}  // namespace tumble::validation::study::stability
