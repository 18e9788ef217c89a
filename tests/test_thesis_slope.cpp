// The slope of Thesis §5.2 at the size its text implies (examples/slope_50m.toml): the thesis
// does not give fig. 5.6's dimensions, but it says which soils slide (§5.2.1, §5.2.3; fig. 5.14,
// 5.15), and cohesion enters a slope's stability only through c / (gamma H). A slope that
// behaves as the text says is the thesis's in the sense that matters for these examples; the
// 10 m slope of examples/slope_collapse.toml barely moves at phi = 24 deg with c = 5 kPa (1 cm
// at 0.5 m cells), which fig. 5.14 shows sliding.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <stdexcept>
#include <string>

#include "bishop_reference.hpp"
#include "run/simulation.hpp"
#include "run/slope_stability.hpp"
#include "scenario/scenario.hpp"
#include "slope_texts.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace skred;

namespace {

// examples/slope_50m.toml at 5 m cells (60 across, the coarsest of the thesis's fig. 5.18
// range is 50) with the soil's friction angle and cohesion and the slide stage's duration set.
std::string slope_text(double phi, double c, double duration) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/slope_50m.toml");
  const auto replace = [&](const std::string& a, const std::string& b) {
    test::replace_once(text, a, b, "examples/slope_50m.toml");
  };
  replace("cell_size = 2.5", "cell_size = 5.0");
  replace("friction = 18.0", "friction = " + std::to_string(phi));
  replace("cohesion = 5000.0", "cohesion = " + std::to_string(c));
  replace("duration = 80.0", "duration = " + std::to_string(duration));
  return text;
}

StageMeasures slide(double phi, double c, double duration, double* limit_equilibrium = nullptr) {
  const std::string text = slope_text(phi, c, duration);
  const fs::path out = skred::test::fresh_temp_dir("slope50");
  RunOptions opt;
  opt.progress = false;
  opt.threads = 2;
  const RunResult r = run_simulation(parse_scenario(text, "slope_50m.toml"), out, opt);
  fs::remove_all(out);
  if (!r.completed || r.stages.size() != 2) throw std::runtime_error("run failed: " + r.message);
  const StageMeasures m = r.stages[1];
  if (limit_equilibrium) *limit_equilibrium = r.limit_equilibrium;
  std::printf("phi = %4.1f deg, c = %5.1f kPa: runout %7.2f m, max displacement %6.3f m, %s at %.1f s\n", phi,
              c / 1e3, m.runout, m.max_displacement, m.ended_by.c_str(), m.end_time - m.start_time);
  return m;
}

}  // namespace

TEST(Slides, FiftyMetreSlopeSlidesAsTheThesisSays) {
  constexpr double kHeight = 50.0, kCell = 5.0;
  constexpr double kToFarEnd = 300.0 - 151.4;  // from the toe to the grid's far side
  // Fig. 5.9-5.11: phi = 18 deg, c = 5 kPa slides, moving soil by tens of metres (measured:
  // runout 34.5 m, largest displacement 48 m, at rest 18 s into the slide).
  const StageMeasures sand = slide(18.0, 5e3, 80.0);
  EXPECT_EQ(sand.ended_by, "rest");
  EXPECT_GT(sand.runout, 4 * kCell);
  EXPECT_GT(sand.max_displacement, 0.4 * kHeight);
  // Fig. 5.15, phi = 5 deg: "for the weakest clay slope with c = 25 kPa, the slide has actually
  // hit the boundary" (149.2 m; reached 149 m 13 s into the slide, 20 s are run) ...
  const StageMeasures weak = slide(5.0, 25e3, 20.0);
  EXPECT_GT(weak.runout, kToFarEnd - kCell);
  // ... "a lower strength implies a larger slide" (75 kPa: 51 m) ...
  const StageMeasures mid = slide(5.0, 75e3, 40.0);
  EXPECT_GT(mid.runout, 4 * kCell);
  EXPECT_LT(mid.runout, weak.runout - 4 * kCell);
  // ... "for the slope with phi = 5 deg and c = 150 kPa, the plastic deformations are
  // negligible" (largest displacement 0.06 m, 0.1 % of the height).
  const StageMeasures strong = slide(5.0, 150e3, 80.0);
  EXPECT_EQ(strong.ended_by, "rest");
  EXPECT_EQ(strong.runout, 0.0);
  EXPECT_LT(strong.max_displacement, 0.005 * kHeight);
}

