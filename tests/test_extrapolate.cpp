// `skred extrapolate` (run/extrapolation_text.hpp): Celik et al.'s procedure applied to values a
// user measured at three cell sizes or more, given as CELL=VALUE in any order; checked against
// Celik et al. (2008)'s Table 1 and a known error expansion, and its refusals of bad input, in
// the library and through the command line (exit code 4, README "Exit codes").
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io_test_util.hpp"
#include "run/extrapolation_text.hpp"

using namespace skred;

namespace {

// The CSV row under the verdict's header, split at its commas.
std::vector<std::string> csv_row(const std::string& text) {
  const auto head = text.find("quantity,h1,");
  const auto start = text.find('\n', head) + 1;
  const std::string row = text.substr(start, text.find('\n', start) - start);
  std::vector<std::string> cells;
  for (std::size_t a = 0, b; a <= row.size(); a = b + 1) {
    b = row.find(',', a);
    if (b == std::string::npos) b = row.size();
    cells.push_back(row.substr(a, b - a));
  }
  return cells;
}

}  // namespace

// Table 1's first column (Celik et al. 2008): the reattachment length on grids with r21 = 1.5 and
// r32 = 1.333 (h proportional to N^(-1/2): 18,000, 8,000 and 4,500 cells), given coarsest first
// and with a fourth, coarser value that the three finest leave out: p = 1.53, phi_ext = 6.1685,
// GCI 2.2 %.
TEST(Extrapolate, CeliksFirstExampleFromPairsInAnyOrder) {
  const double h1 = 1.0 / std::sqrt(18000.0), h2 = 1.0 / std::sqrt(8000.0), h3 = 1.0 / std::sqrt(4500.0);
  const auto pair = [](double h, double v) { return std::to_string(h) + "=" + std::to_string(v); };
  const std::string text = extrapolate_text(
      {pair(2.0 * h3, 5.5), pair(h3, 5.863), pair(h1, 6.063), pair(h2, 5.972)}, "reattachment length", "");
  const std::vector<std::string> c = csv_row(text);
  ASSERT_EQ(c.size(), 13u) << text;
  EXPECT_EQ(c[0], "reattachment length");
  EXPECT_NEAR(std::stod(c[1]), h1, 1e-6);
  EXPECT_NEAR(std::stod(c[3]), h3, 1e-6);
  EXPECT_EQ(c[7], "monotone");
  EXPECT_NEAR(std::stod(c[9]), 1.53, 0.005);
  EXPECT_NEAR(std::stod(c[10]), 6.1685, 0.0001);
  EXPECT_NEAR(100.0 * std::stod(c[11]), 2.2, 0.05);
  EXPECT_NE(text.find("converges monotonically with apparent order p = 1.53 towards 6.168"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("one more refinement by 1.5"), std::string::npos) << text;
}

// phi(h) = 4.2 - 1.3 h at h = 0.5, 0.25, 0.125: first order towards 4.2, and one more halving
// moves it by phi(h/16) - phi(h/8); the 10 m slope's runout (docs/method.md, +1.455 m, then
// +1.664 m) is not extrapolated.
TEST(Extrapolate, KnownExpansionAndGrowingChanges) {
  const auto phi = [](double h) { return 4.2 - 1.3 * h; };
  const std::vector<std::string> pairs = {"0.5=" + std::to_string(phi(0.5)),
                                          "0.25=" + std::to_string(phi(0.25)),
                                          "0.125=" + std::to_string(phi(0.125))};
  const std::vector<std::string> c = csv_row(extrapolate_text(pairs, "runout", "m"));
  EXPECT_NEAR(std::stod(c[9]), 1.0, 1e-5);
  EXPECT_NEAR(std::stod(c[10]), 4.2, 1e-5);
  EXPECT_NEAR(std::stod(c[12]), phi(0.0625) - phi(0.125), 1e-5);
  const std::string d = extrapolate_text({"1=0.869", "0.5=2.324", "0.25=3.988"}, "runout", "m");
  EXPECT_EQ(csv_row(d)[7], "diverging");
  EXPECT_NE(d.find("the last halving moved it by +1.664 m, the one before by +1.455 m"), std::string::npos)
      << d;
  EXPECT_NE(d.find("nothing is extrapolated"), std::string::npos) << d;
}

// An apparent order outside 0.5 to 4 is reported with a caution: the 50 m slope's mean tips with
// the default at h = 10/3, 5/3 and 5/6 m (docs/studies/2026-11-29-slope-50m-at-the-thesis-discretisation.md),
// +5.89 and +5.88 m, give R = 1.00 and p = 0.00 towards some 3.5 km. Sizes given to 7 digits are
// still halvings.
TEST(Extrapolate, AnImplausibleOrderIsFlagged) {
  const std::string t =
      extrapolate_text({"3.3333333=51.24", "1.6666667=57.13", "0.8333333=63.01"}, "tip", "m");
  EXPECT_NE(t.find("apparent order p = 0.00"), std::string::npos) << t;
  EXPECT_NE(t.find("one more halving"), std::string::npos) << t;
  EXPECT_NE(t.find("do not rely on this extrapolation"), std::string::npos) << t;
  const std::string ok = extrapolate_text({"0.5=3.753", "0.25=4.123", "0.125=4.238"}, "tip", "m");
  EXPECT_EQ(ok.find("do not rely"), std::string::npos) << ok;
}

TEST(Extrapolate, BadPairsAreRefusedByName) {
  const auto message = [](const std::vector<std::string>& pairs) {
    try {
      three_finest(pairs);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({"0.5=3", "0.25=x", "0.1=2"}).find("'0.25=x': the value 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(message({"0.5=3", "0.25", "0.1=2"}).find("'0.25': give CELL=VALUE"), std::string::npos);
  EXPECT_NE(message({"0.5=3", "0.25=4"}).find("needs the value at three cell sizes"), std::string::npos);
  EXPECT_NE(message({"0.5=3", "0.5=4", "0.1=2"}).find("given twice"), std::string::npos);
  EXPECT_NE(message({"0.5=3", "-1=4", "0.1=2"}).find("'-1=4': the cell size must be positive"),
            std::string::npos);
  EXPECT_NE(message({"0.5=3", "0.25=nan", "0.1=2"}).find("must be finite"), std::string::npos);
  EXPECT_NE(message({"0.5=3", "0.25=4=5", "0.1=2"}).find("is not a number"), std::string::npos);
}

// Through the command line: the verdict and exit 0, and a bad pair exits with the usage code 4
// naming it.
TEST(Extrapolate, CommandLine) {
  const std::string skred = std::string(SKRED_BINARY) + " extrapolate ";
  const auto [code, output] =
      iotest::run_command(skred + "0.5=3.753 0.25=4.123 0.125=4.238 --name runout --unit m");
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("runout over h = 0.5, 0.25, 0.125: converges monotonically with apparent order "
                        "p = 1.69 towards 4.28986 m"),
            std::string::npos)
      << output;
  const auto [bad_code, bad_output] = iotest::run_command(skred + "0.5=3.753 0.25=four 0.125=4.238");
  EXPECT_EQ(bad_code, 4) << bad_output;
  EXPECT_NE(bad_output.find("'0.25=four'"), std::string::npos) << bad_output;
}
