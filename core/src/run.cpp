// SPDX-License-Identifier: MIT
// The run driver (tumble/run.hpp): the schedule of a run's steps and what each one writes.
#include "tumble/run.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "tumble/checkpoint.hpp"
#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/output_file.hpp"
#include "tumble/scene_io.hpp"

namespace tumble {

Run::Run(const Scene& scene)
    : m_pouring(std::make_unique<const Pouring>(scene)), m_world(m_pouring->worldWith(m_pouring->initialBodies())) {
  // Of every body the run will have: the pours' too.
  const Pouring& pouring = *m_pouring;
  m_dtWarning = tumble::timeStepWarning(pouring.any() ? pouring.worldWith(pouring.finalBodies()) : m_world);
}

void Run::resume(const std::string& path, const std::string& sceneName) {
  if (m_pipeline) throw Error("resume: the run is loaded already (resume before load)");
  const Pouring& pouring = *m_pouring;
  const Checkpoint ck = Checkpoint::read(path);
  try {
    // A run that pours resumes the world of the bodies that had entered by then.
    World world = pouring.worldWith(pouring.initialBodies());
    if (pouring.any() && ck.state.size() > world.numBodies() && ck.state.size() <= pouring.finalBodies())
      world = pouring.worldWith(ck.state.size());
    m_world = ck.resume(world, &m_resumeWarning);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw Error(path + ": cannot resume " + (sceneName.empty() ? pouring.scene().name : sceneName) + ": " + e.what());
  }
}

Run::~Run() = default;

namespace {

// What needs the pipeline, before load() gave it one: a programming error, said as one.
void requireLoaded(const std::unique_ptr<Pipeline>& pipeline, const char* what) {
  if (!pipeline) throw Error(std::string("Run::") + what + " before Run::load(): load the run's pipeline first");
}

}  // namespace

void Run::load(std::unique_ptr<Pipeline> pipeline, const RunChecks& checks, RunHooks* hooks) {
  if (checks.every < 1) throw Error("the guard's interval must be at least 1 step");
  m_checks = checks;
  if (hooks) m_hooks = hooks;
  m_pipeline = std::move(pipeline);
  m_pipeline->load(m_world);
  if (checks.stop || checks.measure) m_guard.emplace(m_world, *m_pipeline);
  m_checkedAt = m_pipeline->stepCount();
}

void Run::captureForces(bool on) {
  requireLoaded(m_pipeline, "captureForces()");
  m_captureForces = on;
  m_pipeline->setDebugCapture(on || (m_recOn && m_recSettings.debug));
}

namespace {

bool finite3(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// The world to load() to go on from the pipeline's state now: `tables` (the run's bodies and
// particles) with that state, as the pipeline integrates it, its step, time and frame.
World continuing(World tables, const Pipeline& pipeline) {
  pipeline.readLocalState(tables.state);
  tables.frame = pipeline.frame();
  tables.step = pipeline.stepCount();
  tables.time = pipeline.time();
  return tables;
}

}  // namespace

void Run::reload(World world) {
  const std::uint32_t pulls = m_pipeline->pulls();  // load() starts from the scene's
  m_statsBefore.add(m_pipeline->stats());           // and its counters afresh
  // Should the new state be refused (the detection cannot take it: at load, or when the guard
  // finds its contacts), the run goes on as it was: the state now, the world and its guard.
  World previous = m_world;
  World back = continuing(m_world, *m_pipeline);
  std::optional<RunGuard> oldGuard;  // it refers to m_world, whose contents come back
  if (m_guard) oldGuard.emplace(std::move(*m_guard));
  m_guard.reset();
  try {
    m_pipeline->load(world);
    m_pipeline->setPulls(pulls);
    m_world = std::move(world);
    if (oldGuard) m_guard.emplace(m_world, *m_pipeline);
  } catch (...) {
    m_world = std::move(previous);
    m_pipeline->load(back);
    m_pipeline->setPulls(pulls);
    if (oldGuard) m_guard.emplace(std::move(*oldGuard));
    throw;
  }
}


void Run::setBodies(const BodyChanges& c) {
  requireLoaded(m_pipeline, "setBodies()");
  const std::size_t n = c.bodies.size(), nb = m_world.numBodies();
  const std::pair<const char*, std::size_t> columns[] = {{"x", c.x.size()}, {"v", c.v.size()}, {"q", c.q.size()},
                                                         {"l", c.l.size()}, {"omega", c.omega.size()}};
  for (const auto& [name, size] : columns)
    if (size != 0 && size != n)
      throw Error(std::string("setBodies: ") + name + " has " + std::to_string(size) + " rows for " +
                  std::to_string(n) + " bodies");
  if (!c.l.empty() && !c.omega.empty()) throw Error("setBodies: give l or omega, not both");
  std::vector<bool> seen(nb, false);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t b = c.bodies[k];
    const std::string what = "setBodies: body " + std::to_string(b);
    if (b >= nb) throw Error(what + " is beyond the " + std::to_string(nb) + " bodies of the run");
    if (seen[b]) throw Error(what + " is named twice");
    seen[b] = true;
    if ((!c.x.empty() && !finite3(c.x[k])) || (!c.v.empty() && !finite3(c.v[k])) ||
        (!c.l.empty() && !finite3(c.l[k])) || (!c.omega.empty() && !finite3(c.omega[k])))
      throw Error(what + ": a value is not finite");
    if (!c.x.empty())
      for (const float v : {c.x[k].x, c.x[k].y, c.x[k].z})
        if (!withinExactRange(double(v)))
          throw Error(what + ": x is beyond +-2^60 m (1.15e18), the range whose contacts single precision decides right");
    if (!c.q.empty()) {
      const Quatf q = c.q[k];
      const double norm = std::sqrt(double(q.w) * q.w + double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z);
      if (!(std::fabs(norm - 1.0) <= kUnitQuaternionTolerance))
        throw Error(what + ": q is not a unit quaternion (|q| = " + std::to_string(norm) + "); normalise it");
    }
    const Vec3f* turn = !c.l.empty() ? &c.l[k] : !c.omega.empty() ? &c.omega[k] : nullptr;
    if (turn && !m_world.bodyRotates(b) && (turn->x != 0.0f || turn->y != 0.0f || turn->z != 0.0f))
      throw Error(what + " does not rotate (a single sphere under the report's law): its l and omega stay 0");
    if (!c.x.empty())
      if (const std::string why = outsidePeriodicBox(m_world.params.periodic, c.x[k]); !why.empty())
        throw Error(what + ": " + why);
  }
  World world = continuing(m_world, *m_pipeline);
  BodyState& s = world.state;
  const LocalFrame f = world.frame.value_or(LocalFrame{});
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t b = c.bodies[k];
    if (!c.x.empty()) {  // into the run's frame, as toLocal() moves a scene's bodies
      s.px[b] = f.active() ? static_cast<float>(double(c.x[k].x) - f.x) : c.x[k].x;
      s.py[b] = f.active() ? static_cast<float>(double(c.x[k].y) - f.y) : c.x[k].y;
      s.pz[b] = f.active() ? static_cast<float>(double(c.x[k].z) - f.z) : c.x[k].z;
    }
    if (!c.v.empty()) s.vx[b] = c.v[k].x, s.vy[b] = c.v[k].y, s.vz[b] = c.v[k].z;
    if (!c.q.empty()) s.qw[b] = c.q[k].w, s.qx[b] = c.q[k].x, s.qy[b] = c.q[k].y, s.qz[b] = c.q[k].z;
    if (!c.l.empty()) s.lx[b] = c.l[k].x, s.ly[b] = c.l[k].y, s.lz[b] = c.l[k].z;
    if (!c.omega.empty()) {  // L = R I0 Rᵀ Ω with the body's Q (the new one when given)
      const Mat3f R = rotationMatrix(Quatf{s.qw[b], s.qx[b], s.qy[b], s.qz[b]});
      const Vec3f L = mul(R, mul(world.inertia[b], mulTransposed(R, c.omega[k])));
      s.lx[b] = L.x, s.ly[b] = L.y, s.lz[b] = L.z;
    }
  }
  reload(std::move(world));
}

