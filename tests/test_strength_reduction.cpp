// `skred fos` (run/strength_reduction.hpp): the MPM's factor of safety by strength reduction,
// bisected, against Bishop's limit equilibrium (tested on its own against published answers in
// test_limit_equilibrium.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "bishop_reference.hpp"
#include "run/slope_stability.hpp"
#include "run/strength_reduction.hpp"
#include "slope_texts.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace skred;

namespace {

// examples/slope_50m.toml at 5 m cells with a 20 s slide, written to `dir`.
fs::path fifty_metre_slope(const fs::path& dir) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/slope_50m.toml");
  for (const auto& [a, b] : {std::pair<std::string, std::string>{"cell_size = 2.5", "cell_size = 5.0"},
                             {"duration = 80.0", "duration = 20.0"}}) {
    const auto at = text.find(a);
    if (at == std::string::npos) throw std::runtime_error("not in examples/slope_50m.toml: " + a);
    text.replace(at, a.size(), b);
  }
  const fs::path file = dir / "slope_50m.toml";
  std::ofstream(file) << text;
  return file;
}

}  // namespace

// Measured (docs/studies/2026-11-28-mpm-slopes-against-limit-equilibrium.md): from [0.5, 0.7] in three
// bisections the slope stands at 0.575 and fails at 0.6, Bishop's F = 0.587 lying between. The
// F that skred computes (on the points' columns of 5 m) is checked against the independent
// reference on the example's polygon (bishop_reference.hpp): measured 0.5874 against 0.5882.
TEST(FactorOfSafety, FiftyMetreSlopeFailsWhereBishopSays) {
  const fs::path dir = test::fresh_temp_dir("fos");
  FosOptions opt;
  opt.low = 0.5, opt.high = 0.7, opt.steps = 3, opt.threads = 1, opt.progress = false;
  const FosResult r = run_strength_reduction(fifty_metre_slope(dir).string(), dir / "out", opt);
  ASSERT_EQ(r.runs.size(), 5u);
  EXPECT_EQ(r.stage, "slide");
  EXPECT_FALSE(r.runs[0].fails);  // 0.5: c and tan(phi) doubled
  EXPECT_TRUE(r.runs[1].fails);   // 0.7
  EXPECT_DOUBLE_EQ(r.runs[2].factor, 0.6);
  ASSERT_TRUE(std::isfinite(r.stands) && std::isfinite(r.fails));
  EXPECT_NEAR(r.fails - r.stands, 0.025, 1e-12);  // three halvings of [0.5, 0.7]
  const double reference =
      test::bishop::critical_circle(test::slope_50m_ground(test::reference_soil(18.0, 5e3)), 1).factor;
  std::printf("50 m slope: Bishop's F %.4f, the reference's %.4f\n", r.limit_equilibrium, reference);
  ASSERT_NEAR(r.limit_equilibrium, reference, 0.01 * reference);
  // The MPM's onset within 5 % of limit equilibrium's: the whole bracket, 5 % of F wide at
  // most, inside F -5 % ... F +5 %.
  EXPECT_GE(r.stands, 0.95 * r.limit_equilibrium);
  EXPECT_LE(r.fails, 1.05 * r.limit_equilibrium);
  for (const FosRun& run : r.runs) {
    EXPECT_EQ(run.status, "completed");
    EXPECT_EQ(run.fails, run.stage.max_displacement > 0.01 * run.stage.height_start);
    EXPECT_DOUBLE_EQ(run.threshold, 0.01 * run.stage.height_start);
    // A failing run ends once it has failed; one that stands runs the stage's whole duration.
    EXPECT_EQ(run.stage.ended_by, run.fails ? "moved" : "duration") << run.factor;
  }
  std::ifstream table(dir / "out" / "fos.csv");
  std::stringstream text;
  text << table.rdbuf();
  EXPECT_EQ(text.str(), fos_table(r));
  EXPECT_EQ(text.str().rfind("factor,status,folder,fails,max_displacement,", 0), 0u);
  EXPECT_NE(text.str().find("\n0.5,completed,run_000,false,"), std::string::npos) << text.str();
  const std::string verdict = fos_verdict(r, opt);
  EXPECT_NE(verdict.find("the MPM's factor of safety lies between"), std::string::npos) << verdict;
  EXPECT_NE(verdict.find("limit equilibrium (Bishop's simplified method on circles): F = 0.5"),
            std::string::npos)
      << verdict;
  fs::remove_all(dir);
}

