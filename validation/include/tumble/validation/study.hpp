// SPDX-License-Identifier: MIT
/// @file study.hpp
/// The validation study (`tumble validate --out DIR`, docs/validation.md): a catalogue of cases,
/// each compared with an analytic formula or a stability criterion, run for every compiled
/// pipeline, written as report.md + CSV + PNG plots.
///
/// A case is a function that runs simulations and returns a CaseResult: named checks (measured
/// value, reference, tolerance, pass/fail), data tables (one CSV each) and plot requests (drawn
/// by gnuplot from those tables).
#pragma once
#include <cstdint>
#include <functional>
#include <cstdio>
#include <string>
#include <vector>

#include "tumble/pipeline.hpp"

namespace tumble::validation::study {

/// How much work a run of the catalogue does.
enum class Depth {
  Quick,  ///< the ctest version: few dt values, short horizons; every case still checked
  Full,   ///< the documented study: ≥ 5 dt values per sweep, long horizons
};

/// What every case gets.
struct CaseContext {
  Backend backend = Backend::Cpu;
  Depth depth = Depth::Full;
  std::uint64_t seed = 20261122;  ///< for any randomness; printed in the report
};

/// One pass/fail comparison with its reference.
struct Check {
  std::string name;       ///< e.g. "restitution e=0.5"
  std::string formula;    ///< what it is compared to, e.g. "e_meas vs e (linear spring-dashpot)"
  double measured = 0.0;
  double expected = 0.0;  ///< NaN when the check is a bound (see tolerance)
  double error = 0.0;     ///< the quantity compared with the tolerance (absolute or relative, see unit)
  double tolerance = 0.0;
  std::string unit;       ///< unit of `error`, e.g. "relative", "m", "m/s²"
  bool pass = false;
};

/// A table of numbers, written as DIR/<case id>_<name>.csv.
struct Table {
  std::string name;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

/// A plot of some columns of one table, drawn to DIR/<case id>_<name>.png by gnuplot.
struct Plot {
  std::string name;
  std::string title;
  std::string table;                ///< Table::name it reads
  std::string x, xlabel, ylabel;    ///< x column name and axis labels
  std::vector<std::string> y;       ///< y column names, one line each
  bool logx = false, logy = false;
  std::string groupBy;              ///< optional column whose distinct values give separate lines
};

struct CaseResult {
  std::string id;       ///< short file-safe name, e.g. "ground_restitution"
  std::string title;    ///< heading in report.md
  std::string summary;  ///< a paragraph (markdown): model, formula, what the numbers mean
  std::vector<Check> checks;
  std::vector<Table> tables;
  std::vector<Plot> plots;
  bool pass() const;    ///< every check passes
};

/// One entry of the catalogue.
struct Case {
  std::string id;
  std::function<CaseResult(const CaseContext&)> run;
};

/// The analytic physics cases (validation/src/study_physics.cpp): restitution, contact
/// duration, momentum, free fall, resting penetration, sliding, slopes, torque-free rotation,
/// Chung & Ooi impacts; each with a dt × integrator sweep (speed against error).
std::vector<Case> physicsCases();
/// The stability cases (validation/src/study_stability.cpp).
std::vector<Case> stabilityCases();
/// physicsCases() followed by stabilityCases().
std::vector<Case> allCases();

/// What runStudy() does.
struct StudyOptions {
  Depth depth = Depth::Full;
  std::string outDir;                 ///< report folder (created); empty = write nothing
  std::vector<std::string> caseIds;   ///< run only these ids (empty = all); unknown ids throw tumble::Error
  std::uint64_t seed = 20261122;
  bool progress = true;               ///< one line per case on stderr (case, backend, elapsed)
  std::string command;                ///< the command line, quoted in report.md
};

/// One case run on one backend.
struct CaseRun {
  Backend backend = Backend::Cpu;
  double seconds = 0.0;  ///< wall time of the case
  CaseResult result;
  std::string notSupported;  ///< the backend does not run the case's model yet (tumble::NotSupported): why
};

/// Everything runStudy() measured.
struct StudyReport {
  std::vector<CaseRun> runs;
  double seconds = 0.0;
  bool plotsDrawn = false;
  std::string plotNote;          ///< why plots were skipped, or the gnuplot version used
  bool pass() const;             ///< every check of every run passes
  std::size_t failedChecks() const;
  std::size_t totalChecks() const;
  std::size_t notSupported() const;  ///< runs whose backend does not run the case's model yet
};

/// Runs `cases` (filtered by options.caseIds) on every backend and, when options.outDir is set,
/// writes report.md, summary.csv, one CSV per table and one PNG per plot (gnuplot; skipped with
/// a note in report.md when gnuplot is missing). A case that throws becomes a failed check,
/// except tumble::NotSupported (the backend lacks the case's model): the run is marked not
/// supported, with the reason, and counts neither as passed nor as failed.
StudyReport runStudy(const std::vector<Case>& cases, const std::vector<Backend>& backends,
                     const StudyOptions& options);

/// Writes the report folder of a finished study (runStudy() calls it when outDir is set).
void writeReport(StudyReport& report, const StudyOptions& options);

/// Markdown table of every check of a report (also the body of summary.csv): used for stdout.
void printSummary(const StudyReport& report, std::FILE* out);

}  // namespace tumble::validation::study