namespace {

enum class Range { Positive, NonNegative, Poisson, Restitution };

// A contact parameter that may change during a run: its key in the scene file and its place.
struct Changeable {
  std::string key;
  Range range;
  float* to;
};

// The contact parameters of `s` that a run may change: those that set the contact forces alone
// (World::fromScene() derives the dampings and the material pairs from them again).
std::vector<Changeable> changeable(Scene& s) {
  ContactParams& c = s.contact;
  GroundParams& g = s.ground;
  const std::string key = cohesionKey(c.cohesion);
  std::vector<Changeable> out;
  switch (c.law) {
    case ContactLaw::Report:
      out = {{"contact.stiffness", Range::Positive, &c.stiffness},
             {"contact.damping", Range::NonNegative, &c.damping},
             {"contact.shear", Range::NonNegative, &c.shear}};
      break;
    case ContactLaw::HookeHistory:
      out = {{"contact.stiffness", Range::Positive, &c.stiffness},
             {"contact.tangential_stiffness", Range::NonNegative, &c.tangentialStiffness},
             {"contact.gamma_n", Range::NonNegative, &c.gammaN},
             {"contact.gamma_t", Range::NonNegative, &c.gammaT},
             {"contact.friction", Range::NonNegative, &c.friction},
             {"contact.rolling_friction", Range::NonNegative, &c.rollingFriction}};
      if (c.cohesion != Cohesion::None) out.push_back({"contact." + key, Range::NonNegative, &c.cohesionValue});
      break;
    case ContactLaw::HertzMindlin:
      for (MaterialDef& m : s.materials) {
        const std::string at = "material." + m.name + ".";
        out.push_back({at + "youngs_modulus", Range::Positive, &m.youngsModulus});
        out.push_back({at + "poisson_ratio", Range::Poisson, &m.poissonRatio});
        out.push_back({at + "restitution", Range::Restitution, &m.restitution});
        out.push_back({at + "friction", Range::NonNegative, &m.friction});
        out.push_back({at + "rolling_friction", Range::NonNegative, &m.rollingFriction});
        if (c.cohesion != Cohesion::None) out.push_back({at + key, Range::NonNegative, &m.cohesion});
      }
      break;
  }
  if (!g.enabled) return out;
  // A plane's own cohesion (docs/model.md#cohesion): set, it replaces the contact's or the pair's.
  if (c.cohesion != Cohesion::None) out.push_back({"ground." + key, Range::NonNegative, &g.cohesion});
  if (c.usesMaterials()) {  // the ground's friction replaces the mixed one, as in the file
    out.push_back({"ground.friction", Range::NonNegative, &g.frictionOverride});
    out.push_back({"ground.rolling_friction", Range::NonNegative, &g.rollingFriction});
    return out;
  }
  out.push_back({"ground.stiffness", Range::Positive, &g.stiffness});
  out.push_back({"ground.friction", Range::NonNegative, &g.friction});
  out.push_back({"ground.tangential_stiffness", Range::NonNegative, &g.tangentialStiffness});
  if (c.rotatesSpheres()) out.push_back({"ground.rolling_friction", Range::NonNegative, &g.rollingFriction});
  return out;
}

// Why `key` cannot change during a run: the reason for the keys one may try, else a list of those
// that can.
std::string cannotChange(const std::string& key, const Scene& s, const std::vector<Changeable>& can) {
  auto ends = [&](const char* tail) {
    const std::size_t n = std::strlen(tail);
    return key.size() > n && key.compare(key.size() - n, n, tail) == 0;
  };
  std::string why;
  if (key == "contact.law")
    why = "the law cannot change during a run (which bodies rotate and the contacts' history depend on it)";
  else if (key == "contact.cohesion")
    why = "the cohesion model cannot change during a run (its coefficients can, under the model the scene chose)";
  else if (ends(".cohesion_energy_density") || ends(".surface_energy"))
    why = s.contact.cohesion == Cohesion::None
              ? "the scene has no cohesion ([contact] cohesion), and its model cannot change during a run"
              : std::string("the scene's cohesion is \"") + toString(s.contact.cohesion) + "\", whose coefficient is " +
                    cohesionKey(s.contact.cohesion);
  else if (key == "ground.enabled" || key == "ground.height" || key == "ground.material")
    why = "the ground's place and material cannot change during a run";
  else if (key.rfind("material.", 0) == 0 && ends(".density"))
    why = "a density sets the masses, which cannot change during a run";
  else if (key.rfind("wall", 0) == 0)
    why = "the walls' contact parameters cannot change during a run";
  else if (key == "scene.dt")
    why = "dt cannot change during a run (its steps and time are counted in it)";
  else
    why = "not a contact parameter that can change during a run";
  std::string list;
  for (const Changeable& c : can) list += (list.empty() ? "" : ", ") + c.key;
  return key + ": " + why + "; under law = \"" + toString(s.contact.law) + "\" these can: " +
         (list.empty() ? std::string("none") : list);
}

}  // namespace

