// Cell-averaged volumetric strain (solver.volumetric_strain = "cell-average";
// src/solver/volumetric_averaging.hpp): the B-bar pairing of the averaged strain with the cell's
// mean pressure in the internal force, checked on its own and in the §5.1 soil column, where
// the stress power then equals the work of the nodal forces and the energy balance closes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "solver/volumetric_averaging.hpp"
#include "support.hpp"
#include "temp_dir.hpp"
#include "text_run.hpp"
#include "transfer/point_selection.hpp"

namespace fs = std::filesystem;
using namespace skred;
using namespace skred::test;

namespace {

// The unit tests' grid: 4 x 3 cells of 0.5 m from the origin.
GridGeometry<2> four_by_three_cells() {
  GridGeometry<2> g;
  g.h = 0.5;
  g.cells = {4, 3};
  return g;
}

}  // namespace

// Random points in a 4 x 3 cell grid, summed as the solver sums them: in every cell the
// corrections keep the cell's volume change, sum V_p (div_c - div_p) = 0, the stress power of
// the corrected strain equals the work of the corrected pressure (the B-bar pairing,
// sum V m_p (div_c - div_p) = sum V (m_c - m_p) div_p), and a cell whose points share one
// divergence and one pressure is left as it is.
TEST(VolumetricAveraging, CellMeansKeepVolumeChangeAndPairWithPressure) {
  const GridGeometry<2> g = four_by_three_cells();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 200;
  std::vector<Vec<2>> x(n);
  std::vector<double> volume(n);
  VolumetricAveraging<2> A;
  A.resize(g, n);
  for (std::size_t p = 0; p < n; ++p) {
    x[p] = Vec<2>(2.0 * u(rng), 1.5 * u(rng));
    volume[p] = 0.01 + 0.02 * u(rng);
    const bool uniform = x[p][0] < 0.5;  // the first column of cells: one divergence, one pressure
    A.cell[p] = VolumetricAveraging<2>::cell_of(g, x[p]);
    A.div[p] = uniform ? 0.3 : u(rng) - 0.5;
    A.mean[p] = uniform ? -2.0e4 : -1.0e5 * u(rng);
    A.div_sum[A.cell[p]] += volume[p] * A.div[p];
    A.volume_sum[A.cell[p]] += volume[p];
    A.mean_sum[A.cell[p]] += volume[p] * A.mean[p];
    A.mean_volume_sum[A.cell[p]] += volume[p];
  }
  std::vector<double> kept(g.node_count()), power(g.node_count()), work(g.node_count()),
      scale(g.node_count());
  for (std::size_t p = 0; p < n; ++p) {
    const std::uint32_t c = A.cell[p];
    EXPECT_EQ(c, (1 + static_cast<int>(x[p][0] / g.h)) + (1 + static_cast<int>(x[p][1] / g.h)) * g.nodes(0));
    kept[c] += volume[p] * A.correction(p) * 2;  // the correction is per axis: d = 2
    power[c] += volume[p] * A.mean[p] * A.correction(p) * 2;
    work[c] += volume[p] * A.pressure_correction(p) * A.div[p];
    scale[c] += volume[p] * 1.0e5;
    if (x[p][0] < 0.5) {
      EXPECT_NEAR(A.correction(p), 0.0, 1e-15);
      EXPECT_NEAR(A.pressure_correction(p), 0.0, 1e-10);
    }
  }
  for (std::size_t c = 0; c < kept.size(); ++c) {
    EXPECT_NEAR(kept[c], 0.0, 1e-15) << c;
    EXPECT_NEAR(power[c], work[c], 1e-12 * scale[c]) << c;
  }
}

