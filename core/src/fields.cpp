// SPDX-License-Identifier: MIT
// Coarse-grained continuum fields (fields.hpp, docs/fields.md).
//
// Design notes
// - Serial and in a fixed order (particles, then contacts, in the frame's order; frames in the
//   recording's order), so that the fields are the same bits on any machine and thread count.
// - Each frame is coarse-grained on its own (its velocity field first, then the fluctuations
//   about it for the kinetic stress) and the frames' fields are averaged; the velocity and the
//   temperature of the average come from the averaged momentum, density and kinetic stress.
// - The contact stress's line integral ∫₀¹ φ(r − x_i + s l) ds is taken by 4-point
//   Gauss–Legendre quadrature on pieces of the branch no longer than half a width (one piece for
//   a branch up to w/2; a reviewer measured 5 × 10⁻⁴ for a single piece of 2w, 8 % for one of 8w).
// - A profile leaves out the particles (and the contacts of the particles i) outside the box's
//   cross-section: its fields are per that area (or FieldGrid::area).
#include "tumble/fields.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "tumble/error.hpp"
#include "tumble/kernels/integrate.hpp"
#include "vtk_xml.hpp"

namespace tumble {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kMaxPoints = std::size_t{1} << 22;
// 4-point Gauss–Legendre on [0, 1]: nodes ½ (1 ± t) and weights ½ w of those on [−1, 1].
constexpr double kGaussT[2] = {0.33998104358485626, 0.86113631159405258};
constexpr double kGaussW[2] = {0.65214515486254614, 0.34785484513745386};

bool finite3(const std::array<double, 3>& a) {
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

}  // namespace

double FieldGrid::at(int a, int k) const {
  if (points(a) == 1 && a != axis && axis >= 0) return 0.5 * (lo[a] + hi[a]);
  return lo[a] + (k + 0.5) * (hi[a] - lo[a]) / n[a];
}

CoarseGraining::CoarseGraining(const FieldGrid& grid, double width) {
  if (!(width > 0.0) || !std::isfinite(width))
    throw Error("coarse-graining: the width must be a positive number (got " + std::to_string(width) + ")");
  if (grid.axis < -1 || grid.axis > 2) throw Error("coarse-graining: the axis must be x, y or z");
  if (!finite3(grid.lo) || !finite3(grid.hi)) throw Error("coarse-graining: the box is not finite");
  std::size_t points = 1;
  for (int a = 0; a < 3; ++a) {
    if (grid.points(a) < 1) throw Error("coarse-graining: every axis needs at least one point");
    const bool across = grid.axis >= 0 && a != grid.axis;
    if (!(grid.hi[a] > grid.lo[a]) && (grid.points(a) > 1 || across || grid.axis == a))
      throw Error("coarse-graining: the box is empty along " + std::string(1, "xyz"[a]) + " (" +
                  std::to_string(grid.lo[a]) + " to " + std::to_string(grid.hi[a]) + ")");
    points *= std::size_t(grid.points(a));
    if (points > kMaxPoints)
      throw Error("coarse-graining: more than " + std::to_string(kMaxPoints) + " points; use a coarser grid");
  }
  m_sum.grid = grid;
  m_sum.width = width;
  m_cut = std::sqrt(12.0) * width;  // Lucy's support radius c: ⟨x²⟩ = c² / 12 along each axis
  m_norm3 = 105.0 / (16.0 * kPi * m_cut * m_cut * m_cut);
  m_area = 1.0;
  if (grid.axis >= 0)
    for (int a = 0; a < 3; ++a)
      if (a != grid.axis) m_area *= grid.hi[a] - grid.lo[a];
  if (grid.axis >= 0 && grid.area > 0.0) m_area = grid.area;
  if (!(m_area > 0.0) || !std::isfinite(m_area)) throw Error("coarse-graining: the profile's area must be a positive number");
  m_norm1 = 105.0 / (8.0 * m_cut * m_area);
  const std::size_t p = m_sum.grid.size();
  m_sum.density.assign(p, 0.0);
  m_sum.packing.assign(p, 0.0);
}

// Whether a point is in the box across a profile's axis (a 3-D grid: every point is).
bool CoarseGraining::inCrossSection(const double c[3]) const {
  const FieldGrid& g = m_sum.grid;
  if (g.axis < 0) return true;
  for (int a = 0; a < 3; ++a)
    if (a != g.axis && !(c[a] >= g.lo[a] && c[a] <= g.hi[a])) return false;
  return true;
}

// φ(d), d = r − x: Lucy's kernel 105 / (16 π c³) (1 + 3t)(1 − t)³, t = |d| / c < 1; along a
// profile's axis its marginal (the 3-D kernel integrated over the plane across the axis),
// 105 / (8 c) (1/10 − t²/2 + 3t⁴/2 − 8t⁵/5 + t⁶/2), t = |d_axis| / c, over the cross-section's area.
double CoarseGraining::kernel(const double d[3]) const {
  const int a = m_sum.grid.axis;
  if (a >= 0) {
    const double t = std::fabs(d[a]) / m_cut;
    if (!(t < 1.0)) return 0.0;
    const double t2 = t * t;
    return m_norm1 * (0.1 + t2 * (-0.5 + t2 * (1.5 + t * (-1.6 + 0.5 * t))));
  }
  const double t = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / m_cut;
  if (!(t < 1.0)) return 0.0;
  const double u = 1.0 - t;
  return m_norm3 * (1.0 + 3.0 * t) * u * u * u;
}

// Calls f(point index, r) for the points whose distance to the box [lo, hi] is under the
// cut-off on every axis the kernel reads (its candidates).
template <class F>
void CoarseGraining::forPointsNear(const double lo[3], const double hi[3], F&& f) const {
  const FieldGrid& g = m_sum.grid;
  int from[3], to[3];
  for (int a = 0; a < 3; ++a) {
    from[a] = 0;
    to[a] = g.points(a);
    if (g.points(a) == 1 || (g.axis >= 0 && a != g.axis)) continue;
    const double h = (g.hi[a] - g.lo[a]) / g.n[a];
    const double first = std::ceil((lo[a] - m_cut - g.lo[a]) / h - 0.5);
    const double last = std::floor((hi[a] + m_cut - g.lo[a]) / h - 0.5);
    from[a] = static_cast<int>(std::clamp(first, 0.0, double(g.n[a])));
    to[a] = static_cast<int>(std::clamp(last + 1.0, 0.0, double(g.n[a])));
  }
  const int nx = g.points(0), ny = g.points(1);
  for (int z = from[2]; z < to[2]; ++z)
    for (int y = from[1]; y < to[1]; ++y)
      for (int x = from[0]; x < to[0]; ++x) {
        const double r[3] = {g.at(0, x), g.at(1, y), g.at(2, z)};
        f(std::size_t(x) + std::size_t(nx) * (std::size_t(y) + std::size_t(ny) * std::size_t(z)), r);
      }
}

void CoarseGraining::add(const FieldFrame& frame) {
  const bool velocities = frame.v != nullptr;
  if (m_sum.frames == 0) {
    m_sum.velocities = velocities;
    m_sum.contacts = frame.contacts;
    const std::size_t p = m_sum.grid.size();
    if (velocities) {
      m_sum.momentum.assign(3 * p, 0.0);
      m_sum.kineticStress.assign(6 * p, 0.0);
    }
    if (frame.contacts) m_sum.contactStress.assign(6 * p, 0.0);
  } else if (velocities != m_sum.velocities || frame.contacts != m_sum.contacts) {
    throw Error("coarse-graining: a frame with" + std::string(velocities != m_sum.velocities ? "" : "out") +
                " velocities or contacts where the first had" +
                std::string(velocities != m_sum.velocities ? "out" : "") + " them");
  }
  const std::size_t p = m_sum.grid.size();
  // This frame's density, momentum and Σ m v ⊗ v φ (for σᵏ = Σ m v v φ − p ⊗ p / ρ).
  std::vector<double> rho(p, 0.0), mom(velocities ? 3 * p : 0, 0.0), m2(velocities ? 6 * p : 0, 0.0);
  for (std::size_t i = 0; i < frame.n; ++i) {
    const float* xi = frame.x + 3 * i;
    const double c[3] = {xi[0], xi[1], xi[2]};
    if (!inCrossSection(c)) continue;
    const double m = frame.mass[i], r = frame.radius[i];
    const double vol = (4.0 / 3.0) * kPi * r * r * r;
    const float* vi = velocities ? frame.v + 3 * i : nullptr;
    forPointsNear(c, c, [&](std::size_t k, const double at[3]) {
      const double d[3] = {at[0] - c[0], at[1] - c[1], at[2] - c[2]};
      const double phi = kernel(d);
      if (phi == 0.0) return;
      rho[k] += m * phi;
      m_sum.packing[k] += vol * phi;
      if (vi == nullptr) return;
      const double v[3] = {vi[0], vi[1], vi[2]};
      for (int a = 0; a < 3; ++a) mom[3 * k + a] += m * v[a] * phi;
      const double vv[6] = {v[0] * v[0], v[1] * v[1], v[2] * v[2], v[0] * v[1], v[0] * v[2], v[1] * v[2]};
      for (int a = 0; a < 6; ++a) m2[6 * k + a] += m * vv[a] * phi;
    });
  }
  for (std::size_t k = 0; k < p; ++k) {
    m_sum.density[k] += rho[k];
    if (!velocities) continue;
    const double* q = &mom[3 * k];
    const double pp[6] = {q[0] * q[0], q[1] * q[1], q[2] * q[2], q[0] * q[1], q[0] * q[2], q[1] * q[2]};
    for (int a = 0; a < 3; ++a) m_sum.momentum[3 * k + a] += q[a];
    for (int a = 0; a < 6; ++a) m_sum.kineticStress[6 * k + a] += m2[6 * k + a] - (rho[k] > 0.0 ? pp[a] / rho[k] : 0.0);
  }
  for (std::size_t c = 0; c < (frame.contacts ? frame.numContacts : 0); ++c) {
    const ContactForce& k = frame.contact[c];
    const float* xi = frame.x + 3 * std::size_t(k.i);
    if (!inCrossSection(std::array<double, 3>{xi[0], xi[1], xi[2]}.data())) continue;
    // The branch l = x_i − x_j (across a periodic boundary, to j's image beside i).
    const std::array<double, 3> l = contactBranch(k, frame.radius[k.i], frame.radius[k.j]);
    const Vec3f fn = k.normal();
    const double f[3] = {double(fn.x) + k.tangential.x, double(fn.y) + k.tangential.y, double(fn.z) + k.tangential.z};
    const double fl[6] = {f[0] * l[0], f[1] * l[1], f[2] * l[2], 0.5 * (f[0] * l[1] + f[1] * l[0]),
                          0.5 * (f[0] * l[2] + f[2] * l[0]), 0.5 * (f[1] * l[2] + f[2] * l[1])};
    const double a[3] = {xi[0], xi[1], xi[2]};
    const double b[3] = {a[0] - l[0], a[1] - l[1], a[2] - l[2]};  // x_j's image next to x_i
    const double lo[3] = {std::min(a[0], b[0]), std::min(a[1], b[1]), std::min(a[2], b[2])};
    const double hi[3] = {std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])};
    // Pieces no longer than half a width (a branch longer than that, a width under a radius):
    // 4-point Gauss–Legendre on each, within about 10⁻⁸ of the integral.
    const double length = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    const int pieces = std::max(1, int(std::ceil(2.0 * length / m_sum.width)));
    forPointsNear(lo, hi, [&](std::size_t point, const double at[3]) {
      double integral = 0.0;  // ∫₀¹ φ(r − x_i + s l) ds
      for (int piece = 0; piece < pieces; ++piece)
        for (int q = 0; q < 4; ++q) {
          const double s = (piece + 0.5 * (1.0 + (q < 2 ? -kGaussT[q] : kGaussT[q - 2]))) / pieces;
          const double d[3] = {at[0] - a[0] + s * l[0], at[1] - a[1] + s * l[1], at[2] - a[2] + s * l[2]};
          integral += 0.5 * kGaussW[q < 2 ? q : q - 2] * kernel(d) / pieces;
        }
      if (integral == 0.0) return;
      for (int e = 0; e < 6; ++e) m_sum.contactStress[6 * point + e] += fl[e] * integral;
    });
  }
  ++m_sum.frames;
}

