// SPDX-License-Identifier: MIT
// The validation study's granular cases: the angle of repose of the heap scenes, the
// Beverloo discharge rate of a hopper and the coarse-grained stress of a settled column.
#include <filesystem>

#include "study_physics_common.hpp"
#include "tumble/factory.hpp"
#include "tumble/fields.hpp"
#include "tumble/run.hpp"

namespace tumble::validation::study::physics {

// ---------------------------------------------------------------------------------------------
// Angle of repose: the heaps of scenes/heap.toml (hooke-history) and heap-hertz.toml.

namespace {

/// The slope of a heap from body centres, as examples/heap_angle.py: the highest centre in each
/// of `bins` rings about the centre of mass (out to the radius holding 98 % of the bodies), a
/// least-squares line through the rings from 20 % to 85 % of that radius. Returns the angle (°)
/// and fills the ring profile (radius, height) of every ring that has a body.
double heapAngle(const BodyState& st, int bins, std::vector<std::pair<double, double>>* profile) {
  const std::size_t n = st.size();
  double cx = 0.0, cy = 0.0;
  for (std::size_t k = 0; k < n; ++k) cx += st.px[k], cy += st.py[k];
  cx /= double(n), cy /= double(n);
  std::vector<double> rad(n);
  for (std::size_t k = 0; k < n; ++k) rad[k] = std::hypot(st.px[k] - cx, st.py[k] - cy);
  std::vector<double> sorted = rad;
  std::sort(sorted.begin(), sorted.end());
  const double rmax = sorted[std::size_t(0.98 * double(n - 1))];
  std::vector<double> top(std::size_t(bins), -std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < n; ++k) {
    const int b = int(rad[k] / rmax * bins);
    if (b < bins) top[std::size_t(b)] = std::max(top[std::size_t(b)], double(st.pz[k]));
  }
  double sx = 0, sz = 0, sxx = 0, sxz = 0;
  int m = 0;
  for (int b = 0; b < bins; ++b) {
    if (top[std::size_t(b)] == -std::numeric_limits<double>::infinity()) continue;
    const double x = (b + 0.5) / bins * rmax, z = top[std::size_t(b)];
    profile->push_back({x, z});
    if (b < 0.2 * bins || b >= 0.85 * bins) continue;
    sx += x, sz += z, sxx += x * x, sxz += x * z, ++m;
  }
  const double slope = (m * sxz - sx * sz) / (m * sxx - sx * sx);
  return std::atan(-slope) * 180.0 / kPi;
}

}  // namespace

CaseResult angleOfRepose(const CaseContext& ctx) {
  CaseResult r;
  r.id = "angle_of_repose";
  r.title = "Angle of repose: the collapse of a column of frictional spheres (regression)";
  Table prof{"profile", {"law", "radius", "height"}, {}};
  {
    // The measurement itself, on a cone of 20 000 points of known slope 25° (law -1 in the table).
    Rng rng(3);
    BodyState cone;
    cone.resize(20000);
    const double slope = std::tan(25.0 * kPi / 180.0);
    for (std::size_t k = 0; k < cone.size(); ++k) {
      const double rr = 0.5 * std::sqrt(double(rng.uniform())), a = 2 * kPi * double(rng.uniform());
      cone.px[k] = float(rr * std::cos(a));
      cone.py[k] = float(rr * std::sin(a));
      cone.pz[k] = float(double(rng.uniform()) * slope * (0.5 - rr));
    }
    std::vector<std::pair<double, double>> rings;
    const double angle = heapAngle(cone, 12, &rings);
    for (const auto& [x, z] : rings) prof.rows.push_back({-1.0, x, z});
    r.checks.push_back(absCheck("slope of a cone of 25° (the measurement)", "25°", angle, 25.0, 1.5, "°"));
  }
  if (ctx.depth == Depth::Quick) {
    r.tables.push_back(prof);
    r.summary = "At quick depth only the measurement is checked, on a cone of known slope (the heaps take two runs "
                "of 30 000 steps on 1960 spheres).";
    return r;
  }
  // The angles measured when the scenes were written (docs/model.md#a-heap): a regression band.
  const struct {
    const char* file;
    double recorded;
  } heaps[] = {{"scenes/heap.toml", 18.5}, {"scenes/heap-hertz.toml", 19.3}, {"scenes/heap-cohesive.toml", 32.8}};
  std::string found;
  double dryHertz = 0.0;
  for (const auto& h : heaps) {
    const Scene s = readSceneFile(sourcePath(h.file));
    PipelineOptions o;  // every thread: the result does not depend on it
    auto p = makePipeline(ctx.backend, o);
    p->load(World::fromScene(s));
    p->step(s.steps);
    BodyState st;
    p->readState(st);
    std::vector<std::pair<double, double>> rings;
    const double angle = heapAngle(st, 12, &rings);
    const bool cohesive = s.contact.cohesion != Cohesion::None;
    const double law = cohesive ? 2.0 : s.contact.law == ContactLaw::HertzMindlin ? 1.0 : 0.0;
    for (const auto& [x, z] : rings) prof.rows.push_back({law, x, z});
    const std::string what = cohesive ? std::string(toString(s.contact.law)) + " + " + toString(s.contact.cohesion)
                                      : std::string(toString(s.contact.law));
    r.checks.push_back(absCheck(fmt("slope of the heap, %s (%s)", h.file, what.c_str()),
                                fmt("the %.1f° recorded in docs/model.md (regression; literature 20–30°)", h.recorded),
                                angle, h.recorded, 1.5, "°"));
    if (cohesive) {
      // How much steeper than heap-hertz's, at least 3°: the error is the shortfall.
      r.checks.push_back(mkCheck("the cohesive heap stands steeper than the dry one (heap-hertz)",
                                 fmt("at least 3° above heap-hertz's %.1f°", dryHertz), angle - dryHertz, 3.0,
                                 std::max(0.0, 3.0 - (angle - dryHertz)), 0.0, "°"));
    } else if (s.contact.law == ContactLaw::HertzMindlin) {
      dryHertz = angle;
    }
    found += fmt("%s %.1f°, ", what.c_str(), angle);
  }
  r.tables.push_back(prof);
  r.plots.push_back(Plot{"profile", "surface of the heaps (highest centre per ring; law 0 hooke-history, 1 hertz-mindlin, 2 hertz-mindlin + sjkr cohesion, -1 the 25° cone)",
                         "profile", "radius", "distance from the centre (m)", "height of the highest centre (m)",
                         {"height"}, false, false, "law"});
  r.summary =
      "`scenes/heap.toml` (hooke-history, μ = 0.5, μ_r = 0.1) and `scenes/heap-hertz.toml` (hertz-mindlin with one "
      "glass-like material, E = 50 MPa, μ = 0.5, μ_r = 0.1), both a column of 1960 spheres (radius 10 and 12 mm) "
      "released on a rough ground and run for 1.5 s; `scenes/heap-cohesive.toml` is heap-hertz with sjkr cohesion "
      "(k_c = 7e5 J/m³, a Bond number near 2.4), whose flanks must stand at least 3° steeper. The slope of the deposit is measured as examples/heap_angle.py "
      "does (the highest centre in each of 12 rings about the centre of mass, a line from 20 % to 85 % of the radius "
      "holding 98 % of the bodies): " + found +
      "against the 20–30° reported for poured heaps of glass beads in experiments and in DEM with rolling "
      "resistance. A collapsed column's flank stands below the angle of repose of a poured heap, so this is a "
      "regression figure (the check: within 1.5° of the value recorded when the scene was written), not an oracle. "
      "The measurement is checked on a cone of 20 000 random points with a slope of 25°.";
  return r;
}

namespace {

// Beverloo: W = C ρ_b √g (D − k d)^{5/2} is W^{2/5} = a (D − k d), a = (C ρ_b √g)^{2/5}: a line
// in D. Fits it to (D, W) by least squares and returns C and k (d the mean diameter).
struct BeverlooFit {
  double c, k, r2;
};
BeverlooFit fitBeverloo(const std::vector<double>& D, const std::vector<double>& W, double rhoB, double d) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  const double n = double(D.size());
  for (std::size_t i = 0; i < D.size(); ++i) {
    const double y = std::pow(W[i], 0.4);
    sx += D[i], sy += y, sxx += D[i] * D[i], sxy += D[i] * y, syy += y * y;
  }
  const double a = (n * sxy - sx * sy) / (n * sxx - sx * sx), b = (sy - a * sx) / n;
  const double r = (n * sxy - sx * sy) / std::sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
  return BeverlooFit{std::pow(a, 2.5) / (rhoB * std::sqrt(kG)), -b / (a * d), r * r};
}

// The discharge rate of a series of (time, discharged mass): the least-squares slope of the
// samples with lo <= mass <= hi (the steady flow, after the start and before the end).
double dischargeRate(const std::vector<std::pair<double, double>>& m, double lo, double hi) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (const auto& [t, x] : m)
    if (x >= lo && x <= hi) sx += t, sy += x, sxx += t * t, sxy += t * x, ++n;
  return n >= 3 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : kNaN;
}

