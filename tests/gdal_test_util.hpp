// Helpers of the raster tests (test_ground3.cpp, test_ground_section.cpp, test_hazard_maps.cpp):
// a CRS as WKT through GDAL's OGR spatial references, an ESRI ASCII grid written by hand.
#pragma once
#include <cpl_conv.h>
#include <fmt/core.h>
#include <ogr_srs_api.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace skred::test {

// The WKT of a CRS given as GDAL reads it (e.g. "EPSG:25833").
inline std::string wkt_of(const char* crs) {
  OGRSpatialReferenceH s = OSRNewSpatialReference(nullptr);
  OSRSetFromUserInput(s, crs);
  char* w = nullptr;
  OSRExportToWkt(s, &w);
  std::string out = w ? w : "";
  CPLFree(w);
  OSRDestroySpatialReference(s);
  return out;
}

// An ESRI ASCII grid of cols x rows cells of side `cell`, lower-left corner (xll, yll), the
// height of cell (column c, row r; row 0 the upper) h(c, r).
inline void write_asc(const std::filesystem::path& p, int cols, int rows, double xll, double yll, double cell,
                      const std::function<double(int, int)>& h) {
  std::string t =
      fmt::format("ncols {}\nnrows {}\nxllcorner {}\nyllcorner {}\ncellsize {}\nNODATA_value -9999\n", cols,
                  rows, xll, yll, cell);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) t += fmt::format("{}{}", c ? " " : "", h(c, r));
    t += "\n";
  }
  std::ofstream(p) << t;
}

}  // namespace skred::test