Fields CoarseGraining::result() const {
  Fields out = m_sum;
  const double n = m_sum.frames > 0 ? double(m_sum.frames) : 1.0;
  for (std::vector<double>* v : {&out.density, &out.packing, &out.momentum, &out.kineticStress, &out.contactStress})
    for (double& x : *v) x /= n;
  const std::size_t p = out.grid.size();
  if (out.velocities) {
    out.velocity.assign(3 * p, 0.0);
    out.temperature.assign(p, 0.0);
    for (std::size_t k = 0; k < p; ++k) {
      if (!(out.density[k] > 0.0)) continue;
      for (int a = 0; a < 3; ++a) out.velocity[3 * k + a] = out.momentum[3 * k + a] / out.density[k];
      const double* s = &out.kineticStress[6 * k];
      out.temperature[k] = (s[0] + s[1] + s[2]) / (3.0 * out.density[k]);
    }
  }
  return out;
}

Fields coarseGrainRecording(RecordingReader& reader, const FieldOptions& o) {
  if (o.every < 1) throw Error("fields: every must be at least 1");
  const std::size_t frames = reader.numFrames();
  if (frames == 0 || o.first >= frames || o.last < o.first)
    throw Error("fields: no frame chosen (the recording has " + std::to_string(frames) + ", frames " +
                std::to_string(o.first) + " to " + (o.last == SIZE_MAX ? "the last" : std::to_string(o.last)) + ")");
  const std::size_t last = std::min(o.last, frames - 1);
  const Recording& table = reader.header();
  RecordedFrame f;
  std::vector<float> x;
  const auto positions = [&](std::size_t k) {
    reader.readFrame(k, f);
    const std::size_t n = table.particlesOf(f.numBodies());
    x.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t b = table.body[i];
      const Vec3f p = particlePosition(Vec3f{f.px[b], f.py[b], f.pz[b]},
                                       rotationMatrix(Quatf{f.qw[b], f.qx[b], f.qy[b], f.qz[b]}),
                                       Vec3f{table.ux[i], table.uy[i], table.uz[i]});
      x[3 * i] = p.x, x[3 * i + 1] = p.y, x[3 * i + 2] = p.z;
    }
    return n;
  };
  FieldGrid grid = o.grid;
  if (grid.lo == grid.hi) {  // the particles' bounds (their spheres) over the frames used
    grid.lo.fill(std::numeric_limits<double>::infinity());
    grid.hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t k = o.first; k <= last; k += o.every) {
      if (o.stop && o.stop()) return Fields{};  // (frames 0)
      const std::size_t n = positions(k);
      for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
          grid.lo[a] = std::min(grid.lo[a], double(x[3 * i + a]) - table.radius[i]);
          grid.hi[a] = std::max(grid.hi[a], double(x[3 * i + a]) + table.radius[i]);
        }
      if (last - k < o.every) break;  // (k + every would pass SIZE_MAX)
    }
  }
  // Cells about a width wide where no count is given, at most 256 per axis and kMaxPoints in all.
  for (double shrink = 1.0;;) {  // each pass widens the cells until they fit (at most a few passes)
    std::size_t points = 1;
    bool free = false;  // an axis whose count this may change
    for (int a = 0; a < 3; ++a) {
      if (o.grid.n[a] == 0) {
        grid.n[a] = int(std::clamp(std::ceil((grid.hi[a] - grid.lo[a]) / o.width / shrink), 1.0, 256.0));
        free = free || grid.n[a] > 1;
      }
      points *= std::size_t(grid.points(a));
    }
    if (points <= kMaxPoints || !free) break;  // (counts given that are too many: CoarseGraining says so)
    shrink *= std::cbrt(double(points) / double(kMaxPoints)) * 1.01;
  }
  CoarseGraining cg(grid, o.width);
  const std::size_t total = (last - o.first) / o.every + 1;
  std::size_t done = 0;
  for (std::size_t k = o.first; k <= last; k += o.every) {
    if (o.stop && o.stop()) break;
    const std::size_t n = positions(k);
    FieldFrame frame;
    frame.x = x.data();
    frame.v = reader.info().debug ? f.debug.v.data() : nullptr;
    frame.radius = table.radius.data();
    frame.mass = table.mass.data();
    frame.n = n;
    frame.contacts = reader.info().contactForces;
    frame.contact = f.debug.contactForces.data();
    frame.numContacts = f.debug.contactForces.size();
    cg.add(frame);
    ++done;
    if (o.progress) o.progress(done, total);
    if (last - k < o.every) break;  // (k + every would pass SIZE_MAX)
  }
  return done > 0 ? cg.result() : Fields{};  // (stopped before the first frame: frames 0)
}

