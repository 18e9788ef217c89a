// Hazard maps of 3D runs (docs/scenario.md, "Hazard maps (3D)"): the deposit thickness
// integrates to the moved volume (by hand and in a column collapse), the GeoTIFF carries the
// scenario's georeference and CRS (read back through GDAL's C API, and by gdalinfo), the .asc
// reads back the same, and summary.json lists the files.
#include <cpl_conv.h>
#include <fmt/core.h>
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_srs_api.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "gdal_test_util.hpp"
#include "io_test_util.hpp"
#include "run/map_files.hpp"
#include "run/simulation.hpp"
#include "scenario/build.hpp"
#include "scenario/raster.hpp"
#include "temp_dir.hpp"

using namespace skred;
using skred::test::wkt_of;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool same_as_epsg(const std::string& wkt, const char* epsg) {
  OGRSpatialReferenceH a = OSRNewSpatialReference(nullptr), b = OSRNewSpatialReference(nullptr);
  const bool same = OSRSetFromUserInput(a, wkt.c_str()) == OGRERR_NONE &&
                    OSRSetFromUserInput(b, epsg) == OGRERR_NONE && OSRIsSame(a, b);
  OSRDestroySpatialReference(a);
  OSRDestroySpatialReference(b);
  return same;
}

// examples/column_3d.toml on 0.25 m cells: a 1.5 m x 1.5 m x 2 m soil column (4.5 m^3) on a
// 6 m x 6 m floor of 24 x 24 columns, for 0.6 s.
std::string column_text() {
  std::string t = read(std::string(SKRED_SOURCE_DIR) + "/examples/column_3d.toml");
  t.replace(t.find("cell_size = 0.125"), 17, "cell_size = 0.25");
  t.replace(t.find("end_time = 2.0"), 14, "end_time = 0.6");
  return t;
}

// The ground of the georeference tests: a flat raster 1 m high, 1 m cells, lower-left corner
// (499990, 5999990), 20 x 20 cells, in ETRS89 / UTM 33N (.prj beside it).
Scenario3 georeferenced(const fs::path& dir, double rotation) {
  std::string asc = "ncols 20\nnrows 20\nxllcorner 499990\nyllcorner 5999990\ncellsize 1\n";
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 20; ++c) asc += c < 19 ? "1 " : "1\n";
  write(dir / "surface.asc", asc);
  write(dir / "surface.prj", wkt_of("EPSG:25833"));
  std::string text = column_text();  // the column becomes a layer 1 m thick under the surface
  const std::size_t box = text.find("shape = \"box\"");
  text.replace(box, text.find("[initial_stress]") - box, "shape = \"layer\"\n\n");
  write(dir / "s.toml", text + fmt::format("[ground]\nsurface = \"surface.asc\"\norigin = [500000, 6000000]\n"
                                           "rotation = {}\n",
                                           rotation));
  return std::get<Scenario3>(load_any_scenario((dir / "s.toml").string()));
}

// The column held elastic for 0.1 s, then let go for 0.3 s.
Scenario3 two_stages(const fs::path& dir) {
  std::string text = column_text();
  text.replace(text.find("end_time = 0.6"), 14, "");
  write(dir / "s.toml", text + R"(
[[stage]]
name = "hold"
duration = 0.1
elastic = true
[[stage]]
name = "collapse"
duration = 0.3
)");
  return std::get<Scenario3>(load_any_scenario((dir / "s.toml").string()));
}

using Dataset = std::unique_ptr<void, void (*)(GDALDatasetH)>;
Dataset open(const fs::path& p) {
  GDALAllRegister();
  return Dataset(GDALOpen(p.c_str(), GA_ReadOnly), GDALClose);
}

}  // namespace

