// The small, fast part of the runout convergence study (issue 12; scripts/convergence.sh,
// docs/method.md "Runout under refinement"): the §5.1 soil column with the example's transfer
// (XPIC once per 2 h/c) at h = 0.5 and 0.25 m, as the script runs it (2 ms of time step per
// metre of cell). What the test sizes can assert honestly: the column comes to rest at both
// sizes, its symmetric deposit gives the same continuous runout both ways, and the runout
// grows from h to h/2 (2.85 and 3.83 m; with the cell-averaged volumetric strain the study
// gets 3.75, 4.12, 4.24 and 4.47 m down to h/8, so "grows" is not asserted as a law). The < 5 %
// criteria need h/4 and finer and are not asserted here: at these sizes the runout moves by 34 %.
#include <gtest/gtest.h>

#include <filesystem>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace skred;
using namespace skred::test;

namespace {

StageMeasures column(double h) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  text.replace(text.find("cell_size = 0.5"), 15, "cell_size = " + std::to_string(h));
  text.replace(text.find("time_step = 0.001"), 17, "time_step = " + std::to_string(0.002 * h));
  const fs::path out = fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;  // 6 s of work in all; two threads on a loaded machine take far longer
  const RunResult r = run_simulation(parse_scenario(text, "column.toml"), out, opt);
  fs::remove_all(out);
  EXPECT_TRUE(r.completed) << r.message;
  return r.stages.empty() ? StageMeasures{} : r.stages.back();
}

}  // namespace

TEST(Convergence, SoilColumnRunoutAtHAndHalfH) {
  const StageMeasures a = column(0.5), b = column(0.25);
  for (const StageMeasures* m : {&a, &b}) {
    std::printf("soil column, xpic per 2 h/c: ended by %s at %.2f s, runout -x %.4f +x %.4f m\n",
                m->ended_by.c_str(), m->end_time - m->start_time, m->runout_x_min, m->runout_x_max);
    EXPECT_EQ(m->ended_by, "rest");
    // Mirror-symmetric column and deposit (measured: equal to 3e-5 m); the runout counted
    // in columns would differ by whole cells or not at all.
    EXPECT_NEAR(m->runout_x_min, m->runout_x_max, 1e-3);
  }
  EXPECT_GT(b.runout, a.runout);  // 2.85 and 3.83 m
}
