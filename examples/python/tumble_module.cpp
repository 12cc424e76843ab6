// SPDX-License-Identifier: MIT
// The Python module `tumble` (its compiled part, tumble._tumble; docs/python.md): scenes from
// files or text, a simulation on either pipeline, its state as NumPy arrays, pulls, recordings,
// checkpoints and the time series. Every value comes from the same library calls as the
// `tumble` command's, so a script and `tumble run` give the same bits.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tumble/config.hpp"
#include "tumble/error.hpp"
#include "tumble/exact_range.hpp"
#include "tumble/factory.hpp"
#include "tumble/fields.hpp"
#include "tumble/guard.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/output_file.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/recording.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"
#include "tumble/thermo.hpp"
#include "tumble/world.hpp"

namespace py = pybind11;
using namespace tumble;

namespace {

constexpr std::uint64_t kMaxStepsPerCall = 1000000000000000ull;  // as tumble run --steps

// A path argument: a str or any os.PathLike (pathlib.Path).
// A str, bytes or os.PathLike path as the file system's text (bytes decoded as os.fsdecode does:
// str() of bytes would be the name "b'...'").
std::string pathOf(const py::object& p) { return py::str(py::module_::import("os").attr("fsdecode")(p)); }

template <class T>
py::array_t<T> array1(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// Columns c[0..k) of length n as one (n, k) array.
py::array_t<float> columns(std::initializer_list<const std::vector<float>*> cols) {
  const std::size_t n = (*cols.begin())->size(), k = cols.size();
  py::array_t<float> a({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(k)});
  float* out = a.mutable_data();
  std::size_t c = 0;
  for (const auto* col : cols) {
    for (std::size_t i = 0; i < n; ++i) out[i * k + c] = (*col)[i];
    ++c;
  }
  return a;
}

py::array_t<std::uint32_t> pairArray(const std::vector<Pair>& pairs) {
  py::array_t<std::uint32_t> a({static_cast<py::ssize_t>(pairs.size()), py::ssize_t{2}});
  std::uint32_t* out = a.mutable_data();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    out[2 * k] = pairs[k].i;
    out[2 * k + 1] = pairs[k].j;
  }
  return a;
}

// Contacts with their forces (ContactForce) as arrays: pairs (C,2) uint32, the normal force
// fn n and the tangential force (C,3), the unit normal n (C,3), fn and the overlap (C,).
py::dict contactForceDict(const std::vector<ContactForce>& cf) {
  std::vector<Pair> pairs(cf.size());
  const auto c = static_cast<py::ssize_t>(cf.size());
  py::array_t<float> normal({c, py::ssize_t{3}}), tangential({c, py::ssize_t{3}}), unit({c, py::ssize_t{3}}), fn(c),
      overlap(c);
  const auto put = [](py::array_t<float>& a, std::size_t k, Vec3f v) {
    float* p = a.mutable_data() + 3 * k;
    p[0] = v.x, p[1] = v.y, p[2] = v.z;
  };
  for (std::size_t k = 0; k < cf.size(); ++k) {
    const ContactForce& x = cf[k];
    pairs[k] = Pair{x.i, x.j};
    put(normal, k, x.normal());
    put(tangential, k, x.tangential);
    put(unit, k, x.n);
    fn.mutable_data()[k] = x.fn;
    overlap.mutable_data()[k] = x.overlap;
  }
  py::dict d;
  d["pairs"] = pairArray(pairs);
  d["normal"] = normal;
  d["tangential"] = tangential;
  d["n"] = unit;
  d["fn"] = fn;
  d["overlap"] = overlap;
  return d;
}

// tumble.fields(): coarseGrainRecording() as arrays, per point: (P,) scalars, (P,3) vectors and
// (P,3,3) symmetric tensors, with the points (P,3) and the grid's shape (nx, ny, nz).
py::dict fieldsOf(const py::object& pathArg, double width, const std::optional<std::vector<int>>& grid,
                  const std::optional<std::string>& axis, const std::optional<std::vector<double>>& box, long first,
                  long last, std::size_t every, std::optional<double> area) {
  FieldOptions o;
  o.width = width;
  o.every = every;
  FieldGrid& g = o.grid;
  if (axis) {
    if (*axis != "x" && *axis != "y" && *axis != "z") throw Error("fields: axis must be 'x', 'y' or 'z'");
    g.axis = (*axis)[0] - 'x';
  }
  if (area) {
    if (g.axis < 0) throw Error("fields: area is a profile's: give axis too");
    if (!(*area > 0.0) || !std::isfinite(*area)) throw Error("fields: area must be a positive number");
    g.area = *area;
  }
  g.n = {0, 0, 0};
  if (grid) {
    const std::size_t want = g.axis >= 0 ? 1 : 3;
    if (grid->size() != want)
      throw Error("fields: grid must be " + std::string(want == 1 ? "one count (along the axis)" : "three counts (nx, ny, nz)"));
    for (int c : *grid)
      if (c < 1 || c > 4096) throw Error("fields: each grid count must be from 1 to 4096");
    if (g.axis >= 0) g.n[std::size_t(g.axis)] = (*grid)[0];
    else g.n = {(*grid)[0], (*grid)[1], (*grid)[2]};
  }
  if (box) {
    if (box->size() != 6) throw Error("fields: box must be (xmin, ymin, zmin, xmax, ymax, zmax)");
    for (std::size_t a = 0; a < 3; ++a) {
      g.lo[a] = (*box)[a];
      g.hi[a] = (*box)[a + 3];
      if (!(g.hi[a] > g.lo[a])) throw Error("fields: box's upper corner must be above its lower one on every axis");
    }
  }
  RecordingReader reader(pathOf(pathArg));
  const long frames = static_cast<long>(reader.numFrames());
  const long a = first < 0 ? first + frames : first, b = last < 0 ? last + frames : last;
  if (frames == 0 || a < 0 || b >= frames || a > b)
    throw Error("fields: frames " + std::to_string(first) + " to " + std::to_string(last) + " of a recording of " +
                std::to_string(frames) + " frames");
  o.first = static_cast<std::size_t>(a);
  o.last = static_cast<std::size_t>(b);
  Fields f;
  {
    py::gil_scoped_release release;
    f = coarseGrainRecording(reader, o);
  }
  const FieldGrid& fg = f.grid;
  const auto p = static_cast<py::ssize_t>(fg.size());
  py::array_t<double> points({p, py::ssize_t{3}});
  for (py::ssize_t k = 0; k < p; ++k) {
    const int ix = int(k % fg.points(0)), iy = int(k / fg.points(0) % fg.points(1)), iz = int(k / (fg.points(0) * fg.points(1)));
    double* row = points.mutable_data(k);
    row[0] = fg.at(0, ix), row[1] = fg.at(1, iy), row[2] = fg.at(2, iz);
  }
  const auto scalars = [&](const std::vector<double>& v) {
    py::array_t<double> out(p);
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  };
  const auto vectors = [&](const std::vector<double>& v) {
    py::array_t<double> out({p, py::ssize_t{3}});
    std::copy(v.begin(), v.end(), out.mutable_data());
    return out;
  };
  const auto tensors = [&](const std::vector<double>& v) {  // xx, yy, zz, xy, xz, yz → 3 × 3
    py::array_t<double> out({p, py::ssize_t{3}, py::ssize_t{3}});
    static const int kAt[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    for (py::ssize_t k = 0; k < p; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) *out.mutable_data(k, r, c) = v[6 * std::size_t(k) + std::size_t(kAt[r][c])];
    return out;
  };
  py::dict d;
  d["points"] = points;
  d["shape"] = py::make_tuple(fg.points(0), fg.points(1), fg.points(2));
  d["width"] = f.width;
  d["frames"] = f.frames;
  d["box"] = py::make_tuple(fg.lo[0], fg.lo[1], fg.lo[2], fg.hi[0], fg.hi[1], fg.hi[2]);
  d["density"] = scalars(f.density);
  d["packing_fraction"] = scalars(f.packing);
  if (f.velocities) {
    d["momentum"] = vectors(f.momentum);
    d["velocity"] = vectors(f.velocity);
    d["temperature"] = scalars(f.temperature);
    d["kinetic_stress"] = tensors(f.kineticStress);
  }
  if (f.contacts) d["contact_stress"] = tensors(f.contactStress);
  return d;
}

// A float column from a 1-D array-like of n values.
std::vector<float> floatColumn(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, std::size_t n,
                               const char* what) {
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw InputError("find_pairs", 0, std::string(what) + ": expected " + std::to_string(n) + " values in one dimension");
  return {a.data(), a.data() + n};
}

// Rows of k floats (an (n, k) array-like, or None: no rows) as T{...} values.
template <class T, int K>
std::vector<T> rowsOf(const py::object& a, std::size_t n, const char* what) {
  if (a.is_none()) return {};
  const auto arr = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!arr || arr.ndim() != 2 || static_cast<std::size_t>(arr.shape(0)) != n || arr.shape(1) != K) {
    PyErr_Clear();
    throw Error(std::string("set_bodies: ") + what + " must have shape (" + std::to_string(n) + ", " +
                std::to_string(K) + "): a row per body named");
  }
  std::vector<T> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    const float* r = arr.data() + K * k;
    if constexpr (K == 3) out[k] = T{r[0], r[1], r[2]};
    else out[k] = T{r[0], r[1], r[2], r[3]};
  }
  return out;
}