WallDef revolvedWall(Vec3f point, Vec3f axis, float length, float r0, float r1, float k, float mu) {
  WallDef w = tumble::revolvedWall(point, axis, length, r0, r1);
  w.contact.stiffness = k;
  w.contact.friction = mu;
  return w;
}

// A flat-bottomed silo under hooke-history (k_n = kn, γ_n = gammaN, μ = 0.5 between the spheres,
// no rolling resistance): a cylinder of radius R, `height` tall, closed by a disk (walls[1]), both
// of stiffness kn and friction muWall; `count` spheres of radius r0 or r1 (2500 kg/m³, drawn at
// random with the seed), placed on a square lattice of `spacing` inside the cylinder, layer by
// layer from z0 up, each with a small random horizontal velocity. (beverloo and janssen.)
Scene siloScene(const char* name, float R, float kn, float gammaN, float muWall, double r0, double r1, double e,
                std::size_t count, double spacing, double z0, float height, std::uint64_t seed) {
  Scene s;
  s.name = name;
  s.dt = 4.0e-5f;
  s.contact.law = ContactLaw::HookeHistory;
  s.contact.stiffness = kn;
  s.contact.gammaN = gammaN;
  s.contact.friction = 0.5f;
  s.contact.rollingFriction = 0.0f;
  s.ground.enabled = false;
  s.shapes = {sphereShape(r0, 2500.0 * 4.0 / 3.0 * kPi * r0 * r0 * r0, e),
              sphereShape(r1, 2500.0 * 4.0 / 3.0 * kPi * r1 * r1 * r1, e)};
  Rng rng(seed);
  const double reach = R - r1 - 0.002;
  const int half = int(reach / spacing);
  for (int layer = 0; s.bodies.size() < count; ++layer)
    for (int i = -half; i <= half && s.bodies.size() < count; ++i)
      for (int j = -half; j <= half && s.bodies.size() < count; ++j) {
        const double x = i * spacing, y = j * spacing;
        if (std::hypot(x, y) > reach) continue;
        s.bodies.push_back(bodyAt(rng.uniform() < 0.5f ? 0u : 1u, x, y, z0 + layer * spacing,
                                  rng.uniform(-0.02f, 0.02f), rng.uniform(-0.02f, 0.02f), 0.0));
      }
  s.walls = {revolvedWall(Vec3f{0, 0, 0}, Vec3f{0, 0, height}, height, R, R, kn, muWall),
             revolvedWall(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.0f, 0.0f, R, kn, muWall)};
  return s;
}

}  // namespace