// The cell sums by chunks of points (the solver's cell_sums): each chunk's runs of points in one
// cell, added in chunk order, give every cell the sum a plain loop over the points gives (to
// rounding), whether the points are sorted by cell, scattered, or a cell's points lie in several
// chunks; a cell the runs touch starts from zero whatever it held.
TEST(VolumetricAveraging, RunsByChunkSumEveryCell) {
  const GridGeometry<2> g = four_by_three_cells();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 3 * VolumetricAveraging<2>::kSumChunk + 100;  // four chunks, the last short
  VolumetricAveraging<2> A;
  A.resize(g, n);
  std::vector<double> value(n);
  for (std::size_t p = 0; p < n; ++p) {
    const Vec<2> x(2.0 * u(rng), 1.5 * u(rng));
    A.cell[p] = VolumetricAveraging<2>::cell_of(g, x);
    A.volume[p] = 0.01 + 0.02 * u(rng);
    value[p] = u(rng) - 0.5;
  }
  // the first half sorted by cell (mostly one run per cell and chunk), the rest scattered
  std::sort(A.cell.begin(), A.cell.begin() + static_cast<long>(n / 2));
  std::vector<double> sum(g.node_count(), 99.0), weight(g.node_count(), 99.0);
  std::vector<double> want(g.node_count(), 0.0), want_weight(g.node_count(), 0.0);
  const long chunks = VolumetricAveraging<2>::chunk_count(n);
  ASSERT_EQ(chunks, 4);
  for (std::size_t p = 0; p < n; ++p) {
    want[A.cell[p]] += A.volume[p] * value[p];
    want_weight[A.cell[p]] += A.volume[p];
  }
  for (long c = 0; c < chunks; ++c) A.sum_chunk(c, static_cast<long>(n), AllPoints{}, value.data());
  EXPECT_LE(A.run_count[0], 12) << "a chunk of points sorted by cell: one run per cell";
  A.add_runs(chunks, sum.data(), weight.data());
  for (std::size_t i = 0; i < sum.size(); ++i) {
    if (want_weight[i] == 0.0) continue;  // not a cell's low node, or an empty cell
    EXPECT_NEAR(sum[i], want[i], 1e-12) << i;
    EXPECT_NEAR(weight[i], want_weight[i], 1e-12) << i;
  }
}

namespace {

struct ColumnRun {
  StageMeasures stage;
  double balance = 0.0;       // total_energy / gravity_work at the end
  double gravity_work = 0.0;  // J per metre
};

// examples/soil_column.toml (Thesis §5.1, APIC) for `seconds` at cell size h (2 ms of time step
// per metre of cell, as scripts/convergence.sh runs it) with the given volumetric strain.
ColumnRun column(double h, const std::string& volumetric, double seconds, int threads = 1,
                 const std::string& scheme = "usf") {
  std::string text =
      with_transfer(read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml"),
                    "velocity_transfer = \"apic\"\nvolumetric_strain = \"" + volumetric + "\"");
  text.replace(text.find("cell_size = 0.5"), 15, "cell_size = " + std::to_string(h));
  text.replace(text.find("time_step = 0.001"), 17, "time_step = " + std::to_string(0.002 * h));
  text.replace(text.find("duration = 6.0"), 14, "duration = " + std::to_string(seconds));
  text.replace(text.find("scheme = \"usf\""), 14, "scheme = \"" + scheme + "\"");
  const TextRun run = run_text(text, threads);  // one: two threads crawl on a loaded machine (libgomp's spin)
  EXPECT_TRUE(run.result.completed) << run.result.message;
  ColumnRun c;
  if (!run.result.stages.empty()) c.stage = run.result.stages.back();
  c.gravity_work = run.row.at("gravity_work");
  c.balance = run.balance();
  return c;
}

}  // namespace

// The soil column with cell-averaged volumetric strain, 3 s at h = 0.5 m: the energy balance
// closes (measured 0.006 % of the gravity work after 5 s; pairing the averaged strain with each
// point's own pressure instead left 0.25 %), the deposit is symmetric, and the column comes
// down further than with each point's own volumetric strain even at h/2 (gravity work 346
// against 277 kJ/m measured: without the average the coarse grid locks the isochoric plastic
// flow of psi = 0; docs/method.md, "Volumetric locking").
TEST(VolumetricAveraging, SoilColumnBalanceClosesAndTheColumnComesDownFurther) {
  const ColumnRun avg = column(0.5, "cell-average", 3.0);
  const ColumnRun point = column(0.25, "point", 3.0);
  std::printf(
      "soil column h = 0.5 m, cell-average: runout %.3f m (-x %.4f, +x %.4f), gravity work %.1f kJ/m, "
      "balance %+.4f %%; h = 0.25 m, point: runout %.3f m, gravity work %.1f kJ/m\n",
      avg.stage.runout, avg.stage.runout_x_min, avg.stage.runout_x_max, avg.gravity_work / 1e3,
      100 * avg.balance, point.stage.runout, point.gravity_work / 1e3);
  EXPECT_LT(std::abs(avg.balance), 5e-4);
  EXPECT_NEAR(avg.stage.runout_x_min, avg.stage.runout_x_max, 1e-3);
  EXPECT_GT(avg.gravity_work, point.gravity_work);
  // The cell sums are made per fixed chunk of points and added in chunk order, not by atomic adds
  // in whatever order the threads come: two runs on two threads are the same bit for bit (as a
  // restart needs).
  const ColumnRun one = column(0.5, "cell-average", 0.2, 2), two = column(0.5, "cell-average", 0.2, 2);
  EXPECT_EQ(one.gravity_work, two.gravity_work);
  EXPECT_EQ(one.balance, two.balance);
}