// Body indices: None (every body, 0..n-1) or a 1-D array-like of whole numbers.
std::vector<std::uint32_t> bodyIndices(const py::object& a, std::uint32_t numBodies) {
  std::vector<std::uint32_t> out;
  if (a.is_none()) {
    for (std::uint32_t b = 0; b < numBodies; ++b) out.push_back(b);
    return out;
  }
  const py::array arr = py::array::ensure(a);
  if (!arr || arr.ndim() != 1 || (arr.size() > 0 && arr.dtype().kind() != 'i' && arr.dtype().kind() != 'u')) {
    PyErr_Clear();
    throw Error("set_bodies: bodies must be a list or 1-D array of body indices (whole numbers)");
  }
  const auto ids = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(arr);
  for (py::ssize_t k = 0; k < arr.size(); ++k) {
    const std::int64_t b = ids.data()[k];
    if (b < 0 || b >= std::int64_t{numBodies})
      throw Error("set_bodies: body " + std::to_string(b) + " is not one of the " + std::to_string(numBodies) +
                  " bodies (0 to " + std::to_string(std::int64_t{numBodies} - 1) + ")");
    out.push_back(static_cast<std::uint32_t>(b));
  }
  return out;
}

// The time-series row as {column: value}, the columns of the CSV file (docs/thermo.md).
py::dict thermoDict(const ThermoSample& s) {
  const std::array<double, kThermoColumns> row = thermoRow(s);
  py::dict d;
  std::string header = thermoHeader();
  std::size_t at = 0;
  for (std::size_t c = 0; c < kThermoColumns; ++c) {
    const std::size_t end = std::min(header.find(',', at), header.size());
    const std::string name = header.substr(at, end - at);
    if (c == kThermoStepColumn) d[name.c_str()] = s.step;
    else if (c == kThermoContactsColumn) d[name.c_str()] = s.contacts;
    else d[name.c_str()] = row[c];
    at = end + 1;
  }
  return d;
}

