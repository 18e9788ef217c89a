// Slide measures from the material (issue 12): runout and heights come from the points and
// their current half-sizes l0 det(F)^(1/d), along the connected deposit, so a point that has
// flown off or a voxel sheared into a needle cannot move the front.
#include <gtest/gtest.h>

#include "run/slide_measures.hpp"

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

}  // namespace

TEST(SlideMeasures, ADetachedPointOrANeedleDoesNotMoveTheFront) {
  const double width = 0.1;
  const int bins = 100;  // columns over [0, 10]
  const Particles<2> start = block(2.0);
  const auto before = surface_profile(start, 0.0, width, bins);
  // The block spread to 3 m: the front advanced 1 m.
  Particles<2> spread = block(3.0);
  auto after = surface_profile(spread, 0.0, width, bins);
  EXPECT_NEAR(runout_of(before, after, width, 0.5 * width).x_max, 1.0, 1e-9);
  // A point thrown 4 m beyond the deposit, across empty columns: no change.
  Particles<2> thrown = spread;
  thrown.add(Vec<2>(7.05, 0.05), Vec<2>::Zero(), 1.0, 0.01, Vec<2>::Constant(0.05), 0, 0);
  after = surface_profile(thrown, 0.0, width, bins);
  EXPECT_NEAR(runout_of(before, after, width, 0.5 * width).x_max, 1.0, 1e-9);
  // A voxel at the front sheared into a needle (F = [[1, 40], [0, 1]], det F = 1): its
  // corners reach 2 m further, the material it stands for does not.
  Particles<2> needle = spread;
  const std::size_t p = needle.size() - 1;  // the top right point
  needle.F[p] << 1.0, 40.0, 0.0, 1.0;
  after = surface_profile(needle, 0.0, width, bins);
  EXPECT_NEAR(runout_of(before, after, width, 0.5 * width).x_max, 1.0, 1e-9);
  const MaterialExtent e = material_extent(needle);
  EXPECT_NEAR(e.x_max, 3.0, 1e-12);
  EXPECT_NEAR(e.y_max - e.y_min, 1.0, 1e-12);
  // A compressed point (det F = 1/4) stands for half the length in 2D.
  Particles<2> squeezed;
  squeezed.add(Vec<2>(0.05, 0.05), Vec<2>::Zero(), 1.0, 0.01, Vec<2>::Constant(0.05), 0, 0);
  squeezed.F[0] = 0.5 * Mat<2>::Identity();
  EXPECT_NEAR(material_extent(squeezed).y_min, 0.05 - 0.025, 1e-12);
}