CaseResult beverloo(const CaseContext& ctx) {
  CaseResult r;
  r.id = "beverloo";
  r.title = "Silo discharge against Beverloo's law (four orifices)";
  // The measurements themselves, on data of known answer: the fit on rates from the law with
  // C = 0.6, k = 1.5, and the rate on a linear discharge with a start and an end.
  {
    const std::vector<double> D = {0.04, 0.05, 0.06, 0.07};
    std::vector<double> W;
    for (double x : D) W.push_back(0.6 * 1500.0 * std::sqrt(kG) * std::pow(x - 1.5 * 0.011, 2.5));
    const BeverlooFit f = fitBeverloo(D, W, 1500.0, 0.011);
    Table known{"known_answer", {"D", "W"}, {}};
    for (std::size_t i = 0; i < D.size(); ++i) known.rows.push_back({D[i], W[i]});
    r.tables.push_back(known);
    r.checks.push_back(relCheck("fit on the law's own rates: C", "C = 0.6 (the fit)", f.c, 0.6, 1e-9));
    r.checks.push_back(relCheck("fit on the law's own rates: k", "k = 1.5 (the fit)", f.k, 1.5, 1e-9));
    std::vector<std::pair<double, double>> m;
    for (int i = 0; i <= 300; ++i) {
      const double t = 0.01 * i;
      m.push_back({t, t < 0.5 ? 0.0 : std::min(0.7 * (t - 0.5), 1.2)});
    }
    r.checks.push_back(relCheck("rate of a linear discharge of 0.7 kg/s (the measurement)", "0.7 kg/s",
                                dischargeRate(m, 0.2, 0.8), 0.7, 1e-9));
  }
  if (ctx.depth == Depth::Quick) {
    r.summary = "At quick depth only the measurements are checked, on data of known answer (table known_answer: "
                "the law's own rates for C = 0.6, k = 1.5); the discharges take about 150 000 steps of 14 000 spheres.";
    return r;
  }
  // The silo: a cylinder of radius 0.15 m; 14000 spheres of radius 5 and 6 mm (2500 kg/m³,
  // drawn at random), hooke-history as scenes/silo.toml, settled for 1 s on a closed floor: a bed
  // about 0.25 m deep, more than 2 orifices and 20 grains (the depth above which the rate no
  // longer depends on it: da Silva et al. 2025, arXiv:2512.03698), and the silo 3.4 orifices
  // wide at the largest.
  // No rolling resistance: Beverloo's law and its constants are for smooth spheres (glass
  // beads); μ_r = 0.02 lowered C to 0.50 and 0.1 to 0.35 (docs/validation.md).
  const float R = 0.15f, kn = 1.0e4f, muWall = 0.3f;
  constexpr std::size_t kBodies = 14000;
  const Scene s = siloScene("beverloo", R, kn, 1500.0f, muWall, 0.005, 0.006, 0.5, kBodies, 0.013, 0.01, 0.8f, ctx.seed);
  const World closed = World::fromScene(s);
  BodyState settled;
  {
    auto p = makePipeline(ctx.backend, PipelineOptions{});
    p->load(closed);
    p->step(stepsFor(1.0, s.dt));
    p->readState(settled);
  }
  // The bed: its mean diameter, its top (the 95th percentile of the heights) and its bulk
  // density between 2 d above the floor and 2 d below the top.
  double d = 0.0, mass = 0.0;
  std::vector<double> z;
  for (std::size_t k = 0; k < settled.size(); ++k) {
    d += 2.0 * closed.radius[k];
    mass += closed.bodyMass[k];
    z.push_back(settled.pz[k]);
  }
  d /= double(settled.size());
  std::sort(z.begin(), z.end());
  const double top = z[std::size_t(0.95 * double(z.size()))], lo = 2.0 * d, hi = top - 2.0 * d;
  double layerMass = 0.0;
  for (std::size_t k = 0; k < settled.size(); ++k)
    if (settled.pz[k] >= lo && settled.pz[k] < hi) layerMass += closed.bodyMass[k];
  const double rhoB = layerMass / (kPi * double(R) * R * (hi - lo));
  // Each orifice: the floor becomes a ring, the settled bed runs until 2 kg has gone (at most
  // 6 s); the rate is the slope of the discharged mass from 0.2 to 2 kg.
  Table flow{"discharge", {"D_over_d", "time", "mass"}, {}};
  Table rates{"rates", {"D", "D_over_d", "W", "W_2_5", "fit_W_2_5"}, {}};
  std::vector<double> Ds, Ws;
  for (const double ratio : {5.0, 6.0, 7.0, 8.0}) {
    const double D = ratio * d;
    Scene o = s;
    o.walls[1] = revolvedWall(Vec3f{0, 0, 0}, Vec3f{0, 0, 1}, 0.0f, float(0.5 * D), R, kn, muWall);
    World w = World::fromScene(o);
    w.state = settled;
    auto p = makePipeline(ctx.backend, PipelineOptions{});
    p->load(w);
    std::vector<std::pair<double, double>> m;
    BodyState st;
    const std::uint64_t chunk = stepsFor(0.01, s.dt);
    for (double t = 0.0, gone = 0.0; gone < 2.0 && t < 6.0;) {
      p->step(chunk);
      t = p->time();
      p->readState(st);
      gone = 0.0;
      for (std::size_t k = 0; k < st.size(); ++k)
        if (st.pz[k] < -d) gone += w.bodyMass[k];
      m.push_back({t, gone});
      flow.rows.push_back({ratio, t, gone});
    }
    const double W = dischargeRate(m, 0.2, 2.0);
    Ds.push_back(D);
    Ws.push_back(W);
    std::fprintf(stderr, "  beverloo: D = %.0f d, %.3f kg/s\n", ratio, W);
  }
  const BeverlooFit f = fitBeverloo(Ds, Ws, rhoB, d);
  const double a = std::pow(f.c * rhoB * std::sqrt(kG), 0.4);
  for (std::size_t i = 0; i < Ds.size(); ++i)
    rates.rows.push_back({Ds[i], Ds[i] / d, Ws[i], std::pow(Ws[i], 0.4), a * (Ds[i] - f.k * d)});
  r.checks.push_back(absCheck("Beverloo's C", "C in 0.55–0.65 (spheres; the literature's range)", f.c, 0.60, 0.05, ""));
  r.checks.push_back(absCheck("Beverloo's k", "k in 1–2 (spheres; the literature's range)", f.k, 1.5, 0.5, ""));
  r.checks.push_back(mkCheck("W^(2/5) is a line in D", "r² of the fit >= 0.99", f.r2, 1.0, 1.0 - f.r2, 0.01, ""));
  r.tables.push_back(rates);
  r.tables.push_back(flow);
  r.plots.push_back(Plot{"rates", "W^(2/5) against the orifice D, and Beverloo's line fitted", "rates", "D",
                         "orifice diameter D (m)", "W^(2/5) ((kg/s)^(2/5))", {"W_2_5", "fit_W_2_5"}, false, false, ""});
  r.plots.push_back(Plot{"discharge", "discharged mass against time, per orifice (D/d)", "discharge", "time",
                         "time since the floor opened (s)", "discharged mass (kg)", {"mass"}, false, false, "D_over_d"});
  r.summary = fmt(
      "A flat-bottomed silo (a cylinder of radius %.2f m and a ring as its floor, docs/scenes.md#wall-walls) "
      "holds %zu spheres of radius 5 and 6 mm (mean diameter d = %.2f mm, 2500 kg/m³; hooke-history, μ = 0.5 "
      "and no rolling resistance between them, μ = 0.3 on the walls), settled for 1 s on a closed floor (a bed %.2f m deep): bulk density "
      "ρ_b = %.0f kg/m³ (between 2 d above the floor and 2 d below the top). The floor is then replaced by a ring "
      "whose hole is the orifice, D = 5, 6, 7, 8 d, and the rate W is the slope of the discharged mass from 0.2 to "
      "2 kg (the steady flow; the bed holds %.1f kg). Beverloo's W = C ρ_b √g (D − k d)^{5/2} is a line in W^{2/5}; its fit gives "
      "C = %.3f and k = %.2f (r² = %.4f), against the literature's C ≈ 0.55–0.65 and k ≈ 1–2 for spheres. "
      "The fit and the rate are checked first on data of known answer.",
      double(R), kBodies, 1e3 * d, top, rhoB, mass, f.c, f.k, f.r2);
  return r;
}

