// Layered ground (docs/scenario.md, "Layered ground"): the [ground] surface, "layer" bodies
// between two profiles read inline or from CSV files (a surveyed cross-section, a line taken
// from a DEM), and the check that bodies do not overlap.
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenario/build.hpp"
#include "scenario/parser_detail.hpp"

namespace skred::scenario_detail {

namespace {

std::string trim_lower(std::string s) {
  const auto a = s.find_first_not_of(" \t\r\"");
  const auto b = s.find_last_not_of(" \t\r\"");
  s = a == std::string::npos ? "" : s.substr(a, b - a + 1);
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  return out;
}

bool parse_double(std::string s, double& v) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  if (a == std::string::npos) return false;
  s = s.substr(a, b - a + 1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size();
}

// The checks every profile meets, wherever it comes from; `at(k)` names point k in messages.
template <class Fail>
void check_profile(const Profile& p, const Scenario& s, Fail&& fail_point) {
  const Vec<2> hi = grid_high(s);
  const double tol = grid_tolerance(s);
  for (std::size_t k = 0; k < p.points.size(); ++k) {
    const Vec<2>& q = p.points[k];
    if (k > 0 && !(q[0] > p.points[k - 1][0]))
      fail_point(k, fmt::format("x must increase strictly along a profile: {} follows {}", q[0],
                                p.points[k - 1][0]));
    if (!((q.array() >= s.origin.array() - tol).all() && (q.array() <= hi.array() + tol).all()))
      fail_point(k, fmt::format("point ({}, {}) lies outside the grid {}", q[0], q[1], grid_bounds(s)));
  }
}

// A profile from a CSV file: a header naming the columns x and z (or y), then one point per
// line; blank lines and lines starting with '#' are skipped.
Profile read_profile_csv(const TableReader& t, std::string_view key, const Scenario& s) {
  const std::string name = t.string(key);
  std::filesystem::path path(name);
  if (path.is_relative()) path = std::filesystem::path(s.source).parent_path() / path;
  if (const std::string why = input_file_problem(path.string(), kMaxProfileBytes); !why.empty())
    t.fail_at(key, fmt::format("cannot read profile file '{}': {}", path.string(), why));
  std::ifstream in(path);
  if (!in)
    t.fail_at(key, fmt::format("cannot open profile file '{}': {}", path.string(), std::strerror(errno)));
  const std::string file = path.string();
  const auto fail_line = [&](int line, const std::string& why) {
    throw ScenarioError(fmt::format("{}:{}: {} (profile '{}' of {}:{})", file, line, why, t.key(key),
                                    s.source, t.where(key).line));
  };
  Profile p;
  std::vector<int> lines;
  int x_col = -1, y_col = -1, columns = 0, number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (trim_lower(line).empty() || trim_lower(line)[0] == '#') continue;
    const auto cells = split_csv(line);
    if (x_col < 0) {  // the header
      columns = static_cast<int>(cells.size());
      for (int c = 0; c < columns; ++c) {
        const std::string h = trim_lower(cells[static_cast<std::size_t>(c)]);
        if (h == "x") x_col = c;
        if (h == "z" || h == "y") y_col = c;
      }
      if (x_col < 0 || y_col < 0)
        fail_line(number, fmt::format("the header must name the columns x and z (or y), got '{}'", line));
      continue;
    }
    if (static_cast<int>(cells.size()) != columns)
      fail_line(number, fmt::format("expected {} columns as in the header, got {}", columns, cells.size()));
    Vec<2> q;
    for (int d = 0; d < 2; ++d) {
      const std::string& cell = cells[static_cast<std::size_t>(d == 0 ? x_col : y_col)];
      if (!parse_double(cell, q[d]) || !std::isfinite(q[d]))
        fail_line(number, fmt::format("'{}' is not a finite number", trim_lower(cell)));
    }
    p.points.push_back(q);
    lines.push_back(number);
  }
  if (x_col < 0) fail_line(number, "the file is empty: expected a header (x, z) and points");
  if (p.points.size() < 2)
    fail_line(number, fmt::format("a profile needs at least 2 points, got {}", p.points.size()));
  check_profile(p, s, [&](std::size_t k, const std::string& why) { fail_line(lines[k], why); });
  return p;
}

// A profile given inline as [[x, y], ...] or as the name of a CSV file.
Profile read_profile(const TableReader& t, std::string_view key, const Scenario& s) {
  const toml::node* n = t.find(key);
  if (n->is_string()) return read_profile_csv(t, key, s);
  const auto* arr = n->as_array();
  if (!arr) t.fail_type(key, "a CSV file name or an array of [x, y] points");
  Profile p;
  for (std::size_t k = 0; k < arr->size(); ++k)
    p.points.push_back(
        node_vec2(*arr->get(k), t.source(), fmt::format("{}[{}]", t.key(key), k), t.where(key)));
  if (p.points.size() < 2)
    t.fail_at(key, fmt::format("a profile needs at least 2 points, got {}", p.points.size()));
  check_profile(p, s, [&](std::size_t k, const std::string& why) {
    fail(t.source(), location_of(arr->get(k)->source(), t.where(key)), fmt::format("{}[{}]", t.key(key), k),
         why);
  });
  return p;
}

// Area where bodies a and b both claim points, sampled at the finer of their point spacings
// on the sub-cell centres build_particles uses (so shared edges never count).
template <int D>
double overlap_measure(const ScenarioOf<D>& s, const BodyOf<D>& a, const BodyOf<D>& b) {
  const ShapeBox<D> ba = bounding_box(a.shape), bb = bounding_box(b.shape);
  const Vec<D> lo = ba.lo.cwiseMax(bb.lo), hi = ba.hi.cwiseMin(bb.hi);
  if (!((hi.array() > lo.array()).all())) return 0.0;
  double spacing = s.cell_size / std::max(a.particles_per_cell, b.particles_per_cell);
  // At most about 1e7 samples: coarser sampling of a huge overlap still finds it.
  while ((hi - lo).prod() / std::pow(spacing, D) > 1e7) spacing *= 2;
  int first[D], count[D];
  for (int d = 0; d < D; ++d) {
    first[d] = static_cast<int>(std::floor((lo[d] - s.origin[d]) / spacing));
    count[d] = static_cast<int>(std::ceil((hi[d] - s.origin[d]) / spacing)) - first[d] + 1;
  }
  double n = 0;
  const int nz = D == 3 ? count[D - 1] : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < count[1]; ++j)
      for (int i = 0; i < count[0]; ++i) {
        Vec<D> x;
        x[0] = s.origin[0] + (first[0] + i + 0.5) * spacing;
        x[1] = s.origin[1] + (first[1] + j + 0.5) * spacing;
        if constexpr (D == 3) x[2] = s.origin[2] + (first[2] + k + 0.5) * spacing;
        if (shape_contains(a.shape, x) && shape_contains(b.shape, x)) n += 1;
      }
  return n * std::pow(spacing, D);
}

}  // namespace

