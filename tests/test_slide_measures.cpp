// Slide measures from the material (issue 12): runout and heights come from the points and
// their current half-sizes l0 det(F)^(1/d), along the connected deposit, so a point that has
// flown off or a voxel sheared into a needle cannot move the front.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "run/slide_measures.hpp"
#include "scenario/scenario.hpp"

using namespace skred;

namespace {

// A block of points 1 m high on [0, 2] (0.1 m points), and what moved.
Particles<2> block(double right_edge) {
  Particles<2> P;
  const double q = 0.1;
  for (double x = 0.5 * q; x < right_edge; x += q)
    for (double y = 0.5 * q; y < 1.0; y += q)
      P.add(Vec<2>(x, y), Vec<2>::Zero(), 1.0, q * q, Vec<2>::Constant(0.5 * q), 0, 0);
  return P;
}

// A point [x - hx, x + hx] x [y - hy, y + hy].
void add(Particles<2>& P, double x, double y, double hx, double hy) {
  P.add(Vec<2>(x, y), Vec<2>::Zero(), 1.0, 4 * hx * hy, Vec<2>(hx, hy), 0, 0);
}

// A slope by hand (1 m columns, points 0.9 m wide so no point touches a neighbour): ground
// 1 m deep everywhere on [0, 20], the surface 4, 3, 2 m high over the first three columns.
Particles<2> hand_made_slope() {
  Particles<2> slope;
  for (int k = 0; k < 20; ++k) add(slope, k + 0.5, 0.5, 0.45, 0.5);
  add(slope, 0.5, 2.5, 0.45, 1.5);
  add(slope, 1.5, 2.0, 0.45, 1.0);
  add(slope, 2.5, 1.5, 0.45, 0.5);
  return slope;
}

}  // namespace

TEST(SlideMeasures, ADetachedPointOrANeedleDoesNotMoveTheFront) {
  const double width = 0.1;
  const int bins = 100;  // columns over [0, 10]
  const Particles<2> start = block(2.0);
  const SurfaceProfile before = start_profile(start, 0.0, width, bins, 0.5 * width);
  const auto runout = [&](const Particles<2>& P) { return runout_of(before, P, 0.0, width, 0.5 * width); };
  // The block spread to 3 m: the front advanced 1 m.
  Particles<2> spread = block(3.0);
  EXPECT_NEAR(runout(spread).x_max, 1.0, 1e-9);
  EXPECT_EQ(runout(spread).x_min, 0.0);
  // A point thrown 4 m beyond the deposit, across empty columns: no change.
  Particles<2> thrown = spread;
  thrown.add(Vec<2>(7.05, 0.05), Vec<2>::Zero(), 1.0, 0.01, Vec<2>::Constant(0.05), 0, 0);
  EXPECT_NEAR(runout(thrown).x_max, 1.0, 1e-9);
  // Beyond a single empty column (3.1-3.2): still no change.
  thrown = spread;
  thrown.add(Vec<2>(3.25, 0.05), Vec<2>::Zero(), 1.0, 0.01, Vec<2>::Constant(0.04), 0, 0);
  EXPECT_NEAR(runout(thrown).x_max, 1.0, 1e-9);
  // A voxel at the front sheared into a needle (F = [[1, 40], [0, 1]], det F = 1): its
  // corners reach 2 m further, the material it stands for does not.
  Particles<2> needle = spread;
  const std::size_t p = needle.size() - 1;  // the top right point
  needle.F[p] << 1.0, 40.0, 0.0, 1.0;
  EXPECT_NEAR(runout(needle).x_max, 1.0, 1e-9);
  const MaterialExtent e = material_extent(needle);
  EXPECT_NEAR(e.x_max, 3.0, 1e-12);
  EXPECT_NEAR(e.y_max - e.y_min, 1.0, 1e-12);
  // A compressed point (det F = 1/4) stands for half the length in 2D.
  Particles<2> squeezed;
  squeezed.add(Vec<2>(0.05, 0.05), Vec<2>::Zero(), 1.0, 0.01, Vec<2>::Constant(0.05), 0, 0);
  squeezed.F[0] = 0.5 * Mat<2>::Identity();
  EXPECT_NEAR(material_extent(squeezed).y_min, 0.05 - 0.025, 1e-12);
}

