// SPDX-License-Identifier: MIT
// The coarse-grained stress of a settled column (issue 37, item 4): 972 spheres poured into a box
// periodic in x and y settle on a rough ground under hooke-history; a recording of ten frames
// with velocities and contact forces is coarse-grained along z (tumble/fields.hpp). At rest the
// momentum balance says that the vertical stress carries the weight above: σ_zz(z) = g ∫_z^∞ ρ dz'
// (the ground's contacts, which the recording does not hold, are the only forces missing: they
// count only within the kernel's reach of the ground). Checked away from the ground and the
// free surface, and as the straight line ρ_b g (H − z) of the bulk density.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "tumble/factory.hpp"
#include "tumble/fields.hpp"
#include "tumble/run.hpp"
#include "tumble/scene_io.hpp"

using namespace tumble;

namespace {

const char* kColumn = R"(
[scene]
name = "column"
dt = 1e-4
steps = 8200
seed = 3
gravity = [0, 0, -9.81]
[contact]
law = "hooke-history"
stiffness = 5000.0
gamma_n = 3000.0
friction = 0.5
[ground]
height = 0.0
friction = 0.5
[periodic]
x = [0.0, 0.1]
y = [0.0, 0.1]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.005
mass = 0.0013
elasticity = 0.3
[[group]]
shape = "ball"
count = [9, 9, 12]
spacing = 0.0111
origin = [0.006, 0.006, 0.006]
jitter = 0.0005
)";

TEST(FieldsColumn, VerticalStressCarriesTheWeightAbove) {
  const Scene scene = parseScene(kColumn, "column (fields_column_test.cpp)");
  std::printf("seed 3 (the group's jitter)\n");
  const std::string path = ::testing::TempDir() + "fields_column.bin";
  {
    tumble::Run run(scene);
    run.load(makePipeline(Backend::Cpu));
    run.advance(8000);  // settled: the ground carries the weight within 1e-4, speeds under 3 mm/s
    RecordSettings rs;
    rs.path = path;
    rs.stepsPerFrame = 20;
    rs.debug = true;
    rs.contactForces = true;
    run.record(rs);
    run.advance(200);
    run.closeRecording();
  }
  RecordingReader reader(path);
  ASSERT_EQ(reader.numFrames(), 10u);
  FieldOptions o;
  o.width = 0.005;  // a particle radius
  o.grid.axis = 2;
  o.grid.lo = {0.0, 0.0, 0.0};
  o.grid.hi = {0.1, 0.1, 0.15};
  o.grid.n = {1, 1, 300};
  const Fields f = coarseGrainRecording(reader, o);
  std::filesystem::remove(path);
  ASSERT_TRUE(f.velocities && f.contacts);
  const std::size_t n = f.density.size();
  const double h = 0.15 / double(n), g = 9.81;
  // The weight above each point, g ∫_z^∞ ρ dz' (midpoint sums; the density is smooth on h = w / 10).
  std::vector<double> above(n, 0.0);
  for (std::size_t k = n; k-- > 0;) above[k] = (k + 1 < n ? above[k + 1] + 0.5 * g * h * f.density[k + 1] : 0.0) +
                                                0.5 * g * h * f.density[k];
  // The bulk: 3.5 widths (the kernel's reach) above the ground and below the surface.
  double top = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    if (f.packing[k] > 0.3) top = o.grid.at(2, int(k));
  const double from = 0.02, to = top - 0.02;
  ASSERT_GT(to - from, 0.04) << "the column is " << top << " m high";
  double worst = 0.0, rhoBulk = 0.0, sz = 0.0, szz = 0.0, ss = 0.0, sxs = 0.0, kinetic = 0.0;
  int count = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double z = o.grid.at(2, int(k));
    if (z < from || z > to) continue;
    const double s = f.contactStress[6 * k + 2];
    worst = std::max(worst, std::fabs(s - above[k]));
    kinetic = std::max(kinetic, std::fabs(f.kineticStress[6 * k + 2]));
    rhoBulk += f.density[k];
    sz += z, szz += z * z, ss += s, sxs += z * s;
    ++count;
  }
  rhoBulk /= count;
  const double slope = (count * sxs - sz * ss) / (count * szz - sz * sz);
  const double stressBottom = above[std::size_t(from / h)];
  std::printf("column %.4f m high; bulk density %.1f kg/m^3 (packing %.3f); from z = %.3f to %.3f m: "
              "|sigma_zz - g int rho| <= %.3g Pa of %.1f Pa; d sigma_zz / dz = %.1f Pa/m against -rho_b g = %.1f; "
              "kinetic sigma_zz <= %.2g Pa\n",
              top, rhoBulk, f.packing[std::size_t(0.05 / h)], from, to, worst, stressBottom, slope, -rhoBulk * g, kinetic);
  EXPECT_LT(worst, 1e-3 * stressBottom) << "the contact stress must carry the weight above";
  EXPECT_NEAR(slope, -rhoBulk * g, 0.01 * rhoBulk * g) << "sigma_zz = rho_b g (H - z) in the bulk";
  EXPECT_LT(kinetic, 1e-4 * stressBottom) << "a column at rest";
  const double nu = f.packing[std::size_t(0.05 / h)];
  EXPECT_TRUE(nu > 0.54 && nu < 0.65) << "a random packing of spheres, " << nu;
}

}  // namespace
