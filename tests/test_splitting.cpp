// Material-point splitting (Thesis §3.4.1-3.4.2): every mode of eq. 3.25 / fig. 3.11 and the
// reference split of fig. 3.13 conserve mass, momentum, volume and the first moment of mass
// exactly; the children of the six modes tile the parent's deformed voxel; at the size floor
// or the cap a point is reshaped into a square instead; and a collapsing column runs to its
// end while its points multiply, with voxels far from the needles it has without splitting.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>

#include <Eigen/SVD>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "solver/splitting.hpp"
#include "temp_dir.hpp"

using namespace skred;

namespace {

struct Totals {
  double mass = 0, volume = 0;
  Vec<2> momentum = Vec<2>::Zero(), moment = Vec<2>::Zero();
};
Totals totals(const Particles<2>& P) {
  Totals t;
  for (std::size_t p = 0; p < P.size(); ++p) {
    t.mass += P.mass[p];
    t.volume += P.F[p].determinant() * P.volume0[p];
    t.momentum += P.mass[p] * P.v[p];
    t.moment += P.mass[p] * P.x[p];
  }
  return t;
}

// Corners of a point's deformed voxel x + F (+-l0) (Thesis eq. 3.6-3.12).
std::array<Vec<2>, 4> corners(const Particles<2>& P, std::size_t p) {
  const Vec<2> a = P.F[p].col(0) * P.half0[p][0], b = P.F[p].col(1) * P.half0[p][1];
  return {P.x[p] - a - b, P.x[p] + a - b, P.x[p] + a + b, P.x[p] - a + b};
}

// Is y inside (or on) the parallelogram x + F [-l0, l0]^2?
bool inside(const Vec<2>& y, const Vec<2>& x, const Mat<2>& F, const Vec<2>& l0) {
  const Vec<2> r = F.inverse() * (y - x);
  return std::abs(r[0]) <= l0[0] * (1 + 1e-12) && std::abs(r[1]) <= l0[1] * (1 + 1e-12);
}

Particles<2> one_point(const Mat<2>& F) {
  Particles<2> P;
  P.add(Vec<2>(1.0, 2.0), Vec<2>(0.3, -0.2), 4.0, 0.25, Vec<2>(0.25, 0.25), 0, 0);
  P.enable_splitting();  // F_split = I from here on, and then it deforms with F
  P.F[0] = F;
  P.stress[0][0] = -1234.0;
  return P;
}

SplitSettings all_split() {
  SplitSettings s;
  s.body_splits = {1};
  return s;
}

}  // namespace

