// SPDX-License-Identifier: MIT
// The validation study's stacks: a mass ratio of 1:1000 and a tower of 50 clumps at rest.
#include "study_stability_common.hpp"

namespace tumble::validation::study::stability {

namespace {

struct StackResult {
  bool ok = true;
  double dGround = 0, dPair = 0;       ///< final overlaps
  double maxDevGround = 0, maxDevPair = 0;  ///< max |overlap − analytic| over the run (held runs)
  double maxRise = 0;                  ///< max over t1 < t2 of E(t2) − E(t1)
  double e0 = 0, eEnd = 0, eMax = 0;
  double maxZTop = 0;                  ///< highest z of body 1
  std::uint64_t steps = 0;
  Table energy{"", {"t", "E", "KE"}, {}};
};

/// Energy of single-sphere bodies on the ground: KE + gravity + springs.
double sphereEnergy(const World& w, const BodyState& s) {
  const Scene& p = w.params;
  double e = 0;
  const std::size_t n = s.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double m = w.bodyMass[i];
    e += 0.5 * m * (double(s.vx[i]) * s.vx[i] + double(s.vy[i]) * s.vy[i] + double(s.vz[i]) * s.vz[i]);
    e -= m * (double(p.gravity.x) * s.px[i] + double(p.gravity.y) * s.py[i] + double(p.gravity.z) * s.pz[i]);
    if (p.ground.enabled) {
      const double d = double(w.radius[i]) - (double(s.pz[i]) - p.ground.height);
      if (d > 0) e += 0.5 * double(p.ground.stiffness) * d * d;
    }
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = double(s.px[i]) - s.px[j], dy = double(s.py[i]) - s.py[j], dz = double(s.pz[i]) - s.pz[j];
      const double d = double(w.radius[i]) + w.radius[j] - std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d > 0) e += 0.5 * double(p.contact.stiffness) * d * d;
    }
  }
  return e;
}

/// Two spheres stacked on the ground: body 0 below, body 1 on top.
StackResult runStack(Scene sc, double seconds, std::size_t samples, double dGa, double dPa, Backend backend,
                     bool stopOnGrowth) {
  StackResult r;
  Sim sim(sc, backend);
  const double rad = sim.world.radius[0];
  const std::uint64_t n = stepsFor(seconds, sc.dt);
  r.e0 = sphereEnergy(sim.world, sim.st);
  double eMin = r.e0;
  r.eMax = r.e0;
  const std::uint64_t every = std::max<std::uint64_t>(1, n / samples);
  for (std::uint64_t i = 0; i < n; ++i) {
    if (!sim.step()) {
      r.ok = false;
      r.steps = i + 1;
      return r;
    }
    const double e = sphereEnergy(sim.world, sim.st);
    r.maxRise = std::max(r.maxRise, e - eMin);
    eMin = std::min(eMin, e);
    r.eMax = std::max(r.eMax, e);
    const double dg = rad - double(sim.st.pz[0]);
    const double dp = 2 * rad - (double(sim.st.pz[1]) - double(sim.st.pz[0]));
    r.maxDevGround = std::max(r.maxDevGround, std::abs(dg - dGa));
    r.maxDevPair = std::max(r.maxDevPair, std::abs(dp - dPa));
    r.dGround = dg;
    r.dPair = dp;
    r.maxZTop = std::max(r.maxZTop, double(sim.st.pz[1]));
    if (i % every == 0) r.energy.rows.push_back({(i + 1) * double(sc.dt), e, kineticEnergy(sim.world, sim.st)});
    if (stopOnGrowth && r.maxZTop > 4.0 * rad) {  // the top sphere was ejected
      r.steps = i + 1;
      r.eEnd = e;
      return r;
    }
  }
  r.steps = n;
  r.eEnd = sphereEnergy(sim.world, sim.st);
  return r;
}

}  // namespace

