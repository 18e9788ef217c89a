// The small, fast part of the runout convergence study (issue 12; scripts/convergence.sh,
// docs/method.md "Runout under refinement"): the §5.1 soil column with the example's transfer
// (XPIC once per 2 h/c) at h = 0.5 and 0.25 m, as the script runs it (2 ms of time step per
// metre of cell). What the test sizes can assert honestly: the column comes to rest at both
// sizes, its symmetric deposit gives the same continuous runout both ways, and the runout
// grows from h to h/2 (2.85 and 3.83 m; with the cell-averaged volumetric strain the study
// gets 3.75, 4.12, 4.24 and 4.47 m down to h/8, so "grows" is not asserted as a law). The < 5 %
// criteria need h/4 and finer and are not asserted here: at these sizes the runout moves by 34 %.
#include <gtest/gtest.h>

#include <cmath>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "support.hpp"
#include "temp_dir.hpp"
#include "text_run.hpp"

using namespace skred;
using namespace skred::test;

namespace {

// The last stage's measures, and the energy balance of series.csv's last row (total energy over
// the gravity work) in `balance`.
StageMeasures column(double h, double& balance) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  text.replace(text.find("cell_size = 0.5"), 15, "cell_size = " + std::to_string(h));
  text.replace(text.find("time_step = 0.001"), 17, "time_step = " + std::to_string(0.002 * h));
  // one thread: 6 s of work in all; two threads on a loaded machine take far longer
  const TextRun run = run_text(text, 1);
  const RunResult& r = run.result;
  balance = run.balance();
  EXPECT_TRUE(r.completed) << r.message;
  return r.stages.empty() ? StageMeasures{} : r.stages.back();
}

}  // namespace

TEST(Convergence, SoilColumnRunoutAtHAndHalfH) {
  double balance[2];
  const StageMeasures a = column(0.5, balance[0]), b = column(0.25, balance[1]);
  for (const StageMeasures* m : {&a, &b}) {
    const double bal = balance[m == &a ? 0 : 1];
    std::printf(
        "soil column, xpic per 2 h/c: ended by %s at %.2f s, runout -x %.4f +x %.4f m, balance %+.2f %%\n",
        m->ended_by.c_str(), m->end_time - m->start_time, m->runout_x_min, m->runout_x_max, 100 * bal);
    EXPECT_EQ(m->ended_by, "rest");
    // issue 12: the shipped example's balance closes within 1 % (measured +0.32 and -0.64 %)
    EXPECT_LT(std::abs(bal), 0.01);
    // Mirror-symmetric column and deposit (measured: equal to round-off); the runout counted
    // in columns would differ by whole cells or not at all.
    EXPECT_NEAR(m->runout_x_min, m->runout_x_max, 1e-3);
  }
  EXPECT_GT(b.runout, a.runout);  // 2.85 and 3.83 m
}