// Body k's angular velocity Ω = R I0⁻¹ Rᵀ L, as the pipelines compute it (0 for a body that
// does not rotate: a single sphere under the report's law).
Vec3f angularVelocityOf(const World& world, const BodyState& s, std::size_t k) {
  if (!world.bodyRotates(k)) return Vec3f{0.0f, 0.0f, 0.0f};
  return angularVelocity(Quatf{s.qw[k], s.qx[k], s.qy[k], s.qz[k]}, world.invInertia[k], Vec3f{s.lx[k], s.ly[k], s.lz[k]});
}

// The module's part of a run (tumble/run.hpp): the GIL let go around the steps, Ctrl-C between
// stretches of them.
class PythonHooks : public RunHooks {
 public:
  bool stopRequested() override {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // KeyboardInterrupt
    return false;
  }
  void stepping(const std::function<void()>& steps) override {
    py::gil_scoped_release release;
    steps();
  }
  void notice(const std::string& message) override {  // a RuntimeWarning (an error under -W error)
    if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 1) != 0) throw py::error_already_set();
  }
};

// One run (tumble::Run): the world it was loaded with, its pipeline, the guard that measures it
// (and, unless guard=False, stops it with tumble.SimulationError), and the optional outputs.
class Simulation {
 public:
  Simulation(const Scene& scene, const std::string& pipeline, int threads, const py::object& resume, bool guard,
             std::uint64_t guardEvery)
      : m_run(scene) {
    if (guardEvery < 1) throw Error("guard_every must be at least 1");
    if (!resume.is_none()) m_run.resume(pathOf(resume));
    PipelineOptions po;
    po.threads = threads;
    RunChecks checks;
    checks.stop = guard;
    checks.every = guardEvery;
    m_run.load(makePipeline(backendFromString(pipeline), po), checks, &m_hooks);
    m_warning = m_run.resumeWarning();
    if (m_warning.empty()) m_warning = m_run.guard()->initialWarning();
    const std::string& dt = m_run.timeStepWarning();
    if (!dt.empty()) m_warning = dt + (m_warning.empty() ? "" : "; " + m_warning);
  }

  // Steps n times. Frames, thermo rows and the guard's checks fall on multiples of their intervals
  // (counted from the start of the run), as in tumble run, however the steps are split into
  // calls; the end of a call is checked on a copy of the guard, which changes nothing.
  void step(std::uint64_t n) {
    const auto lock = exclusive();
    if (n > kMaxStepsPerCall) throw Error("step: n = " + std::to_string(n) + " is more than 10^15 steps");
    m_run.advance(n);
  }

  py::dict bodies() const {
    const auto lock = exclusive();
    BodyState s;
    m_run.pipeline().readState(s);
    py::dict d;
    d["x"] = columns({&s.px, &s.py, &s.pz});
    d["v"] = columns({&s.vx, &s.vy, &s.vz});
    d["q"] = columns({&s.qw, &s.qx, &s.qy, &s.qz});
    d["l"] = columns({&s.lx, &s.ly, &s.lz});
    const World& world = m_run.world();
    std::vector<float> wx(s.size()), wy(s.size()), wz(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      const Vec3f w = angularVelocityOf(world, s, k);
      wx[k] = w.x, wy[k] = w.y, wz[k] = w.z;
    }
    d["omega"] = columns({&wx, &wy, &wz});
    d["mass"] = array1(world.bodyMass);
    std::vector<std::uint32_t> shape(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) shape[k] = m_run.pouring().shapeOf(k);
    d["shape"] = array1(shape);
    return d;
  }

  py::dict particles() const {
    const auto lock = exclusive();
    BodyState s;
    m_run.pipeline().readState(s);
    const World& world = m_run.world();
    const std::size_t n = world.numParticles();
    py::array_t<float> x({static_cast<py::ssize_t>(n), py::ssize_t{3}});
    py::array_t<float> v({static_cast<py::ssize_t>(n), py::ssize_t{3}});
    float* out = x.mutable_data();
    float* vout = v.mutable_data();
    for (std::uint32_t b = 0; b < world.numBodies(); ++b) {
      const Mat3f R = rotationMatrix(Quatf{s.qw[b], s.qx[b], s.qy[b], s.qz[b]});
      const Vec3f X{s.px[b], s.py[b], s.pz[b]}, V{s.vx[b], s.vy[b], s.vz[b]};
      const Vec3f omega = angularVelocityOf(world, s, b);
      for (std::uint32_t i = world.first[b], e = i + world.numParticlesOf[b]; i < e; ++i) {
        // x = X + R(Q) u and v = V + Ω × R(Q) u, the pipelines' own expressions
        const Vec3f u{world.ux[i], world.uy[i], world.uz[i]};
        const Vec3f p = particlePosition(X, R, u);
        const Vec3f pv = pointVelocity(V, omega, mul(R, u));
        out[3 * i] = p.x, out[3 * i + 1] = p.y, out[3 * i + 2] = p.z;
        vout[3 * i] = pv.x, vout[3 * i + 1] = pv.y, vout[3 * i + 2] = pv.z;
      }
    }
    py::dict d;
    d["x"] = x;
    d["v"] = v;
    d["radius"] = array1(world.radius);
    d["body"] = array1(world.body);
    d["mass"] = array1(world.mass);
    d["elasticity"] = array1(world.elasticity);
    return d;
  }

