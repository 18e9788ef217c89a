// Layered ground in 3D (docs/scenario.md, "Layered ground from rasters (3D)"): the [ground]
// surface and the "layer" bodies' top and bottom as elevation rasters, mapped from the map's
// easting and northing onto the scenario's x and z, and checked where the grid samples them.
#include <cmath>
#include <filesystem>
#include <limits>
#include <utility>

#include "scenario/parser_detail.hpp"
#include "scenario/raster.hpp"

namespace skred::scenario_detail {

Vec<2> cell_of(const ElevationRaster& r, double x, double z) {
  const auto& t = r.to_cell;
  return {t[0] + t[1] * x + t[2] * z, t[3] + t[4] * x + t[5] * z};
}

// Scenario (x, z) of the fractional cell (u, v).
Vec<2> scenario_of(const ElevationRaster& r, double u, double v) {
  const auto& t = r.to_cell;
  const double det = t[1] * t[5] - t[2] * t[4], a = u - t[0], b = v - t[3];
  return {(t[5] * a - t[2] * b) / det, (t[1] * b - t[4] * a) / det};
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The scenario's horizontal axes on the map: x at `rotation` counter-clockwise from east, z a
// right angle clockwise from x seen from above (so x, y up, z are right-handed: x east, z south).
struct MapFrame {
  Vec<2> origin, ex, ez;
  Vec<2> map(double x, double z) const { return origin + x * ex + z * ez; }
};

MapFrame frame_of(const Scenario3& s) {
  double c = std::cos(s.map_rotation), sn = std::sin(s.map_rotation);
  if (std::abs(std::remainder(s.map_rotation, M_PI / 2)) < 1e-12) c = std::round(c), sn = std::round(sn);
  return {s.map_origin, Vec<2>(c, sn), Vec<2>(sn, -c)};
}

// The raster in scenario coordinates: (column, row) = G^-1 (map(x, z) - g), G and g the
// geotransform of the cell centres.
ElevationRaster to_scenario(RasterFile&& f, const MapFrame& m, const std::string& file) {
  const auto& g = f.geo;
  const double det = g[1] * g[5] - g[2] * g[4];
  if (!(std::abs(det) > 0) || !std::isfinite(det))
    throw RasterError(fmt::format("{}: the raster's geotransform is degenerate (cell size zero)", file));
  const double i00 = g[5] / det, i01 = -g[2] / det, i10 = -g[4] / det, i11 = g[1] / det;
  const Vec<2> d = m.origin - Vec<2>(g[0], g[3]);
  ElevationRaster r;
  r.file = file;
  r.columns = f.columns;
  r.rows = f.rows;
  r.heights = std::move(f.heights);
  r.crs = std::move(f.crs);
  r.to_cell = {i00 * d[0] + i01 * d[1], i00 * m.ex[0] + i01 * m.ex[1], i00 * m.ez[0] + i01 * m.ez[1],
               i10 * d[0] + i11 * d[1], i10 * m.ex[0] + i11 * m.ex[1], i10 * m.ez[0] + i11 * m.ez[1]};
  return r;
}

// The u range of the part of convex polygon p (in (u, v)) with a <= v <= b; empty if lo > hi.
std::pair<double, double> u_range_in_band(std::vector<Vec<2>> p, double a, double b) {
  const auto clip = [&p](double level, double sign) {  // keeps sign (v - level) >= 0
    std::vector<Vec<2>> out;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const Vec<2>&P = p[k], &Q = p[(k + 1) % p.size()];
      const double dp = sign * (P[1] - level), dq = sign * (Q[1] - level);
      if (dp >= 0) out.push_back(P);
      if ((dp >= 0) != (dq >= 0)) out.push_back(P + (Q - P) * (dp / (dp - dq)));
    }
    p = std::move(out);
  };
  if (std::isfinite(a)) clip(a, 1.0);
  if (std::isfinite(b)) clip(b, -1.0);
  std::pair<double, double> range{kInf, -kInf};
  for (const Vec<2>& q : p) range = {std::min(range.first, q[0]), std::max(range.second, q[0])};
  return range;
}

// A raster cell for messages: its place in the file and where it lies on the map and in the scenario.
std::string cell_text(const ElevationRaster& r, const MapFrame& m, int i, int j) {
  const Vec<2> xz = scenario_of(r, i, j), e = m.map(xz[0], xz[1]);
  return fmt::format(
      "cell (column {}, row {}; counted from 1 at the upper left) at map ({:.6g}, {:.6g}), "
      "scenario x = {:.6g}, z = {:.6g}",
      i + 1, j + 1, e[0], e[1], xz[0], xz[1]);
}

// Checks a raster where the grid samples it: it covers the grid's horizontal extent, every cell
// bilinear sampling reads there holds a height, and the cells inside the extent lie within the
// grid's y range and not above `surface`. Returns the lowest and highest height sampled.
std::pair<double, double> check_raster(const ElevationRaster& r, const Scenario3& s, const MapFrame& m,
                                       const ElevationRaster* surface) {
  const Vec<3> lo = s.origin, hi = grid_high(s);
  const double tol = grid_tolerance(s);
  const auto fail = [&](const std::string& why) { throw RasterError(fmt::format("{}: {}", r.file, why)); };
  std::vector<Vec<2>> footprint;
  for (const auto& [x, z] : {std::pair{lo[0], lo[2]}, {hi[0], lo[2]}, {hi[0], hi[2]}, {lo[0], hi[2]}}) {
    const Vec<2> c = cell_of(r, x, z);
    const double eps = 1e-9 * std::max(r.columns, r.rows);
    if (c[0] < -0.5 - eps || c[0] > r.columns - 0.5 + eps || c[1] < -0.5 - eps || c[1] > r.rows - 0.5 + eps) {
      const Vec<2> e = m.map(x, z);
      fail(
          fmt::format("the raster does not cover the grid: the grid's corner x = {}, z = {} lies at map "
                      "({:.6g}, {:.6g}), outside the raster's {} x {} cells (at column {:.4g}, row {:.4g} "
                      "counted from 1); check [ground] origin and rotation",
                      x, z, e[0], e[1], r.columns, r.rows, c[0] + 1, c[1] + 1));
    }
    footprint.push_back(c);
  }
  double v_lo = kInf, v_hi = -kInf;
  for (const Vec<2>& c : footprint) v_lo = std::min(v_lo, c[1]), v_hi = std::max(v_hi, c[1]);
  std::pair<double, double> range{kInf, -kInf};
  const int j0 = std::max(0, static_cast<int>(std::floor(v_lo)) - 1);
  const int j1 = std::min(r.rows - 1, static_cast<int>(std::ceil(v_hi)) + 1);
  for (int j = j0; j <= j1; ++j) {
    // Bilinear sampling reads node j for clamped rows in [j - 1, j + 1] (its neighbours' cells).
    const auto [u_lo, u_hi] =
        u_range_in_band(footprint, j - 1 <= 0 ? -kInf : j - 1.0, j + 1 >= r.rows - 1 ? kInf : j + 1.0);
    if (!(u_lo <= u_hi)) continue;
    const int i0 = std::max(0, static_cast<int>(std::ceil(u_lo - 1)));
    const int i1 = std::min(r.columns - 1, static_cast<int>(std::floor(u_hi + 1)));
    for (int i = i0; i <= i1; ++i) {
      const double h = r.heights[static_cast<std::size_t>(j) * r.columns + i];
      if (std::isnan(h))
        fail(
            fmt::format("{} holds no data, inside the grid's footprint: the body would have a hole there. "
                        "Fill the raster's gaps (e.g. gdal_fillnodata) or shrink the grid",
                        cell_text(r, m, i, j)));
      range = {std::min(range.first, h), std::max(range.second, h)};
      const Vec<2> xz = scenario_of(r, i, j);
      if (xz[0] < lo[0] - tol || xz[0] > hi[0] + tol || xz[1] < lo[2] - tol || xz[1] > hi[2] + tol) continue;
      if (h < lo[1] - tol || h > hi[1] + tol)
        fail(fmt::format("the height {} of {} lies outside the grid's y range [{}, {}]", h,
                         cell_text(r, m, i, j), lo[1], hi[1]));
      const double top = surface ? surface->at(xz[0], xz[1]) : kInf;
      if (h > top + tol)
        fail(
            fmt::format("the layer lies above the ground surface at {}: y = {} there, the surface ({}) "
                        "y = {}; a layer lies below the ground: clip it to the surface",
                        cell_text(r, m, i, j), h, surface->file, top));
    }
  }
  return range;
}

// A raster already read for this scenario from the same file, or null.
std::shared_ptr<const ElevationRaster> loaded(const Scenario3& s, const std::string& file) {
  std::vector<std::shared_ptr<const ElevationRaster>> all = {s.ground_raster};
  for (const Body3& b : s.bodies)
    if (const auto* l = std::get_if<Layer3>(&b.shape)) all.insert(all.end(), {l->top, l->bottom});
  for (const auto& r : all)
    if (r && r->file == file) return r;
  return nullptr;
}

// The first raster of the scenario (or `also`) that has a CRS, or null.
const ElevationRaster* with_crs(const Scenario3& s, const ElevationRaster* also) {
  if (s.ground_raster && !s.ground_raster->crs.empty()) return s.ground_raster.get();
  for (const Body3& b : s.bodies)
    if (const auto* l = std::get_if<Layer3>(&b.shape))
      for (const auto& r : {l->top, l->bottom})
        if (r && !r->crs.empty()) return r.get();
  return also && !also->crs.empty() ? also : nullptr;
}

// The raster named by key `key`, read, mapped and checked (below `surface` if given; the
// same CRS as `also` and the scenario's other rasters).
std::shared_ptr<const ElevationRaster> read_elevation(const TableReader& t, std::string_view key,
                                                      const Scenario3& s, const ElevationRaster* surface,
                                                      const ElevationRaster* also,
                                                      std::pair<double, double>& heights) {
  if (!t.find(key)->is_string()) t.fail_type(key, "the name of a raster file (.asc, GeoTIFF)");
  std::filesystem::path path(t.string(key));
  if (path.is_relative()) path = std::filesystem::path(s.source).parent_path() / path;
  const std::string file = path.string();
  if (const std::string why = input_file_problem(file, kMaxProfileBytes); !why.empty())
    t.fail_at(key, fmt::format("cannot read raster file '{}': {}", file, why));
  if (!std::filesystem::exists(path))
    t.fail_at(key, fmt::format("cannot open raster file '{}': no such file", file));
  const MapFrame m = frame_of(s);
  try {
    std::shared_ptr<const ElevationRaster> r = loaded(s, file);
    if (!r) r = std::make_shared<const ElevationRaster>(to_scenario(read_raster(file), m, file));
    heights = check_raster(*r, s, m, surface);
    if (const ElevationRaster* other = with_crs(s, also);
        other && !r->crs.empty() && !same_crs(r->crs, other->crs))
      throw RasterError(
          fmt::format("{}: its coordinate reference system \"{}\" differs from \"{}\" of {}: the "
                      "rasters of a scenario share one (reproject with gdalwarp)",
                      file, crs_name(r->crs), crs_name(other->crs), other->file));
    return r;
  } catch (const RasterError& e) {
    throw ScenarioError(
        fmt::format("{} (raster '{}' of {}:{})", e.what(), t.key(key), s.source, t.where(key).line));
  }
}

}  // namespace

