// SPDX-License-Identifier: MIT
// The coarse-grained stress of a settled column (issue 37, item 4), as the validation study's
// case column_stress runs it at full depth (validation/src/study_physics_granular.cpp): 972
// spheres of scenes/column.toml settled in a box periodic in x and y, ten frames with velocities
// and contact forces coarse-grained along z (tumble/fields.hpp). At rest the contact stress must
// carry the weight above, σ_zz(z) = g ∫_z^∞ ρ dz', away from the ground (whose contacts the
// recording does not hold) and the free surface, and fall as ρ_b g (H − z) in the bulk; the
// kinetic stress must vanish. Each check of the case is a test here (2 s).
#include <gtest/gtest.h>

#include <cstdio>

#include "tumble/validation/study.hpp"

using namespace tumble;
using namespace tumble::validation::study;

TEST(FieldsColumn, VerticalStressCarriesTheWeightAbove) {
  StudyOptions o;
  o.depth = Depth::Full;
  o.caseIds = {"column_stress"};
  o.progress = false;
  const StudyReport rep = runStudy(physicsCases(), {Backend::Cpu}, o);
  ASSERT_EQ(rep.runs.size(), 1u);
  const CaseResult& r = rep.runs[0].result;
  EXPECT_GE(r.checks.size(), 5u) << "the crystal, the balance, the slope, the kinetic stress, the packing";
  for (const Check& c : r.checks) {
    std::printf("%s: %.6g (expected %.6g, error %.3g, tolerance %.3g%s)\n", c.name.c_str(), c.measured, c.expected,
                c.error, c.tolerance, c.unit.c_str());
    EXPECT_TRUE(c.pass) << c.name << " [" << c.formula << "]";
  }
}
