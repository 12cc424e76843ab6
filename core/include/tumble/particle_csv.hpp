// SPDX-License-Identifier: MIT
/// @file particle_csv.hpp
/// The particle list that `tumble pairs` reads: a header line `x,y,z,r,body` (spaces allowed),
/// then one particle per line, five comma-separated fields; blank lines are skipped.
#pragma once
#include <string>
#include <string_view>

#include "tumble/pipeline.hpp"

namespace tumble {

/// Parses a particle list. Throws tumble::InputError naming `sourceName`, the line and what is
/// wrong: a missing or wrong header, a wrong field count, a field that is not a number (or has
/// trailing bytes, a NUL among them), a non-finite value, r ≤ 0, a body outside [0, 2^32).
/// Never crashes on bad bytes (fuzzed: validation/fuzz). Thread safety: none shared.
ParticleCloud parseParticleCsv(std::string_view text, const std::string& sourceName);

/// Reads the file at `path` and parses it; "cannot open" with the reason when it is unreadable.
ParticleCloud readParticleCsv(const std::string& path);

}  // namespace tumble
