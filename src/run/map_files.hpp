// The hazard maps' files (docs/scenario.md, "Hazard maps (3D)"): each map as an ESRI ASCII grid
// (.asc) and a GeoTIFF (through GDAL), georeferenced as the scenario's rasters are ([ground]
// origin and rotation, their CRS), else in the local frame (easting x, northing -z).
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "run/hazard_maps.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// Where the maps lie: GDAL's geotransform of the cells' corners (easting = g[0] + g[1] i + g[2] j,
// northing = g[3] + g[4] i + g[5] j for column i along x, row j along z), the CRS as WKT (empty:
// none), and whether the map axes are the scenario's (a rotation of 0: the .asc can hold it);
// `local` the same in the local frame (easting x, northing -z).
struct MapGeoreference {
  std::array<double, 6> geo{}, local{};
  std::string crs;
  bool axis_aligned = true;
};
MapGeoreference map_georeference(const Scenario3& s);

// The value written for no data (a NaN) in both formats.
inline constexpr double kMapNoData = -9999.0;

// Writes `values` (nx x nz, index i + nx j) as `base`.asc (with a .prj beside it when there is a
// CRS and the map is axis-aligned; otherwise in the local frame) and `base`.tif, each atomically.
// Throws std::runtime_error naming the file.
void write_map_asc(const std::filesystem::path& base, int nx, int nz, const std::vector<double>& values,
                   const MapGeoreference& g);
void write_map_tif(const std::filesystem::path& base, int nx, int nz, const std::vector<double>& values,
                   const MapGeoreference& g);

// Writes every map of `set` into `outdir`/`folder` (map_names(): NAME.asc and NAME.tif) and returns
// their paths relative to `outdir` (split among processes, the first writes them).
std::vector<std::string> write_map_set(const Scenario3& s, const HazardMaps& maps, const MapSet& set,
                                       const std::filesystem::path& outdir, const std::string& folder);

// The maps of a run of `s` from the points `P` at its start (off when output.maps is false).
HazardMaps start_hazard_maps(const Scenario3& s, const Particles<3>& P, const Processes& procs = {});

// After stage `k`: its maps taken and merged into the run's (HazardMaps::finish_stage); written
// under maps/stage_<k+1> when the run has more than one stage, their paths added to `files`.
void finish_stage_maps(const Scenario3& s, Particles<3>& P, HazardMaps& maps, std::size_t k,
                       const std::filesystem::path& outdir, std::vector<std::string>& files);

}  // namespace skred
