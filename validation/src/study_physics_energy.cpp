// SPDX-License-Identifier: MIT
// The energy balance of the time series (docs/thermo.md#energy-balance): kinetic + potential +
// dissipated − work in stays at its initial value on a heap, a turning drum and a silo.
#include <algorithm>
#include <cmath>

#include "study_physics_common.hpp"
#include "tumble/factory.hpp"
#include "tumble/guard.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/thermo.hpp"

namespace tumble::validation::study::physics {

CaseResult energyBalance(const CaseContext& ctx) {
  CaseResult r;
  r.id = "energy_balance";
  r.title = "Energy balance: E + dissipated − wall work stays constant";
  // The drum and the silo with their bodies thrown down at 3 m/s and the drum turning from the
  // first step (thrownAtWalls()): every kind of contact within the first steps.
  struct Scenario {
    const char* name;
    Scene scene;
  };
  const Scenario scenarios[] = {{"heap", readSceneFile(sourcePath("scenes/heap.toml"))},
                                {"drum", thrownAtWalls("scenes/drum.toml")},
                                {"silo", thrownAtWalls("scenes/silo.toml")}};
  const std::uint64_t steps = ctx.depth == Depth::Quick ? 1500 : 6000, every = 250;
  Table t{"balance", {"scene_index", "time", "energy", "dissipated", "wall_work", "balance_change"}, {}};
  std::string parts;
  for (std::size_t k = 0; k < std::size(scenarios); ++k) {
    const World w = World::fromScene(scenarios[k].scene);
    auto p = makePipeline(ctx.backend, PipelineOptions{});
    p->load(w);
    p->setEnergyTally(true);
    RunGuard guard(w, *p);
    const double b0 = withEnergy(guard.sample(), p->stats().energy).balance();
    double worst = 0.0, flowed = 0.0;
    for (std::uint64_t done = 0; done < steps; done += every) {
      p->step(every);
      (void)guard.check(*p);
      const ThermoSample s = withEnergy(guard.sample(), p->stats().energy);
      const double dissipated =
          ((s.dissipatedNormal + s.dissipatedTangential) + s.dissipatedFriction) + s.dissipatedCohesion;
      t.rows.push_back({double(k), s.time, s.energy(), dissipated, s.wallWork, s.balance() - b0});
      worst = std::max(worst, std::fabs(s.balance() - b0));
      flowed = dissipated + std::fabs(s.wallWork);
    }
    r.checks.push_back(boundCheck(std::string(scenarios[k].name) + ": largest change of the balance / energy that flowed",
                                  "≤ 5e-3 (the integration's error)", worst / flowed, 5e-3, "relative"));
    parts += fmt("%s%s: %.4g J dissipated or put in, the balance moved by %.3g J at most", parts.empty() ? "" : "; ",
                 scenarios[k].name, flowed, worst);
  }
  r.tables.push_back(t);
  r.plots.push_back(Plot{"balance", "change of E + dissipated − wall work against time", "balance", "time", "time (s)",
                         "balance − its initial value (J)", {"balance_change"}, false, false, "scene_index"});
  r.plots.push_back(Plot{"dissipated", "energy dissipated by the contacts", "balance", "time", "time (s)",
                         "dissipated (J)", {"dissipated"}, false, false, "scene_index"});
  r.summary = fmt(
      "The energy tally (docs/thermo.md#energy-balance) over %llu steps of scenes/heap.toml (hooke-history "
      "clumps with rolling resistance; scene 0), the drum turning from the first step with its bodies thrown down "
      "at 3 m/s (1) and the silo likewise (2): the mechanical energy plus what the normal dashpots, the tangential "
      "dashpots and friction dissipated, less the walls' work, must stay at its initial value within 5e-3 of the "
      "energy that flowed. %s.",
      static_cast<unsigned long long>(steps), parts.c_str());
  return r;
}

}  // namespace tumble::validation::study::physics
