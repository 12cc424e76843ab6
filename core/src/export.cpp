// SPDX-License-Identifier: MIT
// VTK XML PolyData and CSV output of a recording (export.hpp, docs/export.md).
//
// The VTK files are written here rather than through Debian's VTK: the format of one .vtp
// (a few XML elements and raw little-endian arrays, "VTK File Formats" in the VTK book) takes
// less code than adapting our columns to vtkPolyData, and a ~100 MB library with Qt and MPI
// behind it would be a dependency of the core library for one command. The test reads the files
// back with VTK's own reader (examples/tumble/export_test.py, ctest export_vtk).
#include "tumble/export.hpp"

#include <algorithm>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "binary_io.hpp"
#include "vtk_xml.hpp"
#include "tumble/error.hpp"
#include "tumble/kernels/integrate.hpp"
#include "tumble/output_file.hpp"
#include "tumble/wall_geometry.hpp"

namespace tumble {
namespace {

using detail::csvField;
using detail::CsvFile;
using detail::number;
using detail::VtkXmlFile;
using detail::writeAll;
using detail::xmlEscaped;

void f32s(detail::Encoder& e, const std::vector<float>& v) {
  for (const float x : v) e.f32(x);
}

std::string pieceHead(std::size_t points, std::size_t verts, std::size_t lines, std::size_t polys) {
  return "    <Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfVerts=\"" + std::to_string(verts) +
         "\" NumberOfLines=\"" + std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
         std::to_string(polys) + "\">\n";
}

// Cells of one kind: `cells` cells of `size` points each, point indices from `point(k)`.
void cellBlock(VtkXmlFile& f, const char* tag, std::size_t cells, int size, const std::function<std::int64_t(std::size_t)>& point) {
  f.xml("      <" + std::string(tag) + ">\n");
  f.array("Int64", "connectivity", 1, [&](detail::Encoder& e) {
    for (std::size_t k = 0; k < cells * static_cast<std::size_t>(size); ++k) e.u64(static_cast<std::uint64_t>(point(k)));
  });
  f.array("Int64", "offsets", 1, [&](detail::Encoder& e) {
    for (std::size_t k = 1; k <= cells; ++k) e.u64(k * static_cast<std::uint64_t>(size));
  });
  f.xml("      </" + std::string(tag) + ">\n");
}

void writeFrameVtp(const std::string& path, const Recording& table, const RecordedFrame& frame,
                   const std::vector<float>& x) {
  const std::size_t n = table.particlesOf(frame.numBodies());  // those present
  const bool debug = frame.debug.v.size() == 3 * n;
  const std::size_t contacts = debug ? frame.debug.contacts.size() : 0;
  VtkXmlFile f("PolyData");
  // The data set's field data (before its piece): ParaView takes "TimeValue" as the time of a
  // file opened on its own.
  f.xml("    <FieldData>\n");
  f.xml("      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">" +
        number(frame.time) + "</DataArray>\n");
  f.xml("      <DataArray type=\"UInt64\" Name=\"step\" NumberOfTuples=\"1\" format=\"ascii\">" +
        std::to_string(frame.step) + "</DataArray>\n");
  f.xml("    </FieldData>\n");
  f.xml(pieceHead(n, n, contacts, 0));
  f.xml("      <PointData Scalars=\"radius\"" + std::string(debug ? " Vectors=\"velocity\"" : "") + ">\n");
  f.array("Float32", "radius", 1, [&](detail::Encoder& e) { f32s(e, table.radius); });
  f.array("UInt32", "body", 1, [&](detail::Encoder& e) {
    for (const std::uint32_t b : table.body) e.u32(b);
  });
  f.array("Float32", "mass", 1, [&](detail::Encoder& e) { f32s(e, table.mass); });
  f.array("Float32", "elasticity", 1, [&](detail::Encoder& e) { f32s(e, table.elasticity); });
  if (debug) {
    f.array("Float32", "velocity", 3, [&](detail::Encoder& e) { f32s(e, frame.debug.v); });
    for (int k = 0; k < 5; ++k)
      f.array("Float32", kDebugForceNames[k], 3, [&](detail::Encoder& e) { f32s(e, frame.debug.force[k]); });
  }
  f.xml("      </PointData>\n      <Points>\n");
  f.array("Float32", "Points", 3, [&](detail::Encoder& e) { f32s(e, x); });
  f.xml("      </Points>\n");
  cellBlock(f, "Verts", n, 1, [](std::size_t k) { return static_cast<std::int64_t>(k); });
  if (contacts > 0)
    cellBlock(f, "Lines", contacts, 2, [&](std::size_t k) {
      const Pair& p = frame.debug.contacts[k / 2];
      return static_cast<std::int64_t>(k % 2 == 0 ? p.i : p.j);
    });
  f.xml("    </Piece>\n");
  f.write(path);
}

// The contacts of a frame with their forces: a line per contact from particle i's centre along
// its branch (contactBranch(): to j, or across a periodic boundary to j's image beside i), two
// points of its own each, with the forces on i, their magnitudes, the normal, the overlap and
// the two particles as cell data.
void writeContactsVtp(const std::string& path, const Recording& table, const RecordedFrame& frame,
                      const std::vector<float>& x) {
  const std::vector<ContactForce>& cf = frame.debug.contactForces;
  const std::size_t c = cf.size();
  VtkXmlFile f("PolyData");
  f.xml(pieceHead(2 * c, 0, c, 0));
  f.xml("      <CellData Scalars=\"normal_magnitude\" Vectors=\"normal_force\">\n");
  const auto vectors = [&](const char* name, const std::function<Vec3f(const ContactForce&)>& value) {
    f.array("Float32", name, 3, [&](detail::Encoder& e) {
      for (const ContactForce& k : cf) {
        const Vec3f v = value(k);
        e.f32(v.x);
        e.f32(v.y);
        e.f32(v.z);
      }
    });
  };
  const auto scalars = [&](const char* name, const std::function<float(const ContactForce&)>& value) {
    f.array("Float32", name, 1, [&](detail::Encoder& e) {
      for (const ContactForce& k : cf) e.f32(value(k));
    });
  };
  vectors("normal_force", [](const ContactForce& k) { return k.normal(); });
  vectors("tangential_force", [](const ContactForce& k) { return k.tangential; });
  vectors("unit_normal", [](const ContactForce& k) { return k.n; });
  scalars("fn", [](const ContactForce& k) { return k.fn; });
  scalars("normal_magnitude", [](const ContactForce& k) { return std::fabs(k.fn); });
  scalars("tangential_magnitude", [](const ContactForce& k) { return norm(k.tangential); });
  scalars("overlap", [](const ContactForce& k) { return k.overlap; });
  for (const bool first : {true, false})
    f.array("UInt32", first ? "particle_i" : "particle_j", 1, [&](detail::Encoder& e) {
      for (const ContactForce& k : cf) e.u32(first ? k.i : k.j);
    });
  f.xml("      </CellData>\n      <Points>\n");
  f.array("Float32", "Points", 3, [&](detail::Encoder& e) {
    for (const ContactForce& k : cf) {
      const float* xi = &x[3 * std::size_t(k.i)];
      const std::array<double, 3> l = contactBranch(k, table.radius[k.i], table.radius[k.j]);
      for (int a = 0; a < 3; ++a) e.f32(xi[a]);
      for (int a = 0; a < 3; ++a) e.f32(float(double(xi[a]) - l[std::size_t(a)]));  // j's centre (or image) at the step
    }
  });
  f.xml("      </Points>\n");
  cellBlock(f, "Lines", c, 2, [](std::size_t k) { return static_cast<std::int64_t>(k); });
  f.xml("    </Piece>\n");
  f.write(path);
}

// The same as CSV: a row per contact.
void writeContactsCsv(const std::string& path, const Recording& table, const RecordedFrame& frame,
                      const std::vector<float>& x) {
  CsvFile out(path,
              "i,j,body_i,body_j,normal_x,normal_y,normal_z,tangential_x,tangential_y,tangential_z,overlap,nx,ny,nz,fn,"
              "xi,yi,zi,xj,yj,zj");
  for (const ContactForce& k : frame.debug.contactForces) {
    for (const std::uint32_t id : {k.i, k.j, table.body[k.i], table.body[k.j]}) out.text(std::to_string(id));
    for (const Vec3f& v : {k.normal(), k.tangential})
      for (const float c : {v.x, v.y, v.z}) out.number(c);
    out.number(k.overlap);
    for (const float c : {k.n.x, k.n.y, k.n.z, k.fn}) out.number(c);
    for (const std::uint32_t p : {k.i, k.j})
      for (int a = 0; a < 3; ++a) out.number(x[3 * std::size_t(p) + a]);
    out.endRow();
  }
  out.commit();
}

// The ground as one square at z = height under everything exported, with a margin.
void writeGroundVtp(const std::string& path, float height, const float lo[2], const float hi[2]) {
  const float span = std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-3f});
  const float m = 0.25f * span;
  const float corners[4][2] = {{lo[0] - m, lo[1] - m}, {hi[0] + m, lo[1] - m}, {hi[0] + m, hi[1] + m}, {lo[0] - m, hi[1] + m}};
  VtkXmlFile f("PolyData");
  f.xml(pieceHead(4, 0, 0, 1));
  f.xml("      <Points>\n");
  f.array("Float32", "Points", 3, [&](detail::Encoder& e) {
    for (const auto& c : corners) {
      e.f32(c[0]);
      e.f32(c[1]);
      e.f32(height);
    }
  });
  f.xml("      </Points>\n");
  cellBlock(f, "Polys", 1, 4, [](std::size_t k) { return static_cast<std::int64_t>(k); });
  f.xml("    </Piece>\n");
  f.write(path);
}