// ---------------------------------------------------------------------------------------------
// The coarse-grained stress of a settled column (tumble/fields.hpp, docs/fields.md).

CaseResult columnStress(const CaseContext& ctx) {
  CaseResult r;
  r.id = "column_stress";
  r.title = "Coarse-grained stress of a settled column against the weight above";
  {
    // The packing fraction of an FCC crystal of 20³ cells (π/(3√2)) at five points inside.
    std::vector<float> x, radius, mass;
    const double sites[4][3] = {{0.25, 0.25, 0.25}, {0.75, 0.75, 0.25}, {0.75, 0.25, 0.75}, {0.25, 0.75, 0.75}};
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j)
        for (int k = 0; k < 20; ++k)
          for (const auto& s : sites) {
            x.insert(x.end(), {float(i + s[0]), float(j + s[1]), float(k + s[2])});
            radius.push_back(float(1.0 / (2.0 * std::sqrt(2.0))));
            mass.push_back(1.0f);
          }
    FieldGrid g;
    g.lo = {6.0, 6.0, 6.0};
    g.hi = {14.0, 14.0, 14.0};
    g.n = {5, 1, 1};
    CoarseGraining cg(g, 0.8);
    FieldFrame f;
    f.x = x.data(), f.radius = radius.data(), f.mass = mass.data(), f.n = radius.size();
    cg.add(f);
    const Fields fcc = cg.result();
    const double want = kPi / (3.0 * std::sqrt(2.0));
    double farthest = want;
    Table crystal{"fcc", {"x", "packing"}, {}};
    for (std::size_t k = 0; k < fcc.packing.size(); ++k) {
      const double nu = fcc.packing[k];
      crystal.rows.push_back({g.at(0, int(k)), nu});
      if (std::fabs(nu - want) > std::fabs(farthest - want)) farthest = nu;
    }
    r.tables.push_back(crystal);
    r.checks.push_back(absCheck("packing fraction of an FCC crystal (width 0.8 cells), the farthest of 5 points",
                                "π/(3√2) = 0.74048", farthest, want, 2e-4, ""));
  }
  if (ctx.depth == Depth::Quick) {
    r.summary = "At quick depth only the coarse-graining is checked, on an FCC crystal (the column takes 8200 steps "
                "of 972 spheres).";
    return r;
  }
  // scenes/column.toml: settled, then ten frames with velocities and contact forces.
  const Scene scene = readSceneFile(sourcePath("scenes/column.toml"));
  const std::string path =
      (std::filesystem::temp_directory_path() / ("tumble_column_stress_" + std::to_string(ctx.seed) + ".bin")).string();
  {
    tumble::Run run(scene);
    run.load(makePipeline(ctx.backend, PipelineOptions{}));
    run.advance(8000);
    RecordSettings rs;
    rs.path = path;
    rs.stepsPerFrame = 20;
    rs.debug = true;
    rs.contactForces = true;
    run.record(rs);
    run.advance(200);
    run.closeRecording();
  }
  FieldOptions o;
  o.width = 0.005;
  o.grid.axis = 2;
  o.grid.lo = {0.0, 0.0, 0.0};
  o.grid.hi = {0.1, 0.1, 0.15};
  o.grid.n = {1, 1, 300};
  Fields f;
  {
    RecordingReader reader(path);
    f = coarseGrainRecording(reader, o);
  }
  std::filesystem::remove(path);
  const std::size_t n = f.density.size();
  const double h = 0.15 / double(n);
  std::vector<double> above(n, 0.0);
  for (std::size_t k = n; k-- > 0;)
    above[k] = (k + 1 < n ? above[k + 1] + 0.5 * kG * h * f.density[k + 1] : 0.0) + 0.5 * kG * h * f.density[k];
  Table prof{"profile", {"z", "contact_szz", "weight_above", "kinetic_szz", "packing"}, {}};
  double top = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double z = o.grid.at(2, int(k));
    prof.rows.push_back({z, f.contactStress[6 * k + 2], above[k], f.kineticStress[6 * k + 2], f.packing[k]});
    if (f.packing[k] > 0.3) top = z;
  }
  double worst = 0.0, kinetic = 0.0, rho = 0.0, sz = 0.0, szz = 0.0, ss = 0.0, sxs = 0.0;
  int m = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double z = o.grid.at(2, int(k)), s = f.contactStress[6 * k + 2];
    if (z < 0.02 || z > top - 0.02) continue;
    worst = std::max(worst, std::fabs(s - above[k]));
    kinetic = std::max(kinetic, std::fabs(f.kineticStress[6 * k + 2]));
    rho += f.density[k], sz += z, szz += z * z, ss += s, sxs += z * s, ++m;
  }
  rho /= m;
  const double slope = (m * sxs - sz * ss) / (m * szz - sz * sz), bottom = above[std::size_t(0.02 / h)];
  const double nu = f.packing[std::size_t(0.05 / h)];
  r.checks.push_back(absCheck("σ_zz against g ∫ρ dz above, worst from 4 radii above the ground to 4 below the top",
                              "0 (the momentum balance at rest), within 10⁻³ of the stress at the bottom", worst / bottom,
                              0.0, 1e-3, " of it"));
  r.checks.push_back(relCheck("slope of σ_zz in the bulk", "−ρ_b g", slope, -rho * kG, 0.01));
  r.checks.push_back(absCheck("kinetic σ_zz in the bulk, largest", "0 (at rest), within 10⁻⁴ of the stress at the bottom",
                              kinetic / bottom, 0.0, 1e-4, " of it"));
  r.checks.push_back(absCheck("packing fraction at z = 0.05 m", "a random packing of spheres, 0.54–0.65", nu, 0.595,
                              0.055, ""));
  r.tables.push_back(prof);
  r.plots.push_back(Plot{"profile", "vertical contact stress and the weight above, along z", "profile", "z",
                         "height z (m)", "stress (Pa)", {"contact_szz", "weight_above"}, false, false, ""});
  r.summary = fmt(
      "`scenes/column.toml`: 972 spheres (radius 5 mm, 1.3 g) settled for 0.8 s on a rough ground in a box periodic in "
      "x and y (hooke-history, μ = 0.5), then ten frames recorded with their velocities and contact forces and "
      "coarse-grained along z with Lucy's kernel of width w = 5 mm (docs/fields.md). At rest the momentum balance "
      "says that the vertical contact stress carries the weight above, σ_zz(z) = g ∫_z^∞ ρ dz'. The column is %.3f m "
      "high with ρ_b = %.0f kg/m³; from 4 radii above the ground (below, the ground's own contacts, which the "
      "recording does not hold, carry the rest) to 4 below the surface the largest difference is %.3g Pa of %.0f Pa, "
      "and the stress falls as ρ_b g (H − z) with slope %.0f Pa/m against %.0f. The coarse-graining is checked first "
      "on an FCC crystal's packing fraction.",
      top, rho, worst, bottom, slope, -rho * kG);
  return r;
}

