// SPDX-License-Identifier: MIT
// Coarse-grained fields (tumble/fields.hpp) against exact values: the packing fraction of FCC and
// simple cubic lattices, the mass and momentum each particle puts into the fields (the kernel
// integrates to one), the kinetic stress of a uniform motion (none) and of two streams, and the
// contact stress's virial (its integral is f ⊗ l), in 3-D and along an axis. The settled column
// (the stress against the weight above) is validation/tests/fields_column_test.cpp.
#include "tumble/fields.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "tumble/error.hpp"

using namespace tumble;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Particles {
  std::vector<float> x, v, radius, mass;
  std::vector<ContactForce> contacts;
  void add(double px, double py, double pz, double r, double m) {
    x.insert(x.end(), {float(px), float(py), float(pz)});
    radius.push_back(float(r));
    mass.push_back(float(m));
  }
  FieldFrame frame(bool velocities = false, bool withContacts = false) const {
    FieldFrame f;
    f.x = x.data();
    f.v = velocities ? v.data() : nullptr;
    f.radius = radius.data();
    f.mass = mass.data();
    f.n = radius.size();
    f.contacts = withContacts;
    f.contact = contacts.data();
    f.numContacts = contacts.size();
    return f;
  }
};

FieldGrid box(double lo, double hi, int n, int axis = -1) {
  FieldGrid g;
  g.lo = {lo, lo, lo};
  g.hi = {hi, hi, hi};
  g.n = {n, n, n};
  g.axis = axis;
  return g;
}

// A lattice of `cells`³ unit cells of side 1 with the given sites per cell, spheres of radius r.
Particles lattice(int cells, const std::vector<std::array<double, 3>>& sites, double r) {
  Particles p;
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (const auto& s : sites) p.add(i + s[0], j + s[1], k + s[2], r, 1.0);
  return p;
}

TEST(Fields, PackingFractionOfLattices) {
  // FCC: 4 spheres of radius 1/(2√2) per unit cell, π/(3√2) = 0.74048; simple cubic: one of
  // radius ½, π/6 = 0.52360. Points well inside (the kernel's support, √12 widths, within the
  // lattice). The error is the lattice's planes seen through the kernel: it falls as the width
  // grows past the spacing of the densest planes (0.58 cells in FCC, 1 in simple cubic).
  struct Case {
    const char* name;
    std::vector<std::array<double, 3>> sites;
    double r, want, width;
  };
  const Case cases[] = {
      {"FCC", {{0.25, 0.25, 0.25}, {0.75, 0.75, 0.25}, {0.75, 0.25, 0.75}, {0.25, 0.75, 0.75}}, 1.0 / (2.0 * std::sqrt(2.0)),
       kPi / (3.0 * std::sqrt(2.0)), 0.8},
      {"simple cubic", {{0.5, 0.5, 0.5}}, 0.5, kPi / 6.0, 1.6},
  };
  for (const Case& c : cases) {
    const Particles p = lattice(24, c.sites, c.r);
    CoarseGraining cg(box(6.0, 18.0, 5), c.width);
    cg.add(p.frame());
    const Fields f = cg.result();
    double worst = 0.0;
    for (const double nu : f.packing) worst = std::max(worst, std::fabs(nu - c.want));
    std::printf("%s, width %.1f: packing fraction %.6f (want %.6f), largest error %.2e over %zu points\n", c.name,
                c.width, f.packing[0], c.want, worst, f.packing.size());
    EXPECT_LT(worst, 2e-4 * c.want) << c.name;
    // Unit masses in unit cells: the density is the sites per cell.
    EXPECT_NEAR(f.density[0], double(c.sites.size()), 2e-4 * double(c.sites.size())) << c.name;
  }
}

TEST(Fields, EachParticlePutsItsMassAndMomentumIntoTheFields) {
  std::mt19937 rng(20261207);
  std::printf("seed 20261207\n");
  std::uniform_real_distribution<double> u(0.3, 0.7), s(-1.0, 1.0);
  Particles p;
  for (int k = 0; k < 50; ++k) {
    p.add(u(rng), u(rng), u(rng), 0.01, 0.5 + u(rng));
    p.v.insert(p.v.end(), {float(s(rng)), float(s(rng)), float(s(rng))});
  }
  double mass = 0.0, momentum[3] = {0, 0, 0};
  for (std::size_t i = 0; i < p.mass.size(); ++i) {
    mass += p.mass[i];
    for (int a = 0; a < 3; ++a) momentum[a] += double(p.mass[i]) * p.v[3 * i + a];
  }
  // 3-D, h = w / 2.5 (a Riemann sum of a smooth kernel), and a profile along each axis.
  for (const int axis : {-1, 0, 1, 2}) {
    const int n = axis < 0 ? 80 : 400;
    CoarseGraining cg(box(0.0, 1.0, n, axis), 0.03);
    cg.add(p.frame(true));
    const Fields f = cg.result();
    const double cell = axis < 0 ? std::pow(1.0 / n, 3) : 1.0 / n;  // a profile's density is per volume: × area 1
    double m = 0.0, q[3] = {0, 0, 0};
    for (std::size_t k = 0; k < f.density.size(); ++k) {
      m += f.density[k] * cell;
      for (int a = 0; a < 3; ++a) q[a] += f.momentum[3 * k + a] * cell;
    }
    EXPECT_NEAR(m, mass, 1e-4 * mass) << "axis " << axis;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(q[a], momentum[a], 1e-4 * mass) << "axis " << axis << ", " << a;
  }
}

