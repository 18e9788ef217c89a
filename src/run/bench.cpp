#include "run/bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include "solver/explicit_solver.hpp"

namespace skred {

double peak_rss_bytes() {
  std::ifstream f("/proc/self/status");
  std::string key;
  while (f >> key) {
    if (key == "VmHWM:") {
      double kb = 0;
      f >> kb;
      return kb * 1024.0;
    }
    std::getline(f, key);
  }
  return 0.0;
}

BenchResult run_bench(const BenchOptions& opt) {
  // A block filling the lower three quarters of a square box, 4 points per cell.
  const int cells = std::max(4, static_cast<int>(std::lround(std::sqrt(opt.particles / 3.0))));
  const double h = 0.1;
  GridGeometry<2> grid;
  grid.h = h;
  grid.cells = {cells, cells};
  Material soil;
  soil.name = "soil";
  soil.density = 2000.0;
  soil.elastic = {20e6, 0.3};

  BenchResult res;
  for (int r = 0; r < opt.repeats; ++r) {
    Particles<2> P;
    const int rows = (3 * cells) / 4;
    P.reserve(static_cast<std::size_t>(4) * cells * rows);
    const double q = h / 2, vol = q * q;
    for (int j = 0; j < 2 * rows; ++j)
      for (int i = 0; i < 2 * cells; ++i)
        P.add(Vec<2>((i + 0.5) * q, (j + 0.5) * q), Vec<2>::Zero(), soil.density * vol, vol,
              Vec<2>(q / 2, q / 2), 0, 0);
    SolverSettings<2> st;
    st.interpolation = opt.interpolation;
    st.quadrature_points = opt.quadrature_points;
    st.scheme = opt.scheme;
    st.dt = 0.3 * h / soil.wave_speed();
    st.gravity = Vec<2>(0.0, -9.81);
    st.boundaries = {BoundarySide{BoundaryKind::Roller, 0}, BoundarySide{BoundaryKind::Roller, 0},
                     BoundarySide{BoundaryKind::Fixed, 0}, BoundarySide{BoundaryKind::Free, 0}};
    ExplicitSolver<2> solver(grid, P, {soil}, st, opt.threads);
    solver.step();  // warm-up (first touch of the grid and buffers)
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < opt.steps; ++s) solver.step();
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    res.particles = static_cast<long>(P.size());
    res.nodes = static_cast<long>(grid.node_count());
    res.updates_per_second.push_back(static_cast<double>(P.size()) * opt.steps / sec);
  }
  std::vector<double> sorted = res.updates_per_second;
  std::sort(sorted.begin(), sorted.end());
  res.median = sorted[sorted.size() / 2];
  res.peak_rss_bytes = peak_rss_bytes();
  return res;
}

}  // namespace skred