// Layered ground against the MPM: the slope example at 1 m cells on a weak base layer (c = 3 kPa,
// phi = 10 deg) into which its critical circle dips (Bishop's F = 0.706; the independent
// reference on the bodies' polygons, bishop_reference.hpp, 0.7108). Measured (docs/method.md,
// "Limit equilibrium"): the MPM's onset lies between f = 0.6625 and 0.694 on these cells. With the
// strength divided by 0.9 F the slope must stand (Bishop's F 1.11), by 1.1 F fail (0.91).
TEST(FactorOfSafety, ASlopeOnAWeakLayerFailsWhereBishopSays) {
  const fs::path dir = test::fresh_temp_dir("fos_layered");
  const fs::path file = dir / "layered.toml";
  std::ofstream(file) << test::two_body_slope(test::mohr_coulomb_material("base", 10.0, 3000.0), 1.0);
  const SlopeStability le = slope_stability(load_scenario(file.string()));
  ASSERT_TRUE(le.computed) << le.why_not;
  const double reference =
      test::bishop::critical_circle(
          test::two_body_slope_ground(test::reference_soil(18.0, 5e3), test::reference_soil(10.0, 3e3)), 1)
          .factor;
  std::printf("10 m slope on a weak layer: Bishop's F %.4f, the reference's %.4f\n", le.critical.factor,
              reference);
  ASSERT_NEAR(le.critical.factor, reference, 0.01 * reference);
  EXPECT_LT(le.critical.circle.yc - le.critical.circle.radius, 4.0) << "the circle dips into the weak layer";
  FosOptions opt;
  opt.low = 0.9 * le.critical.factor, opt.high = 1.1 * le.critical.factor;
  opt.steps = 0, opt.threads = 1, opt.progress = false;
  const FosResult r = run_strength_reduction(file.string(), dir / "out", opt);
  ASSERT_EQ(r.runs.size(), 2u);
  EXPECT_FALSE(r.runs[0].fails) << r.runs[0].stage.max_displacement;
  EXPECT_TRUE(r.runs[1].fails) << r.runs[1].stage.max_displacement;
  EXPECT_DOUBLE_EQ(r.limit_equilibrium, le.critical.factor);
  fs::remove_all(dir);
}

TEST(FactorOfSafety, BadOptionsAndElasticScenariosAreRefused) {
  for (const auto& [low, high, steps, moved] :
       {std::tuple{0.0, 1.0, 5, 0.01}, {1.0, 0.5, 5, 0.01}, {0.5, 2.0, 13, 0.01}, {0.5, 2.0, 5, 1.5}}) {
    FosOptions o;
    o.low = low, o.high = high, o.steps = steps, o.moved = moved;
    EXPECT_THROW(check_fos_options(o), std::invalid_argument) << low << " " << high << " " << steps;
  }
  for (const int levels : {0, 5}) {
    FosOptions o;
    o.levels = levels;
    EXPECT_THROW(check_fos_options(o), std::invalid_argument) << levels;
  }
  const fs::path dir = test::fresh_temp_dir("fos_elastic");
  FosOptions o;
  o.progress = false;
  const std::pair<std::string, std::string> refused[] = {
      {"elastic_column.toml", "no material can yield in the last stage that is not held elastic"},
      {"column_3d.toml", "the scenario has no [[stage]] table"}};
  for (const auto& [file, message] : refused) {
    try {
      run_strength_reduction(std::string(SKRED_SOURCE_DIR) + "/examples/" + file, dir / "out", o);
      ADD_FAILURE() << file << " was accepted";
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "run_000"));
  fs::remove_all(dir);
}

// The onset at three cell sizes, extrapolated to h -> 0 (post/grid_convergence.hpp): the 10 m
// slope's brackets at 1, 0.5 and 0.25 m cells (docs/method.md, "The slope's strength under
// refinement": 0.838-0.844, 0.806-0.813, 0.788-0.791) converge with p = 0.66 towards 0.755, and
// predict the next halving's onset inside the bracket measured at 0.125 m cells, 0.77-0.78.
TEST(FactorOfSafety, OnsetsAtThreeCellSizesExtrapolate) {
  FosResult r;
  r.stage = "slide";
  r.levels = {{1.0, 0.838, 0.844}, {0.5, 0.806, 0.813}, {0.25, 0.788, 0.791}};
  r.stands = 0.788, r.fails = 0.791;
  const std::optional<GridConvergence> g = fos_extrapolation(r);
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->kind, ConvergenceKind::monotone);
  EXPECT_NEAR(g->order, std::log(0.0315 / 0.02) / std::log(2.0), 1e-9);
  EXPECT_NEAR(g->extrapolated, 0.7547, 5e-5);
  const double next = 0.7895 + g->next_change;
  EXPECT_GT(next, 0.77);
  EXPECT_LT(next, 0.78);
  FosOptions opt;
  opt.levels = 3;
  const std::string verdict = fos_verdict(r, opt);
  EXPECT_NE(verdict.find("at h = 0.25 m the MPM's factor of safety lies between 0.788 and 0.791"),
            std::string::npos)
      << verdict;
  EXPECT_NE(
      verdict.find("it converges monotonically with apparent order p = 0.66, towards f = 0.755 as h -> 0"),
      std::string::npos)
      << verdict;
  EXPECT_EQ(verdict.find("raise --steps"), std::string::npos) << verdict;
  // A finest bracket wider than the last change of its midpoint: the bisection's resolution.
  r.levels.back() = {0.25, 0.78, 0.80};
  EXPECT_NE(fos_verdict(r, opt).find("the extrapolation rests on the bisection's resolution; raise --steps"),
            std::string::npos);
  // Two levels, or a level that did not bracket the onset, extrapolate nothing.
  r.levels.back() = {0.25, NAN, NAN};
  EXPECT_FALSE(fos_extrapolation(r).has_value());
  r.levels.pop_back();
  EXPECT_FALSE(fos_extrapolation(r).has_value());
}