  py::object contacts(bool forces) const {
    const auto lock = exclusive();
    if (!forces) return pairArray(m_run.pipeline().pairs());
    return contactForceDict(debugOfLastStep("contacts(forces=True)").contactForces);
  }

  // Pipeline::readDebug() of the last step, which capture_forces must have kept (`what` names the call).
  ParticleDebug debugOfLastStep(const std::string& what) const {
    if (!m_run.capturingForces())
      throw Error(what + ": set capture_forces = True first; the steps after that keep their forces");
    ParticleDebug dbg;
    try {
      m_run.pipeline().readDebug(dbg);
    } catch (const Error&) {
      throw Error(what + ": no step has run since capture_forces was set (or since set_bodies or set_parameters); "
                  "step first");
    }
    return dbg;
  }

  // The quantities now, measured on a copy of the guard (the run's own checks stay where they fall).
  py::dict thermo() const {
    const auto lock = exclusive();
    return thermoDict(m_run.sampleNow());
  }

  void checkpoint(const py::object& path) {
    const auto lock = exclusive();
    const std::string p = pathOf(path);
    refuseOpenOutput(p, "checkpoint");
    m_run.writeCheckpoint(p);
  }

  void record(const py::object& pathArg, std::optional<int> perFrame, bool debug, bool contacts) {
    const auto lock = exclusive();
    RecordSettings rs;
    rs.path = pathOf(pathArg);
    rs.stepsPerFrame = perFrame.value_or(m_run.world().params.stepsPerFrame);
    rs.debug = debug;
    rs.contactForces = contacts;
    if (m_run.thermoOn() && sameFile(rs.path, m_run.thermo()->path()))
      throw Error("record: " + rs.path + " is the time series' file (write_thermo): name another file");
    m_run.record(rs);  // when the new file cannot be opened, the recording under way goes on
  }

  void closeRecording() {
    const auto lock = exclusive();
    m_run.closeRecording();
  }

  void writeThermo(const py::object& pathArg, std::optional<std::uint64_t> everyArg,
                   std::optional<bool> energyBalanceArg) {
    const auto lock = exclusive();
    const std::string path = pathOf(pathArg);
    const std::uint64_t every = everyArg.value_or(m_run.world().params.thermoEvery);
    if (every < 1) throw Error("every must be at least 1");
    if (m_run.recordingOn() && sameFile(path, m_run.recording()->path()))
      throw Error("write_thermo: " + path + " is the recording's file (record): name another file");
    // a failure keeps the series under way
    m_run.writeThermo(path, every, energyBalanceArg.value_or(m_run.world().params.energyBalance));
  }

  void closeThermo() {
    const auto lock = exclusive();
    m_run.closeThermo();
  }

  void close() {
    const auto lock = exclusive();
    m_run.closeOutputs();
  }

  void setBodies(const py::object& bodies, const py::object& x, const py::object& v, const py::object& q,
                 const py::object& l, const py::object& omega) {
    const auto lock = exclusive();
    BodyChanges c;
    c.bodies = bodyIndices(bodies, m_run.world().numBodies());
    const std::size_t n = c.bodies.size();
    c.x = rowsOf<Vec3f, 3>(x, n, "x");
    c.v = rowsOf<Vec3f, 3>(v, n, "v");
    c.q = rowsOf<Quatf, 4>(q, n, "q");
    c.l = rowsOf<Vec3f, 3>(l, n, "l");
    c.omega = rowsOf<Vec3f, 3>(omega, n, "omega");
    m_run.setBodies(c);
    m_warning = m_run.guard() ? m_run.guard()->initialWarning() : std::string();
  }

  void setParameters(const py::dict& changes) {
    std::vector<std::pair<std::string, double>> c;
    for (const auto& [key, value] : changes) {
      const std::string k = py::str(key);
      const auto notANumber = [&] {
        return Error("set_parameters: " + k + " = " + std::string(py::repr(value)) + ": expected a number");
      };
      if (py::isinstance<py::bool_>(value)) throw notANumber();  // True is not 1.0 here
      try {
        c.emplace_back(k, value.cast<double>());
      } catch (const py::cast_error&) {
        throw notANumber();
      }
    }
    const auto lock = exclusive();
    m_run.setParameters(c);
    m_warning = m_run.timeStepWarning();
    const std::string pressed = m_run.guard() ? m_run.guard()->initialWarning() : std::string();
    if (!pressed.empty()) m_warning += (m_warning.empty() ? "" : "; ") + pressed;
  }

  bool captureForces() const { return m_run.capturingForces(); }
  void setCaptureForces(bool on) {
    const auto lock = exclusive();
    m_run.captureForces(on);
  }