// A hand-made front: the block [0, 2] x [0, 1] and, after, two points beyond it covering
// [2, 2.2] x [0, 0.2] and [2.2, 2.34] x [0, 0.14]: the front is their outer edge, 2.34 m, the
// toe the block's side, 2 m, so the runout is 0.34 m (not a whole number of 0.1 m columns).
TEST(SlideMeasures, RunoutIsTheFrontEdgeMinusTheToeEdge) {
  const double width = 0.1;
  const SurfaceProfile before = start_profile(block(2.0), 0.0, width, 100, 0.5 * width);
  Particles<2> after = block(2.0);
  after.add(Vec<2>(2.1, 0.1), Vec<2>::Zero(), 1.0, 0.04, Vec<2>::Constant(0.1), 0, 0);
  after.add(Vec<2>(2.27, 0.07), Vec<2>::Zero(), 1.0, 0.02, Vec<2>::Constant(0.07), 0, 0);
  const Runout r = runout_of(before, after, 0.0, width, 0.5 * width);
  EXPECT_NEAR(r.x_max, 0.34, 1e-12);
  EXPECT_EQ(r.x_min, 0.0);  // nothing went towards -x
  // A point compressed to det F = 1/4 stands for half its length: the front at 2.2 + 0.07.
  after.F[after.size() - 1] = 0.5 * Mat<2>::Identity();
  after.x[after.size() - 1][0] = 2.2 + 0.035;
  EXPECT_NEAR(runout_of(before, after, 0.0, width, 0.5 * width).x_max, 0.27, 1e-12);
  // Mirrored towards -x: the block on [8, 10], the same points on its left.
  Particles<2> left, left_after;
  for (const bool moved : {false, true}) {
    Particles<2>& Q = moved ? left_after : left;
    const Particles<2> src = moved ? after : block(2.0);
    for (std::size_t p = 0; p < src.size(); ++p)
      Q.add(Vec<2>(10.0 - src.x[p][0], src.x[p][1]), Vec<2>::Zero(), 1.0, 0.01, src.half0[p], 0, 0);
    if (moved) Q.F[Q.size() - 1] = src.F[src.size() - 1];
  }
  const Runout m =
      runout_of(start_profile(left, 0.0, width, 100, 0.5 * width), left_after, 0.0, width, 0.5 * width);
  EXPECT_NEAR(m.x_min, 0.27, 1e-12);
  EXPECT_EQ(m.x_max, 0.0);
}

// A slope by hand (1 m columns, points 0.9 m wide so no point touches a neighbour): ground
// 1 m deep everywhere, the surface 4, 3, 2 m high over the first three columns, then 1 m.
// A deposit point [x - 0.25, x + 0.25] x [1, 1.8] stands 0.8 m above the ground (threshold
// 0.5 m). The toe is the outer edge of the original material standing higher than 1 + 0.5 m,
// the point [2.05, 2.95] x [1, 2]: x = 2.95 (by the front's own rule; the column tops joined
// between column centres, (2.5, 2) and (3.5, 1), would put it at 3). The runout is
// x + 0.25 - 2.95, continuous as the point moves by fractions of a column, across a column
// boundary.
TEST(SlideMeasures, SlopeRunoutIsContinuousAsTheFrontMoves) {
  const double width = 1.0;
  const Particles<2> slope = hand_made_slope();
  const SurfaceProfile before = start_profile(slope, 0.0, width, 20, 0.5);
  ASSERT_EQ(before.top[2], 2.0);
  ASSERT_EQ(before.top[3], 1.0);
  EXPECT_EQ(runout_of(before, slope, 0.0, width, 0.5).x_max, 0.0);  // nothing moved
  double previous = 0.0;
  for (int k = 0; k <= 20; ++k) {
    const double x = 5.35 + 0.05 * k;  // the front from 5.6 to 6.6 m
    Particles<2> after = slope;
    add(after, x, 1.4, 0.25, 0.4);
    const double r = runout_of(before, after, 0.0, width, 0.5).x_max;
    EXPECT_NEAR(r, x + 0.25 - 2.95, 1e-12) << "front point at " << x;
    if (k > 0) {
      EXPECT_NEAR(r - previous, 0.05, 1e-12);
    }
    previous = r;
  }
  // A point lying on the ground, 0.4 m thick (under the threshold), moves no front.
  Particles<2> after = slope;
  add(after, 5.35, 1.4, 0.25, 0.4);
  add(after, 9.5, 1.2, 0.3, 0.2);
  EXPECT_NEAR(runout_of(before, after, 0.0, width, 0.5).x_max, 2.65, 1e-12);
}