// ---------------------------------------------------------------------------------------------
// Janssen: the vertical stress in a silo saturates with depth, the walls' friction carrying the
// weight below (a regression figure of the coarse-grained stress).

namespace {

// σ(h) = σ∞ (1 − exp(−h/λ)) fitted to (depth, stress) by least squares: for each λ of a
// logarithmic grid the best σ∞ in closed form, the λ of the smallest residual kept.
struct JanssenFit {
  double sigmaInf, lambda, r2;
};
JanssenFit fitJanssen(const std::vector<double>& h, const std::vector<double>& s) {
  JanssenFit best{0.0, 0.0, -1.0};
  double mean = 0.0;
  for (const double v : s) mean += v;
  mean /= double(s.size());
  double total = 0.0;
  for (const double v : s) total += (v - mean) * (v - mean);
  double bestResidual = INFINITY;
  for (int k = 0; k <= 4000; ++k) {
    const double lambda = 1e-3 * std::pow(10.0, 4.0 * k / 4000.0);  // 1 mm to 10 m
    double sf = 0.0, ff = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      const double f = 1.0 - std::exp(-h[i] / lambda);
      sf += s[i] * f, ff += f * f;
    }
    const double sigma = sf / ff;
    double residual = 0.0;
    for (std::size_t i = 0; i < h.size(); ++i) {
      const double e = s[i] - sigma * (1.0 - std::exp(-h[i] / lambda));
      residual += e * e;
    }
    if (residual < bestResidual) bestResidual = residual, best = {sigma, lambda, 1.0 - residual / total};
  }
  return best;
}

}  // namespace