CaseResult massRatioCase(const CaseContext& ctx) {
  const bool full = ctx.depth == Depth::Full;
  CaseResult res;
  res.id = "mass_ratio_1000";
  res.title = "Mass ratio 1:1000";
  const float r = 0.1f, mL = 0.01f, mH = 10.0f, k = 1.0e4f, e = 0.1f;
  const double meff = double(mL) * mH / (double(mL) + mH);
  const float eta = float(2.0 * 0.5 * std::sqrt(double(k) * meff));  // ζ = 0.5 on the light pair
  auto base = [&](bool lightOnTop) {
    Scene sc;
    sc.gravity = {0, 0, float(-kG)};
    sc.ground.enabled = true;
    sc.ground.stiffness = k;
    sc.contact = {k, eta, 0.0f};
    sc.shapes = {sphereShape(r, mL, e), sphereShape(r, mH, e)};
    sc.bodies = {bodyAt(lightOnTop ? 1 : 0, 0, 0, r), bodyAt(lightOnTop ? 0 : 1, 0, 0, 3 * r)};
    return sc;
  };
  const double g = double(float(kG));
  Scene a = base(true);
  const World wa = World::fromScene(a);
  const double tc = shortestContactTime(wa);
  a.dt = float(tc / 20.0);
  const double dt = a.dt;
  const double seconds = full ? 5.0 : 2.0;
  // Highest frequency: the light sphere on its contact(s).
  const double hA = std::sqrt(double(k) / meff) * dt;
  // A: light on heavy, dropped from touching.
  const double dGA = (double(mL) + mH) * g / k, dPA = double(mL) * g / k;
  const StackResult A = runStack(a, seconds, 400, dGA, dPA, ctx.backend, false);
  // Released energy ΔE = E0 − E_eq (analytic rest state).
  const double eEqA = double(mH) * g * (r - dGA) + double(mL) * g * (3 * r - dGA - dPA) + 0.5 * k * dGA * dGA +
                      0.5 * k * dPA * dPA;
  const double dEA = A.e0 - eEqA;
  // B: heavy on light, started at the analytic rest state.
  Scene b = base(false);
  b.dt = a.dt;
  const double dGB = (double(mL) + mH) * g / k, dPB = double(mH) * g / k;
  b.bodies[0].position.z = float(r - dGB);
  b.bodies[1].position.z = float(double(r - dGB) + 2 * r - dPB);
  const StackResult B = runStack(b, seconds, 400, dGB, dPB, ctx.backend, false);
  const double hB = std::sqrt(2.0 * k / mL) * dt;  // light sphere between two springs
  // C: A at the dt the heavy pair alone would suggest (t_c of m_eff = m_H/2, /20).
  Scene c = a;
  c.dt = float(kPi * std::sqrt(0.5 * mH / k) / 20.0);
  const double hC = std::sqrt(double(k) / meff) * c.dt;
  const StackResult C = runStack(c, seconds, 400, dGA, dPA, ctx.backend, true);
  // Ejected: the light sphere, dropped from touching, rises a radius above where it started.
  const bool cBlew = !C.ok || C.maxZTop > 4.0 * r;

  const double zTop = 3 * r;
  const double ulpTop = ulpf(zTop);
  auto tolFor = [&](double d) { return 0.01 + 4 * ulpTop / d; };
  res.checks.push_back(mkCheck("A light on heavy: finite", "no SimulationError, finite state", A.ok ? 0 : 1, 0,
                               A.ok ? 0 : 1, 0, "flag"));
  res.checks.push_back(relCheck("A ground overlap", "(m_L + m_H) g / k_g", A.dGround, dGA, tolFor(dGA)));
  res.checks.push_back(relCheck("A pair overlap", "m_L g / k_s", A.dPair, dPA, tolFor(dPA)));
  res.checks.push_back(boundCheck("A energy non-increasing", "max_{t1<t2} E(t2) − E(t1) <= (h/2)·ΔE + rounding",
                                  A.maxRise, 0.5 * hA * dEA + 1e-6 * std::abs(A.e0), "J"));
  res.checks.push_back(mkCheck("B heavy on light: finite", "no SimulationError, finite state", B.ok ? 0 : 1, 0,
                               B.ok ? 0 : 1, 0, "flag"));
  res.checks.push_back(relCheck("B ground overlap (held)", "(m_L + m_H) g / k_g, max deviation over the run",
                                dGB + B.maxDevGround, dGB, tolFor(dGB)));
  res.checks.push_back(relCheck("B pair overlap (held)", "m_H g / k_s, max deviation over the run",
                                dPB + B.maxDevPair, dPB, tolFor(dPB)));
  // B starts at rest at the analytic state: E may only wobble by rounding: each body's z is
  // off by up to ½ ulp, worth (m g + k δ) ulp of energy each.
  const double eRoundB = 4 * ((double(mL) + mH) * g + 2 * k * dPB + k * dGB) * ulpTop;
  res.checks.push_back(boundCheck("B energy non-increasing", "max_{t1<t2} E(t2) − E(t1) <= 4 (Σ m g + k Σ δ) ulp(z)",
                                  B.maxRise, eRoundB, "J"));
  res.checks.push_back(mkCheck("C heavy-pair dt blows up (as predicted)",
                               "h = ω_light dt > h_c(ζ) predicts growth: light sphere rises > r above its start, or NaN",
                               cBlew ? 1 : 0, 1, cBlew ? 0 : 1, 0, "flag (0 = as predicted)"));
  Table t{"runs",
          {"run", "dt", "h_max", "h_c", "ground_overlap", "ground_analytic", "pair_overlap", "pair_analytic", "E0",
           "E_end", "max_rise", "steps"},
          {}};
  const double hcA = criticalH(0.5);
  t.rows.push_back({0, dt, hA, hcA, A.dGround, dGA, A.dPair, dPA, A.e0, A.eEnd, A.maxRise, double(A.steps)});
  t.rows.push_back({1, dt, hB, kNaN, B.dGround, dGB, B.dPair, dPB, B.e0, B.eEnd, B.maxRise, double(B.steps)});
  t.rows.push_back({2, double(c.dt), hC, hcA, C.dGround, dGA, C.dPair, dPA, C.e0, C.eEnd, C.eMax - C.e0,
                    double(C.steps)});
  Table ea = A.energy;
  ea.name = "energy_A";
  Table ec = C.energy;
  ec.name = "energy_C";
  res.tables = {t, ea, ec};
  res.plots.push_back(Plot{"energy_A", "Light (0.01 kg) on heavy (10 kg): energy while settling", "energy_A", "t",
                           "t [s]", "E [J]", {"E"}, false, false, ""});
  res.plots.push_back(Plot{"energy_C", "Same at the heavy pair's dt (h > h_c): energy grows", "energy_C", "t",
                           "t [s]", "E [J]", {"E"}, false, false, ""});
  res.summary = fmt(
      "Spheres r = 0.1 m of m_L = 0.01 kg and m_H = 10 kg (ratio 1:1000), k_s = k_g = 10⁴ N/m, e = 0.1 on the "
      "ground, pair damping η = %.3g N s/m (ζ = 0.5 for the light pair, m_eff = %.4g kg), gravity 9.81. "
      "dt = t_c/20 of the shortest contact as the scene suggests (`shortestContactTime`, m_eff = m_L/2 "
      "conservatively): dt = %.4g s, so the light sphere's contact has h = ω dt = %.3f (A) and %.3f (B, "
      "two springs), far below h_c.\n\n"
      "- **A**, light on heavy, dropped from touching, %.1f s: final overlaps vs the static values "
      "δ_g = (m_L+m_H) g/k_g = %.4g m and δ_p = m_L g/k_s = %.4g m; measured %.6g and %.6g. Tolerance 1 %% "
      "+ 4 ulp(z = 0.3 m)/δ (the light pair's overlap is only %.0f ulps of its height). Energy "
      "E = KE + Σ m g z + ½kδ² must not rise: leapfrog's stored energy differs from its conserved "
      "(shadow) energy by at most ω²dt·x·v ≤ (h/2)·E_osc, with E_osc ≤ ΔE = E0 − E_eq = %.4g J, so the "
      "largest rise over any interval is bounded by (h/2)ΔE = %.3g J; measured %.3g J.\n"
      "- **B**, heavy on light, started at the analytic rest state (its heavy mode is damped only "
      "through the light sphere's dashpots, ζ ≈ 0.01, so a drop would take tens of seconds to settle): "
      "the overlaps must stay at δ_g = %.4g, δ_p = m_H g/k_s = %.4g m throughout (max deviations %.3g, "
      "%.3g m) and the energy may rise only by rounding (%.3g J; measured %.3g J).\n"
      "- **C**, A at dt = t_c/20 of the heavy pair (%.4g s): h = %.2f > h_c = %.3f for the light "
      "contact, so the scheme must be unstable: the light sphere is ejected (rises more than r above its start; "
      "max height %.4g m vs start 0.3 m; %s): every contact kicks it harder than the last. This is why the "
      "scene's dt must follow the lightest pair.",
      double(eta), meff, dt, hA, hB, seconds, dGA, dPA, A.dGround, A.dPair, dPA / ulpTop, dEA, 0.5 * hA * dEA,
      A.maxRise, dGB, dPB, B.maxDevGround, B.maxDevPair, eRoundB, B.maxRise, double(c.dt), hC, hcA, C.maxZTop, C.ok ? "state stayed finite" : "SimulationError/NaN");
  return res;
}