void Run::setParameters(const std::vector<std::pair<std::string, double>>& changes) {
  requireLoaded(m_pipeline, "setParameters()");
  Scene s = scene();
  const std::vector<Changeable> can = changeable(s);
  for (const auto& change : changes) {
    const std::string& key = change.first;  // (a named variable: Clang 14 captures no structured binding)
    const double value = change.second;
    const auto it = std::find_if(can.begin(), can.end(), [&](const Changeable& c) { return c.key == key; });
    if (it == can.end()) throw Error("setParameters: " + cannotChange(key, s, can));
    const float v = static_cast<float>(value);
    const bool ok = std::isfinite(v) && (it->range == Range::Positive      ? v > 0.0f
                                         : it->range == Range::NonNegative ? v >= 0.0f
                                         : it->range == Range::Poisson     ? v >= 0.0f && v < 0.5f
                                                                           : v > 0.0f && v <= 1.0f);
    if (!ok) {
      char shown[32];
      std::snprintf(shown, sizeof shown, "%.9g", value);  // as the scene reader shows a number
      throw Error("setParameters: " + key + " = " + shown + ": must be " +
                  (it->range == Range::Positive      ? "a finite number > 0"
                   : it->range == Range::NonNegative ? "a finite number >= 0"
                   : it->range == Range::Poisson     ? "in [0, 0.5)"
                                                     : "in (0, 1]"));
    }
    *it->to = v;
  }
  auto pouring = std::make_unique<const Pouring>(s);
  World tables, final;
  try {
    tables = pouring->worldWith(m_world.numBodies());  // the dampings and material pairs again, checked
    // With pours, the world of every body that will enter, checked too (a coefficient may suit the
    // bodies present and not those to come), before anything changes.
    if (pouring->any()) final = pouring->worldWith(pouring->finalBodies());
  } catch (const Error& e) {
    throw Error(std::string("setParameters: ") + e.what());
  }
  reload(continuing(std::move(tables), *m_pipeline));
  m_pouring = std::move(pouring);
  m_dtWarning = tumble::timeStepWarning(m_pouring->any() ? final : m_world);
}