TEST(Splitting, EveryModeConservesAndTilesTheDeformedVoxel) {
  struct Case {
    const char* name;
    Mat<2> F;
    int axis;  // expected separation axis
    int i, j;  // the component reset
  };
  Mat<2> stretch_x, stretch_y, squeeze_x, squeeze_y, shear_xy, shear_yx;
  stretch_x << 2.2, 0.1, 0.0, 1.0;
  stretch_y << 1.0, 0.0, 0.2, 2.5;
  squeeze_x << 0.4, 0.0, 0.1, 1.6;
  squeeze_y << 1.7, 0.1, 0.0, 0.45;
  shear_xy << 1.0, 1.3, 0.0, 1.0;
  shear_yx << 1.0, 0.0, -1.4, 1.0;
  const Case cases[] = {{"F11 > alpha", stretch_x, 0, 0, 0},  {"F22 > alpha", stretch_y, 1, 1, 1},
                        {"F11 < beta", squeeze_x, 1, 0, 0},   {"F22 < beta", squeeze_y, 0, 1, 1},
                        {"|F12| > gamma", shear_xy, 1, 0, 1}, {"|F21| > gamma", shear_yx, 0, 1, 0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Particles<2> P = one_point(c.F);
    const Totals before = totals(P);
    const Vec<2> x0 = P.x[0], l0 = P.half0[0];
    ASSERT_EQ(split_points(P, all_split()), 1);
    ASSERT_EQ(P.size(), 2u);
    const Totals after = totals(P);
    EXPECT_NEAR(after.mass, before.mass, 1e-15 * before.mass);
    EXPECT_NEAR(after.volume, before.volume, 1e-12 * before.volume);
    EXPECT_LT((after.momentum - before.momentum).norm(), 1e-15);
    EXPECT_LT((after.moment - before.moment).norm(), 1e-12);
    // Children across the expected axis, halves of the deformed voxel: inside the parent,
    // their areas adding up to its area, their centres half a voxel apart along F e_axis.
    EXPECT_NEAR(P.half0[0][c.axis], 0.5 * l0[c.axis], 1e-15);
    const double parent_area = 4 * c.F.determinant() * l0.prod();
    double area = 0;
    for (std::size_t q = 0; q < 2; ++q) {
      area += 4 * P.F[q].determinant() * P.half0[q].prod();
      for (const auto& y : corners(P, q)) EXPECT_TRUE(inside(y, x0, c.F, l0));
      EXPECT_EQ(P.F[q], c.F);              // F inherited
      EXPECT_EQ(P.stress[q][0], -1234.0);  // stress inherited
      EXPECT_EQ(P.splits[q], 1);
      const Mat<2> Fs = P.F[q] * P.split_gauge[q];
      EXPECT_NEAR(Fs(c.i, c.j), c.i == c.j ? 1.0 : 0.0, 1e-14);  // the mode is reset
    }
    EXPECT_NEAR(area, parent_area, 1e-12 * parent_area);
    EXPECT_LT((P.x[1] - P.x[0] - c.F.col(c.axis) * l0[c.axis]).norm(), 1e-14);
  }
}

TEST(Splitting, ReferenceSplitAfterFourSplitsGivesSquaresOfHalfTheVolume) {
  Mat<2> F;
  F << 1.0, 1.5, 0.0, 1.0;  // a needle-bound shear
  Particles<2> P = one_point(F);
  P.enable_splitting();
  P.splits[0] = 4;
  const Totals before = totals(P);
  ASSERT_EQ(split_points(P, all_split()), 1);
  ASSERT_EQ(P.size(), 2u);
  const Totals after = totals(P);
  EXPECT_NEAR(after.mass, before.mass, 1e-15 * before.mass);
  EXPECT_NEAR(after.volume, before.volume, 1e-12 * before.volume);
  EXPECT_LT((after.momentum - before.momentum).norm(), 1e-15);
  EXPECT_LT((after.moment - before.moment).norm(), 1e-12);
  for (std::size_t q = 0; q < 2; ++q) {
    EXPECT_EQ(P.F[q], Mat<2>::Identity());
    EXPECT_EQ(P.split_gauge[q], Mat<2>::Identity());
    EXPECT_EQ(P.splits[q], 0);
    EXPECT_NEAR(P.half0[q][0], P.half0[q][1], 0.0);  // a square
    EXPECT_NEAR(4 * P.half0[q].prod(), 0.5 * before.volume, 1e-14);
    EXPECT_EQ(P.stress[q][0], -1234.0);  // stress carried
  }
}

// At the size floor (min_volume) a point that meets a criterion is not split: it keeps its
// place, mass, velocity, stress and current volume and becomes a square with F = F_split = I
// (the reference treatment with n = 1); above the floor the same point splits in two.
TEST(Splitting, AtTheSizeFloorAPointIsReshapedNotSplit) {
  Mat<2> F;
  F << 1.0, 1.5, 0.0, 1.1;  // sheared past gamma
  Particles<2> P = one_point(F);
  const Totals before = totals(P);
  const double volume = F.determinant() * P.volume0[0];  // 0.275
  SplitSettings floor = all_split();
  floor.min_volume = 0.5 * volume * (1 + 1e-9);  // the children would be just below it
  ASSERT_EQ(split_points(P, floor), 1);
  ASSERT_EQ(P.size(), 1u);
  const Totals after = totals(P);
  EXPECT_EQ(after.mass, before.mass);
  EXPECT_EQ(after.momentum, before.momentum);
  EXPECT_EQ(after.moment, before.moment);
  EXPECT_NEAR(after.volume, before.volume, 1e-15 * before.volume);
  EXPECT_EQ(P.F[0], Mat<2>::Identity());
  EXPECT_EQ(P.split_gauge[0], Mat<2>::Identity());
  EXPECT_EQ(P.half0[0][0], P.half0[0][1]);
  EXPECT_NEAR(4 * P.half0[0].prod(), volume, 1e-15);
  EXPECT_EQ(P.stress[0][0], -1234.0);
  EXPECT_EQ(split_points(P, floor), 0) << "a square meets no criterion";

  Particles<2> Q = one_point(F);
  floor.min_volume = 0.5 * volume * (1 - 1e-9);
  ASSERT_EQ(split_points(Q, floor), 1);
  EXPECT_EQ(Q.size(), 2u);
}

TEST(Splitting, NothingSplitsBelowTheCriteriaOrPastTheCap) {
  Mat<2> F;
  F << 1.9, 0.9, -0.9, 0.55;
  Particles<2> P = one_point(F);
  EXPECT_EQ(split_points(P, all_split()), 0);
  SplitSettings off = all_split();
  off.body_splits = {0};
  F << 3.0, 0.0, 0.0, 1.0;
  P.F[0] = F;
  EXPECT_EQ(split_points(P, off), 0);
  EXPECT_EQ(split_points(P, all_split()), 1);
  EXPECT_EQ(P.size(), 2u);
  // At the cap a point that meets a criterion is reshaped (a square, F = I), not split.
  P.F[0] = F;
  P.split_gauge[0] = Mat<2>::Identity();  // F_split = F
  SplitSettings capped = all_split();
  capped.max_points = 2;
  EXPECT_EQ(split_points(P, capped), 1);
  EXPECT_EQ(P.size(), 2u);
  EXPECT_EQ(P.F[0], Mat<2>::Identity());
  EXPECT_EQ(split_points(P, capped), 0);
}

TEST(Splitting, ACollapsingColumnSplitsUpToTheCap) {
  // A 1 x 2 m Mohr-Coulomb column (phi 20 deg, c 1 kPa) collapsing on a rough floor.
  const std::string text = R"(
[grid]
size = [6.0, 2.5]
cell_size = 0.125
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 2000
young = 5e6
poisson = 0.3
friction = 20
cohesion = 1000
[[body]]
material = "soil"
shape = "rectangle"
min = [0.0, 0.0]
max = [1.0, 2.0]
split = true
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
y_min = "fixed"
[solver]
end_time = 1.0
velocity_transfer = "flip"
volumetric_strain = "point"
[output]
interval = 0.5
)";
  const Scenario s = parse_scenario(text, "split.toml");
  EXPECT_EQ(s.splitting.max_points, 10 * 512);                             // 8 x 16 cells, 2 x 2 points each
  EXPECT_NEAR(s.splitting.min_volume, std::pow(0.125 * 0.125, 2), 1e-18);  // min_size 1/8
  // The largest aspect ratio of the drawn voxels (singular values of the edge matrix
  // [F e_0 l0_0, F e_1 l0_1]) before the last step.
  const auto run = [](const Scenario& sc, double& aspect) {
    const auto out = skred::test::fresh_temp_dir();
    RunOptions opt;
    opt.progress = false;
    opt.threads = 1;
    opt.edit_points = [&aspect](Particles<2>& P, const ExplicitSolver<2>&) {
      aspect = 1.0;
      for (std::size_t p = 0; p < P.size(); ++p) {
        Mat<2> edges;
        edges << P.F[p].col(0) * P.half0[p][0], P.F[p].col(1) * P.half0[p][1];
        const Vec<2> sv = Eigen::JacobiSVD<Mat<2>>(edges).singularValues();
        aspect = std::max(aspect, sv[0] / sv[1]);
      }
      return false;
    };
    const RunResult r = run_simulation(sc, out, opt);
    std::filesystem::remove_all(out);
    return r;
  };
  double aspect = 0.0, aspect_unsplit = 0.0;
  const RunResult r = run(s, aspect);
  ASSERT_TRUE(r.completed) << r.message;
  Scenario unsplit = s;
  unsplit.bodies[0].split = false;
  unsplit.splitting = SplitSettings{};
  ASSERT_TRUE(run(unsplit, aspect_unsplit).completed);
  std::printf("column with splitting: %ld points from 512, largest voxel aspect ratio %.2f (without: %.2f)\n",
              r.particles, aspect, aspect_unsplit);
  EXPECT_GT(r.particles, 512);
  EXPECT_LE(r.particles, 5120);
  // Splitting keeps the voxels from becoming needles (measured: 13.8 against 50.0; with no size
  // floor, min_size = 0, the points reach the cap of 5,120 and the largest is 29.1).
  EXPECT_LT(aspect, aspect_unsplit / 3);
}
