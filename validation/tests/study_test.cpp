// SPDX-License-Identifier: MIT
// The validation study (docs/validation.md) at quick depth on the CPU pipeline: every analytic
// physics check within its tolerance, and the runner writes report.md, summary.csv and the CSVs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
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

// A case whose model the backend does not have yet (tumble::NotSupported, as the CUDA pipeline
// throws for mesh walls and periodic boundaries) is marked not run, with the reason,
// and fails nothing; any other exception still fails the case.
TEST(StudyTest, NotSupportedMarksTheRunInsteadOfFailingIt) {
  std::vector<Case> cases{{"needs_walls", [](const CaseContext&) -> CaseResult {
                             throw NotSupported("the CUDA pipeline has no walls yet");
                           }}};
  StudyOptions o;
  o.progress = false;
  o.outDir = testing::TempDir() + "tumble_study_not_supported";
  const StudyReport rep = runStudy(cases, {Backend::Cpu}, o);
  ASSERT_EQ(rep.runs.size(), 1u);
  EXPECT_EQ(rep.runs[0].notSupported, "the CUDA pipeline has no walls yet");
  EXPECT_TRUE(rep.pass());
  EXPECT_EQ(rep.failedChecks(), 0u);
  EXPECT_EQ(rep.notSupported(), 1u);
  std::ifstream md(o.outDir + "/report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("not supported: the CUDA pipeline has no walls yet"), std::string::npos) << text;
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

namespace {

bool haveGnuplot() { return std::system("gnuplot --version >/dev/null 2>&1") == 0; }

// Sets an environment variable for one scope and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (m_old) ::setenv(m_name, m_old->c_str(), 1);
    else ::unsetenv(m_name);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* m_name;
  std::optional<std::string> m_old;
};

}  // namespace

// The report folder's name reaches the shell that runs gnuplot: $, ` and quotes must stay
// literal, and the PNGs must land in the folder asked for.
TEST(StudyTest, PlotsLandInAFolderWhoseNameHasShellCharacters) {
  if (!haveGnuplot()) GTEST_SKIP() << "gnuplot not installed";
  const auto base = std::filesystem::temp_directory_path() / ("tumble_study_quote_" + std::to_string(::getpid()));
  std::filesystem::remove_all(base);
  const auto dir = base / "it's $HOME and $(echo x) and `echo y`";
  StudyOptions o;
  o.depth = Depth::Quick;
  o.progress = false;
  o.outDir = dir.string();
  o.caseIds = {"free_fall"};
  StudyReport rep = runStudy(physicsCases(), {Backend::Cpu}, o);
  EXPECT_TRUE(rep.plotsDrawn) << rep.plotNote << "\n" << slurp(dir / "plots.log");
  EXPECT_TRUE(std::filesystem::exists(dir / "cpu" / "free_fall_speed.png"));
  EXPECT_EQ(rep.plotNote.find("exit status"), std::string::npos) << rep.plotNote;
  EXPECT_NE(slurp(dir / "report.md").find("](cpu/free_fall_speed.png)"), std::string::npos);
  // Nothing went to a folder named after an expansion.
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(base)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), dir.filename());
  }
  EXPECT_EQ(entries, 1u);
  std::filesystem::remove_all(base);
}

// A PNG left in the folder by an earlier report is not shown as this report's plot when gnuplot
// fails, and the note gives gnuplot's exit status (1), not the raw wait status (256).
TEST(StudyTest, StalePlotIsNotReportedWhenGnuplotFails) {
  const auto dir = std::filesystem::temp_directory_path() / ("tumble_study_stale_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "bin");
  std::filesystem::create_directories(dir / "out" / "cpu");
  // A gnuplot that answers --version and fails at everything else; the runner finds it on PATH.
  {
    std::ofstream f(dir / "bin" / "gnuplot");
    f << "#!/bin/sh\nif [ \"$1\" = --version ]; then echo 'gnuplot 0.0 (fake)'; exit 0; fi\necho fake failure >&2\n"
         "exit 1\n";
  }
  std::filesystem::permissions(dir / "bin" / "gnuplot", std::filesystem::perms::owner_all);
  const auto png = dir / "out" / "cpu" / "free_fall_speed.png";
  std::ofstream(png) << "stale image from an earlier report";
  StudyOptions o;
  o.depth = Depth::Quick;
  o.progress = false;
  o.outDir = (dir / "out").string();
  o.caseIds = {"free_fall"};
  StudyReport rep;
  {
    const ScopedEnv path("PATH", (dir / "bin").string());
    rep = runStudy(physicsCases(), {Backend::Cpu}, o);
  }
  EXPECT_FALSE(rep.plotsDrawn);
  EXPECT_FALSE(std::filesystem::exists(png)) << "the stale PNG must be removed";
  EXPECT_NE(rep.plotNote.find("gnuplot 0.0 (fake)"), std::string::npos) << rep.plotNote;
  EXPECT_NE(rep.plotNote.find("exit status 1,"), std::string::npos) << rep.plotNote;
  EXPECT_EQ(rep.plotNote.find("256"), std::string::npos) << rep.plotNote;
  const std::string md = slurp(dir / "out" / "report.md");
  EXPECT_EQ(md.find("!["), std::string::npos) << "no plot may be linked:\n" << md;
  EXPECT_NE(md.find("plot `speed` not drawn: gnuplot did not write it"), std::string::npos) << md;
  EXPECT_NE(slurp(dir / "out" / "plots.log").find("fake failure"), std::string::npos);
  std::filesystem::remove_all(dir);
}