std::string fieldsOutputProblem(const std::string& path) {
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : path;
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".vti" || ext == ".csv" ? std::string()
                                        : path + ": the fields are written as VTK image data (a name ending in .vti) "
                                                 "or CSV (.csv): name the file so";
}

void writeFields(const Fields& fields, const std::string& path) {
  const FieldGrid& g = fields.grid;
  const std::size_t p = g.size();
  struct Column {
    const char* name;
    const std::vector<double>* v;
    int components;
  };
  std::vector<Column> columns = {{"density", &fields.density, 1}, {"packing_fraction", &fields.packing, 1}};
  if (fields.velocities) {
    columns.push_back({"momentum", &fields.momentum, 3});
    columns.push_back({"velocity", &fields.velocity, 3});
    columns.push_back({"temperature", &fields.temperature, 1});
    columns.push_back({"kinetic_stress", &fields.kineticStress, 6});
  }
  if (fields.contacts) columns.push_back({"contact_stress", &fields.contactStress, 6});
  if (const std::string why = fieldsOutputProblem(path); !why.empty()) throw Error(why);
  std::string ext = path.substr(path.size() - 4);
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  const bool csv = ext == ".csv";
  if (csv) {
    static const char* const kVector[3] = {"_x", "_y", "_z"};
    static const char* const kTensor[6] = {"_xx", "_yy", "_zz", "_xy", "_xz", "_yz"};
    std::string header = "x,y,z";
    for (const Column& c : columns)
      for (int e = 0; e < c.components; ++e)
        header += std::string(",") + c.name + (c.components == 3 ? kVector[e] : c.components == 6 ? kTensor[e] : "");
    detail::CsvFile out(path, header);
    const int nx = g.points(0), ny = g.points(1);
    for (std::size_t k = 0; k < p; ++k) {
      out.number(g.at(0, int(k % std::size_t(nx))));
      out.number(g.at(1, int(k / std::size_t(nx) % std::size_t(ny))));
      out.number(g.at(2, int(k / (std::size_t(nx) * std::size_t(ny)))));
      for (const Column& c : columns)
        for (int e = 0; e < c.components; ++e) out.number((*c.v)[std::size_t(c.components) * k + e]);
      out.endRow();
    }
    out.commit();
    return;
  }
  // ImageData: point data on the points, extent 0 … points − 1 per axis.
  std::string extent, origin, spacing;
  for (int a = 0; a < 3; ++a) {
    const char* gap = a == 0 ? "" : " ";
    extent.append(gap).append("0 ").append(std::to_string(g.points(a) - 1));
    origin.append(gap).append(detail::number(g.at(a, 0)));
    spacing.append(gap).append(detail::number(g.points(a) > 1 ? (g.hi[a] - g.lo[a]) / g.n[a] : 1.0));
  }
  detail::VtkXmlFile file("ImageData", "WholeExtent=\"" + extent + "\" Origin=\"" + origin + "\" Spacing=\"" +
                                           spacing + "\"");
  file.xml("    <FieldData>\n      <DataArray type=\"Float64\" Name=\"width\" NumberOfTuples=\"1\" format=\"ascii\">" +
           detail::number(fields.width) + "</DataArray>\n      <DataArray type=\"UInt64\" Name=\"frames\" "
           "NumberOfTuples=\"1\" format=\"ascii\">" + std::to_string(fields.frames) + "</DataArray>\n    </FieldData>\n");
  file.xml("    <Piece Extent=\"" + extent + "\">\n      <PointData Scalars=\"packing_fraction\">\n");
  for (const Column& c : columns) {
    // VTK's symmetric tensors take 6 components in the order xx, yy, zz, xy, yz, xz.
    static const int kVtkTensor[6] = {0, 1, 2, 3, 5, 4};
    file.array("Float64", c.name, c.components, [&](detail::Encoder& e) {
      for (std::size_t k = 0; k < p; ++k)
        for (int a = 0; a < c.components; ++a)
          e.f64((*c.v)[std::size_t(c.components) * k + (c.components == 6 ? kVtkTensor[a] : a)]);
    });
  }
  file.xml("      </PointData>\n    </Piece>\n");
  file.write(path);
}

}  // namespace tumble
