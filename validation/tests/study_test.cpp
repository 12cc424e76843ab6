// SPDX-License-Identifier: MIT
// The validation study (docs/validation.md) at quick depth on the CPU pipeline: every analytic
// physics check within its tolerance, and the runner writes report.md, summary.csv and the CSVs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "tumble/error.hpp"
#include "tumble/validation/study.hpp"

using namespace tumble;
using namespace tumble::validation::study;

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

// Every quick physics check passes on the CPU pipeline; failing checks are printed in full.
TEST(StudyTest, QuickPhysicsCatalogPasses) {
  StudyOptions o;
  o.depth = Depth::Quick;
  o.progress = true;
  const StudyReport rep = runStudy(physicsCases(), {Backend::Cpu}, o);
  ASSERT_EQ(rep.runs.size(), physicsCases().size());
  std::size_t checks = 0;
  for (const auto& run : rep.runs) {
    EXPECT_FALSE(run.result.checks.empty()) << run.result.id << " has no checks";
    EXPECT_FALSE(run.result.tables.empty()) << run.result.id << " has no tables";
    for (const auto& c : run.result.checks) {
      ++checks;
      EXPECT_TRUE(c.pass) << run.result.id << ": " << c.name << " [" << c.formula << "] measured " << c.measured
                          << " expected " << c.expected << " error " << c.error << " > tolerance " << c.tolerance
                          << " " << c.unit;
    }
  }
  std::printf("quick physics catalogue: %zu checks, %zu failed, %.1f s\n", checks, rep.failedChecks(), rep.seconds);
  EXPECT_TRUE(rep.pass());
}

// A check outside its tolerance fails the case and the study (the exit status of `tumble
// validate` follows from this).
TEST(StudyTest, FailingCheckFailsTheStudy) {
  std::vector<Case> cases{{"always_fails", [](const CaseContext&) {
                             CaseResult r;
                             r.id = "always_fails";
                             Check c;
                             c.name = "one";
                             c.measured = 2.0;
                             c.expected = 1.0;
                             c.error = 1.0;
                             c.tolerance = 0.1;
                             c.pass = false;
                             r.checks.push_back(c);
                             return r;
                           }},
                          {"throws", [](const CaseContext&) -> CaseResult { throw std::runtime_error("boom"); }}};
  StudyOptions o;
  o.progress = false;
  const StudyReport rep = runStudy(cases, {Backend::Cpu}, o);
  EXPECT_FALSE(rep.pass());
  EXPECT_EQ(rep.failedChecks(), 2u);
  EXPECT_FALSE(rep.runs[0].result.pass());
  o.caseIds = {"nope"};
  EXPECT_THROW(runStudy(cases, {Backend::Cpu}, o), Error);
}

// The runner writes report.md, summary.csv, one CSV per table and (with gnuplot) one PNG per plot.
TEST(StudyTest, RunnerWritesReportFolder) {
  const auto dir = std::filesystem::temp_directory_path() / ("tumble_study_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  StudyOptions o;
  o.depth = Depth::Quick;
  o.progress = false;
  o.outDir = (dir / "out").string();  // created, parents included
  o.caseIds = {"free_fall"};
  StudyReport rep = runStudy(physicsCases(), {Backend::Cpu}, o);
  ASSERT_EQ(rep.runs.size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "report.md"));
  const std::string summary = slurp(dir / "out" / "summary.csv");
  EXPECT_EQ(summary.rfind("case,backend,check,measured,expected,error,tolerance,unit,pass", 0), 0u) << summary;
  EXPECT_NE(summary.find("free_fall,cpu,"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "cpu" / "free_fall_sweep.csv"));
  const std::string sweep = slurp(dir / "out" / "cpu" / "free_fall_sweep.csv");
  EXPECT_EQ(sweep.rfind("dt,", 0), 0u) << sweep;
  const std::string md = slurp(dir / "out" / "report.md");
  EXPECT_NE(md.find("Free fall"), std::string::npos);
  if (rep.plotsDrawn) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "cpu" / "free_fall_speed.png"));
    EXPECT_NE(md.find("![") , std::string::npos);
  } else {
    EXPECT_NE(md.find("plots skipped"), std::string::npos) << "report must say why plots are missing";
  }
  std::filesystem::remove_all(dir);
}
