// SPDX-License-Identifier: MIT
// The validation study's stiff contacts at the stability limit, with the run-time guard: the
// scheme's spectral radius, the amplification and the guard's trips (docs/validation.md).
#include "study_stability_common.hpp"
#include "tumble/factory.hpp"

namespace tumble::validation::study::stability {

// ---------------------------------------------------------------------------------------------
// Linear algebra of the discrete scheme.

namespace {

/// Spectral radius of the kick-drift map of x'' = −ω² x − 2ζω x' at h = ω dt:
/// M = [[1 − h², dt(1 − 2ζh)], [−ω² dt, 1 − 2ζh]] (in units where dt = 1/ω):
/// trace T = 2 − h² − 2ζh, det D = 1 − 2ζh.
double spectralRadius(double h, double zeta) {
  const double T = 2.0 - h * h - 2.0 * zeta * h, D = 1.0 - 2.0 * zeta * h;
  const double disc = T * T - 4.0 * D;
  if (disc < 0.0) return std::sqrt(std::abs(D));
  const double s = std::sqrt(disc);
  return std::max(std::abs(0.5 * (T + s)), std::abs(0.5 * (T - s)));
}
/// The h above which a perturbation grows by `factor` within n steps (ρ(h)ⁿ ≥ factor).
double detectableH(double zeta, double factor, double n) {
  const double target = std::pow(factor, 1.0 / n);
  double lo = criticalH(zeta), hi = 2.0 * lo;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (spectralRadius(mid, zeta) >= target ? hi : lo) = mid;
  }
  return hi;
}

// =============================================================================================
// 1. Stiff contacts at the stability limit.

struct StiffConfig {
  const char* id;
  bool pair;         ///< two particles held together by the x pull; else a sphere on the ground
  double zetaGoal;   ///< damping ratio asked for (0 = undamped)
};

/// One resting contact set up for the stability test; ω and ζ are those the kernels see.
struct StiffSetup {
  Scene scene;
  double omega = 0, zeta = 0, deltaEq = 0;
};

StiffSetup stiffSetup(const StiffConfig& c) {
  StiffSetup s;
  Scene& sc = s.scene;
  sc.name = c.id;
  const float r = 0.1f, m = 1.0f, k = 1.0e3f;
  if (!c.pair) {
    // e from ζ: e = exp(−ζπ/√(1−ζ²)).
    const double e = c.zetaGoal > 0 ? std::exp(-c.zetaGoal * kPi / std::sqrt(1 - c.zetaGoal * c.zetaGoal)) : 1.0;
    sc.gravity = {0, 0, float(-kG)};
    sc.ground.enabled = true;
    sc.ground.stiffness = k;
    sc.ground.friction = 0.0f;
    sc.shapes = {sphereShape(r, m, float(e))};
    sc.bodies = {bodyAt(0, 0, 0, r)};
    const World w = World::fromScene(sc);
    s.omega = std::sqrt(double(k) / double(m));
    s.zeta = std::abs(double(w.groundDamping[0])) / (2.0 * std::sqrt(double(k) * double(m)));
    s.deltaEq = double(m) * double(float(kG)) / double(k);
  } else {
    const float kappa = 100.0f;  // x pull [1/s²]: holds the pair together
    sc.gravity = {0, 0, 0};
    const double meff = 0.5 * m;
    s.omega = std::sqrt(double(k) / meff + double(kappa));
    const float eta = float(2.0 * c.zetaGoal * meff * s.omega);
    sc.contact = {k, eta, 0.0f};
    sc.pulls.x = kappa;
    sc.pulls.active = kPullX;
    sc.shapes = {sphereShape(r, m, 1.0f)};
    sc.bodies = {bodyAt(0, -r, 0, 0), bodyAt(0, r, 0, 0)};
    s.zeta = double(eta) / meff / (2.0 * s.omega);
    // k δ = m κ (r − δ/2)
    s.deltaEq = double(m) * kappa * r / (double(k) + 0.5 * double(m) * kappa);
  }
  return s;
}

/// Places the contact at overlap δ_eq − δ0 (δ0 = δ_eq / 100) at rest.
void placeStiff(StiffSetup& s, const StiffConfig& c, double delta) {
  const double r = 0.1;
  if (!c.pair) {
    s.scene.bodies[0].position.z = float(r - delta);
  } else {
    s.scene.bodies[0].position.x = float(-(r - 0.5 * delta));
    s.scene.bodies[1].position.x = float(r - 0.5 * delta);
  }
}

double stiffOverlap(const Sim& sim, const StiffConfig& c) {
  const double r = 0.1;
  if (!c.pair) return r - double(sim.st.pz[0]);
  return 2 * r - (double(sim.st.px[1]) - double(sim.st.px[0]));
}

struct AmpResult {
  double amp = 0;          ///< max |δ − δ_eq| / δ0
  std::uint64_t steps = 0; ///< steps run (to the trip, or n)
  bool tripped = false;
};

/// Runs the perturbed resting contact for n steps at dt; trips when the amplitude exceeds
/// `trip` × δ0 (the contact would open at 100 ×) or the state is non-finite.
AmpResult amplification(const StiffConfig& c, double dt, std::uint64_t n, double trip, Backend backend) {
  StiffSetup s = stiffSetup(c);
  const double d0 = s.deltaEq / 100.0;
  placeStiff(s, c, s.deltaEq - d0);
  s.scene.dt = float(dt);
  Sim sim(s.scene, backend);
  AmpResult a;
  const double start = std::abs(stiffOverlap(sim, c) - s.deltaEq);
  for (std::uint64_t i = 0; i < n; ++i) {
    if (!sim.step()) {
      a.tripped = true;
      a.amp = std::numeric_limits<double>::infinity();
      a.steps = i + 1;
      return a;
    }
    const double amp = std::abs(stiffOverlap(sim, c) - s.deltaEq) / start;
    a.amp = std::max(a.amp, amp);
    if (amp > trip) {
      a.tripped = true;
      a.steps = i + 1;
      return a;
    }
  }
  a.steps = n;
  return a;
}

/// One undamped bounce on the ground without gravity: (v_out / v_in)² at ω dt = h, the contact
/// entered at phase φ of a step.
double bounceEnergyRatio(double h, double phase, Backend backend) {
  const float r = 0.1f, m = 1.0f, k = 1.0e5f;
  const double omega = std::sqrt(double(k) / double(m));
  const double dt = h / omega, v = 1.0;
  Scene sc = groundScene({0, 0, 0}, k, sphereShape(r, m, 1.0f), dt);
  sc.ground.friction = 0.0f;
  sc.bodies = {bodyAt(0, 0, 0, r + (1.0 - phase) * v * dt + 1e-6, 0, 0, -v)};
  Sim sim(sc, backend);
  for (int i = 0; i < 100000; ++i) {
    if (!sim.step()) return std::numeric_limits<double>::infinity();
    if (sim.st.vz[0] > 0.0f && sim.st.pz[0] >= r) {
      const double vo = sim.st.vz[0];
      return vo * vo / (v * v);
    }
  }
  return kNaN;
}

/// The run-time guard (core/include/tumble/guard.hpp) on the perturbed resting contact at dt.
struct GuardRunResult {
  bool tripped = false;
  bool threw = false;            ///< the pipeline itself stopped (SimulationError) before a trip
  GuardTrip::Kind kind = GuardTrip::Kind::NonFinite;
  std::uint64_t step = 0;        ///< the trip's step (steps since load), or the steps run
  double suggestedDt = 0;        ///< the trip's dt advice (or the guard's, when quiet)
  double maxOverlap = 0;         ///< largest overlap seen by the checks (fraction of r)
  double maxRise = 0;            ///< largest E − E0 seen by the checks (J)
  std::string message;
};

/// Steps the perturbed resting contact of `c` at dt, the guard checking after every step (the
/// strictest interval; `tumble run` checks every frame), until it trips or n steps have run.
GuardRunResult guardRun(const StiffConfig& c, double dt, std::uint64_t n, Backend backend) {
  StiffSetup s = stiffSetup(c);
  placeStiff(s, c, s.deltaEq - s.deltaEq / 100.0);
  s.scene.dt = float(dt);
  const World world = World::fromScene(s.scene);
  std::unique_ptr<Pipeline> pipe = makePipeline(backend);
  pipe->load(world);
  RunGuard guard(world, *pipe);
  const double e0 = guard.energy();
  GuardRunResult g;
  g.suggestedDt = guard.suggestedDt();
  for (std::uint64_t i = 0; i < n; ++i) {
    try {
      pipe->step(1);
    } catch (const Error& e) {
      g.threw = true;
      g.step = i + 1;
      g.message = e.what();
      return g;
    }
    const std::optional<GuardTrip> t = guard.check(*pipe);
    if (t) {
      g.tripped = true;
      g.kind = t->kind;
      g.step = t->step;
      g.suggestedDt = t->suggestedDt;
      g.message = t->message;
      return g;
    }
    g.maxOverlap = std::max(g.maxOverlap, guard.maxOverlap());
    g.maxRise = std::max(g.maxRise, guard.energy() - e0);
  }
  g.step = n;
  return g;
}

/// Steps for ρ(h)^(2m) ≥ ratio: when a perturbation of energy E_p that grows by ρ per step
/// reaches ratio × E_p (linear theory; the energy goes as the amplitude squared).
double growthSteps(double h, double zeta, double ratio) {
  return std::log(ratio) / (2.0 * std::log(spectralRadius(h, zeta)));
}

const char* kindName(const GuardRunResult& g) {
  if (g.threw) return "pipeline error";
  if (!g.tripped) return "quiet";
  switch (g.kind) {
    case GuardTrip::Kind::NonFinite: return "non-finite";
    case GuardTrip::Kind::Energy: return "energy";
    case GuardTrip::Kind::Overlap: return "overlap";
  }
  return "?";
}
double kindCode(const GuardRunResult& g) {
  if (g.threw) return -1;
  if (!g.tripped) return 0;
  return g.kind == GuardTrip::Kind::NonFinite ? 1 : g.kind == GuardTrip::Kind::Energy ? 2 : 3;
}

}  // namespace