// By hand: the column's upper half moved 1.5 m along x; its volume is what the deposit holds.
TEST(HazardMaps, DepositThicknessHoldsTheMovedVolume) {
  const test::TempDir dir;
  write(dir.path() / "s.toml", column_text());
  const Scenario3 s = std::get<Scenario3>(load_any_scenario((dir.path() / "s.toml").string()));
  Particles<3> P = build_particles(s);
  HazardMaps maps = start_hazard_maps(s, P);
  maps.begin_stage(P, 1.0);
  double moved = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.x[p][1] > 1.0) {  // the upper half slides 1.5 m towards +x at 2 m/s
      P.x[p][0] += 1.5;
      P.v[p] = Vec<3>(2.0, 0.0, 0.0);
      moved += P.volume0[p];
    }
  maps.sample(P, 1.5);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 200; ++k) maps.sample(P, 1.5);  // changes nothing: the cost of a sample
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ measured ] a map sample: %.2f ns per point\n", ns / (200.0 * static_cast<double>(P.size())));
  maps.finish_stage(P);
  const MapSet& m = maps.stage();
  double integral = 0.0;
  for (double t : m.thickness) integral += t * 0.25 * 0.25;
  EXPECT_NEAR(integral, 2.25, 1e-12);  // the column's upper half, 1.5 x 1 x 1.5 m
  EXPECT_NEAR(integral, moved, 1e-12);
  const auto at = [&](const std::vector<double>& v, double x, double z) {
    return v[static_cast<std::size_t>(x / 0.25) + 24 * static_cast<std::size_t>(z / 0.25)];
  };
  EXPECT_DOUBLE_EQ(at(m.arrival, 4.6, 3.0), 0.5);    // stage time
  EXPECT_TRUE(std::isnan(at(m.arrival, 2.6, 3.0)));  // only the lower half, which stayed
  EXPECT_TRUE(std::isnan(at(m.arrival, 0.1, 0.1)));
  EXPECT_NEAR(at(m.height_change, 2.6, 3.0), -1.0, 1e-12);  // the upper half left
  EXPECT_NEAR(at(m.height_change, 4.6, 3.0), 2.0, 1e-12);   // an empty column now 2 m high
  EXPECT_DOUBLE_EQ(at(m.max_speed, 4.6, 3.0), 2.0);
  EXPECT_NEAR(at(m.max_displacement, 4.6, 3.0), 1.5, 1e-12);
  EXPECT_NEAR(at(maps.run().arrival, 4.6, 3.0), 1.5, 1e-12);  // run time
  EXPECT_NEAR(at(m.top_start, 2.6, 3.0), 2.0, 1e-12);         // the terrain map
}

// By hand, two stages: the column's upper half moves 1.5 m along x in the first, its lower half
// 1 m along z in the second. The second stage's deposit holds the lower half; the run's holds
// both, the whole column (4.5 m^3), not only the last stage's.
TEST(HazardMaps, TheRunsDepositHoldsThePointsMovedInEveryStage) {
  const test::TempDir dir;
  write(dir.path() / "s.toml", column_text());
  const Scenario3 s = std::get<Scenario3>(load_any_scenario((dir.path() / "s.toml").string()));
  Particles<3> P = build_particles(s);
  HazardMaps maps = start_hazard_maps(s, P);
  const auto integral = [](const std::vector<double>& thickness) {
    double sum = 0.0;
    for (double t : thickness) sum += t * 0.25 * 0.25;
    return sum;
  };
  double column = 0.0, lower = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    column += P.volume0[p];
    if (P.x[p][1] <= 1.0) lower += P.volume0[p];
  }
  maps.begin_stage(P, 0.0);
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.x[p][1] > 1.0) P.x[p][0] += 1.5;
  maps.sample(P, 1.0);
  maps.finish_stage(P);
  EXPECT_NEAR(integral(maps.run().thickness), column - lower, 1e-12);
  P.x_ref = P.x;  // the solver's stage start
  maps.begin_stage(P, 1.0);
  for (std::size_t p = 0; p < P.size(); ++p)
    if (P.x[p][1] <= 1.0) P.x[p][2] += 1.0;
  maps.sample(P, 2.0);
  maps.finish_stage(P);
  EXPECT_NEAR(integral(maps.stage().thickness), lower, 1e-12);
  EXPECT_NEAR(lower, 2.25, 1e-12);
  EXPECT_NEAR(integral(maps.run().thickness), column, 1e-12);
  EXPECT_NEAR(column, 4.5, 1e-12);  // 1.5 m x 1.5 m x 2 m
}

