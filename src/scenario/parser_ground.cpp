// Layered ground (docs/scenario.md, "Layered ground"): the [ground] surface, "layer" bodies
// between two profiles read inline, from CSV files (a surveyed cross-section, a line taken
// from a DEM) or sampled from elevation rasters along the [ground] section, and the check that
// bodies do not overlap.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenario/build.hpp"
#include "scenario/parser_detail.hpp"
#include "scenario/raster.hpp"

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

bool ends_with(std::string name, std::initializer_list<const char*> extensions) {
  name = trim_lower(name);
  for (const char* e : extensions)
    if (name.size() >= std::strlen(e) &&
        name.compare(name.size() - std::strlen(e), std::string::npos, e) == 0)
      return true;
  return false;
}

// The [ground] section: at least 2 [easting, northing] vertices, no two in a row the same.
std::vector<Vec<2>> read_section_line(const TableReader& g) {
  const auto* arr = g.find("section")->as_array();
  if (!arr) g.fail_type("section", "an array of [easting, northing] map points");
  std::vector<Vec<2>> line;
  for (std::size_t k = 0; k < arr->size(); ++k) {
    const std::string key = fmt::format("{}[{}]", g.key("section"), k);
    line.push_back(node_vec2(*arr->get(k), g.source(), key, g.where("section")));
    if (k > 0 && !((line[k] - line[k - 1]).norm() > 0))
      fail(g.source(), location_of(arr->get(k)->source(), g.where("section")), key,
           fmt::format("repeats the vertex before it, ({}, {}): a section's vertices must differ", line[k][0],
                       line[k][1]));
  }
  if (line.size() < 2)
    g.fail_at("section", fmt::format("a section needs at least 2 vertices, got {}", line.size()));
  return line;
}

// The cell of a raster for messages: its place in the file and on the map.
std::string map_cell_text(const ElevationRaster& r, int i, int j) {
  const Vec<2> e = scenario_of(r, i, j);
  return fmt::format("cell (column {}, row {}; counted from 1 at the upper left) at map ({:.6g}, {:.6g})",
                     i + 1, j + 1, e[0], e[1]);
}