ElevationRaster raster_on_map(const std::string& file) {
  return to_scenario(read_raster(file), MapFrame{Vec<2>::Zero(), Vec<2>(1, 0), Vec<2>(0, 1)}, file);
}

void parse_ground3(const TableReader& root, Scenario3& s) {
  const auto g = root.table("ground", false);
  if (!g) return;
  g->allow_declared();
  if (g->has("section"))
    g->fail_at("section",
               "2D only: a 2D scenario samples its rasters along it; a 3D [ground] takes the "
               "rasters whole (place them with origin and rotation)");
  s.map_origin = g->vec2("origin", Vec<2>::Zero());
  s.map_rotation = g->number("rotation") * kDeg;
  if (!g->has("surface")) g->fail_missing("surface");
  std::pair<double, double> heights;
  s.ground_raster = read_elevation(*g, "surface", s, nullptr, nullptr, heights);
}

Layer3 parse_layer3(const TableReader& b, const Scenario3& s) {
  Layer3 l;
  std::pair<double, double> top{s.origin[1], grid_high(s)[1]}, bottom{s.origin[1], s.origin[1]};
  const ElevationRaster* surface = s.ground_raster.get();
  if (b.has("top")) {
    l.top = read_elevation(b, "top", s, surface, nullptr, top);
    l.surface = s.ground_raster;
  } else if (s.ground_raster) {
    l.top = s.ground_raster;
    top = check_raster(*l.top, s, frame_of(s), nullptr);
  } else {
    b.fail_at("shape", "a layer needs `top`, or a [ground] surface to lie below");
  }
  if (b.has("bottom")) l.bottom = read_elevation(b, "bottom", s, surface, l.top.get(), bottom);
  const Vec<3> hi = grid_high(s);
  l.lo = Vec<3>(s.origin[0], std::max(s.origin[1], bottom.first), s.origin[2]);
  l.hi = Vec<3>(hi[0], std::clamp(top.second, l.lo[1], hi[1]), hi[2]);
  return l;
}

}  // namespace skred::scenario_detail