// A 2D run has no hazard maps: asking for them (or setting their threshold) is an error naming
// the key, not silently ignored.
TEST(HazardMaps, MapKeysOfA2DScenarioAreAnError) {
  const test::TempDir dir;
  const std::string text = read(std::string(SKRED_SOURCE_DIR) + "/examples/slope_collapse.toml");
  for (const char* key : {"maps = true", "map_threshold = 0.1"}) {
    std::string t = text;
    t.replace(t.find("[output]"), 8, std::string("[output]\n") + key);
    write(dir.path() / "s.toml", t);
    std::string e;
    try {
      load_any_scenario((dir.path() / "s.toml").string());
    } catch (const ScenarioError& x) {
      e = x.what();
    }
    const std::string name = std::string(key).substr(0, std::string(key).find(' '));
    EXPECT_NE(e.find("s.toml:73:"), std::string::npos) << e;  // the line [output] takes the key on
    EXPECT_NE(e.find("key 'output." + name + "': 3D only: the hazard maps lie over a 3D run's x-z plane"),
              std::string::npos)
        << e;
  }
}

// A column collapsing on 24 x 24 columns: every map written in both formats and listed in
// summary.json; the deposit (every point counted as moved) integrates to the column's volume;
// `skred render --view top --map` draws it.
TEST(HazardMaps, ColumnCollapseConservesTheVolumeAndListsTheMaps) {
  const test::TempDir dir;
  std::string text = column_text();
  text.replace(text.find("[output]"), 8, "[output]\nmap_threshold = 1e-9");
  write(dir.path() / "s.toml", text);
  const Scenario3 s = std::get<Scenario3>(load_any_scenario((dir.path() / "s.toml").string()));
  RunOptions opt;
  opt.progress = false;
  const fs::path out = dir.path() / "out";
  const RunResult r = run_simulation(s, out, opt);
  ASSERT_TRUE(r.completed) << r.message;
  const std::string summary = read(out / "summary.json");
  for (const std::string& name : map_names())
    for (const char* ext : {".asc", ".tif"}) {
      const std::string file = "maps/" + name + ext;
      EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
      EXPECT_NE(summary.find("\"" + file + "\""), std::string::npos) << file;
      EXPECT_FALSE(fs::exists(out / (file + ".tmp"))) << file;
    }
  const RasterFile t = read_esri_ascii((out / "maps/deposit_thickness.asc").string());
  ASSERT_EQ(t.columns, 24);
  ASSERT_EQ(t.rows, 24);
  double volume = 0.0;
  for (double h : t.heights) volume += h * 0.25 * 0.25;
  EXPECT_NEAR(volume, 4.5, 0.045) << "the column's 4.5 m^3, within 1 %";
  const RasterFile dh = read_esri_ascii((out / "maps/height_change.asc").string());
  const RasterFile v = read_esri_ascii((out / "maps/max_speed.asc").string());
  const std::size_t centre = 12 + 24 * 12, corner = 0;
  EXPECT_LT(dh.heights[centre], -0.05) << "the column came down";
  EXPECT_GT(v.heights[centre], 0.1);
  EXPECT_EQ(v.heights[corner], 0.0);
  const RasterFile a = read_esri_ascii((out / "maps/arrival_time.asc").string());
  EXPECT_TRUE(std::isnan(a.heights[corner])) << "no data where the flow never came";
  // The local frame: easting x, northing -z, no CRS.
  const Dataset ds = open(out / "maps/deposit_thickness.tif");
  ASSERT_TRUE(ds);
  double g[6];
  ASSERT_EQ(GDALGetGeoTransform(ds.get(), g), CE_None);
  EXPECT_EQ((std::array<double, 6>{g[0], g[1], g[2], g[3], g[4], g[5]}),
            (std::array<double, 6>{0.0, 0.25, 0.0, 0.0, 0.0, -0.25}));
  std::printf("[ measured ] deposit volume %.6f m^3 of 4.5 m^3 (error %.3g %%)\n", volume,
              100 * (volume / 4.5 - 1.0));
  // skred render --view top --map: the deposit over the terrain's hillshade (Python, matplotlib).
  using iotest::shell_quote;
  const fs::path png = dir.path() / "map.png";
  const auto [status, said] =
      iotest::run_command(std::string(SKRED_BINARY) + " render " + shell_quote(out.string()) +
                          " --view top --map deposit_thickness -o " + shell_quote(png.string()));
  EXPECT_EQ(status, 0) << said;
  EXPECT_TRUE(fs::exists(png) && fs::file_size(png) > 1000);
}

