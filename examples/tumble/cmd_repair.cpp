// SPDX-License-Identifier: MIT
// `tumble repair REC [-o OUT]`: a recording cut short (a crash-left temporary, a full disk, an
// interrupted copy) as the recording of its whole frames (tumble::repairRecording).
#include <memory>
#include <string>

#include "commands.hpp"
#include "tumble/output_file.hpp"
#include "tumble/recording.hpp"

namespace tumble::cli {
namespace {

struct RepairOptions {
  std::string file;
  std::string out;
};

// heap.bin → heap.repaired.bin; a writer's temporary heap.bin.part-Ab12Cd (or .part) too.
std::string repairedName(std::string path) {
  const std::size_t slash = path.rfind('/');
  const std::size_t part = path.rfind(".part");
  if (part != std::string::npos && (slash == std::string::npos || part > slash) &&
      (part + 5 == path.size() || path[part + 5] == '-'))
    path.erase(part);
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash) || dot == slash + 1)
    return path + ".repaired";
  return path.substr(0, dot) + ".repaired" + path.substr(dot);
}

void repair(const RepairOptions& o) {
  const std::string out = o.out.empty() ? repairedName(o.file) : o.out;
  refuseSameFile({{"-o", out}, {"recording", o.file}});
  const RepairResult r = repairRecording(o.file, out);
  if (r.why.empty()) {
    std::fprintf(stderr, "tumble repair: %s is whole (%zu frames): nothing to repair, nothing written\n",
                 o.file.c_str(), r.kept);
    return;
  }
  const std::string kept = r.kept == 1 ? "kept the 1 whole frame" : "kept the " + std::to_string(r.kept) + " whole frames";
  std::fprintf(stderr, "tumble repair: %s of %s in %s; %llu bytes after them left out (%s)\n", kept.c_str(),
               o.file.c_str(), out.c_str(), static_cast<unsigned long long>(r.droppedBytes), r.why.c_str());
}

}  // namespace

void addRepair(CLI::App& app) {
  auto o = std::make_shared<RepairOptions>();
  CLI::App* c = app.add_subcommand(
      "repair", "Keep the whole frames of a recording cut short (a crash, a full disk) in a recording of its own");
  c->add_option("recording", o->file, "The recording, or the FILE.part-XXXXXX a stopped writer left")->required();
  c->add_option("-o,--out", o->out, "Where to write it (default: NAME.repaired.EXT next to it; never the input)");
  c->callback([o] { repair(*o); });
}

}  // namespace tumble::cli