void parse_ground(const TableReader& root, Scenario& s) {
  const auto g = root.table("ground", false);
  if (!g) return;
  g->allow_declared();
  for (const char* key : {"origin", "rotation"})
    if (g->has(key)) g->fail_at(key, "3D only: it places the rasters of a 3D [ground] on the map");
  if (!g->has("surface")) g->fail_missing("surface");
  s.ground_surface = read_profile(*g, "surface", s);
}

Layer parse_layer(const TableReader& b, const Scenario& s) {
  Layer l;
  if (b.has("top")) {
    l.top = read_profile(b, "top", s);
    l.surface = s.ground_surface;
  } else if (s.ground_surface) {
    l.top = *s.ground_surface;
  } else {
    b.fail_at("shape", "a layer needs `top`, or a [ground] surface to lie below");
  }
  if (b.has("bottom")) {
    l.bottom = read_profile(b, "bottom", s);
  } else {
    const double x0 = s.origin[0], x1 = grid_high(s)[0];
    l.bottom.points = {Vec<2>(x0, s.origin[1]), Vec<2>(x1, s.origin[1])};
  }
  return l;
}

template <int D>
void check_overlaps(const TableReader& root, const ScenarioOf<D>& s) {
  if (s.later_body_wins) return;
  const auto tables = root.array_of_tables("body");
  for (std::size_t j = 1; j < s.bodies.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      const double area = overlap_measure(s, s.bodies[i], s.bodies[j]);
      if (area > 0)
        tables[j].fail_at(
            "shape",
            fmt::format("body \"{}\" overlaps body \"{}\" (line {}) over about {:.4g} m^{}: both would get "
                        "material points there (double the mass). Reshape them, or set body_overlap = "
                        "\"later-wins\" to give the overlap to the later body",
                        s.bodies[j].name, s.bodies[i].name, tables[i].where().line, area, D));
    }
}

template void check_overlaps<2>(const TableReader&, const Scenario&);
template void check_overlaps<3>(const TableReader&, const Scenario3&);

}  // namespace skred::scenario_detail
