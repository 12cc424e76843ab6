// SPDX-License-Identifier: MIT
// The table of the ranks' shares and traffic that `tumble run` prints under mpirun.
#include <cstdio>
#include <string>

#include "tumble/mpi/mpi_pipeline.hpp"

namespace tumble::mpi {

std::string describe(const std::vector<MpiStats>& stats) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%4s %8s %10s %8s %10s %7s %6s %12s %10s %11s %13s %14s %12s\n", "rank", "bodies",
                "particles", "ghosts", "ghost part", "halo", "neigh", "halo B/step", "msgs/step", "redistrib.",
                "B/redistrib.", "ms/redistrib.", "reads B/step");
  out += line;
  for (const MpiStats& r : stats) {
    const MpiStats::Counts& s = r.counts;
    const double steps = s.steps > 0 ? double(s.steps) : 1.0;
    const double share =
        r.ownedParticles > 0 ? 100.0 * double(r.ghostParticles) / double(r.ownedParticles) : 0.0;
    // The gathers after the load: the state of the other ranks, once per redistribution.
    const double perRedistribution =
        s.redistributions > 1 ? double(s.redistributeBytes) / double(s.redistributions - 1) : 0.0;
    std::snprintf(line, sizeof line, "%4d %8llu %10llu %8llu %10llu %6.1f%% %6llu %12.0f %10.2f %11llu %13.0f %14.1f %12.0f\n",
                  r.rank, static_cast<unsigned long long>(r.ownedBodies),
                  static_cast<unsigned long long>(r.ownedParticles), static_cast<unsigned long long>(r.ghostBodies),
                  static_cast<unsigned long long>(r.ghostParticles), share, static_cast<unsigned long long>(r.neighbours),
                  double(s.haloBytes) / steps, double(s.haloMessages) / steps,
                  static_cast<unsigned long long>(s.redistributions), perRedistribution,
                  s.redistributions > 1 ? 1e3 * s.redistributeSeconds / double(s.redistributions - 1) : 0.0,
                  double(s.readBytes) / steps);
    out += line;
  }
  return out;
}

}  // namespace tumble::mpi
