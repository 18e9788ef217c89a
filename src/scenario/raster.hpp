// Elevation rasters as their files hold them (docs/scenario.md, "Layered ground from rasters
// (3D)"): the ESRI ASCII grid (.asc) read here, GeoTIFF and the other formats through GDAL.
#pragma once
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace skred {

// A raster as read: heights at the cell centres, the file's first row the upper one.
struct RasterFile {
  int columns = 0, rows = 0;
  std::vector<double> heights;  // row-major; NaN: no data
  // The map coordinates of the centre of cell (column c, row r), counted from 0:
  // easting = geo[0] + geo[1] c + geo[2] r, northing = geo[3] + geo[4] c + geo[5] r.
  std::array<double, 6> geo{};
  std::string crs;    // the coordinate reference system as WKT; empty: the file gives none
  double nodata = 0;  // the file's no-data value (for messages)
  bool has_nodata = false;
};

// A raster that cannot be used; what() starts with the file (and line).
struct RasterError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Reads an ESRI ASCII grid (its CRS from the .prj beside it, if any) or, for any other
// extension, a raster through GDAL (its first band). Throws RasterError.
RasterFile read_raster(const std::string& path);
RasterFile read_esri_ascii(const std::string& path);

// Whether two CRS (WKT) are the same, and a CRS's name for messages.
bool same_crs(const std::string& a, const std::string& b);
std::string crs_name(const std::string& wkt);

}  // namespace skred