  // The five forces of the last step per particle (Pipeline::readDebug).
  py::dict forces() const {
    const auto lock = exclusive();
    const ParticleDebug dbg = debugOfLastStep("forces()");
    py::dict d;
    const std::size_t n = m_run.world().numParticles();
    for (int c = 0; c < 5; ++c) {
      py::array_t<float> a({static_cast<py::ssize_t>(n), py::ssize_t{3}});
      std::copy(dbg.force[c].begin(), dbg.force[c].end(), a.mutable_data());
      d[kDebugForceNames[c]] = a;
    }
    return d;
  }

  std::uint64_t stepCount() const { return m_run.pipeline().stepCount(); }
  double time() const { return m_run.pipeline().time(); }
  std::uint32_t pulls() const { return m_run.pipeline().pulls(); }
  void setPulls(std::uint32_t mask) {
    const auto lock = exclusive();
    if (mask & ~std::uint32_t{kPullX | kPullY | kPullSwirl})
      throw Error("pulls: unknown bits in " + std::to_string(mask) + " (PULL_X = 1, PULL_Y = 2, PULL_SWIRL = 4)");
    m_run.pipeline().setPulls(mask);
  }
  std::vector<std::string> shapeNames() const {
    std::vector<std::string> names;
    for (const ShapeDef& sh : m_run.scene().shapes) names.push_back(sh.name);
    return names;
  }
  std::uint32_t numBodies() const { return m_run.world().numBodies(); }
  std::size_t bodiesToCome() const { return m_run.bodiesToCome(); }
  std::uint32_t numParticles() const { return m_run.world().numParticles(); }
  const std::string& warning() const { return m_warning; }
  std::string pipelineName() const { return toString(m_run.pipeline().backend()); }
  py::dict stats() const {
    const StepStats st = m_run.stats();
    py::dict d;
    d["steps"] = st.steps;
    d["rebuilds"] = st.numRebuilds;
    d["candidates"] = st.numCandidates;
    d["pairs"] = st.numPairs;
    d["skin"] = st.skin;
    d["cell_size"] = st.cellSize;
    d["seconds"] = st.totalSeconds();
    return d;
  }

 private:
  // One call at a time: step() lets go of the GIL, and another Python thread must not read or
  // change the pipeline meanwhile (it gets tumble.Error instead of a torn state).
  std::unique_lock<std::mutex> exclusive() const {
    std::unique_lock<std::mutex> lock(m_busy, std::try_to_lock);
    if (!lock.owns_lock())
      throw Error("this Simulation is in use by another thread (step() runs there); use one Simulation per thread");
    return lock;
  }

  void refuseOpenOutput(const std::string& path, const char* what) const {
    if ((m_run.recordingOn() && sameFile(path, m_run.recording()->path())) ||
        (m_run.thermoOn() && sameFile(path, m_run.thermo()->path())))
      throw Error(std::string(what) + ": " + path + " is a file this Simulation is writing (record, write_thermo)");
  }

  mutable std::mutex m_busy;
  PythonHooks m_hooks;
  Run m_run;
  std::string m_warning;
};

// A recording read one frame at a time (RecordingReader): the particle table once, each frame
// as NumPy arrays when asked, so that a long recording costs one frame of memory.
class RecordingFile {
 public:
  explicit RecordingFile(const py::object& path) : m_reader(std::make_unique<RecordingReader>(pathOf(path))) {}

  std::size_t size() const { return reader().numFrames(); }
  const RecordingInfo& info() const { return reader().info(); }

  // Frame k (negative: from the end) as a dict of arrays; IndexError beyond the frames.
  py::dict frame(std::int64_t index) {
    const std::int64_t n = static_cast<std::int64_t>(size());
    const std::int64_t k = index < 0 ? index + n : index;
    if (k < 0 || k >= n)
      throw py::index_error("frame " + std::to_string(index) + " of a recording of " + std::to_string(n) + " frames");
    RecordingReader& r = reader();
    r.readFrame(static_cast<std::size_t>(k), m_frame);
    const RecordedFrame& f = m_frame;
    const Recording& table = r.header();
    const std::size_t np = table.particlesOf(f.numBodies());
    py::array_t<float> x({static_cast<py::ssize_t>(np), py::ssize_t{3}});
    float* out = x.mutable_data();
    for (std::size_t i = 0; i < np; ++i) {  // x = X + R(Q) u, as Simulation.particles()
      const std::uint32_t b = table.body[i];
      const Vec3f p = particlePosition(Vec3f{f.px[b], f.py[b], f.pz[b]},
                                       rotationMatrix(Quatf{f.qw[b], f.qx[b], f.qy[b], f.qz[b]}),
                                       Vec3f{table.ux[i], table.uy[i], table.uz[i]});
      out[3 * i] = p.x;
      out[3 * i + 1] = p.y;
      out[3 * i + 2] = p.z;
    }
    py::dict d;
    d["step"] = f.step;
    d["time"] = f.time;
    d["pulls"] = f.pulls;
    d["x"] = columns({&f.px, &f.py, &f.pz});
    d["q"] = columns({&f.qw, &f.qx, &f.qy, &f.qz});
    d["particles"] = x;
    if (info().debug) {
      d["v"] = triples(f.debug.v);
      py::dict forces;
      for (int c = 0; c < 5; ++c) forces[kDebugForceNames[c]] = triples(f.debug.force[c]);
      d["forces"] = forces;
      d["contacts"] = pairArray(f.debug.contacts);
    }
    if (info().contactForces) d["contact_forces"] = contactForceDict(f.debug.contactForces);
    return d;
  }

