// SPDX-License-Identifier: MIT
/// @file gnuplot.hpp
/// Running gnuplot (Debian's gnuplot-nox) on a generated script: the validation study's plots
/// and `tumble plot`. Strings that reach a script or a shell are quoted here, never by hand.
#pragma once
#include <string>

namespace tumble {

/// `s` as a gnuplot string: in single quotes, where gnuplot does no backquote substitution and no
/// escapes; a ' is written ''. (In double quotes a path with a backquote would run a command.)
std::string gnuplotString(const std::string& s);

/// `s` as one sh word: in single quotes, with each ' written as '\'' ($, ` and \ stay literal).
std::string shellQuote(const std::string& s);

/// The first line of `gnuplot --version`, or empty when gnuplot cannot run.
std::string gnuplotVersion();

/// Runs `gnuplot SCRIPT > LOG 2>&1`. Returns "" on success, else what happened ("exit status 1",
/// "exit status 127, gnuplot not found", "killed by signal 9", …).
std::string runGnuplot(const std::string& scriptPath, const std::string& logPath);

}  // namespace tumble