World Run::finalWorld() const {
  return m_pouring->any() ? m_pouring->worldWith(m_pouring->finalBodies()) : m_world;
}

StepStats Run::stats() const {
  requireLoaded(m_pipeline, "stats()");
  StepStats st = m_statsBefore;
  st.add(m_pipeline->stats());
  return st;
}

ThermoSample Run::sampleNow() const {
  requireLoaded(m_pipeline, "sampleNow()");
  if (!m_guard) throw Error("this run measures nothing (no guard: RunChecks::stop and measure are off)");
  if (m_guard->sample().step == m_pipeline->stepCount()) return withTally(m_guard->sample());  // checked at this step
  RunGuard probe(*m_guard);
  probe.check(*m_pipeline);
  return withTally(probe.sample());
}

ThermoSample Run::withTally(ThermoSample s) const {
  if (!m_tallying) return withEnergy(s, kNoEnergyTally);
  const EnergyTotals e = stats().energy;  // since the series began: less what was there then
  return withEnergy(s, e - m_tallyBase);
}

bool Run::writeOrGiveUp(const std::function<void()>& write) {
  bool givenUp = false;
  m_hooks->write([&] {
    try {
      write();
    } catch (const Error&) {
      if (!m_hooks->mayGiveUpWrite()) throw;
      givenUp = true;
    }
  });
  return m_hooks->any(givenUp);
}

