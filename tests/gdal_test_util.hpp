// Helpers of the raster tests (test_ground3.cpp, test_hazard_maps.cpp): a CRS as WKT through
// GDAL's OGR spatial references.
#pragma once
#include <cpl_conv.h>
#include <ogr_srs_api.h>

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

}  // namespace skred::test
