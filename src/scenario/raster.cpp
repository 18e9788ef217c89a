// Elevation raster files (raster.hpp): the ESRI ASCII grid, read here; GeoTIFF and the other
// formats through GDAL's C API; CRS comparison through GDAL's OGR spatial references.
#include "scenario/raster.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <fmt/format.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

namespace skred {

namespace {

// GDAL's messages go to the exception, not to stderr, while one of these lives.
struct QuietGdal {
  QuietGdal() {
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
  static std::string last() {
    const char* m = CPLGetLastErrorMsg();
    return m && *m ? m : "no reason given";
  }
};

using Srs = std::unique_ptr<void, void (*)(OGRSpatialReferenceH)>;

// The spatial reference of `text` (WKT, ESRI WKT, "EPSG:n", ...), or null if GDAL cannot read it.
Srs srs_of(const std::string& text) {
  Srs s(OSRNewSpatialReference(nullptr), OSRDestroySpatialReference);
  if (OSRSetFromUserInput(s.get(), text.c_str()) != OGRERR_NONE) s.reset();
  return s;
}

// The CRS of `text` as WKT; throws RasterError naming `file` if it cannot be read.
std::string crs_wkt(const std::string& text, const std::string& file) {
  const QuietGdal quiet;
  const Srs s = srs_of(text);
  if (!s)
    throw RasterError(fmt::format("{}: cannot read its coordinate reference system: {}", file, quiet.last()));
  char* wkt = nullptr;
  OSRExportToWkt(s.get(), &wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool to_number(std::string_view t, double& v) {
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && end == t.data() + t.size();
}

// The header of an ESRI ASCII grid: ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter,
// cellsize (or dx and dy), NODATA_value (optional), one "key value" per line.
struct AsciiHeader {
  double ncols = -1, nrows = -1, x = NAN, y = NAN, dx = NAN, dy = NAN;
  bool centre = false;
  bool has_nodata = false;
  double nodata = 0;
};

}  // namespace

RasterFile read_esri_ascii(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RasterError(fmt::format("{}: cannot open the raster file", path));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const auto fail = [&](int line, const std::string& why) {
    throw RasterError(fmt::format("{}:{}: {}", path, line, why));
  };
  AsciiHeader h;
  std::size_t pos = 0;
  int line = 1;
  // Header lines until the first line that starts with a number.
  while (pos < text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::istringstream words(text.substr(pos, end - pos));
    std::string key, value;
    words >> key;
    double probe;  // a line of heights ("nan" is a number)
    if (!key.empty() && (!std::isalpha(static_cast<unsigned char>(key[0])) || to_number(key, probe))) break;
    if (!key.empty()) {
      words >> value;
      double v;
      if (!to_number(value, v) || !std::isfinite(v))
        fail(line, fmt::format("header '{}': '{}' is not a finite number", key, value));
      const std::string k = lower(key);
      if (k == "ncols")
        h.ncols = v;
      else if (k == "nrows")
        h.nrows = v;
      else if (k == "xllcorner" || k == "xllcenter")
        h.x = v, h.centre = k == "xllcenter";
      else if (k == "yllcorner" || k == "yllcenter")
        h.y = v;
      else if (k == "cellsize")
        h.dx = h.dy = v;
      else if (k == "dx")
        h.dx = v;
      else if (k == "dy")
        h.dy = v;
      else if (k == "nodata_value")
        h.has_nodata = true, h.nodata = v;
      else
        fail(line, fmt::format("unknown header key '{}' (an ESRI ASCII grid has ncols, nrows, xllcorner or "
                               "xllcenter, yllcorner or yllcenter, cellsize, NODATA_value)",
                               key));
    }
    pos = end + 1;
    ++line;
  }
  const auto whole = [](double v) { return v >= 1 && v <= 1e6 && v == std::floor(v); };
  if (!whole(h.ncols) || !whole(h.nrows))
    fail(line, "the header needs ncols and nrows, whole numbers from 1 to 1000000");
  if (std::isnan(h.x) || std::isnan(h.y))
    fail(line, "the header needs xllcorner (or xllcenter) and yllcorner (or yllcenter)");
  if (!(h.dx > 0) || !(h.dy > 0)) fail(line, "the header needs a positive cellsize");
  RasterFile r;
  r.columns = static_cast<int>(h.ncols);
  r.rows = static_cast<int>(h.nrows);
  const std::size_t n = static_cast<std::size_t>(r.columns) * static_cast<std::size_t>(r.rows);
  if (n > (std::size_t{1} << 28))
    fail(line, fmt::format("{} x {} cells are too many (at most 2^28)", r.columns, r.rows));
  r.has_nodata = h.has_nodata;
  r.nodata = h.nodata;
  // Cell centres: the lower-left corner (or centre) is that of the last row.
  const double x0 = h.centre ? h.x : h.x + 0.5 * h.dx;
  const double y0 = h.centre ? h.y : h.y + 0.5 * h.dy;
  r.geo = {x0, h.dx, 0.0, y0 + (r.rows - 1) * h.dy, 0.0, -h.dy};
  r.heights.reserve(n);
  while (pos < text.size()) {
    const char c = text[pos];
    if (c == '\n') {
      ++line, ++pos;
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++pos;
      continue;
    }
    std::size_t end = pos;
    while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end]))) ++end;
    const std::string_view token(text.data() + pos, end - pos);
    double v;
    if (!to_number(token, v)) fail(line, fmt::format("'{}' is not a number", token));
    if (r.heights.size() == n)
      fail(line, fmt::format("more values than the header's {} x {} cells", r.columns, r.rows));
    r.heights.push_back(!std::isfinite(v) || (h.has_nodata && v == h.nodata) ? NAN : v);
    pos = end;
  }
  if (r.heights.size() < n)
    fail(line, fmt::format("the file ends after {} of the {} x {} heights (in row {} of {}): truncated?",
                           r.heights.size(), r.columns, r.rows, r.heights.size() / r.columns + 1, r.rows));
  // The CRS from the .prj beside it, if there is one.
  std::filesystem::path prj(path);
  prj.replace_extension(".prj");
  if (std::filesystem::is_regular_file(prj)) {
    std::ifstream p(prj);
    std::ostringstream wkt;
    wkt << p.rdbuf();
    std::string t = wkt.str();
    t.erase(t.find_last_not_of(" \t\r\n") + 1);
    t.erase(0, std::min(t.size(),
                        t.find_first_not_of(" \t\r\n")));  // (gdalsrsinfo -o wkt starts with a blank line)
    if (t.empty())
      throw RasterError(
          fmt::format("{}: cannot read its coordinate reference system: {} is empty", path, prj.string()));
    r.crs = crs_wkt(t, fmt::format("{} ({})", path, prj.string()));
  }
  return r;
}