CaseResult stiffContactCase(const CaseContext& ctx) {
  const bool full = ctx.depth == Depth::Full;
  CaseResult res;
  res.id = "stiff_contact_limit";
  res.title = "Stiff contacts at the stability limit";
  const std::uint64_t n = full ? 20000 : 2000;
  const int iters = full ? 16 : 11;
  const double trip = 50.0;
  const StiffConfig configs[] = {
      {"ground_undamped", false, 0.0},
      {"ground_damped", false, 0.2155},  // e = 0.5
      {"pair_undamped", true, 0.0},
      {"pair_damped", true, 0.3},
  };
  Table scan{"amplification", {"config", "dt_over_dtc", "h", "amplification", "bound", "steps"}, {}};
  Table limits{"limits",
               {"config", "omega", "zeta", "dtc_analytic", "dtc_measured", "rel_error", "tolerance", "h_detect"},
               {}};
  const std::vector<double> ratios =
      full ? std::vector<double>{0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.999, 1.001, 1.005,
                                 1.01, 1.02, 1.05, 1.1, 1.2}
           : std::vector<double>{0.3, 0.7, 0.9, 0.99, 1.01, 1.05, 1.2};
  std::string details;
  for (std::size_t ci = 0; ci < std::size(configs); ++ci) {
    const StiffConfig& c = configs[ci];
    const StiffSetup s = stiffSetup(c);
    const double hc = criticalH(s.zeta), dtc = hc / s.omega;
    // Scan.
    for (double q : ratios) {
      const AmpResult a = amplification(c, q * dtc, n, trip, ctx.backend);
      const double h = q * hc;
      const double bound = (s.zeta == 0.0 && h < 2.0) ? 1.0 / std::sqrt(1.0 - h * h / 4.0) : kNaN;
      scan.rows.push_back({double(ci), q, h, a.tripped ? trip : a.amp, bound, double(a.steps)});
    }
    // Bisection of the blow-up dt.
    double lo = 0.5 * dtc, hi = 1.5 * dtc;
    const bool loOk = !amplification(c, lo, n, trip, ctx.backend).tripped;
    const bool hiBad = amplification(c, hi, n, trip, ctx.backend).tripped;
    for (int i = 0; i < iters && loOk && hiBad; ++i) {
      const double mid = 0.5 * (lo + hi);
      (amplification(c, mid, n, trip, ctx.backend).tripped ? hi : lo) = mid;
    }
    const double measured = (loOk && hiBad) ? 0.5 * (lo + hi) : kNaN;
    // Tolerance: on the unstable side the growth must reach trip× within n steps (ρ(h)ⁿ ≥ trip,
    // with a factor 4 for the initial projection on the growing mode); on the stable side the
    // undamped amplitude 1/√(1 − h²/4) (×1.1 for rounding noise) reaches trip just below h_c.
    // Plus the bisection's half-width and float dt.
    const double hDet = detectableH(s.zeta, 4.0 * trip, double(n));
    const double hLo = s.zeta == 0.0 ? 2.0 * std::sqrt(1.0 - (1.1 / trip) * (1.1 / trip)) : hc;
    const double tol = std::max(hDet - hc, hc - hLo) / hc + (hi - lo) / dtc + 1e-6;
    const double err = (measured - dtc) / dtc;
    limits.rows.push_back({double(ci), s.omega, s.zeta, dtc, measured, err, tol, hDet});
    res.checks.push_back(mkCheck(fmt("blow-up dt, %s", c.id),
                                 "bisected dt where a 1 % perturbation of the resting contact grows 50x within "
                                 "n steps vs dt_c = 2(sqrt(1+zeta^2) - zeta)/omega",
                                 measured, dtc, std::abs(err), tol, "relative"));
    details += fmt("| %s | %.6g | %.4f | %.4f | %.6g | %.6g | %+.2e | %.1e |\n", c.id, s.omega, s.zeta, hc, dtc,
                   measured, err, tol);
  }
  // Stable side of the undamped ground contact: amplitude within 1/√(1 − h²/4).
  {
    double worst = 0.0;
    for (const auto& row : scan.rows)
      if (row[0] == 0.0 && row[1] < 1.0) worst = std::max(worst, row[3] / row[4]);
    // Rounding: each step rounds z to ½ ulp(r); undamped, these kicks random-walk the invariant:
    // relative amplitude noise ~ √n · ½ ulp(r) / δ0, amplified near h_c; allow 5 × √n ulp/δ0.
    const StiffSetup s0 = stiffSetup(configs[0]);
    const double noise = 5.0 * std::sqrt(double(n)) * ulpf(0.1) / (s0.deltaEq / 100.0);
    res.checks.push_back(boundCheck("undamped amplitude within the leapfrog invariant",
                                    "max_n |delta_n - delta_eq| / delta0 / (1/sqrt(1 - h^2/4)) <= 1 + 5 sqrt(n) ulp(r)/delta0",
                                    worst, 1.0 + noise, "ratio to bound"));
  }
  // Single bounces: energy ratio within [1 − h²/4, 1/(1 − h²/4)].
  Table bounce{"bounce", {"dt_over_dtc", "h", "phase", "energy_ratio", "lower", "upper"}, {}};
  int violations = 0;
  const std::vector<double> bq = full ? std::vector<double>{0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95,
                                                            0.98, 0.99, 1.02, 1.1, 1.3}
                                      : std::vector<double>{0.1, 0.3, 0.5, 0.8, 0.95, 1.1};
  const int phases = full ? 16 : 4;
  for (double q : bq)
    for (int p = 0; p < phases; ++p) {
      const double h = 2.0 * q, phase = (p + 0.5) / phases;
      const double er = bounceEnergyRatio(h, phase, ctx.backend);
      const double lower = h < 2 ? 1 - h * h / 4 : kNaN, upper = h < 2 ? 1 / (1 - h * h / 4) : kNaN;
      if (h < 2 && !(er >= lower * (1 - 1e-5) && er <= upper * (1 + 1e-5))) ++violations;
      bounce.rows.push_back({q, h, phase, er, lower, upper});
    }
  res.checks.push_back(zeroCheck("undamped bounce energy within the leapfrog bounds",
                                 "1 - h^2/4 <= (v_out/v_in)^2 <= 1/(1 - h^2/4) for h < 2 (rel. 1e-5 rounding)",
                                 violations));
  // The run-time guard (tumble run's RunGuard) on the same perturbed resting contacts: it must
  // trip (energy or overlap, before anything is non-finite) within a bounded number of steps at
  // 1.1 dt_c, and stay quiet for the whole run at 0.9 dt_c and at the dt its trip message suggests.
  Table guardTable{"guard",
                   {"config", "dt_over_dtc", "dt", "outcome", "step", "predicted_steps", "step_bound", "max_overlap",
                    "energy_rise"},
                   {}};
  const std::uint64_t guardMax = 1000;  // steps allowed for a trip at 1.1 dt_c
  int loudAt09 = 0, loudAtSuggested = 0;
  std::string guardDetails;
  for (std::size_t ci = 0; ci < std::size(configs); ++ci) {
    const StiffConfig& c = configs[ci];
    const StiffSetup s = stiffSetup(c);
    const double hc = criticalH(s.zeta), dtc = hc / s.omega;
    // Energy the guard allows to appear: energyGrowth (0.5) × S, S = springs + pulls' potential
    // + Σ M|g| r_max of the initial state + the fall of the ground sphere's centre to the ground
    // plane, m g (r − d) (the pair, without gravity, has nothing to drop). Perturbation energy
    // E_p = ½ m_eff ω² δ0² (m_eff = m on the ground, m/2 for the pair).
    const double r = 0.1, m = 1.0, k = 1.0e3, d0 = s.deltaEq / 100.0, d = s.deltaEq - d0;
    const double meff = c.pair ? 0.5 * m : m;
    const double S = c.pair ? 0.5 * k * d * d + 2.0 * 0.5 * m * 100.0 * (r - 0.5 * d) * (r - 0.5 * d)
                            : 0.5 * k * d * d + m * double(float(kG)) * r + m * double(float(kG)) * (r - d);
    const double ep = 0.5 * meff * s.omega * s.omega * d0 * d0;
    const double hTrip = 1.1 * hc;
    const double predicted = growthSteps(hTrip, s.zeta, (ep + 0.5 * S) / ep);
    // Bound: twice the linear prediction (the initial state projects onto the growing mode with
    // a factor ≤ 4 in energy, and the contact opens — the ground sphere is thrown up — once the
    // amplitude passes δ_eq, after which growth continues bounce by bounce) plus 20 steps.
    const double bound = std::ceil(2.0 * predicted) + 20.0;
    const GuardRunResult a = guardRun(c, 1.1 * dtc, guardMax, ctx.backend);
    const GuardRunResult b = guardRun(c, 0.9 * dtc, n, ctx.backend);
    const double dtSuggested = a.tripped ? a.suggestedDt : 0.05 * kPi * std::sqrt(meff / k);
    const GuardRunResult q = guardRun(c, dtSuggested, n, ctx.backend);
    const bool kindOk = a.tripped && !a.threw && a.kind != GuardTrip::Kind::NonFinite;
    res.checks.push_back(mkCheck(fmt("guard trips at 1.1 dt_c, %s", c.id),
                                 "RunGuard::check after every step: trips by energy or overlap (not non-finite) "
                                 "within 2 n_lin + 20 steps, n_lin = ln((E_p + S/2)/E_p) / (2 ln rho(1.1 h_c))",
                                 double(a.step), predicted, kindOk ? double(a.step) : kNaN, bound, "steps"));
    if (b.tripped || b.threw) ++loudAt09;
    if (q.tripped || q.threw) ++loudAtSuggested;
    for (const auto* g : {&a, &b, &q}) {
      const double ratio = g == &a ? 1.1 : g == &b ? 0.9 : dtSuggested / dtc;
      guardTable.rows.push_back({double(ci), ratio, ratio * dtc, kindCode(*g), double(g->step),
                                 g == &a ? predicted : kNaN, g == &a ? bound : kNaN, g->maxOverlap, g->maxRise});
    }
    guardDetails += fmt("| %s | %s at step %llu | %.1f | %.0f | %s, %llu steps (max overlap %.3g r) | %.4f dt_c: %s, %llu steps |\n",
                        c.id, kindName(a), static_cast<unsigned long long>(a.step), predicted, bound, kindName(b),
                        static_cast<unsigned long long>(b.step), b.maxOverlap, dtSuggested / dtc, kindName(q),
                        static_cast<unsigned long long>(q.step));
    if (!kindOk || b.tripped || b.threw || q.tripped || q.threw)
      guardDetails += fmt("\n(%s: %s / %s / %s)\n\n", c.id, a.message.c_str(), b.message.c_str(), q.message.c_str());
  }
  res.checks.push_back(zeroCheck("guard quiet at 0.9 dt_c", "RunGuard::check after every step of n steps at 0.9 dt_c: "
                                 "number of configs where it trips (or the pipeline stops)", loudAt09));
  res.checks.push_back(zeroCheck("guard quiet at its suggested dt",
                                 "n steps at the trip message's dt (t_c/20 of the contact): number of configs where it "
                                 "trips", loudAtSuggested));
  res.tables = {scan, limits, bounce, guardTable};
  res.plots.push_back(Plot{"amplification", "Growth of a 1 % perturbation of a resting contact vs dt/dt_c",
                           "amplification", "dt_over_dtc", "dt / dt_c (analytic)", "max |δ−δ_eq| / δ0 (capped at 50)",
                           {"amplification"}, false, true, "config"});
  res.plots.push_back(Plot{"bounce", "Undamped bounce: (v_out/v_in)² and the leapfrog bounds", "bounce", "h",
                           "ω dt", "energy ratio", {"energy_ratio", "lower", "upper"}, false, true, ""});
  res.summary =
      "The translation scheme is leapfrog in kick-drift form, v ← v + (F/m) dt, x ← x + v dt, with the spring "
      "and the dashpot evaluated on the start-of-step state. For x'' = −ω²x − 2ζωx' the one-step map has trace "
      "T = 2 − h² − 2ζh and determinant D = 1 − 2ζh (h = ω dt); by the Jury criterion it is stable iff "
      "**h < h_c = 2(√(1+ζ²) − ζ)** (2 undamped; explicit damping lowers the limit: e = 0.5 on the ground, "
      "ζ = 0.2155, gives h_c = 1.615). Ground contact: ω = √(k_g/m), ζ = c/(2√(k_g m)). Particle pair held "
      "by the x pull κ: relative coordinate with ω² = k_s/m_eff + κ, 2ζω = η/m_eff.\n\n"
      "Test (sphere or pair: r = 0.1 m, m = 1 kg, k = 10³ N/m, κ = 100 s⁻² for the pair): the contact rests at its equilibrium overlap δ_eq (mg/k, or m κ r/(k + mκ/2) for the pair) "
      "perturbed by δ0 = δ_eq/100; it trips when max|δ − δ_eq| > 50 δ0 (the contact would open at 100) or the "
      "state is non-finite. The blow-up dt is bisected between dt_c/2 and 3dt_c/2. On the stable side the "
      "undamped amplitude is bounded by the invariant Q = v² + ω²x² − ω²dt·x·v of the map: "
      "max|δ−δ_eq|/δ0 ≤ 1/√(1 − h²/4), which exceeds 50 only within 2·10⁻⁴ of h_c. On the unstable side "
      "detection needs ρ(h)ⁿ ≥ 200 (factor 4 for the projection on the growing mode): that h_detect, "
      "the stable-side margin (the undamped bound reaches 50/1.1 at 1 − 2.4·10⁻⁴ of h_c), the bisection "
      "half-width and float dt give the stated tolerance. The amplitude bound is checked on the stable "
      "scan points with a rounding allowance 5√n·ulp(r)/δ0 (undamped, float rounding of z random-walks "
      "the invariant).\n\n"
      "Single undamped bounce (no gravity): the contact is entered and left at an overlap between 0 and "
      "v dt, where the invariant Q differs from v² by ω²x(x − v dt) ∈ [−h²v²/4, 0], so "
      "**1 − h²/4 ≤ (v_out/v_in)² ≤ 1/(1 − h²/4)** for any entry phase; checked for every phase.\n\n"
      "| config | ω [1/s] | ζ | h_c | dt_c [s] | measured [s] | rel. error | tolerance |\n|---|---|---|---|---|---|---|---|\n" +
      details + fmt("\nn = %llu steps per trial; config index in the CSV: 0 ground_undamped, 1 ground_damped, "
                    "2 pair_undamped, 3 pair_damped.",
                    static_cast<unsigned long long>(n)) +
      "\n\n**The run-time guard** (`RunGuard`, core/include/tumble/guard.hpp, as in `tumble run`) watches the "
      "same perturbed contacts, checking after every step. At 1.1 dt_c it must trip by energy (E − E₀ beyond "
      "half of what the initial state can release, S) or overlap, before the state is non-finite, within "
      "2 n_lin + 20 steps, where n_lin = ln((E_p + S/2)/E_p) / (2 ln ρ) is when the linear growth ρ(h) per "
      "step brings the perturbation energy E_p = ½ m_eff ω² δ0² to S/2 (margin: projection on the growing mode, "
      "and the contact opening — the ground sphere is thrown up — once the amplitude passes δ_eq). At 0.9 dt_c "
      "and at the dt the trip message suggests (t_c/20) it must stay quiet for all n steps.\n\n"
      "| config | 1.1 dt_c | n_lin | bound | 0.9 dt_c | suggested dt |\n|---|---|---|---|---|---|\n" +
      guardDetails + "\nOutcome codes in guard.csv: 0 quiet, 1 non-finite, 2 energy, 3 overlap, −1 pipeline error.";
  return res;
}

// =============================================================================================
// 2. Mass ratio 1:1000.

}  // namespace tumble::validation::study::stability