// Two stages (the column held elastic, then let go): each stage's maps under maps/stage_N, the
// run's arrival the second stage's in simulation time, its largest speed the larger of the two.
TEST(HazardMaps, StagesWriteTheirOwnMaps) {
  const test::TempDir dir;
  const Scenario3 s = two_stages(dir.path());
  RunOptions opt;
  opt.progress = false;
  const fs::path out = dir.path() / "out";
  ASSERT_TRUE(run_simulation(s, out, opt).completed);
  const std::string summary = read(out / "summary.json");
  for (const char* f :
       {"maps/stage_1/arrival_time.tif", "maps/stage_2/arrival_time.asc", "maps/max_speed.asc"}) {
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
    EXPECT_NE(summary.find(f), std::string::npos) << f;
  }
  const auto heights = [&](const char* f) { return read_esri_ascii((out / f).string()).heights; };
  const auto a1 = heights("maps/stage_1/arrival_time.asc"), a2 = heights("maps/stage_2/arrival_time.asc"),
             a = heights("maps/arrival_time.asc");
  const auto v1 = heights("maps/stage_1/max_speed.asc"), v2 = heights("maps/stage_2/max_speed.asc"),
             v = heights("maps/max_speed.asc");
  int arrived = 0;
  for (std::size_t c = 0; c < a.size(); ++c) {
    EXPECT_TRUE(std::isnan(a1[c])) << "the held column does not flow";
    EXPECT_EQ(std::isnan(a[c]), std::isnan(a2[c]));
    if (!std::isnan(a2[c])) {
      EXPECT_NEAR(a[c], a2[c] + 0.1, 2e-3) << "the stage starts after whole steps";
      ++arrived;
    }
    EXPECT_EQ(v[c], std::max(v1[c], v2[c]));
  }
  EXPECT_GT(arrived, 0);
}

// A run stopped in its second stage and resumed from the checkpoint writes the same maps, byte
// for byte, as the run that went through (the maps are kept in the checkpoint).
TEST(HazardMaps, AResumedRunWritesTheSameMaps) {
  const test::TempDir dir;
  const Scenario3 s = two_stages(dir.path());
  RunOptions opt;
  opt.progress = false;
  opt.checkpoint_every = 1000000;  // only the final one
  ASSERT_TRUE(run_simulation(s, dir.path() / "a", opt).completed);
  RunOptions stop = opt;
  stop.stop_at_step = 200;  // in the second stage (about 86 steps each 0.1 s)
  ASSERT_TRUE(run_simulation(s, dir.path() / "b", stop).interrupted);
  EXPECT_FALSE(fs::exists(dir.path() / "b/maps/max_speed.asc")) << "an interrupted run writes no run maps";
  RunOptions again = opt;
  again.restart = dir.path() / "b/checkpoint.skc";
  ASSERT_TRUE(run_simulation(s, dir.path() / "b", again).completed);
  for (const std::string& name : map_names())
    for (const char* folder : {"maps/", "maps/stage_1/", "maps/stage_2/"}) {
      const std::string f = folder + name + ".asc";
      EXPECT_EQ(read(dir.path() / "a" / f), read(dir.path() / "b" / f)) << f;
    }
  EXPECT_NE(read(dir.path() / "b/summary.json").find("maps/stage_1/terrain.tif"), std::string::npos);
}