// The walls at time t as triangles (three points each, posed by their motion), with the wall's
// index in the recording and its kind per triangle.
void writeWallsVtp(const std::string& path, const std::vector<WallSurface>& walls, double t) {
  std::size_t triangles = 0;
  for (const WallSurface& w : walls) triangles += w.numTriangles();
  VtkXmlFile f("PolyData");
  f.xml(pieceHead(3 * triangles, 0, 0, triangles));
  f.xml("      <CellData Scalars=\"wall\">\n");
  f.array("UInt32", "wall", 1, [&](detail::Encoder& e) {
    for (std::size_t k = 0; k < walls.size(); ++k)
      for (std::size_t i = 0; i < walls[k].numTriangles(); ++i) e.u32(static_cast<std::uint32_t>(k));
  });
  f.array("UInt32", "kind", 1, [&](detail::Encoder& e) {
    for (const WallSurface& w : walls)
      for (std::size_t i = 0; i < w.numTriangles(); ++i) e.u32(static_cast<std::uint32_t>(w.kind));
  });
  f.xml("      </CellData>\n      <Points>\n");
  f.array("Float32", "Points", 3, [&](detail::Encoder& e) {
    for (const WallSurface& w : walls) {
      const WallPose pose = wallPose(w.motion, t);
      for (std::size_t i = 0; i + 2 < w.triangles.size(); i += 3) {
        const Vec3f p = pose.apply(Vec3f{w.triangles[i], w.triangles[i + 1], w.triangles[i + 2]});
        e.f32(p.x);
        e.f32(p.y);
        e.f32(p.z);
      }
    }
  });
  f.xml("      </Points>\n");
  cellBlock(f, "Polys", triangles, 3, [](std::size_t k) { return static_cast<std::int64_t>(k); });
  f.xml("    </Piece>\n");
  f.write(path);
}