// USL and the averaged scheme take it too: the averaged strain in their stress update from the
// remapped velocities (and the averaged scheme's first half, as USF), the cell's mean pressure in
// USL's force from sigma^k. The column at h = 0.5 m, 3 s, comes down as far as with USF
// (measured runout 3.993 and 3.988 m against 3.997 m, gravity work within 0.1 %), and the
// balance closes within 1 % (measured -0.42 % for both at 4 s: the force and the strain are
// paired within a phase only in USF, -0.015 % there).
TEST(VolumetricAveraging, EverySchemeTakesIt) {
  const ColumnRun usf = column(0.5, "cell-average", 3.0);
  for (const char* scheme : {"usl", "averaged"}) {
    const ColumnRun r = column(0.5, "cell-average", 3.0, 1, scheme);
    std::printf(
        "soil column h = 0.5 m, cell-average, %s: runout %.3f m, gravity work %.1f kJ/m, balance %+.3f %%\n",
        scheme, r.stage.runout, r.gravity_work / 1e3, 100 * r.balance);
    EXPECT_NEAR(r.stage.runout, usf.stage.runout, 0.01 * usf.stage.runout) << scheme;
    EXPECT_NEAR(r.gravity_work, usf.gravity_work, 0.005 * usf.gravity_work) << scheme;
    EXPECT_LT(std::abs(r.balance), 0.01) << scheme;
    EXPECT_NEAR(r.stage.runout_x_min, r.stage.runout_x_max, 1e-3) << scheme;
  }
}

TEST(VolumetricAveraging, ScenarioKey) {
  std::string base = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/soil_column.toml");
  base.replace(base.find("volumetric_strain = \"point\""), 27, "");  // the example's own choice
  const auto with = [&](const std::string& scheme, const std::string& value) {
    std::string t = base;
    t.replace(t.find("scheme = \"usf\""), 14,
              "scheme = \"" + scheme + "\"\nvolumetric_strain = \"" + value + "\"");
    return parse_scenario(t, "column.toml");
  };
  for (const char* scheme : {"usf", "usl", "averaged"}) {
    EXPECT_TRUE(solver_settings(with(scheme, "cell-average")).volumetric_averaging);
    EXPECT_FALSE(solver_settings(with(scheme, "point")).volumetric_averaging);
  }
  // "auto", the default, averages for a slide (the column's soil can yield)
  EXPECT_TRUE(solver_settings(parse_scenario(base, "column.toml")).volumetric_averaging);
  try {
    (void)with("usf", "mean");
    ADD_FAILURE() << "volumetric_strain = \"mean\" was accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.volumetric_strain"), std::string::npos) << e.what();
  }
}

// Two Mohr-Coulomb columns of different soils in frictional contact (mu = 0.3; Paper III
// §C.2.7), each continuum averaged over its own points in each cell: they collapse against each
// other and the energy balance, contact work included, closes within the issue's 1 % (measured
// +0.45 %, against +1.04 % with each point's own volumetric strain).
TEST(VolumetricAveraging, TwoBodiesInContact) {
  const std::string text = R"(
[grid]
size = [0.6, 0.2]
cell_size = 0.01
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 1800.0
young = 1e6
poisson = 0.3
friction = 25.0
cohesion = 5.0
[[material]]
name = "clay"
model = "mohr-coulomb"
density = 1600.0
young = 2e6
poisson = 0.25
friction = 15.0
cohesion = 20.0
[[body]]
name = "left"
material = "sand"
shape = "rectangle"
min = [0.0, 0.0]
max = [0.1, 0.12]
[[body]]
name = "right"
material = "clay"
shape = "rectangle"
min = [0.1, 0.0]
max = [0.2, 0.1]
[[contact]]
bodies = ["left", "right"]
friction = 0.3
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
y_min = { type = "friction", friction = 0.5 }
[solver]
cfl = 0.3
scheme = "usf"
velocity_transfer = "apic"
volumetric_strain = "cell-average"
[[stage]]
name = "collapse"
duration = 0.6
[output]
interval = 0.1
)";
  const fs::path out = fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.threads = 1;
  const RunResult r = run_simulation(parse_scenario(text, "two_bodies.toml"), out, opt);
  const auto row = last_series_row(out / "series.csv");
  fs::remove_all(out);
  ASSERT_TRUE(r.completed) << r.message;
  const double work = row.at("gravity_work"), balance = row.at("total_energy") / work;
  std::printf(
      "two columns in contact, cell-average: runout %.3f m, gravity work %.3f J/m, contact work %.4f J/m, "
      "balance %+.3f %%\n",
      r.stages.back().runout, work, row.at("contact_work"), 100 * balance);
  EXPECT_GT(r.stages.back().runout, 0.05);  // they collapse (measured 0.18 m)
  EXPECT_LT(std::abs(balance), 0.01);
}
