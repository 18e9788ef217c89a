// The collapsing soil column of Thesis §5.1 as printed: 1,800 points, dt = 1 ms, the adaptive
// splitting of §3.4. The thesis: "the time of the collapse is t = 2.5 s", "The final
// configuration consists of 9402 material points". It gives neither the column's size nor its
// points per cell; 1,800 = 30 x 60 points (the memo's finer column, 4,050 = 45 x 90) is
// examples/soil_column.toml's 10 x 5 m column at 3 x 3 points per 0.5 m cell. What the unknowns
// move (docs/studies/2026-12-04-thesis-column-as-printed.md): over 2 x 2 points per cell, a
// column twice as high as wide, FLIP and the averaged scheme, the collapse ends at 2.28-2.91 s
// and splitting as printed ends with 7,426-19,634 points; at 2 x 2 points per cell 11,720, at
// 3 x 3 7,552: the thesis's 9,402 lies between, within 25 % of each.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "slope_texts.hpp"
#include "temp_dir.hpp"

using namespace skred;

namespace {

// examples/soil_column.toml with splitting on; `min_size` 0 is the thesis's rule as printed,
// an empty string skred's default floor.
RunResult column_run(const std::string& min_size) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  const auto replace = [&](const std::string& a, const std::string& b) {
    test::replace_once(text, a, b, "examples/soil_column.toml");
  };
  replace("particles_per_cell = 3\n", "particles_per_cell = 3\nsplit = true\n");
  replace("interval = 0.1\n", "interval = 10.0\n");
  text += "\n[splitting]\nmax_points = 1000000\n" + (min_size.empty() ? "" : "min_size = " + min_size + "\n");
  const std::filesystem::path out = test::fresh_temp_dir("column51");
  RunOptions opt;
  opt.progress = false;
  opt.threads = 2;
  RunResult r = run_simulation(parse_scenario(text, "soil_column.toml"), out, opt);
  std::filesystem::remove_all(out);
  return r;
}

}  // namespace

TEST(ThesisColumn, CollapsesInTheThesissTimeAndSplitsToItsCount) {
  const RunResult printed = column_run("0.0");
  const RunResult floored = column_run("");
  for (const RunResult* r : {&printed, &floored}) {
    ASSERT_TRUE(r->completed) << r->message;
    ASSERT_EQ(r->stages.size(), 1u);
    EXPECT_EQ(r->stages[0].ended_by, "rest");  // it comes to rest, as the thesis's column does
    // The collapse ends (the rest test's stop: the speed below rest_speed for good) at the
    // thesis's 2.5 s within the 20 % the unknown set-up moves it.
    ASSERT_TRUE(r->stages[0].stop_time.has_value());
    EXPECT_NEAR(*r->stages[0].stop_time, 2.5, 0.5);
    std::printf("min_size %s: %ld points, collapse over at %.2f s\n", r == &printed ? "0" : "default",
                r->particles, *r->stages[0].stop_time);
  }
  EXPECT_NEAR(static_cast<double>(printed.particles), 9402.0, 0.25 * 9402.0);
  // The floor (no child finer than h/8) splits fewer points, but splits.
  EXPECT_LT(floored.particles, printed.particles / 2);
  EXPECT_GT(floored.particles, 1800 * 3 / 2);
}