TEST(Fields, KineticStressIsTheFluctuationAboutTheLocalVelocity) {
  Particles p;  // one particle, or two at one place: no fluctuation, whatever their velocity
  p.add(0.5, 0.5, 0.5, 0.01, 2.0);
  p.v = {3.0f, -1.0f, 0.5f};
  CoarseGraining one(box(0.0, 1.0, 20), 0.1);
  one.add(p.frame(true));
  Fields f = one.result();
  for (std::size_t k = 0; k < f.density.size(); ++k)
    for (int e = 0; e < 6; ++e) ASSERT_NEAR(f.kineticStress[6 * k + e], 0.0, 1e-9 * f.density[k]);
  // Two particles at one place moving apart along x at ±u: σᵏ_xx = ρ u², T = u² / 3, V = 0.
  p.add(0.5, 0.5, 0.5, 0.01, 2.0);
  p.v = {1.5f, 0.0f, 0.0f, -1.5f, 0.0f, 0.0f};
  CoarseGraining two(box(0.0, 1.0, 5), 0.1);
  two.add(p.frame(true));
  f = two.result();
  const std::size_t middle = 2 + 5 * (2 + 5 * 2);
  EXPECT_NEAR(f.kineticStress[6 * middle], f.density[middle] * 2.25, 1e-9 * f.density[middle]);
  EXPECT_NEAR(f.kineticStress[6 * middle + 1], 0.0, 1e-12);
  EXPECT_NEAR(f.temperature[middle], 0.75, 1e-9);
  EXPECT_NEAR(f.velocity[3 * middle], 0.0, 1e-9);
}

TEST(Fields, ContactStressIntegratesToTheVirial) {
  // Two spheres pressed along a tilted branch l = x_i − x_j with a force on i of a normal and a
  // tangential part: ∫ σᶜ dV = sym(f ⊗ l), per component, in 3-D and along each axis.
  Particles p;
  p.add(0.52, 0.49, 0.51, 0.02, 1.0);
  p.add(0.50, 0.47, 0.48, 0.02, 1.0);
  const double l[3] = {0.02, 0.02, 0.03};
  const double f[3] = {3.0, 2.5, 4.0};  // (not along l: a tangential part too)
  const double len = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  const double along = (f[0] * l[0] + f[1] * l[1] + f[2] * l[2]) / (len * len);
  ContactForce c{0, 1, {}, {}, float(0.04 - len)};
  c.normal = {float(along * l[0]), float(along * l[1]), float(along * l[2])};
  c.tangential = {float(f[0] - along * l[0]), float(f[1] - along * l[1]), float(f[2] - along * l[2])};
  p.contacts.push_back(c);
  const double fx = double(c.normal.x) + c.tangential.x, fy = double(c.normal.y) + c.tangential.y,
               fz = double(c.normal.z) + c.tangential.z;
  const double want[6] = {fx * l[0], fy * l[1], fz * l[2], 0.5 * (fx * l[1] + fy * l[0]), 0.5 * (fx * l[2] + fz * l[0]),
                          0.5 * (fy * l[2] + fz * l[1])};
  for (const int axis : {-1, 0, 1, 2}) {
    const int n = axis < 0 ? 60 : 300;
    CoarseGraining cg(box(0.2, 0.8, n, axis), 0.04);
    cg.add(p.frame(false, true));
    const Fields fl = cg.result();
    const double cell = axis < 0 ? std::pow(0.6 / n, 3) : 0.6 / n * 0.36;  // a profile: × its cross-section
    double sum[6] = {0, 0, 0, 0, 0, 0};
    for (std::size_t k = 0; k < fl.density.size(); ++k)
      for (int e = 0; e < 6; ++e) sum[e] += fl.contactStress[6 * k + e] * cell;
    for (int e = 0; e < 6; ++e) EXPECT_NEAR(sum[e], want[e], 1e-4 * 0.2) << "axis " << axis << ", component " << e;
  }
}

TEST(Fields, RefusesWhatItCannotCompute) {
  EXPECT_THROW(CoarseGraining(box(0.0, 1.0, 4), 0.0), Error);
  EXPECT_THROW(CoarseGraining(box(0.0, 1.0, 4), std::nan("")), Error);
  EXPECT_THROW(CoarseGraining(box(1.0, 1.0, 4), 0.1), Error);  // an empty box
  EXPECT_THROW(CoarseGraining(box(0.0, 1.0, 0), 0.1), Error);
  EXPECT_THROW(CoarseGraining(box(0.0, 1.0, 1000), 0.1), Error);  // 10⁹ points
  FieldGrid profile = box(0.0, 1.0, 10, 2);
  profile.hi[0] = 0.0;  // no cross-section
  EXPECT_THROW(CoarseGraining(profile, 0.1), Error);
  Particles p;
  p.add(0.5, 0.5, 0.5, 0.01, 1.0);
  p.v = {0.0f, 0.0f, 0.0f};
  CoarseGraining cg(box(0.0, 1.0, 4), 0.1);
  cg.add(p.frame(true));
  EXPECT_THROW(cg.add(p.frame(false)), Error) << "a frame without the velocities the first had";
}

}  // namespace