// The GeoTIFF and the .asc carry the [ground] raster's origin, cell size and CRS; rotated, the
// GeoTIFF's geotransform turns with the map and the .asc falls back to the local frame.
TEST(HazardMaps, GeoreferenceRoundTrip) {
  for (const double rotation : {0.0, 30.0}) {
    const test::TempDir dir;
    const Scenario3 s = georeferenced(dir.path(), rotation);
    const MapGeoreference g = map_georeference(s);
    std::vector<double> values(576);
    for (std::size_t c = 0; c < values.size(); ++c) values[c] = 0.1 * static_cast<double>(c) - 3.3;
    values[5] = NAN;
    const fs::path base = dir.path() / "m";
    write_map_asc(base, 24, 24, values, g);
    write_map_tif(base, 24, 24, values, g);
    const Dataset ds = open(dir.path() / "m.tif");
    ASSERT_TRUE(ds);
    EXPECT_EQ(GDALGetRasterXSize(ds.get()), 24);
    EXPECT_EQ(GDALGetRasterYSize(ds.get()), 24);
    double t[6];
    ASSERT_EQ(GDALGetGeoTransform(ds.get(), t), CE_None);
    const double c = std::cos(rotation * M_PI / 180), sn = std::sin(rotation * M_PI / 180);
    const std::array<double, 6> expected{500000, 0.25 * c, 0.25 * sn, 6000000, 0.25 * sn, -0.25 * c};
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(t[k], expected[k], 1e-9) << "rotation " << rotation << ", " << k;
    EXPECT_TRUE(same_as_epsg(GDALGetProjectionRef(ds.get()), "EPSG:25833"));
    std::vector<double> back(576);
    GDALRasterBandH band = GDALGetRasterBand(ds.get(), 1);
    ASSERT_EQ(GDALRasterIO(band, GF_Read, 0, 0, 24, 24, back.data(), 24, 24, GDT_Float64, 0, 0), CE_None);
    int has = 0;
    EXPECT_EQ(GDALGetRasterNoDataValue(band, &has), kMapNoData);
    EXPECT_TRUE(has);
    // The .asc: the same values (NaN as no data), at the cells' centres of the map or local frame.
    const RasterFile a = read_esri_ascii((dir.path() / "m.asc").string());
    ASSERT_EQ(a.heights.size(), 576u);
    for (std::size_t k = 0; k < 576; ++k) {
      EXPECT_EQ(back[k], k == 5 ? kMapNoData : values[k]);
      if (k == 5)
        EXPECT_TRUE(std::isnan(a.heights[k]));
      else
        EXPECT_EQ(a.heights[k], values[k]) << k;
    }
    if (rotation == 0) {
      EXPECT_EQ(a.geo, (std::array<double, 6>{500000.125, 0.25, 0, 5999999.875, 0, -0.25}));
      EXPECT_TRUE(same_as_epsg(a.crs, "EPSG:25833"));
    } else {
      EXPECT_EQ(a.geo, (std::array<double, 6>{0.125, 0.25, 0, -0.125, 0, -0.25}));
      EXPECT_TRUE(a.crs.empty());
      EXPECT_FALSE(fs::exists(dir.path() / "m.prj"));
    }
  }
}

// gdalinfo, GDAL's own tool, opens a map and reads its size, cell, CRS and no-data value.
TEST(HazardMaps, GdalinfoOpensTheMap) {
  ASSERT_EQ(std::system("gdalinfo --version > /dev/null 2>&1"), 0)
      << "gdalinfo (Debian's gdal-bin, installed by scripts/install-deps.sh) is not on the PATH";
  const test::TempDir dir;
  const Scenario3 s = georeferenced(dir.path(), 0.0);
  const Particles<3> P = build_particles(s);
  const HazardMaps maps = start_hazard_maps(s, P);
  const std::vector<std::string> files = write_map_set(s, maps, maps.run(), dir.path(), "maps");
  ASSERT_EQ(files.size(), 12u);
  const std::string cmd = fmt::format("gdalinfo '{}' 2>&1", (dir.path() / "maps/max_speed.tif").string());
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  ASSERT_TRUE(pipe);
  std::string text;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe.get())) text += buf;
  EXPECT_NE(text.find("Driver: GTiff"), std::string::npos) << text;
  EXPECT_NE(text.find("Size is 24, 24"), std::string::npos) << text;
  EXPECT_NE(text.find("Origin = (500000.000000000000000,6000000.000000000000000)"), std::string::npos)
      << text;
  EXPECT_NE(text.find("Pixel Size = (0.250000000000000,-0.250000000000000)"), std::string::npos) << text;
  EXPECT_NE(text.find("UTM zone 33N"), std::string::npos) << text;
  EXPECT_NE(text.find("NoData Value=-9999"), std::string::npos) << text;
}