Advanced Run::advance(std::uint64_t n) {
  requireLoaded(m_pipeline, "advance()");
  Pipeline& pipeline = *m_pipeline;
  const std::uint64_t start = pipeline.stepCount();
  const std::uint64_t end = start + n;
  const bool guarding = m_checks.stop;
  const std::uint64_t perFrame = stepsPerFrame();
  Advanced a;
  std::uint64_t done = start;
  while (done < end) {
    if (m_hooks->stopRequested()) {
      a.stopped = true;
      break;
    }
    // Bodies of a [[pour]] enter at its batch steps, after the frame, checks and checkpoint of
    // the state before them; the guard then starts its energy budget afresh from the state they
    // entered (at that step, whatever the calls).
    bool entered = false;
    const bool batch = m_pouring->nextBatch(pipeline.stepCount(), m_world.numBodies()) == pipeline.stepCount();
    m_hooks->stepping([&] { entered = m_pouring->enter(pipeline, m_world, &m_statsBefore); });
    if (entered) {
      a.entered = true;
      if (m_guard) m_guard.emplace(m_world, pipeline);
    }
    if (batch) {
      m_pourWaiting = m_pouring->waiting(m_world.numBodies(), pipeline.time());
      if (m_pourWaiting > 0 && !m_toldBehind) {
        m_toldBehind = true;
        m_hooks->notice("step " + std::to_string(pipeline.stepCount()) + ": the [[pour]] fell behind: " +
                        std::to_string(m_pourWaiting) + " bodies due by now found no place clear of the others "
                        "and the walls in their region (each tried its pour's `attempts` places); they wait for the "
                        "next batches (a larger region, a lower rate or more attempts keeps up)");
      }
    }
    // The stretch ends where the next thing is due: a frame, a check, a row, a checkpoint, the
    // end of the run or the next pour batch.
    std::uint64_t chunk = std::min(end - done, kStepsBetweenStops);
    if (m_recOn && done < m_recSettings.lastStep) chunk = std::min(chunk, perFrame - done % perFrame);
    if (guarding) chunk = std::min(chunk, m_checks.every - done % m_checks.every);
    if (m_thermoOn) chunk = std::min(chunk, m_thermoEvery - done % m_thermoEvery);
    if (m_checkpointEvery) chunk = std::min(chunk, m_checkpointEvery - done % m_checkpointEvery);
    if (m_endStep && done < *m_endStep) chunk = std::min(chunk, *m_endStep - done);
    chunk = std::min(chunk, m_pouring->nextBatch(done + 1, m_world.numBodies()) - done);
    // A recording of contact forces without the debug block captures only the step before each frame.
    const bool frameAhead = m_recOn && done + chunk <= m_recSettings.lastStep && (done + chunk) % perFrame == 0;
    const bool captureLast = frameAhead && m_recSettings.contactForces && !m_recSettings.debug && !m_captureForces;
    m_hooks->stepping([&] {
      if (!captureLast) return pipeline.step(chunk);
      if (chunk > 1) pipeline.step(chunk - 1);
      pipeline.setDebugCapture(true);
      pipeline.step(1);
      pipeline.setDebugCapture(false);
    });
    done += chunk;
    a.steps = done - start;
    const bool atEnd = m_endStep && done == *m_endStep;
    const bool frameDue = m_recOn && done <= m_recSettings.lastStep && done % perFrame == 0;
    const bool checkpointDue = m_checkpointEvery && done % m_checkpointEvery == 0 && !atEnd;
    const bool rowDue = m_thermoOn && (done % m_thermoEvery == 0 || atEnd);
    if (rowDue || (guarding && (frameDue || checkpointDue || done % m_checks.every == 0 || atEnd))) {
      const auto trip = m_guard->check(pipeline);
      if (rowDue && writeOrGiveUp([&] { m_thermo->write(withTally(m_guard->sample())); })) {
        a.rowGivenUp = a.stopped = true;
        break;
      }
      if (trip && guarding) throw SimulationError(trip->message);
      m_checkedAt = done;
    }
    if (frameDue) {
      pipeline.readState(m_state);
      const bool debug = m_recSettings.debug || m_recSettings.contactForces;
      if (debug) pipeline.readDebug(m_debug);
      if (writeOrGiveUp([&] {
            m_rec->writeFrame(done, pipeline.time(), pipeline.pulls(), m_state, debug ? &m_debug : nullptr);
          })) {
        a.frameGivenUp = a.stopped = true;
        break;
      }
      if (done + perFrame > m_recSettings.lastStep) closeRecording();  // the last frame: the file is complete
    }
    if (checkpointDue) writeCheckpoint(m_checkpointPath);
    m_hooks->progress(done);
  }
  // The state handed back is checked, on a copy of the guard: the run's own checks stay where
  // they fall, however the steps are split into calls.
  if (guarding && a.steps > 0 && m_checkedAt != done) {
    RunGuard probe(*m_guard);
    if (const auto trip = probe.check(pipeline)) throw SimulationError(trip->message);
  }
  return a;
}