void writeFrameCsv(const std::string& path, const Recording& table, const RecordedFrame& frame,
                   const std::vector<float>& x) {
  const std::size_t n = table.particlesOf(frame.numBodies());  // those present
  const bool debug = frame.debug.v.size() == 3 * n;
  std::string header = "particle,body,x,y,z,r,mass,elasticity";
  if (debug) {
    header += ",vx,vy,vz";
    for (const char* name : kDebugForceNames) header += std::string(",") + name + "_x," + name + "_y," + name + "_z";
  }
  CsvFile out(path, header);
  for (std::size_t i = 0; i < n; ++i) {
    out.text(std::to_string(i));
    out.text(std::to_string(table.body[i]));
    for (int c = 0; c < 3; ++c) out.number(x[3 * i + c]);
    out.number(table.radius[i]);
    out.number(table.mass[i]);
    out.number(table.elasticity[i]);
    if (debug) {
      for (int c = 0; c < 3; ++c) out.number(frame.debug.v[3 * i + c]);
      for (const auto& force : frame.debug.force)
        for (int c = 0; c < 3; ++c) out.number(force[3 * i + c]);
    }
    out.endRow();
  }
  out.commit();
}

void writeText(const std::string& path, const std::string& text) {
  OutputFile out(path);
  writeAll(out, text);
  out.commit();
}

}  // namespace