// A slope as skred builds one: 3 x 3 points per 0.5 m cell on the lattice, a base layer 1 m deep
// on [0, 20] and above it a slope 5 m high whose face runs from (2 + shift, 5) down to (8 + shift,
// 1). The slope above the base layer is moved by d along +x, rigidly: the material's edge at every
// level moves by d, and so must the runout (front and toe at the same level, half a cell above
// the base layer), wherever the face falls in its cells. The column tops joined between column
// centres had put the toe 0.5-0.8 of a cell beyond the material's edge, since a column's top is
// its uphill point's (on the 50 m slope, docs/method.md, "The runout measure").
TEST(SlideMeasures, ASlopeMovedRigidlyRunsOutByTheDistanceItMoved) {
  const double h = 0.5, q = h / 3;
  for (const double shift : {0.0, 0.1, 0.23, 0.37}) {
    const auto slope = [&](double d) {
      Particles<2> P;
      for (int i = 0; i < 120; ++i)
        for (int j = 0; j < 30; ++j) {
          const double x = (i + 0.5) * q, y = (j + 0.5) * q;
          const double surface = std::min(5.0, 1.0 + 4.0 * (8.0 + shift - x) / 6.0);
          if (y > 1.0 && y >= surface) continue;
          add(P, x + (y > 1.0 ? d : 0.0), y, 0.5 * q, 0.5 * q);
        }
      return P;
    };
    const SurfaceProfile before = start_profile(slope(0.0), 0.0, h, 40, 0.5 * h);
    for (const double d : {0.5, 0.77, 1.0, 2.31}) {
      const Runout r = runout_of(before, slope(d), 0.0, h, 0.5 * h);
      EXPECT_NEAR(r.x_max, d, 1e-12) << "face shifted by " << shift << " m, slope moved by " << d << " m";
      EXPECT_EQ(r.x_min, 0.0);
    }
  }
}

// Over a base layer every column holds material, so the deposit is also cut where the slide left
// a column unraised: a clump that came to rest beyond bare ground is not the front, however high
// it stands (on the 50 m slope at 10/7 m cells such a clump, 3 m^2 two columns beyond the
// deposit, had set the runout 4.6 m too far; docs/studies/2026-11-29-slope-50m-at-the-
// thesis-discretisation.md).
TEST(SlideMeasures, AClumpBeyondBareGroundOnABaseLayerDoesNotMoveTheFront) {
  const double width = 1.0;
  const Particles<2> slope = hand_made_slope();
  const SurfaceProfile before = start_profile(slope, 0.0, width, 20, 0.5);
  Particles<2> after = slope;
  for (int k = 3; k <= 6; ++k) add(after, k + 0.5, 1.4, 0.45, 0.4);  // the deposit, 0.8 m thick
  // Its front 6.95 m, the toe the edge of the material that stood above 1.5 m: x = 2.95.
  EXPECT_NEAR(runout_of(before, after, 0.0, width, 0.5).x_max, 4.0, 1e-12);
  Particles<2> clump = after;
  add(clump, 9.5, 1.6, 0.45, 0.6);  // 1.2 m thick, beyond the bare columns 7 and 8
  EXPECT_NEAR(runout_of(before, clump, 0.0, width, 0.5).x_max, 4.0, 1e-12);
  // Joined to the deposit by material raising the columns between, it is the front.
  for (int k = 7; k <= 8; ++k) add(clump, k + 0.5, 1.35, 0.45, 0.35);
  EXPECT_NEAR(runout_of(before, clump, 0.0, width, 0.5).x_max, 9.95 - 2.95, 1e-12);
  // A wider clump beyond the gap is the deposit, as the wider of two runs.
  Particles<2> wide = after;
  for (int k = 9; k <= 13; ++k) add(wide, k + 0.5, 1.4, 0.45, 0.4);
  EXPECT_NEAR(runout_of(before, wide, 0.0, width, 0.5).x_max, 13.95 - 2.95, 1e-12);
}

