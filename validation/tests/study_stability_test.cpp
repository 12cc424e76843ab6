// SPDX-License-Identifier: MIT
// The stability cases of the validation study (validation/src/study_stability.cpp) at
// Depth::Quick on the CPU pipeline: every check must pass.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "tumble/validation/study.hpp"

using namespace tumble;
using namespace tumble::validation::study;

namespace {

class StabilityStudyTest : public ::testing::TestWithParam<std::string> {};

std::vector<std::string> caseIds() {
  std::vector<std::string> ids;
  for (const auto& c : stabilityCases()) ids.push_back(c.id);
  return ids;
}

}  // namespace

TEST_P(StabilityStudyTest, QuickChecksPass) {
  const auto cases = stabilityCases();
  const Case* found = nullptr;
  for (const auto& c : cases)
    if (c.id == GetParam()) found = &c;
  ASSERT_NE(found, nullptr);
  CaseContext ctx;
  ctx.backend = Backend::Cpu;
  ctx.depth = Depth::Quick;
  const auto t0 = std::chrono::steady_clock::now();
  const CaseResult r = found->run(ctx);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.id, GetParam());
  EXPECT_FALSE(r.title.empty());
  EXPECT_FALSE(r.summary.empty());
  ASSERT_FALSE(r.checks.empty());
  std::printf("%s (%.2f s):\n", r.id.c_str(), sec);
  for (const auto& c : r.checks) {
    std::printf("  [%s] %s: measured %.6g expected %.6g error %.3g (tol %.3g %s)\n", c.pass ? "ok" : "FAIL",
                c.name.c_str(), c.measured, c.expected, c.error, c.tolerance, c.unit.c_str());
    EXPECT_TRUE(c.pass) << c.name << " (" << c.formula << "): measured " << c.measured << ", expected "
                        << c.expected << ", error " << c.error << " > tolerance " << c.tolerance << " " << c.unit;
  }
  // Tables and plots must be consistent: every plot names an existing table and columns.
  for (const auto& p : r.plots) {
    const Table* t = nullptr;
    for (const auto& tb : r.tables)
      if (tb.name == p.table) t = &tb;
    ASSERT_NE(t, nullptr) << "plot " << p.name << " reads a missing table " << p.table;
    auto has = [&](const std::string& col) {
      for (const auto& c : t->columns)
        if (c == col) return true;
      return false;
    };
    EXPECT_TRUE(has(p.x)) << p.name << ": no column " << p.x;
    for (const auto& y : p.y) EXPECT_TRUE(has(y)) << p.name << ": no column " << y;
    if (!p.groupBy.empty()) {
      EXPECT_TRUE(has(p.groupBy)) << p.name << ": no column " << p.groupBy;
    }
  }
  for (const auto& t : r.tables)
    for (const auto& row : t.rows) EXPECT_EQ(row.size(), t.columns.size()) << "table " << t.name;
}

INSTANTIATE_TEST_SUITE_P(Cases, StabilityStudyTest, ::testing::ValuesIn(caseIds()),
                         [](const auto& info) { return info.param; });