std::string exportFrameName(const std::string& name, std::size_t k, std::size_t numFrames, ExportFormat format) {
  int width = 6;
  for (std::size_t m = numFrames > 0 ? numFrames - 1 : 0; m >= 1000000; m /= 10) ++width;
  char digits[32];
  std::snprintf(digits, sizeof digits, "%0*zu", width, k);
  return name + "_" + digits + (format == ExportFormat::Vtk ? ".vtp" : ".csv");
}

std::string exportNameProblem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxExportName)
    return "is " + std::to_string(name.size()) + " bytes long: at most " + std::to_string(kMaxExportName) +
           " (a frame's file name and its temporary must fit the file system's 255)";
  for (std::size_t k = 0; k < name.size();) {
    const auto c = static_cast<unsigned char>(name[k]);
    if (c == '/') return "contains '/'";
    if (c < 0x20 || c == 0x7f) return "contains a control character (XML cannot hold it)";
    // UTF-8: the length from the lead byte, then continuation bytes 10xxxxxx (no overlong forms
    // checked beyond the lead bytes C0, C1 and F5–FF, which never occur).
    const std::size_t len = c < 0x80 ? 1 : (c >= 0xc2 && c < 0xe0) ? 2 : (c >= 0xe0 && c < 0xf0) ? 3 : (c >= 0xf0 && c < 0xf5) ? 4 : 0;
    if (len == 0 || k + len > name.size()) return "is not UTF-8 text (XML needs it)";
    for (std::size_t j = 1; j < len; ++j)
      if ((static_cast<unsigned char>(name[k + j]) & 0xc0) != 0x80) return "is not UTF-8 text (XML needs it)";
    k += len;
  }
  return "";
}