// The stage's runout_thickness (metres) is the level the runout's front must stand above the
// original surface, in place of half a cell. On the slope of the test above, a point lying on
// the ground 0.4 m thick, its outer edge at 9.8 m, joined to the front point at 5.35 m by a sheet
// 0.35 m thick, is the front at 0.3 m: the toe is the edge of the material that stood above
// 1.3 m, the point [2.05, 2.95] x [1, 2], so the runout is 9.8 - 2.95 = 6.85 m; at half a cell
// (0.5 m) neither the sheet nor the point is, and the runout stays 2.65 m.
TEST(SlideMeasures, TheStagesRunoutThicknessSetsTheFrontsLevel) {
  const auto text = [](const std::string& slide_extra) {
    return std::string(R"(
[grid]
size = [20.0, 8.0]
cell_size = 1.0
[[material]]
name = "soil"
model = "linear-elastic"
density = 2000.0
young = 1e7
poisson = 0.3
[[body]]
material = "soil"
particles_per_cell = 2
shape = "rectangle"
min = [0.0, 0.0]
max = [20.0, 1.0]
[[stage]]
name = "equilibrium"
duration = 0.1
[[stage]]
name = "slide"
duration = 0.1
)") + slide_extra;
  };
  const Scenario s = parse_scenario(text("runout_thickness = 0.3\n"), "slide.toml");
  EXPECT_EQ(s.stages[0].runout_thickness, 0.0);  // not given: half a cell
  EXPECT_EQ(s.stages[1].runout_thickness, 0.3);
  try {
    parse_scenario(text("runout_thickness = -0.3\n"), "slide.toml");
    ADD_FAILURE() << "a negative thickness was accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("runout_thickness"), std::string::npos) << e.what();
  }

  Particles<2> slope = hand_made_slope();  // (the tracker records each point's strain in it)
  Particles<2> after = slope;
  add(after, 5.35, 1.4, 0.25, 0.4);
  for (int k = 6; k <= 8; ++k) add(after, k + 0.5, 1.175, 0.45, 0.175);
  add(after, 9.5, 1.2, 0.3, 0.2);
  const StageTracker<2> at_half_cell("slide", slope, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 20.0, 0.0);
  const StageTracker<2> at_thickness("slide", slope, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 20.0, 0.3);
  EXPECT_NEAR(at_half_cell.runout(after), 2.65, 1e-12);
  EXPECT_NEAR(at_thickness.runout(after), 6.85, 1e-12);

  // On bare ground (the block of the first test on the floor y = 0, 0.1 m columns), a column
  // that held no material counts any material by default, and with a thickness set its
  // surface is the floor: a sheet 0.1 m thick to 2.4 m is the front by default and not at
  // 0.3 m, where a lump 0.5 m thick to 2.2 m is.
  Particles<2> column = block(2.0);
  const StageTracker<2> any("slide", column, 0.0, 0.0, 0.0, 0.0, 0.0, 0.1, 10.0, 0.0);
  const StageTracker<2> on_floor("slide", column, 0.0, 0.0, 0.0, 0.0, 0.0, 0.1, 10.0, 0.3);
  Particles<2> sheet = block(2.0);
  add(sheet, 2.2, 0.05, 0.2, 0.05);
  EXPECT_NEAR(any.runout(sheet), 0.4, 1e-12);
  EXPECT_EQ(on_floor.runout(sheet), 0.0);
  add(sheet, 2.1, 0.25, 0.1, 0.25);
  EXPECT_NEAR(on_floor.runout(sheet), 0.2, 1e-12);
}
