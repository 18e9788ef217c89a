// The hazard maps' files (map_files.hpp): ESRI ASCII grids written here, GeoTIFF through GDAL's
// C API (the GTiff driver), each to a temporary name renamed onto the file (io/atomic_file.hpp).
#include "run/map_files.hpp"

#include <cpl_error.h>
#include <fmt/format.h>
#include <gdal.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace skred {

namespace fs = std::filesystem;

MapGeoreference map_georeference(const Scenario3& s) {
  MapGeoreference g;
  // The scenario's axes on the map (parser_ground3.cpp): x at the rotation from east, z a right
  // angle clockwise from it seen from above; exact for multiples of 90 degrees.
  double c = std::cos(s.map_rotation), sn = std::sin(s.map_rotation);
  if (std::abs(std::remainder(s.map_rotation, M_PI / 2)) < 1e-12) c = std::round(c), sn = std::round(sn);
  const double h = s.cell_size, x0 = s.origin[0], z0 = s.origin[2];
  g.geo = {s.map_origin[0] + x0 * c + z0 * sn, h * c,  h * sn,
           s.map_origin[1] + x0 * sn - z0 * c, h * sn, -h * c};
  g.local = {x0, h, 0.0, -z0, 0.0, -h};
  g.axis_aligned = c == 1.0 && sn == 0.0;
  std::vector<std::shared_ptr<const ElevationRaster>> rasters = {s.ground_raster};
  for (const Body3& b : s.bodies)
    if (const auto* l = std::get_if<Layer3>(&b.shape)) rasters.insert(rasters.end(), {l->top, l->bottom});
  for (const auto& r : rasters)
    if (r && !r->crs.empty()) {
      g.crs = r->crs;
      break;
    }
  return g;
}

void write_map_asc(const fs::path& base, int nx, int nz, const std::vector<double>& values,
                   const MapGeoreference& g) {
  // A rotated map cannot be an ESRI grid: that one is written in the local frame, without a CRS.
  const std::array<double, 6>& t = g.axis_aligned ? g.geo : g.local;
  const double h = t[1], xll = t[0], top = t[3];
  std::string text =
      fmt::format("ncols {}\nnrows {}\nxllcorner {}\nyllcorner {}\ncellsize {}\nNODATA_value {}\n", nx, nz,
                  xll, top - nz * h, h, kMapNoData);
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double v = values[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j];
      text += fmt::format("{}{}", i ? " " : "", std::isfinite(v) ? v : kMapNoData);
    }
    text += '\n';
  }
  fs::path asc = base, prj = base;
  asc += ".asc";
  prj += ".prj";
  write_file_atomically(asc, [&](std::ostream& os) { os << text; });
  if (g.axis_aligned && !g.crs.empty()) write_file_atomically(prj, [&](std::ostream& os) { os << g.crs; });
}

void write_map_tif(const fs::path& base, int nx, int nz, const std::vector<double>& values,
                   const MapGeoreference& g) {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
  fs::path tif = base;
  tif += ".tif";
  const fs::path tmp = temporary_path_for(tif);
  std::unique_ptr<void, void (*)(GDALDatasetH)> ds(nullptr, GDALClose);
  const auto fail = [&](const std::string& what) {
    const char* m = CPLGetLastErrorMsg();
    const std::string why = m && *m ? m : "no reason given";
    ds.reset();
    fs::remove(tmp);
    throw std::runtime_error(fmt::format("{}: cannot write the GeoTIFF: {}: {}", tif.string(), what, why));
  };
  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (!driver) fail("GDAL has no GTiff driver");
  CPLErrorReset();
  ds.reset(GDALCreate(driver, tmp.c_str(), nx, nz, 1, GDT_Float64, nullptr));
  if (!ds) fail("cannot create it");
  double geo[6];
  std::copy(g.geo.begin(), g.geo.end(), geo);
  if (GDALSetGeoTransform(ds.get(), geo) != CE_None) fail("its geotransform");
  if (!g.crs.empty() && GDALSetProjection(ds.get(), g.crs.c_str()) != CE_None) fail("its CRS");
  GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
  GDALSetRasterNoDataValue(band, kMapNoData);
  std::vector<double> data(values);
  for (double& v : data)
    if (!std::isfinite(v)) v = kMapNoData;
  if (GDALRasterIO(band, GF_Write, 0, 0, nx, nz, data.data(), nx, nz, GDT_Float64, 0, 0) != CE_None)
    fail("its values");
  ds.reset();  // closed: flushed to the file
  if (CPLGetLastErrorType() >= CE_Failure) fail("on closing it");
  std::error_code ec;
  fs::rename(tmp, tif, ec);
  if (ec) fail("renaming " + tmp.string() + ": " + ec.message());
}

std::vector<std::string> write_map_set(const Scenario3& s, const HazardMaps& maps, const MapSet& set,
                                       const fs::path& outdir, const std::string& folder) {
  const MapGeoreference g = map_georeference(s);
  const bool writes = maps.processes().rank() == 0;  // (every process has the maps)
  if (writes) fs::create_directories(outdir / folder);
  std::vector<std::string> files;
  for (const std::string& name : map_names()) {
    const fs::path rel = fs::path(folder) / name;
    const std::vector<double>& v = HazardMaps::field(set, name);
    if (writes) {
      write_map_asc(outdir / rel, maps.nx(), maps.nz(), v, g);
      write_map_tif(outdir / rel, maps.nx(), maps.nz(), v, g);
    }
    files.push_back(rel.string() + ".asc");
    files.push_back(rel.string() + ".tif");
  }
  return files;
}

HazardMaps start_hazard_maps(const Scenario3& s, const Particles<3>& P, const Processes& procs) {
  if (!s.output_maps) return {};
  const double threshold = s.map_threshold > 0 ? s.map_threshold : 0.5 * s.cell_size;
  HazardMaps maps(s.origin[0], s.origin[2], s.cell_size, s.cells[0], s.cells[2], threshold);
  maps.set_processes(procs);
  maps.begin_run(P);
  return maps;
}

void finish_stage_maps(const Scenario3& s, Particles<3>& P, HazardMaps& maps, std::size_t k,
                       const fs::path& outdir, std::vector<std::string>& files) {
  if (!maps.enabled()) return;
  maps.finish_stage(P);
  if (s.stages.size() < 2) return;
  for (std::string& f : write_map_set(s, maps, maps.stage(), outdir, fmt::format("maps/stage_{}", k + 1)))
    files.push_back(std::move(f));
}

}  // namespace skred
