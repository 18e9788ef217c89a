// Reference R1: vibrating elastic bar, fixed at x = 0 and free at x = L (run as a 2D strip
// with roller sides). Exact: u = v0/w1 sin(w1 t) sin(b1 x), v_cm = v0/(b1 L) cos(w1 t),
// L = 25, E = 100, rho = 1, nu = 0, v0 = 0.1, b1 = pi/(2L), w1 = b1 c, period T = 10.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "support.hpp"
#include "temp_dir.hpp"

using namespace skred;
using namespace skred::test;

namespace {

constexpr double L = 25.0, E = 100.0, rho = 1.0, v0 = 0.1;
const double beta = std::numbers::pi / (2 * L), omega = beta * std::sqrt(E / rho);

struct BarRun {
  std::vector<double> t, vcm;
  double disp_error = 0.0;    // RMS displacement error at the end, relative to the amplitude
  double energy_drift = 0.0;  // |E(end) - E(0)| / E(0)
};

BarRun run_bar(Interpolation interp, int cells_on_bar, StressScheme scheme, double periods) {
  const double h = L / cells_on_bar;
  const Material m = elastic(rho, E, 0.0);
  Particles<2> P;
  fill_rectangle(P, m, h, 2, 0.0, 0.0, L, h);
  for (std::size_t p = 0; p < P.size(); ++p) P.v[p][0] = v0 * std::sin(beta * P.x[p][0]);
  // Room beyond the free end, one cell high with roller walls top and bottom.
  const int nx = cells_on_bar + cells_on_bar / 4 + 2;
  SolverSettings<2> st;
  st.interpolation = interp;
  st.scheme = scheme;
  st.dt = 0.1 * h / std::sqrt(E / rho);
  st.boundaries = {side(BoundaryKind::Fixed), side(BoundaryKind::Free), side(BoundaryKind::Roller),
                   side(BoundaryKind::Roller)};
  ExplicitSolver<2> solver(grid2(h, nx, 1), P, {m}, st, 1);
  BarRun r;
  const double e0 = solver.totals().kinetic_energy;
  const long steps = std::lround(periods * 10.0 / st.dt);
  for (long s = 0; s <= steps; ++s) {
    const auto tot = solver.totals();
    r.t.push_back(solver.time());
    r.vcm.push_back(tot.momentum[0] / tot.mass);
    if (s < steps) {
      EXPECT_TRUE(solver.step().ok);
    }
  }
  const double amp = v0 / omega;
  double se = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const double x0 = P.x_ref[p][0];
    const double exact = amp * std::sin(omega * solver.time()) * std::sin(beta * x0);
    const double e = (P.x[p][0] - x0) - exact;
    se += e * e;
  }
  r.disp_error = std::sqrt(se / P.size()) / amp;
  r.energy_drift = std::abs(solver.totals().kinetic_energy + solver.energy().strain_energy - e0) / e0;
  return r;
}

void check_vcm(const BarRun& r, const char* label) {
  const double vcm_amp = v0 / (beta * L);  // 0.063662
  const auto z = zero_crossings(r.t, r.vcm);
  ASSERT_GE(z.size(), 3u);
  const double period = (z.back() - z.front()) / (z.size() - 1);
  double amp = 0;
  for (std::size_t i = r.t.size() / 2; i < r.t.size(); ++i) amp = std::max(amp, std::abs(r.vcm[i]));
  std::printf("%s: period %.5f (exact 10), v_cm amplitude %.6f (exact %.6f)\n", label, period, amp, vcm_amp);
  EXPECT_NEAR(period, 10.0, 0.1);             // 1 %
  EXPECT_NEAR(amp, vcm_amp, 0.01 * vcm_amp);  // 1 %
}

}  // namespace

TEST(VibratingBar, GimpPeriodAndAmplitude) {
  check_vcm(run_bar(Interpolation::Gimp, 25, StressScheme::Averaged, 3.0), "GIMP 25 cells");
}

TEST(VibratingBar, BsplinePeriodAndAmplitude) {
  check_vcm(run_bar(Interpolation::Bspline, 25, StressScheme::Averaged, 3.0), "B-spline 25 cells");
}

// Displacement error under refinement 16 -> 32 -> 64 cells after one period and a quarter.
TEST(VibratingBar, DisplacementConvergesUnderRefinement) {
  for (Interpolation interp : {Interpolation::Gimp, Interpolation::Bspline}) {
    double e[3];
    const int n[3] = {16, 32, 64};
    for (int k = 0; k < 3; ++k) e[k] = run_bar(interp, n[k], StressScheme::Averaged, 1.25).disp_error;
    const double r1 = std::log2(e[0] / e[1]), r2 = std::log2(e[1] / e[2]);
    std::printf("%s: relative RMS displacement error %.3e %.3e %.3e, rates %.2f %.2f\n", to_string(interp),
                e[0], e[1], e[2], r1, r2);
    EXPECT_LT(e[1], e[0]);
    EXPECT_LT(e[2], e[1]);
    EXPECT_GT(r1, 1.0);
    EXPECT_GT(r2, 1.0);
  }
}

// The shipped example file (examples/vibrating_bar.toml) reproduces R1 through the scenario
// path: the sine initial velocity, the walls and the series output.
TEST(VibratingBar, ExampleFileMatchesTheExactSolution) {
  const Scenario s = load_scenario(std::string(SKRED_SOURCE_DIR) + "/examples/vibrating_bar.toml");
  const std::filesystem::path out = test::fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  const RunResult r = run_simulation(s, out, opt);
  ASSERT_TRUE(r.completed) << r.message;
  std::ifstream csv(out / "series.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<double> t, vcm;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    t.push_back(std::stod(f[1]));
    vcm.push_back(std::stod(f[11]) / (rho * L));  // momentum_x / bar mass
  }
  std::filesystem::remove_all(out);
  const double amp = *std::max_element(vcm.begin(), vcm.end());
  const auto z = zero_crossings(t, vcm);
  ASSERT_GE(z.size(), 3u);
  const double period = (z.back() - z.front()) / (z.size() - 1);
  const double exact_amp = v0 / (beta * L), exact_period = 2 * std::numbers::pi / omega;
  std::printf("example: v_cm amplitude %.6f (exact %.6f), period %.4f (exact %.4f)\n", amp, exact_amp, period,
              exact_period);
  EXPECT_NEAR(amp, exact_amp, 0.01 * exact_amp);
  EXPECT_NEAR(period, exact_period, 0.01 * exact_period);
}
