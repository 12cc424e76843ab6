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
  // The branch comes from the unit normal and the overlap (contactBranch()): r_i + r_j − δ = |l|.
  ContactForce c{0, 1, {float(l[0] / len), float(l[1] / len), float(l[2] / len)}, float(along * len), {}, float(0.04 - len)};
  c.tangential = {float(f[0] - along * l[0]), float(f[1] - along * l[1]), float(f[2] - along * l[2])};
  p.contacts.push_back(c);
  const Vec3f normal = c.normal();
  const double fx = double(normal.x) + c.tangential.x, fy = double(normal.y) + c.tangential.y,
               fz = double(normal.z) + c.tangential.z;
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

namespace {

// A profile takes the particles in its box's cross-section, per its area (or the area given).
TEST(Fields, AProfileTakesItsCrossSection) {
  std::mt19937 rng(7);
  std::printf("seed 7\n");
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Particles p;
  for (int k = 0; k < 20000; ++k) p.add(u(rng), u(rng), u(rng), 0.001, 1.0);  // density 20000
  for (const double side : {1.0, 0.5, 0.25}) {
    FieldGrid g = box(0.0, 1.0, 10, 2);
    g.hi[0] = side;
    CoarseGraining cg(g, 0.05);
    cg.add(p.frame());
    const Fields f = cg.result();
    EXPECT_NEAR(f.density[5], 20000.0, 0.05 * 20000.0) << "box x up to " << side;
    g.area = 2.0 * side;  // the same particles per twice the area
    CoarseGraining half(g, 0.05);
    half.add(p.frame());
    EXPECT_NEAR(half.result().density[5], 0.5 * f.density[5], 1e-9 * f.density[5]);
  }
}

// The branch of a contact comes from its unit normal and its overlap, whatever the positions say
// (across a periodic boundary the centres are a period apart) and whatever the force's sign.
TEST(Fields, TheBranchComesFromTheContact) {
  ContactForce push{0, 1, {1.0f, 0.0f, 0.0f}, 2.0f, {0.0f, 0.5f, 0.0f}, 0.05f};
  ContactForce pull = push, none = push;
  pull.fn = -1.0f;
  none.fn = 0.0f;
  for (const ContactForce& c : {push, pull, none}) {
    const std::array<double, 3> l = contactBranch(c, 0.5f, 0.5f);
    EXPECT_NEAR(l[0], 0.95, 1e-6) << "fn " << c.fn;
    EXPECT_EQ(l[1], 0.0);
  }
  // In the fields: x_i at 0.2, x_j drawn at 9.25 (its image at −0.75 in a period of 10): the
  // virial is fn (x_i − x_j's image) = ±0.95, the shear's f_y l_x / 2 the same for each.
  Particles p;
  p.add(0.2, 0.0, 0.0, 0.5, 1.0);
  p.add(9.25, 0.0, 0.0, 0.5, 1.0);
  for (const ContactForce& c : {push, pull, none}) {
    p.contacts = {c};
    CoarseGraining cg(box(-3.0, 3.0, 600, 0), 0.2);
    cg.add(p.frame(false, true));
    const Fields f = cg.result();
    double xx = 0.0, xy = 0.0;
    for (std::size_t k = 0; k < f.density.size(); ++k)
      xx += f.contactStress[6 * k] * 0.01 * 36.0, xy += f.contactStress[6 * k + 3] * 0.01 * 36.0;
    EXPECT_NEAR(xx, c.fn * 0.95, 1e-6) << "fn " << c.fn;
    EXPECT_NEAR(xy, 0.5 * 0.5 * 0.95, 1e-6) << "fn " << c.fn << ": the tangential force with no normal one";
  }
}

// The line integral along a branch 8 widths long (a width of a quarter radius) against the
// marginal kernel integrated along it in 20 000 steps: the contact stress's profile point by point.
TEST(Fields, TheLineIntegralHoldsForShortWidths) {
  const double w = 0.005, c = std::sqrt(12.0) * w, len = 8.0 * w;
  Particles p;
  p.add(0.5, 0.5, 0.5, 0.02, 1.0);
  p.add(0.5 - len, 0.5, 0.5, 0.02, 1.0);
  p.contacts = {ContactForce{0, 1, {1.0f, 0.0f, 0.0f}, 1.0f, {0.0f, 0.0f, 0.0f}, float(0.04 - len)}};
  const double l = double(0.02f) + 0.02f - p.contacts[0].overlap;  // the branch contactBranch() gives
  FieldGrid g = box(0.4, 0.6, 400, 0);
  CoarseGraining cg(g, w);
  cg.add(p.frame(false, true));
  const Fields f = cg.result();
  const auto marginal = [&](double z) {  // Lucy's kernel integrated over the plane across x, area 0.04
    const double t = std::fabs(z) / c;
    if (t >= 1.0) return 0.0;
    return 105.0 / (8.0 * c) * (0.1 - t * t / 2 + 1.5 * t * t * t * t - 1.6 * std::pow(t, 5) + 0.5 * std::pow(t, 6)) / 0.04;
  };
  double worst = 0.0, peak = 0.0;
  for (int k = 0; k < 400; ++k) {
    const double x = g.at(0, k);
    double ref = 0.0;
    for (int s = 0; s < 20000; ++s) ref += marginal(x - 0.5 + (s + 0.5) / 20000.0 * l) / 20000.0;
    ref *= 1.0 * l;  // f_x l_x
    worst = std::max(worst, std::fabs(f.contactStress[6 * std::size_t(k)] - ref));
    peak = std::max(peak, ref);
  }
  std::printf("branch of 8 widths: largest error %.2e of %.3g\n", worst, peak);
  EXPECT_LT(worst, 1e-5 * peak);
}

}  // namespace
