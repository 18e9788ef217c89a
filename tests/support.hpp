// Helpers for the simulation tests: material points filling rectangles, a solver built
// around them, and small measurements on time series.
#pragma once
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/explicit_solver.hpp"

namespace skred::test {

inline Material elastic(double rho, double E, double nu) {
  Material m;
  m.name = "elastic";
  m.density = rho;
  m.elastic = {E, nu};
  return m;
}

// n x n points per cell of size h filling [x0, x1] x [y0, y1] (edges on cell lines).
inline void fill_rectangle(Particles<2>& P, const Material& m, double h, int n, double x0, double y0,
                           double x1, double y1, Vec<2> v = Vec<2>::Zero(), int material = 0, int body = 0) {
  const double q = h / n;
  const int nx = static_cast<int>(std::lround((x1 - x0) / q));
  const int ny = static_cast<int>(std::lround((y1 - y0) / q));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      P.add(Vec<2>(x0 + (i + 0.5) * q, y0 + (j + 0.5) * q), v, m.density * q * q, q * q, Vec<2>(q / 2, q / 2),
            material, body);
}

// The vibrating block of the velocity-transfer tests: an elastic block (rho = 1000 kg/m^3,
// E = 10 kPa, nu = 0.3: c_p = 3.7 m/s), 2 x 2 points per cell of h = 0.1 m filling
// [0.5, 1.5]^2, free in space, whose points start with a short-wave velocity field (wavelength
// 4 h). On a 20 x 20 grid2(0.1, ...).
inline Material vibrating_block(Particles<2>& P) {
  const Material m = elastic(1000.0, 1.0e4, 0.3);
  const double h = 0.1;
  fill_rectangle(P, m, h, 2, 0.5, 0.5, 1.5, 1.5);
  const double k = M_PI / (2.0 * h);  // wavelength 4 h
  for (std::size_t p = 0; p < P.size(); ++p)
    P.v[p] = Vec<2>(0.05 * std::sin(k * P.x[p][0]) * std::cos(0.3 * k * P.x[p][1]),
                    0.05 * std::sin(k * P.x[p][1]));
  return m;
}

// The velocity-transfer lines of examples/soil_column.toml and examples/slope_collapse.toml.
inline const std::string kExampleTransfer = "velocity_transfer = \"xpic\"\nxpic_period = 2.0";

// An example's scenario text with its transfer lines replaced by `lines` (empty: the engine's
// default); throws if the example no longer has them. If `lines` set the volumetric strain,
// the example's own volumetric_strain line goes.
inline std::string with_transfer(std::string text, const std::string& lines) {
  const auto at = text.find(kExampleTransfer);
  if (at == std::string::npos)
    throw std::runtime_error("the example's velocity-transfer lines are not in it");
  text.replace(at, kExampleTransfer.size(), lines);
  if (lines.find("volumetric_strain") != std::string::npos) {
    const auto own = text.find("\nvolumetric_strain", at + lines.size());
    if (own != std::string::npos) text.erase(own + 1, text.find('\n', own + 1) - own);
  }
  return text;
}

// R2's column: width 0.02 m, height H = 0.1 m, cells of 5 mm, rho = 1800, E = 1 MPa, nu = 0,
// on a fixed base between rollers (the implicit and axisymmetric tests); `solver` and later tables
// are appended.
inline std::string r2_column_text(const std::string& solver) {
  return R"(
[grid]
size = [0.02, 0.1]
cell_size = 0.005
[[material]]
name = "soil"
model = "linear-elastic"
density = 1800.0
young = 1e6
poisson = 0.0
[[body]]
name = "column"
material = "soil"
shape = "rectangle"
min = [0.0, 0.0]
max = [0.02, 0.1]
[gravity]
acceleration = [0, -9.81]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
)" + solver;
}

// R6 on Acosta's mesh (seed 001 §3.1): cells of 0.2 m from r = 0.1 (the walls r = 0.5 and 1.5
// on cell lines), 2 x 2 points per cell, E = 1000 kPa, nu = 0.3, outer wall fixed, rollers above
// and below, a pressure of 10 kPa on the inner wall in one load step; `solver` and `implicit`
// add keys.
inline std::string acosta_cylinder_text(const std::string& solver, const std::string& implicit) {
  return "[grid]\norigin = [0.1, 0.0]\nsize = [1.4, 0.8]\ncell_size = 0.2\ngeometry = \"axisymmetric\"\n"
         "[[material]]\nname = \"m\"\nmodel = \"linear-elastic\"\ndensity = 1000.0\nyoung = 1e6\npoisson = "
         "0.3\n"
         "[[body]]\nname = \"cylinder\"\nmaterial = \"m\"\nshape = \"rectangle\"\nmin = [0.5, 0.0]\n"
         "max = [1.5, 0.8]\n"
         "[[pressure]]\nbody = \"cylinder\"\nside = \"x_min\"\nvalue = 1e4\nramp_time = 1.0\n"
         "[boundary]\nx_max = \"fixed\"\ny_min = \"roller\"\ny_max = \"roller\"\n"
         "[solver]\nend_time = 1.0\nintegrator = \"implicit\"\n" +
         solver + "\n[implicit]\n" + implicit + "\n";
}