// A profile sampled from the raster named by `key` along the [ground] section, x the distance
// along it: the bilinear heights at the section's vertices, where it crosses a row or column
// of cell centres (between those the height is a quadratic in x, linear where the section runs
// along a row or column) and half-way between them, and at the grid's x edges; the part
// within the grid's x range is kept. Every cell centre the sampling reads must hold data.
// `crs` gets the raster's CRS (WKT), if asked.
Profile read_section(const TableReader& t, std::string_view key, const Scenario& s, std::string* crs) {
  std::filesystem::path path(t.string(key));
  if (path.is_relative()) path = std::filesystem::path(s.source).parent_path() / path;
  const std::string file = path.string();
  if (s.ground_section.empty())
    t.fail_at(key, fmt::format("'{}' is a raster: a 2D scenario samples it along [ground] section = "
                               "[[easting, northing], ...], which is not given (a profile is a .csv file)",
                               file));
  if (const std::string why = input_file_problem(file, kMaxProfileBytes); !why.empty())
    t.fail_at(key, fmt::format("cannot read raster file '{}': {}", file, why));
  if (!std::filesystem::exists(path))
    t.fail_at(key, fmt::format("cannot open raster file '{}': no such file", file));
  const auto fail_raster = [&](const std::string& why) {
    throw ScenarioError(
        fmt::format("{}: {} (raster '{}' of {}:{})", file, why, t.key(key), s.source, t.where(key).line));
  };
  ElevationRaster r;
  try {
    r = raster_on_map(file);
  } catch (const RasterError& e) {
    throw ScenarioError(
        fmt::format("{} (raster '{}' of {}:{})", e.what(), t.key(key), s.source, t.where(key).line));
  }
  if (crs) *crs = r.crs;
  if (!r.crs.empty() && !s.section_crs.empty() && !same_crs(r.crs, s.section_crs))
    fail_raster(
        fmt::format("its coordinate reference system \"{}\" differs from \"{}\" of {}: the rasters of a "
                    "scenario share one (reproject with gdalwarp)",
                    crs_name(r.crs), crs_name(s.section_crs), s.section_crs_file));
  const std::vector<Vec<2>>& line = s.ground_section;
  const double eps = 1e-9 * std::max(r.columns, r.rows);
  double length = 0;
  for (std::size_t k = 0; k < line.size(); ++k) {
    if (k > 0) length += (line[k] - line[k - 1]).norm();
    const Vec<2> c = cell_of(r, line[k][0], line[k][1]);
    if (c[0] < -0.5 - eps || c[0] > r.columns - 0.5 + eps || c[1] < -0.5 - eps || c[1] > r.rows - 0.5 + eps)
      fail_raster(
          fmt::format("the section leaves the raster: its vertex ground.section[{}] at map ({:.6g}, "
                      "{:.6g}), x = {:.6g}, lies outside the raster's {} x {} cells (at column {:.4g}, "
                      "row {:.4g} counted from 1)",
                      k, line[k][0], line[k][1], length, r.columns, r.rows, c[0] + 1, c[1] + 1));
  }
  // The samples: (x, map point).
  const double x_lo = s.origin[0], x_hi = grid_high(s)[0], tol = grid_tolerance(s);
  std::vector<std::pair<double, Vec<2>>> samples;
  double chain = 0;
  for (std::size_t k = 1; k < line.size(); ++k) {
    const Vec<2> a = line[k - 1], b = line[k];
    const double l = (b - a).norm();
    const Vec<2> ca = cell_of(r, a[0], a[1]), cb = cell_of(r, b[0], b[1]);
    std::vector<double> ts = {0.0, 1.0};
    for (int d = 0; d < 2; ++d)
      for (double m = std::floor(std::min(ca[d], cb[d])) + 1; m < std::max(ca[d], cb[d]); m += 1)
        ts.push_back((m - ca[d]) / (cb[d] - ca[d]));
    for (const double edge : {x_lo, x_hi})
      if (edge > chain && edge < chain + l) ts.push_back((edge - chain) / l);
    std::sort(ts.begin(), ts.end());
    ts.erase(std::unique(ts.begin(), ts.end(), [l](double p, double q) { return (q - p) * l < 1e-9; }),
             ts.end());
    for (std::size_t i = k == 1 ? 0 : 1; i < ts.size(); ++i) {
      if (i > 0) {
        const double m = 0.5 * (ts[i - 1] + ts[i]);
        samples.push_back({chain + m * l, a + m * (b - a)});
      }
      samples.push_back({chain + ts[i] * l, a + ts[i] * (b - a)});
    }
    chain += l;
  }
  // No data where the sampling reads: the cell centres around each piece's midpoint.
  for (std::size_t k = 1; k < samples.size(); k += 2) {
    const Vec<2> c = cell_of(r, samples[k].second[0], samples[k].second[1]);
    const int i = std::clamp(static_cast<int>(std::floor(c[0])), 0, std::max(r.columns - 2, 0));
    const int j = std::clamp(static_cast<int>(std::floor(c[1])), 0, std::max(r.rows - 2, 0));
    for (const int jj : {j, std::min(j + 1, r.rows - 1)})
      for (const int ii : {i, std::min(i + 1, r.columns - 1)})
        if (std::isnan(r.heights[static_cast<std::size_t>(jj) * r.columns + ii]))
          fail_raster(
              fmt::format("{} holds no data, on the section near x = {:.6g}: the profile would have "
                          "a hole there. Fill the raster's gaps (e.g. gdal_fillnodata)",
                          map_cell_text(r, ii, jj), samples[k].first));
  }
  Profile p;
  std::vector<Vec<2>> where;
  for (const auto& [x, e] : samples)
    if (x >= x_lo - tol && x <= x_hi + tol) {
      p.points.push_back(Vec<2>(x, r.at(e[0], e[1])));
      where.push_back(e);
      if (std::isnan(p.points.back()[1]))  // a no-data cell beside a crossing, at weight 0
        fail_raster(
            fmt::format("a cell beside the section at map ({:.6g}, {:.6g}), x = {:.6g}, holds no data. "
                        "Fill the raster's gaps (e.g. gdal_fillnodata)",
                        e[0], e[1], x));
    }
  if (p.points.size() < 2)
    fail_raster(
        fmt::format("the section, {:.6g} m long, does not reach into the grid's x range [{}, {}]: x is "
                    "the distance along it from its first vertex",
                    length, x_lo, x_hi));
  check_profile(p, s, [&](std::size_t k, const std::string& why) {
    fail_raster(fmt::format("at map ({:.6g}, {:.6g}) on the section: {}", where[k][0], where[k][1], why));
  });
  return p;
}

// A profile given inline as [[x, y], ...], as the name of a CSV file or, along the [ground]
// section, of a raster (any other file; without a section, .asc and GeoTIFF are rasters).
Profile read_profile(const TableReader& t, std::string_view key, const Scenario& s,
                     std::string* crs = nullptr) {
  const toml::node* n = t.find(key);
  if (n->is_string()) {
    const std::string name = t.string(key);
    const bool raster =
        s.ground_section.empty() ? ends_with(name, {".asc", ".tif", ".tiff"}) : !ends_with(name, {".csv"});
    return raster ? read_section(t, key, s, crs) : read_profile_csv(t, key, s);
  }
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
    if (g->has(key))
      g->fail_at(key,
                 "3D only: it places the rasters of a 3D [ground] on the map (a 2D [ground] samples "
                 "them along its section)");
  if (g->has("section")) s.ground_section = read_section_line(*g);
  if (!g->has("surface")) g->fail_missing("surface");
  std::string crs;  // the surface raster's: the layers' rasters must share it
  s.ground_surface = read_profile(*g, "surface", s, &crs);
  if (!crs.empty()) s.section_crs = crs, s.section_crs_file = g->string("surface");
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