CaseResult janssen(const CaseContext& ctx) {
  CaseResult r;
  r.id = "janssen";
  r.title = "Janssen: the vertical stress in a silo saturates with depth (regression)";
  {
    // The fit on Janssen's own curve, σ∞ = 800 Pa, λ = 0.07 m.
    std::vector<double> h, s;
    Table known{"known_answer", {"depth", "stress"}, {}};
    for (int i = 0; i < 60; ++i) {
      h.push_back(0.005 * i);
      s.push_back(800.0 * (1.0 - std::exp(-h.back() / 0.07)));
      known.rows.push_back({h.back(), s.back()});
    }
    const JanssenFit f = fitJanssen(h, s);
    r.tables.push_back(known);
    r.checks.push_back(relCheck("fit on Janssen's own curve: lambda", "0.07 m (the fit)", f.lambda, 0.07, 2e-3));
    r.checks.push_back(relCheck("fit on Janssen's own curve: sigma_inf", "800 Pa (the fit)", f.sigmaInf, 800.0, 2e-3));
  }
  if (ctx.depth == Depth::Quick) {
    r.summary = "At quick depth only the fit is checked, on Janssen's own curve (the silo takes 55 000 steps of "
                "8000 spheres, about 90 s on 2 threads).";
    return r;
  }
  // A silo: a cylinder of radius R = 6 cm, μ = 0.5 on the walls and between the spheres (radius
  // 4 and 5 mm, 2500 kg/m³, drawn at random), closed by a disk; 8000 spheres dropped from a
  // lattice settle into a bed about 7 R deep.
  const float R = 0.06f, kn = 1.0e4f, muWall = 0.5f, top = 1.2f;  // (the lattice reaches 0.93 m)
  constexpr std::size_t kBodies = 8000;
  Scene s = siloScene("janssen", R, kn, 2000.0f, muWall, 0.004, 0.005, 0.3, kBodies, 0.0105, 0.006, top, ctx.seed);
  // Settled, the bed rests on its floor with the walls' friction only partly mobilised (its
  // stress then depends on how it was filled); the floor then sinks 2 mm at 1 cm/s, the bed
  // slides down the walls and their friction is fully mobilised, as Janssen assumes (and as
  // experiments do it, lowering the bottom).
  s.walls[1].velocity = {0.0f, 0.0f, -0.01f};
  s.walls[1].start = 2.0;
  s.walls[1].stop = 2.2;
  const std::string path =
      (std::filesystem::temp_directory_path() / ("tumble_janssen_" + std::to_string(ctx.seed) + ".bin")).string();
  {
    tumble::Run run(s);
    run.load(makePipeline(ctx.backend, PipelineOptions{}));
    run.advance(stepsFor(2.1, s.dt));  // settled, and sliding for 0.1 s
    RecordSettings rs;
    rs.path = path;
    rs.stepsPerFrame = 250;
    rs.debug = true;
    rs.contactForces = true;
    run.record(rs);
    run.advance(2500);  // ten frames while the floor sinks
    run.closeRecording();
  }
  // The profile along z over the silo's cross-section (its circle in the square box around it),
  // w = 5 mm.
  FieldOptions o;
  o.width = 0.005;
  o.grid.axis = 2;
  o.grid.lo = {-double(R), -double(R), 0.0};
  o.grid.hi = {double(R), double(R), double(top)};
  o.grid.area = kPi * double(R) * double(R);
  o.grid.n = {1, 1, int(std::ceil(top / 0.001))};
  Fields f;
  {
    RecordingReader reader(path);
    f = coarseGrainRecording(reader, o);
  }
  std::filesystem::remove(path);
  const std::size_t n = f.density.size();
  double surface = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    if (f.packing[k] > 0.3) surface = o.grid.at(2, int(k));
  // The bed from two radii of the silo above the floor up: below, the sinking floor unloads the
  // bed's foot (and within 5 widths the floor's contacts, not in the recording, are missing).
  double rho = 0.0;
  int m = 0;
  std::vector<double> depth, stress;
  Table prof{"profile", {"depth", "stress", "hydrostatic", "janssen"}, {}};
  for (std::size_t k = 0; k < n; ++k) {
    const double z = o.grid.at(2, int(k));
    if (z < 2.0 * double(R) || z > surface) continue;
    depth.push_back(surface - z);
    stress.push_back(f.contactStress[6 * k + 2] + f.kineticStress[6 * k + 2]);
    if (z < surface - 0.02) rho += f.density[k], ++m;
  }
  rho /= m;
  const JanssenFit fit = fitJanssen(depth, stress);
  for (std::size_t i = 0; i < depth.size(); ++i)
    prof.rows.push_back({depth[i], stress[i], rho * kG * depth[i], fit.sigmaInf * (1.0 - std::exp(-depth[i] / fit.lambda))});
  const double deepest = depth.front(), atBottom = stress.front(), K = double(R) / (2.0 * double(muWall) * fit.lambda);
  r.checks.push_back(mkCheck("stress at the bottom of the bed over the weight of the bed above it",
                             "below 0.8: the walls carry the rest (Janssen)", atBottom / (rho * kG * deepest), 0.0,
                             atBottom / (rho * kG * deepest), 0.8, ""));
  r.checks.push_back(mkCheck("Janssen's law fits the profile", "r² of the fit >= 0.98", fit.r2, 1.0, 1.0 - fit.r2, 0.02, ""));
  const double kSigma = double(R) * rho * kG / (2.0 * double(muWall) * fit.sigmaInf);
  r.checks.push_back(absCheck("Janssen's K from the length, R / (2 mu_w lambda)",
                              "0.2–1.0 (the literature's range, 0.4–0.8 typical)", K, 0.6, 0.4, ""));
  r.checks.push_back(absCheck("Janssen's K from the saturation, R rho_b g / (2 mu_w sigma_inf)",
                              "0.2–1.0 (the literature's range, 0.4–0.8 typical)", kSigma, 0.6, 0.4, ""));
  r.tables.push_back(prof);
  r.plots.push_back(Plot{"profile", "vertical stress against depth: the coarse-grained, the hydrostatic and Janssen's fit",
                         "profile", "depth", "depth below the free surface (m)", "vertical stress (Pa)",
                         {"stress", "hydrostatic", "janssen"}, false, false, ""});
  r.summary = fmt(
      "A silo of radius R = %.0f mm (a cylinder closed by a disk, μ_w = %.1f on its walls) holds %zu spheres of "
      "radius 4 and 5 mm (2500 kg/m³, hooke-history, μ = 0.5), dropped from a lattice and settled for 2 s into a "
      "bed %.3f m deep (bulk density ρ_b = %.0f kg/m³); the floor then sinks at 1 cm/s, so that the bed slides down "
      "the walls and their friction is fully mobilised, as Janssen assumes. Ten frames 0.01 s apart while it sinks, "
      "with velocities and contact forces, coarse-grained along z over the silo's circle with w = 5 mm "
      "(docs/fields.md), give the vertical stress, from two silo radii above the floor up (below, the sinking floor "
      "unloads the bed's foot), against the depth h below the free surface. It falls below the weight of the bed above, ρ_b g h, and saturates as Janssen's "
      "σ(h) = σ∞ (1 − exp(−h/λ)): the fit gives σ∞ = %.0f Pa and λ = %.3f m (r² = %.4f), so K = R / (2 μ_w λ) = %.2f "
      "from the length and R ρ_b g / (2 μ_w σ∞) = %.2f from the saturation (Janssen's model has one K; the top of "
      "the bed, hydrostatic for a few centimetres, pulls them apart). At the bottom the stress is %.2f of the "
      "hydrostatic. Without the sinking floor the walls' friction stays partly mobilised and the same bed gave "
      "K = 0.09 (the stress a filled silo keeps depends on its filling). A regression figure: the checks are "
      "Janssen's shape and the literature's range of K, not an oracle; the fit is checked first on Janssen's own "
      "curve.",
      1e3 * double(R), double(muWall), kBodies, surface, rho, fit.sigmaInf, fit.lambda, fit.r2, K, kSigma,
      atBottom / (rho * kG * deepest));
  return r;
}

}  // namespace tumble::validation::study::physics