  // The particle table: radius, mass, elasticity, body (N,) and the offsets u (N,3).
  py::dict table() const {
    const Recording& t = reader().header();
    py::dict d;
    d["radius"] = array1(t.radius);
    d["mass"] = array1(t.mass);
    d["elasticity"] = array1(t.elasticity);
    d["body"] = array1(t.body);
    d["u"] = columns({&t.ux, &t.uy, &t.uz});
    return d;
  }

  void close() { m_reader.reset(); }

 private:
  // 3 floats per row as an (n, 3) array.
  static py::array_t<float> triples(const std::vector<float>& v) {
    py::array_t<float> a({static_cast<py::ssize_t>(v.size() / 3), py::ssize_t{3}});
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
  }
  RecordingReader& reader() const {
    if (!m_reader) throw Error("this Recording is closed");
    return *m_reader;
  }

  std::unique_ptr<RecordingReader> m_reader;
  RecordedFrame m_frame;  // reused: readFrame() keeps its storage
};

}  // namespace

PYBIND11_MODULE(_tumble, m) {
  m.doc() = "tumble: rigid bodies made of spheres (the compiled part; import tumble)";
  // pybind11 before 2.12 reads NumPy 2's array descriptors at the wrong offsets: every array it
  // makes repeats its first element (a pip-installed NumPy 2 beside Debian 12's pybind11 2.10
  // gave particles()["radius"] = [0.1, 0.1, 0.1] for [0.1, 0.06, 0.06], silently). Refused here.
#if PYBIND11_VERSION_MAJOR < 3 && PYBIND11_VERSION_MINOR < 12
  {
    const std::string numpy = py::str(py::module_::import("numpy").attr("__version__"));
    if (!numpy.empty() && numpy[0] >= '2' && numpy[0] <= '9' && numpy[1] == '.')
      throw py::import_error("tumble was built with pybind11 " + std::to_string(PYBIND11_VERSION_MAJOR) + "." +
                             std::to_string(PYBIND11_VERSION_MINOR) + ", which reads the arrays of NumPy " + numpy +
                             " wrong; use NumPy 1 (Debian 12's python3-numpy: remove a NumPy 2 installed by pip, e.g. "
                             "pip uninstall numpy, or run in a virtual environment with numpy<2), or build tumble with "
                             "pybind11 2.12 or later");
  }
#endif
  m.attr("__version__") = TUMBLE_VERSION_STRING;
  m.attr("PULL_X") = std::uint32_t{kPullX};
  m.attr("PULL_Y") = std::uint32_t{kPullY};
  m.attr("PULL_SWIRL") = std::uint32_t{kPullSwirl};

  // Translators run newest first: the base class is registered before the classes derived from it.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<InputError> inputError(m, "InputError", error.ptr());
  static py::exception<SimulationError> simulationError(m, "SimulationError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(inputError.ptr(), e.what());
    } catch (const SimulationError& e) {
      PyErr_SetString(simulationError.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<Scene>(m, "Scene", "A scene: bodies, shapes and parameters (docs/scenes.md)")
      .def_static(
          "load",
          [](const py::object& path, const std::vector<std::string>& set) {
            return readSceneFile(pathOf(path), set, OverrideSource::Python);
          },
          py::arg("path"), py::arg("set") = std::vector<std::string>{},
          "Reads a scene file; set: overrides as tumble run --set takes them, 'SECTION.KEY=VALUE', "
          "'wall[1].friction=0.1' or 'material.glass.friction=0.3'")
      .def_static(
          "parse",
          [](const std::string& text, const std::string& name, const std::vector<std::string>& set,
             const py::object& base) {
            return parseScene(text, name, set, OverrideSource::Python, base.is_none() ? std::string() : pathOf(base));
          },
          py::arg("text"), py::arg("name") = "<python>", py::arg("set") = std::vector<std::string>{},
          py::arg("base") = py::none(),
          "Parses a scene from TOML text; name: what error messages call it; base: the folder relative mesh "
          "files are found from (default: the folder of name, the working directory for '<python>')")
      .def_property_readonly("name", [](const Scene& s) { return s.name; })
      .def_property_readonly("dt", [](const Scene& s) { return s.dt; })
      .def_property_readonly("steps", [](const Scene& s) { return s.steps; })
      .def_property_readonly(
          "num_bodies", [](const Scene& s) { return s.bodies.size() + s.pourBodies.size(); },
          "Bodies of the run once its [[pour]]s are in (those at the start: num_bodies - pour_bodies)")
      .def_property_readonly(
          "pour_bodies", [](const Scene& s) { return s.pourBodies.size(); }, "Bodies its [[pour]]s bring in")
      .def("__repr__", [](const Scene& s) {
        char dt[32];
        std::snprintf(dt, sizeof dt, "%g", static_cast<double>(s.dt));
        return "<tumble.Scene '" + s.name + "': " + std::to_string(s.bodies.size() + s.pourBodies.size()) +
               " bodies, dt " + dt + " s, " + std::to_string(s.steps) + " steps>";
      });

  py::class_<Simulation>(m, "Simulation", "A run of a scene on one pipeline (docs/python.md)")
      .def(py::init<const Scene&, const std::string&, int, const py::object&, bool, std::uint64_t>(),
           py::arg("scene"), py::arg("pipeline") = "cpu", py::arg("threads") = 0, py::arg("resume") = py::none(),
           py::arg("guard") = true, py::arg("guard_every") = kDefaultGuardEvery)
      .def("step", &Simulation::step, py::arg("n") = 1,
           "Advances n steps (raises tumble.SimulationError when a guard trips, unless guard=False)")
      .def("bodies", &Simulation::bodies,
           "Body state: x (B,3), v (B,3), q (B,4) w,x,y,z, l (B,3), omega (B,3), mass (B,), shape (B,) index into "
           "shape_names")
      .def("particles", &Simulation::particles,
           "Particles: x (N,3) world positions, v (N,3) velocities, radius, body, mass, elasticity (N,)")
      .def("set_bodies", &Simulation::setBodies, py::arg("bodies") = py::none(), py::arg("x") = py::none(),
           py::arg("v") = py::none(), py::arg("q") = py::none(), py::arg("l") = py::none(),
           py::arg("omega") = py::none(),
           "Between steps: sets the centre x, velocity v, orientation q, angular momentum l or angular velocity "
           "omega of the bodies named (default: all), a row each; the next step goes on from there")
      .def("set_parameters", &Simulation::setParameters, py::arg("changes"),
           "Between steps: changes contact parameters, {'ground.friction': 0.3, ...} (the scene file's keys); "
           "what cannot change raises tumble.Error naming it")
      .def_property("capture_forces", &Simulation::captureForces, &Simulation::setCaptureForces,
                    "Keep the forces of each step for forces() (off by default; changes no result)")
      .def("forces", &Simulation::forces,
           "The forces of the last step on each particle: repulsion, damping, shear, ground, friction (N,3) each")
      .def("contacts", &Simulation::contacts, py::arg("forces") = false,
           "The touching pairs (i, j), i < j, of the last step: (C,2) uint32; forces=True (needs capture_forces): a "
           "dict of those pairs with the force on i from j split along the normal and across it, normal and "
           "tangential (C,3), and the overlap (C,)")
      .def("thermo", &Simulation::thermo, "The time-series quantities now (docs/thermo.md) as a dict")
      .def("checkpoint", &Simulation::checkpoint, py::arg("path"), "Writes a checkpoint (resume with resume=path)")
      .def("record", &Simulation::record, py::arg("path"), py::arg("steps_per_frame") = py::none(),
           py::arg("debug") = false, py::arg("contacts") = false,
           "Starts a recording: a frame every steps_per_frame steps (default: the scene's), counted from the start "
           "of the run; debug: velocities, the five forces and the contacts in each frame; contacts: the contacts "
           "with their forces (frame()['contact_forces'])")
      .def("close_recording", &Simulation::closeRecording)
      .def("write_thermo", &Simulation::writeThermo, py::arg("path"), py::arg("every") = py::none(),
           py::arg("energy_balance") = py::none(),
           "Writes the time series to a CSV file, a row now and every `every` steps (default: the scene's "
           "thermo_every), as tumble run --thermo; energy_balance: with the energy tally's columns (default: "
           "the scene's [output] energy_balance), as --energy-balance")
      .def("close_thermo", &Simulation::closeThermo)
      .def("close", &Simulation::close, "Finishes the recording and the time series")
      .def("__enter__", [](Simulation& s) -> Simulation& { return s; }, py::return_value_policy::reference)
      .def("__exit__", [](Simulation& s, py::args) { s.close(); })
      .def_property_readonly("step_count", &Simulation::stepCount, "Steps since the start of the run")
      .def_property_readonly("time", &Simulation::time, "Simulated time (s)")
      .def_property("pulls", &Simulation::pulls, &Simulation::setPulls, "PULL_X | PULL_Y | PULL_SWIRL bits on")
      .def_property_readonly("shape_names", &Simulation::shapeNames,
                             "The scene's shapes by index (bodies()['shape']); a scaled one of a [[fill]] or "
                             "[[pour]] is named 'NAME x FACTOR'")
      .def_property_readonly("num_bodies", &Simulation::numBodies)
      .def_property_readonly(
          "bodies_to_come", &Simulation::bodiesToCome,
          "Bodies of the [[pour]]s yet to enter (a pour that fell behind warns once: RuntimeWarning)")
      .def_property_readonly("num_particles", &Simulation::numParticles)
      .def_property_readonly("pipeline", &Simulation::pipelineName)
      .def_property_readonly("warning", &Simulation::warning, "A warning about the start (pressed bodies), or ''")
      .def("stats", &Simulation::stats, "Detection counters and the time spent stepping");

  py::class_<RecordingFile>(m, "Recording", "A recording read frame by frame (docs/python.md#recordings)")
      .def(py::init<const py::object&>(), py::arg("path"))
      .def("__len__", &RecordingFile::size)
      .def("__getitem__", &RecordingFile::frame, py::arg("k"),
           "Frame k as a dict: step, time, pulls, x (B,3), q (B,4), particles (N,3); a debug recording's also v, "
           "forces, contacts")
      .def("table", &RecordingFile::table, "The particle table: radius, mass, elasticity, body (N,), u (N,3)")
      .def("close", &RecordingFile::close)
      .def("__enter__", [](RecordingFile& r) -> RecordingFile& { return r; }, py::return_value_policy::reference)
      .def("__exit__", [](RecordingFile& r, py::args) { r.close(); })
      .def_property_readonly("version", [](const RecordingFile& r) { return r.info().version; })
      .def_property_readonly("num_particles", [](const RecordingFile& r) { return r.info().numParticles; })
      .def_property_readonly("num_bodies", [](const RecordingFile& r) { return r.info().numBodies; })
      .def_property_readonly("steps_per_frame", [](const RecordingFile& r) { return r.info().stepsPerFrame; })
      .def_property_readonly("dt", [](const RecordingFile& r) { return r.info().dt; })
      .def_property_readonly("fps", [](const RecordingFile& r) { return r.info().fps; })
      .def_property_readonly("debug", [](const RecordingFile& r) { return r.info().debug; })
      .def_property_readonly("grows", [](const RecordingFile& r) { return r.info().grows; })
      .def_property_readonly("contact_forces", [](const RecordingFile& r) { return r.info().contactForces; },
                             "Each frame holds its contacts with their forces (frame(k)['contact_forces'])")
      .def_property_readonly("ground",
                             [](const RecordingFile& r) -> py::object {
                               if (!r.info().groundEnabled) return py::none();
                               return py::float_(r.info().groundHeight);
                             },
                             "The ground's height, or None without a ground")
      .def_property_readonly("gravity",
                             [](const RecordingFile& r) {
                               const Vec3f g = r.info().gravity;
                               return py::make_tuple(g.x, g.y, g.z);
                             })
      .def_property_readonly("scene_name", [](const RecordingFile& r) { return r.info().sceneName; });

  m.def("fields", &fieldsOf, py::arg("path"), py::arg("width"), py::arg("grid") = py::none(),
        py::arg("axis") = py::none(), py::arg("box") = py::none(), py::arg("first") = 0, py::arg("last") = -1,
        py::arg("every") = 1, py::arg("area") = py::none(),
        "Continuum fields of a recording by coarse-graining (docs/fields.md), as tumble fields: width (the "
        "kernel's standard deviation, m), grid (nx, ny, nz), or (n,) with axis 'x'/'y'/'z' for a profile; box "
        "(xmin, ymin, zmin, xmax, ymax, zmax; default the particles' bounds); area: a profile's fields per this area "
        "instead of the box's cross-section; frames first..last (negative from the end), every k-th. Returns a dict: points (P,3), shape, density, packing_fraction (P,), and with "
        "velocities (a debug recording) momentum, velocity (P,3), temperature (P,), kinetic_stress (P,3,3); with "
        "contact forces contact_stress (P,3,3); stresses positive in compression");
  m.def(
      "find_pairs",
      [](const py::array_t<float, py::array::c_style | py::array::forcecast>& x,
         const py::array_t<float, py::array::c_style | py::array::forcecast>& radius,
         const py::array& body, const std::string& pipeline, int threads) {
        if (x.ndim() != 2 || x.shape(1) != 3) throw InputError("find_pairs", 0, "x must have shape (N, 3)");
        const std::size_t n = static_cast<std::size_t>(x.shape(0));
        ParticleCloud cloud;
        for (std::size_t i = 0; i < n; ++i) {
          cloud.x.push_back(x.data()[3 * i]);
          cloud.y.push_back(x.data()[3 * i + 1]);
          cloud.z.push_back(x.data()[3 * i + 2]);
        }
        cloud.r = floatColumn(radius, n, "radius");
        if (body.ndim() != 1 || static_cast<std::size_t>(body.shape(0)) != n)
          throw InputError("find_pairs", 0, "body: expected " + std::to_string(n) + " values in one dimension");
        const char kind = body.dtype().kind();
        if (kind != 'i' && kind != 'u' && n > 0)
          throw InputError("find_pairs", 0, "body: expected whole numbers (an integer array), got dtype " +
                                                std::string(py::str(body.dtype())));
        const auto ids = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(body);
        if (!ids && n > 0) throw InputError("find_pairs", 0, "body: ids beyond 64 bits");
        for (std::size_t i = 0; i < n; ++i) {
          const std::int64_t b = ids.data()[i];
          if (b < 0 || b > std::int64_t{0xffffffff})
            throw InputError("find_pairs", 0, "body[" + std::to_string(i) + "] = " + std::to_string(b) +
                                                  ": expected 0 to 2^32 - 1");
          cloud.body.push_back(static_cast<std::uint32_t>(b));
        }
        for (std::size_t i = 0; i < n; ++i) {
          if (!std::isfinite(cloud.x[i]) || !std::isfinite(cloud.y[i]) || !std::isfinite(cloud.z[i]))
            throw InputError("find_pairs", 0, "x[" + std::to_string(i) + "] is not finite");
          // The range the CSV of `tumble pairs` is held to (exact_range.hpp); a radius <= 0 is
          // the pipeline's own message.
          if (cloud.r[i] > 0.0f)
            if (const std::string why = sphereOutOfRange(cloud.x[i], cloud.y[i], cloud.z[i], cloud.r[i]); !why.empty())
              throw InputError("find_pairs", 0, "particle " + std::to_string(i) + ": " + why);
        }
        try {
          checkCloud(cloud);
        } catch (const InputError&) {
          throw;
        } catch (const Error& e) {
          throw InputError("find_pairs", 0, e.what());
        }
        PipelineOptions po;
        po.threads = threads;
        auto p = makePipeline(backendFromString(pipeline), po);
        std::vector<Pair> pairs;
        {
          py::gil_scoped_release release;
          pairs = p->findPairs(cloud, BroadphaseParams{});
        }
        return pairArray(pairs);
      },
      py::arg("x"), py::arg("radius"), py::arg("body"), py::arg("pipeline") = "cpu", py::arg("threads") = 0,
      "The overlapping pairs (i, j), i < j, of particles of different bodies, sorted, as tumble pairs finds them");
}
