// SPDX-License-Identifier: MIT
// `tumble clump MESH [--spheres N] [--tolerance D] [--fill inside|surface] [-o shape.toml]`: a clump of spheres that
// approximates a closed mesh (tumble/clump.hpp), written as a [[shape]] table with the mesh's
// own mass properties, and the approximation's quality.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "tumble/clump.hpp"
#include "tumble/mesh.hpp"
#include "tumble/output_file.hpp"

namespace tumble::cli {
namespace {

struct ClumpCommand {
  std::string mesh;
  std::string out;
  std::string name;
  ClumpOptions options;
  std::vector<double> scale{1.0};
  double density = 1000.0;
  std::string fill = "inside";
};

void clump(const ClumpCommand& o) {
  if (!o.out.empty()) refuseSameFile({{"-o", o.out}, {"mesh", o.mesh}});
  if (o.scale.size() != 1 && o.scale.size() != 3)
    throw Error("--scale takes one factor or three (x, y, z), e.g. --scale 0.001 or --scale 1,1,2");
  const std::array<double, 3> scale =
      o.scale.size() == 1 ? std::array<double, 3>{o.scale[0], o.scale[0], o.scale[0]}
                          : std::array<double, 3>{o.scale[0], o.scale[1], o.scale[2]};
  for (double f : scale)
    if (!(f > 0.0) || !std::isfinite(f)) throw Error("--scale: each factor must be a finite number > 0");
  const TriangleMesh mesh = readMeshFile(o.mesh);
  const Clump c = clumpFromMesh(mesh, o.options, scale);
  const ShapeDef shape = clumpShape(c, o.name.empty() ? std::filesystem::path(o.mesh).stem().string() : o.name, o.density);
  char limits[160] = "";
  if (o.options.spheres != 0 && o.options.tolerance > 0.0)
    std::snprintf(limits, sizeof limits, "at most %u, tolerance %g m", o.options.spheres, o.options.tolerance);
  else if (o.options.spheres != 0)
    std::snprintf(limits, sizeof limits, "at most %u", o.options.spheres);
  else
    std::snprintf(limits, sizeof limits, "tolerance %g m", o.options.tolerance);
  if (o.options.fill == ClumpFill::Surface) {
    const std::size_t used = std::strlen(limits);
    std::snprintf(limits + used, sizeof limits - used, "; a layer under the surface, radius %.4g m", c.layerRadius);
  }
  char numbers[640];  // (the mesh's path, of any length, outside it)
  std::snprintf(numbers, sizeof numbers,
                ": %zu sphere%s (%s), %zu triangles, voxels of %.4g m (resolution %u)\n"
                "volume %.6g m^3, mass %.6g kg at %.6g kg/m^3 (the mesh's solid, not the spheres')\n"
                "quality: the spheres' union holds %.1f %% of the volume; the mesh's surface lies at most %.4g m and on "
                "average %.4g m from the spheres (%zu points)",
                c.spheres.size(), c.spheres.size() == 1 ? "" : "s", limits, mesh.numTriangles(), c.voxel,
                o.options.resolution, c.solid.volume, shape.solid->mass, o.density, 100.0 * c.quality.volumeRatio,
                c.quality.largestDeviation, c.quality.meanDeviation, c.quality.samples);
  std::string head = "tumble clump " + o.mesh + numbers;
  if (c.uncoveredDepth > 0.0) {  // the sphere count ended it
    char left[320];
    const char* plural = c.spheres.size() == 1 ? "" : "s";
    if (o.options.tolerance > 0.0)
      std::snprintf(left, sizeof left,
                    "\nthe tolerance is not reached: with %zu sphere%s a part of the solid %.4g m deep is left uncovered "
                    "(more than %g m); allow more spheres or give a larger tolerance",
                    c.spheres.size(), plural, c.uncoveredDepth, o.options.tolerance);
    else
      std::snprintf(left, sizeof left, "\nwith %zu sphere%s a part of the solid %.4g m deep is left uncovered",
                    c.spheres.size(), plural, c.uncoveredDepth);
    head += left;
  }
  if (o.options.fill == ClumpFill::Surface && o.options.tolerance > 0.0 &&
      c.quality.largestDeviation > o.options.tolerance) {  // the sphere count ended it
    char left[240];
    std::snprintf(left, sizeof left,
                  "\nthe tolerance is not reached: with %zu spheres the layer's radius is %.4g m, and the surface lies up "
                  "to %.4g m from it (more than %g m); allow more spheres or give a larger tolerance",
                  c.spheres.size(), c.layerRadius, c.quality.largestDeviation, o.options.tolerance);
    head += left;
  }
  std::fprintf(stderr, "%s\n", head.c_str());
  const std::string text = shapeToml(shape, head);
  if (o.out.empty()) {
    std::fputs(text.c_str(), stdout);
    return;
  }
  writeAtomically(o.out, [&](std::FILE* f) {
    if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) throw Error("cannot write " + o.out);
  });
  std::fprintf(stderr, "tumble clump: wrote the [[shape]] table to %s\n", o.out.c_str());
}

}  // namespace

void addClump(CLI::App& app) {
  auto o = std::make_shared<ClumpCommand>();
  CLI::App* c = app.add_subcommand(
      "clump", "Approximate a closed mesh (STL, OBJ) by overlapping spheres: print or write its [[shape]] table, "
               "with the mesh's own mass, centre of mass and inertia, and how well the spheres fit it");
  c->add_option("mesh", o->mesh, "The mesh file: binary or ASCII STL, or OBJ; closed (watertight)")->required();
  c->add_option("--spheres", o->options.spheres, "At most this many spheres (the deepest first)");
  c->add_option("--tolerance", o->options.tolerance,
                "Stop when no uncovered part of the solid is deeper than this (m): the largest surface deviation, "
                "about");
  c->add_option("--fill", o->fill,
                "inside: spheres filling the solid, the largest first; surface: a layer of spheres of one radius under "
                "its surface (hollow), for thin parts and flat faces")
      ->check(CLI::IsMember({"inside", "surface"}))
      ->default_val("inside");
  c->add_option("--resolution", o->options.resolution, "Voxels along the solid's longest side, 8 to 512")
      ->default_val(64);
  c->add_option("--scale", o->scale, "The factor of the file's coordinates, one or x,y,z (as a mesh wall's scale)")
      ->delimiter(',')
      ->expected(1, 3);
  c->add_option("--density", o->density, "kg/m^3: the mass is the mesh's volume times it")->default_val(1000.0);
  c->add_option("--name", o->name, "The shape's name (default: the file's stem)");
  c->add_option("-o,--out", o->out, "Write the table here (default: print it)");
  c->callback([o] {
    if (o->options.spheres == 0 && !(o->options.tolerance > 0.0))
      throw Error("give --spheres N, --tolerance D or both");
    o->options.fill = o->fill == "surface" ? ClumpFill::Surface : ClumpFill::Inside;
    if (!(o->density > 0.0) || !std::isfinite(o->density)) throw Error("--density must be a finite number > 0");
    clump(*o);
  });
}

}  // namespace tumble::cli
