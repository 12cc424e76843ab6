// SPDX-License-Identifier: MIT
#include <string>

#include "tumble/error.hpp"
#include "tumble/pipeline.hpp"

namespace tumble {

const char* toString(Backend b) { return b == Backend::Cpu ? "cpu" : "cuda"; }

Backend backendFromString(const std::string& s) {
  if (s == "cpu") return Backend::Cpu;
  if (s == "cuda") return Backend::Cuda;
  throw Error("unknown pipeline '" + s + "' (expected cpu or cuda)");
}

const char* toString(Phase p) {
  switch (p) {
    case Phase::State: return "state";
    case Phase::Axis: return "axis";
    case Phase::Keys: return "keys";
    case Phase::Sort: return "sort";
    case Phase::Sweep: return "sweep";
    case Phase::Forces: return "forces";
    case Phase::Integrate: return "integrate";
    default: return "?";
  }
}

double StepStats::totalSeconds() const {
  double t = 0.0;
  for (double s : seconds) t += s;
  return t;
}

}  // namespace tumble