ExportResult exportRecording(RecordingReader& reader, const std::string& dir, const ExportOptions& options) {
  if (options.every < 1) throw Error("export: every must be at least 1");
  const std::string name = options.name.empty() ? "frame" : options.name;
  if (const std::string why = exportNameProblem(name); !why.empty()) throw Error("export: the name '" + name + "' " + why);
  if (options.contacts && !reader.info().contactForces)
    throw Error("export: the recording holds no contact forces: record the run with them (tumble run "
                "--record-contacts, [output] contacts = true, or record(..., contacts=True) in Python)");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir))
    throw Error(dir + ": cannot create the export folder: " +
                (std::filesystem::symlink_status(dir, ec).type() == std::filesystem::file_type::not_found
                     ? std::string(ec ? ec.message() : "not found")
                     : std::string("a file or a dangling link of that name is in the way")));
  const std::filesystem::path folder(dir);
  const std::string indexPath =
      (folder / (options.format == ExportFormat::Vtk ? name + ".pvd" : name + "_frames.csv")).string();
  // An index from an earlier export of this name would list frames this one replaces: it goes
  // first, and comes back only for this export's frames.
  std::remove(indexPath.c_str());

  const Recording& table = reader.header();
  const std::size_t n = table.radius.size();
  const std::size_t total = reader.numFrames() == 0 ? 0 : (reader.numFrames() - 1) / options.every + 1;
  RecordedFrame frame;
  std::vector<float> x(3 * n);
  float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  ExportResult result;
  // The walls (VTK only): one file for all frames when none moves, else one per frame, posed.
  const std::vector<WallSurface>& walls = table.walls;
  const bool anyWall = std::any_of(walls.begin(), walls.end(), [](const WallSurface& w) { return w.numTriangles() > 0; });
  const bool wallsMove = std::any_of(walls.begin(), walls.end(), [](const WallSurface& w) { return w.motion.moves(); });
  struct Set {
    double time;
    std::string file, walls, contacts;
  };
  std::vector<Set> sets;  // the .pvd's: per time the frame's file and its walls' file
  std::string rows;       // the CSV index's
  const auto writeIndex = [&] {
    if (options.format == ExportFormat::Vtk) {
      // Part 1 of every time step is the ground, part 1 or 2 the walls (a .pvd lists each part per time).
      const bool ground = reader.info().groundEnabled && result.frames > 0;
      const std::string groundFile = name + "_ground.vtp";
      if (ground) writeGroundVtp((folder / groundFile).string(), reader.info().groundHeight, lo, hi);
      const std::string wallsPart = ground ? "2" : "1";
      const std::string contactsPart = std::to_string((ground ? 2 : 1) + (anyWall ? 1 : 0));
      std::string xml;
      for (const Set& set : sets) {
        const std::string at = "    <DataSet timestep=\"" + number(set.time) + "\" part=\"";
        xml += at + "0\" file=\"" + xmlEscaped(set.file) + "\"/>\n";
        if (ground) xml += at + "1\" file=\"" + xmlEscaped(groundFile) + "\"/>\n";
        if (!set.walls.empty()) xml += at + wallsPart + "\" file=\"" + xmlEscaped(set.walls) + "\"/>\n";
        if (!set.contacts.empty()) xml += at + contactsPart + "\" file=\"" + xmlEscaped(set.contacts) + "\"/>\n";
      }
      writeText(indexPath, "<?xml version=\"1.0\"?>\n"
                           "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                           "  <Collection>\n" + xml + "  </Collection>\n</VTKFile>\n");
    } else {
      writeText(indexPath, std::string("frame,step,time,file") + (options.contacts ? ",contacts_file" : "") + "\n" + rows);
    }
  };
  try {
    for (std::size_t k = 0; k < reader.numFrames(); k += options.every) {
      if (options.stop && options.stop()) {
        result.stopped = true;
        break;
      }
      reader.readFrame(k, frame);
      for (std::size_t i = 0, present = table.particlesOf(frame.numBodies()); i < present; ++i) {
        const std::uint32_t b = table.body[i];
        const Mat3f R = rotationMatrix(Quatf{frame.qw[b], frame.qx[b], frame.qy[b], frame.qz[b]});
        const Vec3f p = particlePosition(Vec3f{frame.px[b], frame.py[b], frame.pz[b]}, R,
                                         Vec3f{table.ux[i], table.uy[i], table.uz[i]});
        x[3 * i] = p.x;
        x[3 * i + 1] = p.y;
        x[3 * i + 2] = p.z;
        lo[0] = std::min(lo[0], p.x - table.radius[i]);
        lo[1] = std::min(lo[1], p.y - table.radius[i]);
        hi[0] = std::max(hi[0], p.x + table.radius[i]);
        hi[1] = std::max(hi[1], p.y + table.radius[i]);
      }
      const std::string file = exportFrameName(name, result.frames, total, options.format);
      const std::string contactsFile =
          options.contacts ? exportFrameName(name + "_contacts", result.frames, total, options.format) : "";
      if (options.format == ExportFormat::Vtk) {
        writeFrameVtp((folder / file).string(), table, frame, x);
        if (options.contacts) writeContactsVtp((folder / contactsFile).string(), table, frame, x);
        std::string wallsFile;
        if (anyWall) {
          wallsFile = wallsMove ? exportFrameName(name + "_walls", result.frames, total, options.format) : name + "_walls.vtp";
          if (wallsMove || result.frames == 0) writeWallsVtp((folder / wallsFile).string(), walls, frame.time);
        }
        sets.push_back({frame.time, file, wallsFile, contactsFile});
      } else {
        writeFrameCsv((folder / file).string(), table, frame, x);
        if (options.contacts) writeContactsCsv((folder / contactsFile).string(), table, frame, x);
        rows += std::to_string(k) + "," + std::to_string(frame.step) + "," + number(frame.time) + "," + csvField(file) +
                (options.contacts ? "," + csvField(contactsFile) : "") + "\n";
      }
      ++result.frames;
      if (options.progress) options.progress(result.frames, total);
    }
  } catch (...) {
    // The frames written so far are this recording's: the index lists them, if it can be written.
    try {
      if (result.frames > 0) writeIndex();
    } catch (...) {
      std::remove(indexPath.c_str());
    }
    throw;
  }
  // A stop before the first frame leaves no index (not an empty one).
  if (result.frames > 0 || !result.stopped) writeIndex();
  result.index = indexPath;
  return result;
}

}  // namespace tumble