// =============================================================================================
// 3. Tower of 50 clumps.

CaseResult towerCase(const CaseContext& ctx) {
  const bool full = ctx.depth == Depth::Full;
  CaseResult res;
  res.id = "tower_50";
  res.title = "Tower of 50 stacked clumps settling";
  const int layers = 50;
  const float r = 0.05f, m = 0.1f, k = 1.0e5f;
  const double meff = 0.5 * m;
  const double zetaPair = 2.0;
  const float eta = float(2.0 * zetaPair * std::sqrt(double(k) * meff));
  Scene sc;
  sc.gravity = {0, 0, float(-kG)};
  sc.ground.enabled = true;
  sc.ground.stiffness = k;
  sc.contact = {k, eta, 0.0f};
  ShapeDef plate{"plate", {}};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      plate.spheres.push_back(SphereDef{{(2 * i - 1) * r, (2 * j - 1) * r, 0}, r, m, 0.1f});
  sc.shapes = {plate};
  for (int l = 0; l < layers; ++l) sc.bodies.push_back(bodyAt(0, 0, 0, r + 2.0 * r * l));
  const World w0 = World::fromScene(sc);
  sc.dt = float(shortestContactTime(w0) / 20.0);
  const double dt = sc.dt;
  const double M = 4.0 * m, g = double(float(kG));
  // Analytic rest state: each of the 4 columns carries a quarter of the weight above.
  std::vector<double> zA(layers), dA(layers);  // dA[0]: ground overlap; dA[l]: between l−1 and l
  for (int l = 0; l < layers; ++l) {
    dA[l] = (layers - l) * M * g / (4.0 * k);
    zA[l] = (l == 0 ? double(r) : zA[l - 1] + 2.0 * r) - dA[l];
  }
  const double e0 = [&] {
    double e = 0;
    for (int l = 0; l < layers; ++l) e += M * g * (r + 2.0 * r * l);
    return e;
  }();
  double eEq = 0;
  for (int l = 0; l < layers; ++l) eEq += M * g * zA[l] + 4 * 0.5 * k * dA[l] * dA[l];
  const double dE = e0 - eEq;
  // Float floor: a plate whose velocity satisfies |V| dt < ½ ulp(z) cannot move (X + V dt rounds
  // back to X), and then its forces, hence V, need not change either: a frozen residual velocity.
  // Settled KE is therefore bounded by KE_dead = Σ ½ M (ulp(z_l)/(2 dt))², not by zero.
  double keDead = 0;
  for (int l = 0; l < layers; ++l) keDead += 0.5 * M * std::pow(ulpf(zA[l]) / (2.0 * dt), 2);
  const double keThresh = 1e-6 * dE + keDead;
  const double maxSeconds = full ? 12.0 : 6.0;
  const double hold = full ? 1.0 : 0.5;  // stay settled this long before stopping
  Sim sim(sc, ctx.backend);
  Table ke{"kinetic_energy", {"t", "KE", "KE_over_dE"}, {}};
  const std::uint64_t chunk = std::max<std::uint64_t>(1, stepsFor(0.01, dt));
  const std::uint64_t nMax = stepsFor(maxSeconds, dt);
  double settle = kNaN, maxOverlap = 0, maxDrift = 0;
  bool order = true;
  const auto t0 = Clock::now();
  std::uint64_t steps = 0;
  double kEnd = kNaN;
  while (steps < nMax) {
    if (!sim.step(chunk)) break;
    steps += chunk;
    const BodyState& s = sim.st;
    const double kin = kineticEnergy(sim.world, s);
    kEnd = kin;
    ke.rows.push_back({steps * dt, kin, kin / dE});
    if (kin < keThresh) {
      if (std::isnan(settle)) settle = steps * dt;
    } else {
      settle = kNaN;
    }
    maxOverlap = std::max(maxOverlap, double(r) - double(s.pz[0]));
    for (int l = 1; l < layers; ++l) {
      maxOverlap = std::max(maxOverlap, 2.0 * r - (double(s.pz[l]) - s.pz[l - 1]));
      if (!(s.pz[l] > s.pz[l - 1])) order = false;
    }
    for (int l = 0; l < layers; ++l)
      maxDrift = std::max({maxDrift, std::abs(double(s.px[l])), std::abs(double(s.py[l]))});
    // Stop `hold` s after settling (it stays settled if the equilibrium is stable).
    if (!std::isnan(settle) && steps * dt > settle + hold) break;
  }
  const double wall = since(t0);
  // Final heights vs analytic.
  const BodyState& s = sim.st;
  Table h{"heights", {"layer", "z", "z_analytic", "gap_overlap", "overlap_analytic", "rel_error"}, {}};
  double worstRel = 0, worstTol = 1, worstRatio = -1;
  int bad = 0;
  for (int l = 0; l < layers; ++l) {
    const double ov = l == 0 ? double(r) - s.pz[0] : 2.0 * r - (double(s.pz[l]) - s.pz[l - 1]);
    const double tol = 0.01 + 4 * ulpf(zA[l]) / dA[l];
    const double rel = std::abs(ov - dA[l]) / dA[l];
    if (!(rel <= tol)) ++bad;
    if (rel / tol > worstRatio) {
      worstRatio = rel / tol;
      worstRel = rel;
      worstTol = tol;
    }
    h.rows.push_back({double(l), s.pz[l], zA[l], ov, dA[l], rel});
  }
  const double topErr = std::abs(double(s.pz[layers - 1]) - zA[layers - 1]);
  double totalComp = 0;
  for (double d : dA) totalComp += d;
  res.checks.push_back(mkCheck("finite, no fall-through", "state finite; z_l > z_(l-1) at every sample",
                               (sim.ok && order) ? 0 : 1, 0, (sim.ok && order) ? 0 : 1, 0, "flag"));
  res.checks.push_back(boundCheck("kinetic energy settles",
                                  "KE at the end <= 1e-6 ΔE + Σ ½ M (ulp(z_l)/(2 dt))² (frozen-velocity floor)", kEnd,
                                  keThresh, "J"));
  res.checks.push_back(zeroCheck("layer overlaps vs analytic",
                                 "|δ_l − (50−l) M g/(4k)| / δ_l <= 1 % + 4 ulp(z_l)/δ_l for every layer", bad));
  res.checks.push_back(relCheck("top height", "z_top = r + 98 r − Σ δ_l", double(s.pz[layers - 1]),
                                zA[layers - 1], (0.01 * totalComp + 4 * ulpf(zA[layers - 1])) / zA[layers - 1]));
  res.checks.push_back(boundCheck("max overlap / r while settling",
                                  "max δ / r <= 2 δ_static,max / r (step load on a spring: at most twice static)",
                                  maxOverlap / r, 2.0 * dA[0] / r, "ratio"));
  res.checks.push_back(boundCheck("horizontal drift", "max |X|,|Y| <= 1e-6 r (aligned tower: symmetric forces)",
                                  maxDrift, 1e-6 * r, "m"));
  Table sum{"summary", {"layers", "dt", "settle_time", "wall_seconds", "steps", "max_overlap_over_r",
                        "bottom_overlap_analytic_over_r", "top_z", "top_z_analytic", "top_error", "total_compression"},
            {}};
  sum.rows.push_back({double(layers), dt, settle, wall, double(steps), maxOverlap / r, dA[0] / r,
                      double(s.pz[layers - 1]), zA[layers - 1], topErr, totalComp});
  res.tables = {sum, h, ke};
  res.plots.push_back(Plot{"kinetic_energy", "Tower of 50 clumps: kinetic energy / released energy", "kinetic_energy",
                           "t", "t [s]", "KE / ΔE", {"KE_over_dE"}, false, true, ""});
  res.plots.push_back(Plot{"overlaps", "Tower: overlap under each layer, measured and analytic", "heights", "layer",
                           "layer (0 = ground contact)", "overlap [m]", {"gap_overlap", "overlap_analytic"}, false,
                           false, ""});
  res.summary = fmt(
      "50 plates of 2×2 spheres (r = %.2g m, m = %.2g kg each, M = %.2g kg per plate) stacked in four "
      "aligned columns, dropped from touching (zero overlap) onto the ground; k_s = k_g = %.0g N/m, pair "
      "damping η = %.3g N s/m (ζ = %.1f per pair), e = 0.1 on the ground, dt = t_c/20 = %.4g s. The lowest "
      "mode of the chain is damped only weakly (modal ζ ≈ ζ_pair·ω₁/ω_pair), which sets the settle time.\n\n"
      "Static solution: each column carries a quarter of the weight above, δ_l = (50 − l) M g/(4k) "
      "(δ_0 = %.4g m = %.2f %% of r at the ground, %.3g m at the top), heights z_l = z_(l−1) + 2r − δ_l; "
      "total compression %.4g m. Settled means KE < 10⁻⁶ ΔE + KE_dead (ΔE = E0 − E_eq = %.4g J). "
      "KE_dead = Σ ½ M (ulp(z_l)/(2 dt))² = %.3g J is a float floor: a plate with |V| dt < ½ ulp(z) "
      "cannot move (X + V dt rounds back to X), so its forces and V need not change either — the tower "
      "keeps a constant residual KE (8.3·10⁻⁶ J, constant to 3 digits from t = 7 s to 20 s in a probe "
      "run) instead of decaying to zero; threshold %.3g J. The residual "
      "amplitude is then ≲ 10⁻² of the compression, well inside the per-layer tolerance of 1 %% + 4 ulp(z_l)/δ_l "
      "(the top overlaps are ~20 ulps of their height). During settling the largest overlap must stay "
      "within twice the static one (step load on a linear spring).\n\n"
      "Measured: settled at t = %.3g s (KE < threshold and stayed there), %llu steps in %.2f s wall "
      "(%.1f µs per step, 200 particles); max overlap %.3f r (static %.3f r); top height %.6f m vs "
      "%.6f m; worst layer error %.2e (tolerance %.2e). The tower is an unstable equilibrium "
      "(spheres on spheres, and the model has no Coulomb friction between particles, SPEC §2.3): it stays "
      "up only because it is exactly symmetric; max horizontal drift %.2g m.",
      double(r), double(m), M, double(k), double(eta), zetaPair, dt, dA[0], 100 * dA[0] / r, dA[layers - 1],
      totalComp, dE, keDead, keThresh, settle, static_cast<unsigned long long>(steps), wall, 1e6 * wall / std::max<double>(1, steps),
      maxOverlap / r, dA[0] / r, double(s.pz[layers - 1]), zA[layers - 1], worstRel, worstTol, maxDrift);
  return res;
}

// =============================================================================================
// 4. Tunnelling.

/// Two equal spheres approaching head-on at relative speed v; true when they end up having
/// passed through each other.

}  // namespace tumble::validation::study::stability