namespace {

// The continuity of a recording continued by a resumed run: its frames must reach the last
// frame due at or before the checkpoint's step.
void checkContinues(const RecordingWriter& rec, std::uint64_t start, const RecordSettings& s) {
  const std::uint64_t perFrame = static_cast<std::uint64_t>(s.stepsPerFrame);
  const std::uint64_t due = (std::min(start, s.lastStep) / perFrame) * perFrame;  // the last frame due by now
  const bool any = !(s.afterSteps() && due == 0);  // debug and contact-force recordings have no step-0 frame
  if (any ? rec.lastStep() != due : rec.numFrames() != 0)
    throw Error("recording '" + rec.path() + "' ends at step " + std::to_string(rec.lastStep()) +
                " but the checkpoint is at step " + std::to_string(start) +
                ": it does not continue there; record the resumed run to another file");
}

}  // namespace

void Run::record(const RecordSettings& s) {
  requireLoaded(m_pipeline, "record()");
  if (s.stepsPerFrame < 1) throw Error("steps_per_frame must be at least 1");
  refuseSceneInput(scene(), s.path, "the recording");
  const std::uint64_t step = m_pipeline->stepCount();
  std::unique_ptr<RecordingWriter> rec;
  m_hooks->write([&] {
    // With pours the recording's table holds every body that may enter, each frame those present.
    const bool grows = m_pouring->any();
    const World grown = grows ? finalWorld() : World{};
    const World& table = grows ? grown : m_world;
    if (s.continues && step > 0) {
      rec = RecordingWriter::continueAt(s.path, table, s.debug, s.stepsPerFrame, step, 60.0f, grows, s.contactForces);
      if (rec->numFrames() > 0) checkContinues(*rec, step, s);
    } else {
      rec = std::make_unique<RecordingWriter>(s.path, table, s.debug, s.stepsPerFrame, 60.0f, grows, s.contactForces);
    }
  });
  closeRecording();  // the new file is open: the one under way ends
  m_rec = std::move(rec);
  m_recSettings = s;
  m_recOn = true;
  m_pipeline->setDebugCapture(s.debug || m_captureForces);
  // The first frame: the state now (debug and contact-force frames start after a step).
  m_pipeline->readState(m_state);
  m_hooks->write([&] {
    if (m_rec->numFrames() == 0 && !s.afterSteps())
      m_rec->writeFrame(step, m_pipeline->time(), m_pipeline->pulls(), m_state);
  });
}

void Run::closeRecording() {
  if (!m_recOn) return;
  m_recOn = false;
  m_pipeline->setDebugCapture(m_captureForces);
  m_hooks->write([&] { m_rec->close(); });
}

