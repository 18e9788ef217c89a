// Richardson's extrapolation and the grid convergence index (post/grid_convergence.hpp) against
// the worked examples of Celik et al. (2008), J. Fluids Eng. 130, 078001, Table 1, and against
// sequences made from a known error expansion.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "post/grid_convergence.hpp"

using namespace skred;

namespace {

// Celik et al.'s representative cell size h = (1/N)^(1/2) of a 2D grid of N cells, and so
// r = (N_fine / N_coarse)^(1/2).
double ratio(double n_fine, double n_coarse) { return std::sqrt(n_fine / n_coarse); }

}  // namespace

// The three columns of Table 1 (a backward-facing step on 2D grids): the dimensionless
// reattachment length on 18,000, 8,000 and 4,500 cells (r21 = 1.5, r32 = 1.333, so p needs the
// iteration of step 3), and two axial velocities on 18,000, 4,500 and 980 cells, one with p < 1
// and one oscillating (s = -1 in step 3; Celik et al. report it with the same formulas). The
// second column's e_ext is checked against its definition (step 5) with the table's phi_ext.
TEST(GridConvergence, CeliksThreeExamples) {
  struct Column {
    double n1, n2, n3, phi1, phi2, phi3;
    ConvergenceKind kind;
    double p, ext, ea_percent, eext_percent, gci_percent;
  };
  const Column table[] = {
      {18000, 8000, 4500, 6.063, 5.972, 5.863, ConvergenceKind::monotone, 1.53, 6.1685, 1.5, 1.7, 2.2},
      {18000, 4500, 980, 10.7880, 10.7250, 10.6050, ConvergenceKind::monotone, 0.75, 10.8801, 0.6,
       100.0 * (10.8801 - 10.788) / 10.8801, 1.1},
      {18000, 4500, 980, 6.0042, 5.9624, 6.0909, ConvergenceKind::oscillatory, 1.51, 6.0269, 0.7, 0.4, 0.5},
  };
  for (const Column& c : table) {
    const GridConvergence g = grid_convergence(c.phi1, c.phi2, c.phi3, ratio(c.n1, c.n2), ratio(c.n2, c.n3));
    EXPECT_EQ(g.kind, c.kind) << c.phi1;
    EXPECT_NEAR(g.order, c.p, 0.005) << c.phi1;
    EXPECT_NEAR(g.extrapolated, c.ext, 0.00005) << c.phi1;
    EXPECT_NEAR(100.0 * g.approximate_error, c.ea_percent, 0.05) << c.phi1;
    EXPECT_NEAR(100.0 * g.extrapolated_error, c.eext_percent, 0.05) << c.phi1;
    EXPECT_NEAR(100.0 * g.gci_fine, c.gci_percent, 0.05) << c.phi1;
  }
}

// phi(h) = phi0 + C h^p exactly: the extrapolation recovers phi0 and p, and predicts phi(h/4)
// from phi(h/2), phi(h) and phi(2h), for the first and second order and a halving ratio.
TEST(GridConvergence, RecoversAKnownErrorExpansion) {
  for (const double p : {1.0, 2.0, 0.6}) {
    const double phi0 = 4.2, C = -1.3, h = 0.25;
    const auto phi = [&](double hh) { return phi0 + C * std::pow(hh, p); };
    const GridConvergence g = grid_convergence(phi(h), phi(2 * h), phi(4 * h), 2.0, 2.0);
    EXPECT_EQ(g.kind, ConvergenceKind::monotone) << p;
    EXPECT_NEAR(g.order, p, 1e-9);
    EXPECT_NEAR(g.extrapolated, phi0, 1e-9);
    EXPECT_NEAR(g.next_change, phi(h / 2) - phi(h), 1e-9);
    EXPECT_NEAR(g.ratio, std::pow(2.0, -p), 1e-9);
    // With unequal ratios the iteration of step 3 finds the same order.
    const GridConvergence u = grid_convergence(phi(h), phi(1.5 * h), phi(2.7 * h), 1.5, 1.8);
    EXPECT_NEAR(u.order, p, 1e-8) << p;
    EXPECT_NEAR(u.extrapolated, phi0, 1e-8) << p;
  }
}

// Changes that do not shrink are not extrapolated (the 10 m slope's runout at 1, 0.5 and 0.25 m
// cells, docs/method.md: +1.455 m and then +1.664 m); two finest values that agree give a GCI
// of zero; bad ratios and values are refused.
TEST(GridConvergence, GrowingChangesAreNotExtrapolatedAndBadInputIsRefused) {
  const GridConvergence d = grid_convergence(3.988, 2.324, 0.869, 2.0, 2.0);
  EXPECT_EQ(d.kind, ConvergenceKind::diverging);
  EXPECT_NEAR(d.ratio, 1.664 / 1.455, 1e-12);
  EXPECT_TRUE(std::isnan(d.order));
  EXPECT_TRUE(std::isnan(d.extrapolated));
  EXPECT_TRUE(std::isnan(d.gci_fine));
  EXPECT_NEAR(d.approximate_error, 1.664 / 3.988, 1e-12);
  EXPECT_EQ(grid_convergence(1.0, 2.0, 2.0, 2.0, 2.0).kind, ConvergenceKind::diverging);    // eps32 = 0
  EXPECT_EQ(grid_convergence(1.0, 3.0, 2.0, 2.0, 2.0).kind, ConvergenceKind::diverging);    // R = -2
  EXPECT_EQ(grid_convergence(1.0, 0.0, 2.0, 2.0, 2.0).kind, ConvergenceKind::oscillatory);  // R = -1/2
  const GridConvergence same = grid_convergence(0.1094, 0.1094, 0.1095, 2.0, 2.0);
  EXPECT_EQ(same.kind, ConvergenceKind::unchanged);
  EXPECT_DOUBLE_EQ(same.extrapolated, 0.1094);
  EXPECT_DOUBLE_EQ(same.gci_fine, 0.0);
  EXPECT_THROW(grid_convergence(1.0, 2.0, 3.0, 1.0, 2.0), std::invalid_argument);
  EXPECT_THROW(grid_convergence(1.0, 2.0, 3.0, 2.0, 0.5), std::invalid_argument);
  EXPECT_THROW(grid_convergence(NAN, 2.0, 3.0, 2.0, 2.0), std::invalid_argument);
  EXPECT_STREQ(convergence_kind_name(ConvergenceKind::oscillatory), "oscillatory");
}
