// SPDX-License-Identifier: MIT
// `tumble export REC.bin DIR`: a recording as one VTK PolyData file per frame and a ParaView
// collection (.pvd), or as one CSV per frame and an index (tumble/export.hpp, docs/export.md).
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>

#include "commands.hpp"
#include "stop_signal.hpp"
#include "tumble/error.hpp"
#include "tumble/export.hpp"
#include "tumble/recording.hpp"

namespace tumble::cli {
namespace {

struct ExportCliOptions {
  std::string recording;
  std::string dir;
  std::string format = "vtk";
  std::string name;
  std::uint64_t every = 1;
  bool contacts = false;
  bool quiet = false;
};

void run(const ExportCliOptions& o) {
  ExportOptions opts;
  if (o.format == "vtk") opts.format = ExportFormat::Vtk;
  else if (o.format == "csv") opts.format = ExportFormat::Csv;
  else throw Error("--format " + o.format + ": expected vtk or csv");
  opts.every = static_cast<std::size_t>(o.every);
  opts.contacts = o.contacts;
  if (!o.name.empty())
    if (const std::string why = exportNameProblem(o.name); !why.empty()) throw Error("--name '" + o.name + "' " + why);

  RecordingReader reader(o.recording);
  if (reader.numFrames() == 0) throw InputError(o.recording, 0, "the recording holds no frame: nothing to export");
  opts.name = o.name;
  if (opts.name.empty()) {  // the recording's name, when it makes one
    opts.name = std::filesystem::path(o.recording).stem().string();
    if (!exportNameProblem(opts.name).empty()) opts.name = "frame";
  }
  std::string shownDir = o.dir;  // for messages: "out/", never "out//"
  while (shownDir.size() > 1 && shownDir.back() == '/') shownDir.pop_back();
  const bool tty = isatty(fileno(stderr)) && !o.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  auto lastPrint = t0;
  std::size_t written = 0;
  opts.progress = [&](std::size_t done, std::size_t total) {
    written = done;
    const auto now = std::chrono::steady_clock::now();
    if (!tty || (now - lastPrint < std::chrono::milliseconds(200) && done != total)) return;
    lastPrint = now;
    const double el = std::chrono::duration<double>(now - t0).count();
    std::fprintf(stderr, "\r  frame %zu/%zu (%5.1f%%)  %.1f frames/s   ", done, total, 100.0 * double(done) / double(total),
                 double(done) / el);
  };
  StopOnSignal stopOnSignal(/*restart=*/true);
  opts.stop = [] { return g_stopSignal != 0; };
  const ExportResult r = [&] {
    try {
      return exportRecording(reader, o.dir, opts);
    } catch (...) {
      if (tty) std::fprintf(stderr, "\n");
      if (written > 0)
        std::fprintf(stderr, "tumble export: %zu frame%s written to %s/ before the error; the index lists them\n",
                     written, written == 1 ? "" : "s", shownDir.c_str());
      throw;
    }
  }();
  if (tty) std::fprintf(stderr, "\n");
  if (r.stopped) {
    if (r.frames > 0)
      std::fprintf(stderr, "tumble export: interrupted after %zu frames (%s lists those)\n", r.frames, r.index.c_str());
    else
      std::fprintf(stderr, "tumble export: interrupted before the first frame; nothing written\n");
    dieOfSignal(g_stopSignal);
  }
  if (!o.quiet) {
    std::fprintf(stderr, "tumble export: %zu frame%s of %s into %s/, %s\n", r.frames, r.frames == 1 ? "" : "s",
                 o.recording.c_str(), shownDir.c_str(), r.index.c_str());
    if (!reader.info().debug)
      std::fprintf(stderr, reader.info().contactForces
                               ? "  (velocities and the forces per particle are in debug recordings only: tumble run --debug-record)\n"
                               : "  (velocities, forces and contacts are in debug recordings only: tumble run --debug-record, "
                                 "or the contacts with their forces: --record-contacts)\n");
    if (reader.info().contactForces && !o.contacts)
      std::fprintf(stderr, "  (the recording holds the contacts with their forces: --contacts exports them)\n");
    if (opts.format == ExportFormat::Csv && !reader.header().walls.empty())
      std::fprintf(stderr, "  (the walls are in the VTK export only: --format vtk)\n");
    if (opts.format == ExportFormat::Vtk) std::fprintf(stderr, "  open in ParaView: paraview %s\n", r.index.c_str());
  }
}

}  // namespace

void addExport(CLI::App& app) {
  auto o = std::make_shared<ExportCliOptions>();
  CLI::App* c = app.add_subcommand(
      "export", "Write a recording as VTK files for ParaView (one .vtp per frame and a .pvd) or as CSV files");
  c->add_option("recording", o->recording, "The recording, e.g. record.bin (tumble run --record)")->required();
  c->add_option("dir", o->dir, "Folder for the files (created when missing; files of the same names are replaced)")
      ->required();
  c->add_option("--format", o->format,
                "vtk (default): NAME_000000.vtp … with radius, body, mass, elasticity per particle (and velocity, the "
                "five forces and the contacts as lines in a debug recording), NAME_ground.vtp, the walls as triangles "
                "(NAME_walls.vtp, or NAME_walls_000000.vtp … per frame when a wall turns) and the collection NAME.pvd; "
                "csv: NAME_000000.csv … one row per particle (no walls) and the index NAME_frames.csv")
      ->check(CLI::IsMember({"vtk", "csv"}));
  c->add_flag("--contacts", o->contacts,
              "Also the contacts with their forces, from a recording made with them (tumble run --record-contacts): "
              "NAME_contacts_000000.vtp … (a line per contact between the two particles' centres, with normal_force, "
              "tangential_force, their magnitudes, overlap, particle_i and particle_j per line; a part of the .pvd) "
              "or NAME_contacts_000000.csv … (a row per contact; a column of the index)");
  c->add_option("--every", o->every, "Export every N-th frame, from the first (default 1)")->check(countIn(1, kMaxSteps));
  c->add_option("--name", o->name, "File name prefix (default: the recording's name without its extension)");
  c->add_flag("-q,--quiet", o->quiet, "No progress and no summary");
  c->callback([o] { run(*o); });
}

}  // namespace tumble::cli