void Run::writeThermo(const std::string& path, std::uint64_t every, bool energyBalance) {
  requireLoaded(m_pipeline, "writeThermo()");
  if (every < 1) throw Error("the time series' interval must be at least 1 step");
  refuseSceneInput(scene(), path, "the time series");
  ThermoSample now = sampleNow();  // collective under MPI: before the writer's part
  std::unique_ptr<ThermoWriter> thermo;
  m_hooks->write([&] { thermo = std::make_unique<ThermoWriter>(path, scene().dt); });  // first: a failure keeps the one under way
  closeThermo();  // (its tally off)
  m_thermo = std::move(thermo);
  m_thermoEvery = every;
  m_thermoOn = true;
  // The tally's columns count from this row on (0 in it): the sums of earlier series are the base.
  m_pipeline->setEnergyTally(energyBalance);
  m_tallying = energyBalance;
  m_tallyBase = stats().energy;
  now = withTally(now);
  m_hooks->write([&] { m_thermo->write(now); });
}

void Run::closeThermo() {
  if (!m_thermoOn) return;
  m_thermoOn = false;
  m_pipeline->setEnergyTally(false);
  m_tallying = false;
  m_hooks->write([&] { m_thermo->close(); });
}

void Run::closeOutputs() {
  closeRecording();
  closeThermo();
}

void Run::abandonOutputs() noexcept {
  if (m_recOn && m_rec) m_rec->abandon();
  if (m_thermoOn && m_thermo) m_thermo->abandon();
  m_recOn = m_thermoOn = m_tallying = false;
  if (m_pipeline) {
    m_pipeline->setDebugCapture(m_captureForces);
    m_pipeline->setEnergyTally(false);
  }
}

void Run::checkpointEvery(const std::string& path, std::uint64_t every) {
  if (every > 0 && path.empty()) throw Error("checkpoints every " + std::to_string(every) + " steps need a file");
  refuseSceneInput(scene(), path, "the checkpoint");
  m_checkpointPath = path;
  m_checkpointEvery = every;
}

void Run::writeCheckpoint(const std::string& path) {
  requireLoaded(m_pipeline, "writeCheckpoint()");
  refuseSceneInput(scene(), path, "the checkpoint");
  const Checkpoint ck = Checkpoint::of(m_world, *m_pipeline);  // collective under MPI
  m_hooks->write([&] { ck.write(path); });
}

void Run::writeState(const std::string& path) {
  requireLoaded(m_pipeline, "writeState()");
  refuseSceneInput(scene(), path, "the state file");
  m_pipeline->readState(m_state);
  m_hooks->write([&] {
    const BodyState& s = m_state;
    OutputFile out(path);  // atomically: a failure leaves `path` as it was
    std::FILE* f = out.file();
    // With periodic boundaries, the periods each centre has crossed (BodyState::imageX, imageY).
    std::fprintf(f, "body,x,y,z,vx,vy,vz,qw,qx,qy,qz,lx,ly,lz%s%s\n", s.imageX.empty() ? "" : ",image_x",
                 s.imageY.empty() ? "" : ",image_y");
    for (std::size_t k = 0; k < s.size(); ++k) {
      const Quatf q = shapeOrientation(m_world, s, k);  // the scene file's shape frame
      // %.9g: nine significant digits read back to the same float bits.
      std::fprintf(f, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", k, s.px[k], s.py[k],
                   s.pz[k], s.vx[k], s.vy[k], s.vz[k], q.w, q.x, q.y, q.z, s.lx[k], s.ly[k], s.lz[k]);
      if (!s.imageX.empty()) std::fprintf(f, ",%d", static_cast<int>(s.imageX[k]));
      if (!s.imageY.empty()) std::fprintf(f, ",%d", static_cast<int>(s.imageY[k]));
      std::fputc('\n', f);
    }
    if (std::ferror(f)) throw Error("cannot write " + path + ": " + std::strerror(errno != 0 ? errno : EIO));
    out.commit();
  });
}

}  // namespace tumble