// The slope's strength from outside the MPM: Bishop's simplified method (run/slope_stability.hpp,
// tested against published answers in test_limit_equilibrium.cpp) gives the 18 deg, 5 kPa slope
// F = 0.59, within 1 % of the independent reference on the example's polygon (bishop_reference.hpp;
// measured 0.5874 against the reference's 0.5882). Dividing c and tan(phi) by F / F_target gives
// the slope whose limit-equilibrium factor is F_target. Measured at these 5 m cells
// (docs/studies/2026-11-28-mpm-slopes-against-limit-equilibrium.md): at F = 0.9 / 0.95 the soil
// moves 17 / 9.5 m, at 1.0 0.5 m, at 1.05 / 1.1 / 1.2 0.10 / 0.09 / 0.07 m: the MPM's onset lies
// within 5 % of Bishop's.
TEST(Slides, FiftyMetreSlopeStandsAndFailsWhereLimitEquilibriumSays) {
  constexpr double kHeight = 50.0;
  const SlopeStability original =
      slope_stability(parse_scenario(slope_text(18.0, 5e3, 20.0), "slope_50m.toml"));
  ASSERT_TRUE(original.computed) << original.why_not;
  const double reference =
      test::bishop::critical_circle(test::slope_50m_ground(test::reference_soil(18.0, 5e3)), 1).factor;
  EXPECT_NEAR(original.critical.factor, reference, 0.01 * reference);
  EXPECT_EQ(original.critical.direction, 1);
  for (const double target : {0.9, 1.1}) {
    const double f = original.critical.factor / target;
    const double phi = std::atan(std::tan(18.0 * std::numbers::pi / 180.0) / f) * 180.0 / std::numbers::pi;
    const std::string text = slope_text(phi, 5e3 / f, 20.0);
    const SlopeStability le = slope_stability(parse_scenario(text, "slope_50m.toml"));
    ASSERT_TRUE(le.computed) << le.why_not;
    EXPECT_NEAR(le.critical.factor, target, 2e-3) << "Bishop's F is a factor on c and tan(phi)";
    double written = NAN;
    const StageMeasures m = slide(phi, 5e3 / f, 20.0, &written);
    EXPECT_DOUBLE_EQ(written, le.critical.factor) << "summary.json's limit_equilibrium";
    if (target < 1.0)
      EXPECT_GT(m.max_displacement, 0.1 * kHeight) << "F = " << target << ": the slope should fail";
    else
      EXPECT_LT(m.max_displacement, 0.005 * kHeight) << "F = " << target << ": the slope should stand";
  }
}

// Thesis §5.2 (after fig. 5.8): "if the soil of the slope is purely frictional, it is stable if
// the friction angle is larger than approximately 35 deg. Similarly, if the slope consists of a
// uniform cohesive soil with no friction, the slope is stable for a cohesion larger than
// approximately 400kPa ... phi = 5 deg and c = 175kPa yield a stable slope in the numerical
// analysis while failure will be observed for phi = 0 deg and c = 300kPa". Asserted here at the
// 5 m cells, with the criteria of the tests above, where they hold in skred. Not asserted
// (docs/studies/2026-12-03-slope-50m-thresholds-of-section-5-2.md, which also runs the thesis's
// 7,127 points): phi = 0, c = 300 kPa stands in skred (Bishop's F = 1.84; the thesis calls its
// failure "unrealistic ... along the lower boundary"), and just above 35 deg with c = 0 the face
// moves 0.39-0.46 m (0.8-0.9 % of the height) at 36 deg and 0.26-0.28 m at 37 deg without
// running out: it does not fail, but it is not the "stands" of these tests (< 0.5 %) until
// 38 deg at these cells and 40 deg at the thesis's 7,127 points.
TEST(Slides, FiftyMetreSlopeThresholdsOfThesisSection52) {
  constexpr double kHeight = 50.0;
  // "phi = 5 deg and c = 175kPa yield a stable slope" (measured 0.018 m).
  const StageMeasures clay = slide(5.0, 175e3, 20.0);
  EXPECT_EQ(clay.runout, 0.0);
  EXPECT_LT(clay.max_displacement, 0.005 * kHeight);
  // "stable for a cohesion larger than approximately 400kPa", phi = 0 (measured 0.015 m).
  const StageMeasures cohesive = slide(0.0, 400e3, 20.0);
  EXPECT_EQ(cohesive.runout, 0.0);
  EXPECT_LT(cohesive.max_displacement, 0.005 * kHeight);
  // Purely frictional, "stable if the friction angle is larger than approximately 35 deg": below
  // it the slope fails (33 deg: 6 m 20 s into the slide, 12 m at rest 38.5 s in; 34 deg moves
  // 1.1 m at these cells and 25 m at the thesis's 7,127 points).
  const StageMeasures sand = slide(33.0, 0.0, 40.0);
  EXPECT_GT(sand.max_displacement, 0.1 * kHeight);
  // Limit equilibrium agrees: Bishop's F of the cohesionless slope is the infinite slope's
  // tan(phi) / tan(35 deg) (measured 0.935 against 0.927; before circles had to reach a cell deep,
  // a sliver under a step of the points' surface gave 0.704).
  const SlopeStability le = slope_stability(parse_scenario(slope_text(33.0, 0.0, 40.0), "slope_50m.toml"));
  ASSERT_TRUE(le.computed) << le.why_not;
  const double infinite =
      std::tan(33.0 * std::numbers::pi / 180.0) / std::tan(35.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(le.critical.factor, infinite, 0.02 * infinite);
}