RasterFile read_raster(const std::string& path) {
  if (lower(std::filesystem::path(path).extension().string()) == ".asc") return read_esri_ascii(path);
  const QuietGdal quiet;
  const std::unique_ptr<void, void (*)(GDALDatasetH)> ds(GDALOpen(path.c_str(), GA_ReadOnly), GDALClose);
  if (!ds) throw RasterError(fmt::format("{}: GDAL cannot read it as a raster: {}", path, quiet.last()));
  RasterFile r;
  r.columns = GDALGetRasterXSize(ds.get());
  r.rows = GDALGetRasterYSize(ds.get());
  if (GDALGetRasterCount(ds.get()) < 1 || r.columns < 1 || r.rows < 1)
    throw RasterError(fmt::format("{}: the file holds no raster band", path));
  if (static_cast<double>(r.columns) * r.rows > double(1 << 28))
    throw RasterError(fmt::format("{}: {} x {} cells are too many (at most 2^28)", path, r.columns, r.rows));
  double gt[6];
  if (GDALGetGeoTransform(ds.get(), gt) != CE_None)
    throw RasterError(fmt::format("{}: the raster has no georeference (geotransform)", path));
  // GDAL's geotransform locates the cells' corners; skred's, their centres.
  r.geo = {gt[0] + 0.5 * (gt[1] + gt[2]), gt[1], gt[2], gt[3] + 0.5 * (gt[4] + gt[5]), gt[4], gt[5]};
  GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
  int has = 0;
  r.nodata = GDALGetRasterNoDataValue(band, &has);
  r.has_nodata = has != 0;
  r.heights.resize(static_cast<std::size_t>(r.columns) * static_cast<std::size_t>(r.rows));
  if (GDALRasterIO(band, GF_Read, 0, 0, r.columns, r.rows, r.heights.data(), r.columns, r.rows, GDT_Float64,
                   0, 0) != CE_None)
    throw RasterError(fmt::format("{}: cannot read its heights (truncated?): {}", path, quiet.last()));
  for (double& v : r.heights)
    if (!std::isfinite(v) || (r.has_nodata && v == r.nodata)) v = NAN;
  const char* wkt = GDALGetProjectionRef(ds.get());
  if (wkt && *wkt) r.crs = crs_wkt(wkt, path);
  return r;
}

bool same_crs(const std::string& a, const std::string& b) {
  const QuietGdal quiet;
  const Srs sa = srs_of(a), sb = srs_of(b);
  return sa && sb && OSRIsSame(sa.get(), sb.get());
}

std::string crs_name(const std::string& wkt) {
  if (wkt.empty()) return "none";
  const QuietGdal quiet;
  const Srs s = srs_of(wkt);
  const char* name = s ? OSRGetName(s.get()) : nullptr;
  return name ? name : "unnamed";
}

}  // namespace skred