inline GridGeometry<2> grid2(double h, int nx, int ny) {
  GridGeometry<2> g;
  g.h = h;
  g.cells = {nx, ny};
  return g;
}

inline BoundarySide side(BoundaryKind k, double mu = 0.0) { return BoundarySide{k, mu}; }

// Step by step, what the wall and contact rules took (ExplicitSolver::wall_step, contact_step):
// the smallest energy a step's rules took from the trial velocities (>= 0 when no rule creates
// energy), and the booked work the clipping of negative terms dropped over the run (the
// friction work's O(dt^2) dips: a rule's work over the step's mean velocity can dip below zero
// where the slip reverses within the step).
struct RuleWork {
  double min_rule = INFINITY;
  double dropped = 0.0;
  double friction = 0.0;  // booked: the walls' work and the contact's friction work
  template <int D>
  void add(const ExplicitSolver<D>& solver) {
    const WallEnergy& w = solver.wall_step();
    const ContactLoss& c = solver.contact_step();
    min_rule = std::min(min_rule, w.rule_dissipation + c.rule_dissipation);
    dropped += (w.work - w.work_sum) + (c.friction - c.friction_sum);
    friction += w.work + c.friction;
  }
};

// Every row of a run's series.csv as column name -> value (.at() on a missing name throws,
// which fails the test).
inline std::vector<std::map<std::string, double>> series_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string header, line;
  std::getline(in, header);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream h(header), v(line);
    std::string name, value;
    auto& row = rows.emplace_back();
    while (std::getline(h, name, ',') && std::getline(v, value, ',')) row[name] = std::stod(value);
  }
  return rows;
}

// The whole text of a file (empty if it cannot be read).
inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The last row of a run's series.csv (empty if it has none).
inline std::map<std::string, double> last_series_row(const std::filesystem::path& file) {
  auto rows = series_rows(file);
  return rows.empty() ? std::map<std::string, double>{} : std::move(rows.back());
}

// Times of the downward zero crossings of a sampled signal (linear interpolation).
inline std::vector<double> zero_crossings(const std::vector<double>& t, const std::vector<double>& y) {
  std::vector<double> z;
  for (std::size_t i = 1; i < y.size(); ++i)
    if (y[i - 1] > 0 && y[i] <= 0) z.push_back(t[i - 1] + (t[i] - t[i - 1]) * y[i - 1] / (y[i - 1] - y[i]));
  return z;
}

}  // namespace skred::test

namespace skred::test {

// n x n points per cell whose centres lie inside the disc.
inline void fill_disc(Particles<2>& P, const Material& m, double h, int n, Vec<2> c, double r, double domain,
                      Vec<2> v, int body) {
  const double q = h / n;
  const int k = static_cast<int>(std::lround(domain / q));
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const Vec<2> x((i + 0.5) * q, (j + 0.5) * q);
      if ((x - c).norm() < r) P.add(x, v, m.density * q * q, q * q, Vec<2>(q / 2, q / 2), 0, body);
    }
}

// The cantilever of Thesis fig. 4.7 as a scenario: L = 8 m, H = 2 m (y = 2 ... 4 m), rho = 10
// kg/m^3, g = 10 m/s^2 over a 1 s sine ramp, E = 10 MPa, nu = 0.3, 0.5 m cells, 2 x 2 points per
// cell, clamped by a fixed wall at x = 0, USF, 2 s. `solver` and `stage` are further lines of
// those tables.
inline std::string thesis_cantilever(const std::string& solver, const std::string& stage = "") {
  return R"(title = "Thesis fig. 4.7 cantilever"
[grid]
size = [10.0, 6.0]
cell_size = 0.5
[[material]]
name = "beam"
model = "linear-elastic"
density = 10.0
young = 10.0e6
poisson = 0.3
[[body]]
name = "beam"
material = "beam"
particles_per_cell = 2
shape = "rectangle"
min = [0.0, 2.0]
max = [8.0, 4.0]
[gravity]
acceleration = [0.0, -10.0]
[boundary]
x_min = "fixed"
[solver]
scheme = "usf"
cfl = 0.4
)" + solver +
         R"(
[[stage]]
name = "load"
duration = 2.0
gravity_ramp_time = 1.0
)" + stage +
         R"(
[output]
interval = 2.0
series_interval = 0.5
)";
}

}  // namespace skred::test
