// SPDX-License-Identifier: MIT
// `tumble fields REC.bin -o OUT.vti|OUT.csv --width W`: continuum fields of a recording by
// coarse-graining (tumble/fields.hpp, docs/fields.md).
#include <unistd.h>

#include <cmath>
#include <memory>

#include "commands.hpp"
#include "stop_signal.hpp"
#include "tumble/error.hpp"
#include "tumble/fields.hpp"
#include "tumble/recording.hpp"

namespace tumble::cli {
namespace {

struct FieldsCliOptions {
  std::string recording;
  std::string out;
  double width = 0.0;
  std::vector<int> grid;
  std::string axis;
  std::vector<double> box;
  double area = 0.0;
  FrameRangeOptions range;
  std::uint64_t every = 1;
  bool quiet = false;
};

void run(const FieldsCliOptions& o) {
  if (const std::string why = fieldsOutputProblem(o.out); !why.empty()) throw Error("-o " + why);
  FieldOptions opts;
  opts.width = o.width;
  FieldGrid& g = opts.grid;
  if (!o.axis.empty()) g.axis = o.axis == "x" ? 0 : o.axis == "y" ? 1 : 2;
  if (std::isnan(o.area)) throw Error("--area must be a positive number");
  if (o.area > 0.0 && g.axis < 0) throw Error("--area is a profile's: give --axis too");
  g.area = o.area;
  if (!o.box.empty()) {
    for (std::size_t a = 0; a < 3; ++a) {
      g.lo[a] = o.box[a];
      g.hi[a] = o.box[a + 3];
      if (!std::isfinite(g.lo[a]) || !std::isfinite(g.hi[a]) || !(g.hi[a] > g.lo[a]))
        throw Error("--box: its corners must be finite and the upper above the lower on every axis");
    }
  }
  RecordingReader reader(o.recording);
  if (reader.numFrames() == 0) throw InputError(o.recording, 0, "the recording holds no frame: nothing to coarse-grain");
  const auto [first, last] = frameRange(o.range, reader.numFrames(), o.recording);
  opts.first = first;
  opts.last = last;
  opts.every = static_cast<std::size_t>(o.every);
  // The grid: --grid, or cells about as wide as the kernel's standard deviation.
  if (!o.grid.empty()) {
    const std::vector<int>& n = o.grid;
    if (n.size() != (g.axis >= 0 ? 1u : 3u))
      throw Error(g.axis >= 0 ? "--grid takes one count along --axis" : "--grid takes three counts, NX,NY,NZ");
    if (g.axis >= 0)
      g.n[std::size_t(g.axis)] = n[0];
    else
      for (std::size_t a = 0; a < 3; ++a) g.n[a] = n[a];
  }
  const bool tty = isatty(fileno(stderr)) && !o.quiet;
  opts.progress = [&](std::size_t done, std::size_t total) {
    if (tty) std::fprintf(stderr, "\r  frame %zu/%zu   ", done, total);
  };
  StopOnSignal stopOnSignal(/*restart=*/true);
  opts.stop = [] { return g_stopSignal != 0; };
  if (o.grid.empty()) g.n = {0, 0, 0};  // cells about a width wide
  const Fields f = coarseGrainRecording(reader, opts);
  if (tty) std::fprintf(stderr, "\n");
  if (g_stopSignal != 0 || f.frames == 0) {
    std::fprintf(stderr, "tumble fields: interrupted; nothing written\n");
    dieOfSignal(g_stopSignal);
  }
  writeFields(f, o.out);
  if (!o.quiet) {
    const FieldGrid& fg = f.grid;
    if (fg.axis >= 0 && o.box.empty() && o.area == 0.0) {
      const int a = (fg.axis + 1) % 3, b = (fg.axis + 2) % 3;
      std::fprintf(stderr,
                   "tumble fields: note: the profile's fields are per the area of the particles' bounds across %c, "
                   "%.4g x %.4g m: give --box (the container, the periodic box) or --area for the area they fill\n",
                   "xyz"[fg.axis], fg.hi[std::size_t(a)] - fg.lo[std::size_t(a)], fg.hi[std::size_t(b)] - fg.lo[std::size_t(b)]);
    }
    std::fprintf(stderr, "tumble fields: %zu frame%s of %s, width %g m, %d x %d x %d points%s in [%g, %g] x [%g, %g] x [%g, %g] -> %s\n",
                 f.frames, f.frames == 1 ? "" : "s", o.recording.c_str(), f.width, fg.points(0), fg.points(1),
                 fg.points(2), fg.axis >= 0 ? (std::string(" (a profile along ") + "xyz"[fg.axis] + ")").c_str() : "",
                 fg.lo[0], fg.hi[0], fg.lo[1], fg.hi[1], fg.lo[2], fg.hi[2], o.out.c_str());
    if (!f.velocities)
      std::fprintf(stderr, "  (no velocity, kinetic stress or temperature: they need a debug recording, "
                           "tumble run --debug-record)\n");
    if (!f.contacts)
      std::fprintf(stderr, "  (no contact stress: it needs a recording with contact forces, tumble run --record-contacts)\n");
  }
}

}  // namespace

void addFields(CLI::App& app) {
  auto o = std::make_shared<FieldsCliOptions>();
  CLI::App* c = app.add_subcommand(
      "fields", "Continuum fields of a recording by coarse-graining: density, packing fraction, velocity, "
                "granular temperature, kinetic and contact stress on a grid or along an axis (docs/fields.md)");
  c->add_option("recording", o->recording, "The recording (tumble run --record; --debug-record for the velocities, "
                                           "--record-contacts for the contact stress)")
      ->required();
  c->add_option("-o,--output", o->out, "OUT.vti (VTK image data, ParaView) or OUT.csv (a row per point)")->required();
  c->add_option("--width", o->width, "The kernel's standard deviation w [m] (Lucy's kernel, support radius 3.46 w); "
                                     "about a particle diameter resolves layers, several average over them")
      ->required()
      ->check(CLI::PositiveNumber);
  c->add_option("--grid", o->grid, "NX,NY,NZ points (or N along --axis); default: cells about w wide, at most 256 "
                                   "per axis")
      ->delimiter(',')
      ->expected(1, 3)
      ->check(CLI::Range(1, 4096));
  c->add_option("--axis", o->axis, "A profile along x, y or z: the fields averaged over the box across that axis")
      ->check(CLI::IsMember({"x", "y", "z"}));
  c->add_option("--box", o->box, "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX [m]: where the points are (default: the particles' "
                                 "bounds over the frames); a profile takes the particles in this box's cross-section "
                                 "and its fields are per its area")
      ->delimiter(',')
      ->expected(6);
  c->add_option("--area", o->area, "A profile's fields per this area [m^2] instead of the box's cross-section (a "
                                   "silo's circle, pi R^2, in the square box around it)")
      ->check(CLI::PositiveNumber);
  addFrameRangeOptions(c, o->range, "");
  c->add_option("--every", o->every, "Every N-th frame of the range, from its first (default 1)")
      ->check(countIn(1, kMaxSteps));
  c->add_flag("-q,--quiet", o->quiet, "No progress and no summary");
  c->callback([o] { run(*o); });
}

}  // namespace tumble::cli
