// 2D layered ground sampled from elevation rasters along a section (docs/scenario.md, "Layered
// ground from profiles (2D)"): a section through the rasters of an extruded slope builds the
// same points as the profiles drawn by hand, with x along easting or northing; a bent section
// through a plane raster gives the plane's heights exactly; every bad section is an error
// naming the raster, the key and the place.
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "gdal_test_util.hpp"
#include "ground_slope.hpp"
#include "scenario/build.hpp"
#include "scenario/scenario.hpp"
#include "temp_dir.hpp"

using namespace skred;
using skred::test::write_asc;
using namespace skred::test::slope;
namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

const std::string kHead2 = flat_head();  // the slope's soils on the 2D grid

// The layers between three profiles, each given as `top`/`bottom` values.
std::string layers(const std::string& clay_base, const std::string& rock) {
  return "[[body]]\nname = \"clay\"\nmaterial = \"clay\"\nshape = \"layer\"\nbottom = " + clay_base +
         "\n[[body]]\nname = \"sand\"\nmaterial = \"sand\"\nshape = \"layer\"\ntop = " + clay_base +
         "\nbottom = " + rock +
         "\n[[body]]\nname = \"rock\"\nmaterial = \"sand\"\nshape = \"layer\"\ntop = " + rock + "\n";
}

const std::string kSection = "[ground]\nsection = [[1000, 4995], [1040, 4995]]\nsurface = \"surface.asc\"\n";

}  // namespace

TEST(GroundSection, SectionsThroughAnExtrudedSlopeAreTheProfilesDrawnByHand) {
  const test::TempDir dir;
  write(dir / "hand.toml", kHead2 + "[ground]\nsurface = [[0, 20], [10, 20], [30, 5], [40, 5]]\n" +
                               layers("[[0, 12], [40, 2]]", "[[0, 1.1], [40, 1.1]]"));
  const Scenario h = std::get<Scenario>(load_any_scenario((dir / "hand.toml").string()));
  const Particles<2> q = build_particles(h);
  ASSERT_GT(q.size(), 0u);
  for (const bool rotated : {false, true}) {
    SCOPED_TRACE(rotated ? "x along northing" : "x along easting");
    write_slope(dir.path(), rotated);
    const std::string section = rotated ? "[[1006, 5000], [1006, 5040]]" : "[[1000, 4995], [1040, 4995]]";
    write(dir / "section.toml", kHead2 + "[ground]\nsection = " + section + "\nsurface = \"surface.asc\"\n" +
                                    layers("\"clay_base.asc\"", "\"rock.asc\""));
    const Scenario s = std::get<Scenario>(load_any_scenario((dir / "section.toml").string()));
    const Particles<2> p = build_particles(s);
    ASSERT_EQ(p.size(), q.size());
    EXPECT_EQ(differing_points(p, q), 0u);
    // The section's profile holds the hand-drawn corners exactly.
    for (const double x : {0.0, 10.0, 30.0, 40.0}) EXPECT_EQ(s.ground_surface->at(x), surface_at(x)) << x;
  }
}

// Bilinear sampling of a plane raster is the plane; along a bent section, clipped to the grid.
TEST(GroundSection, ABentSectionThroughAPlaneRasterGivesThePlanesHeights) {
  const test::TempDir dir;
  const auto plane = [](double e, double n) { return 8.0 + 0.1 * (e - 460) + 0.05 * (n - 760); };
  // 40 x 40 cells of 2.5 m from (460, 760): centres at 461.25 + 2.5 c, 858.75 - 2.5 r.
  write_asc(dir / "plane.asc", 40, 40, 460, 760, 2.5,
            [&](int c, int r) { return plane(461.25 + 2.5 * c, 858.75 - 2.5 * r); });
  // 30 m north-east at 3:4, then 25 m east: 55 m, of which the grid takes x = 0..40.
  write(dir / "s.toml", kHead2 +
                            "[ground]\nsection = [[470, 780], [488, 804], [513, 804]]\n"
                            "surface = \"plane.asc\"\n[[body]]\nmaterial = \"sand\"\nshape = \"layer\"\n");
  const Scenario s = std::get<Scenario>(load_any_scenario((dir / "s.toml").string()));
  const Profile& p = *s.ground_surface;
  EXPECT_EQ(p.points.front()[0], 0.0);
  EXPECT_DOUBLE_EQ(p.points.back()[0], 40.0);
  const auto map_of = [](double x) {
    return x <= 30 ? Vec<2>(470 + 0.6 * x, 780 + 0.8 * x) : Vec<2>(488 + (x - 30), 804);
  };
  double worst = 0;
  for (double x = 0; x <= 40; x += 0.125) {
    const Vec<2> e = map_of(x);
    worst = std::max(worst, std::abs(p.at(x) - plane(e[0], e[1])));
  }
  EXPECT_LT(worst, 1e-12);
  // The bend at x = 30 and every crossing of a row or column of cell centres are profile points.
  EXPECT_TRUE(std::any_of(p.points.begin(), p.points.end(), [](const Vec<2>& q) { return q[0] == 30; }));
}

TEST(GroundSection, BadSectionsAreErrorsNamingTheRasterAndKey) {
  const test::TempDir dir;
  const fs::path toml = dir / "s.toml";
  const auto ground = [&](const std::string& ground_table) {
    write(toml, kHead2 + ground_table + layers("\"clay_base.asc\"", "\"rock.asc\""));
    return error_of(toml);
  };
  write_slope(dir.path(), false);
  EXPECT_EQ(ground(kSection), "");
  // The section leaving the raster: its end 10 m past the raster's east edge.
  std::string e = ground("[ground]\nsection = [[1000, 4995], [1050, 4995]]\nsurface = \"surface.asc\"\n");
  EXPECT_NE(
      e.find("surface.asc: the section leaves the raster: its vertex ground.section[1] at map (1050, 4995), "
             "x = 50, lies outside the raster's 21 x 7 cells"),
      std::string::npos)
      << e;
  EXPECT_NE(e.find("(raster 'ground.surface' of "), std::string::npos) << e;
  // No data on the section: refused with its cell; off the section (row 7), ignored.
  write_asc(dir / "surface.asc", 21, 7, 999, 4987, 2,
            [](int c, int r) { return (c == 5 && r == 2) || r == 6 ? -9999 : surface_at(2 * c); });
  e = ground(kSection);
  EXPECT_NE(
      e.find("surface.asc: cell (column 6, row 3; counted from 1 at the upper left) at map (1010, 4996) "
             "holds no data, on the section near x = 9"),
      std::string::npos)
      << e;
  write_asc(dir / "surface.asc", 21, 7, 999, 4987, 2,
            [](int c, int r) { return r == 6 ? -9999 : surface_at(2 * c); });
  EXPECT_EQ(ground(kSection), "");
  // Heights above the grid: the place on the section and on the map.
  write_asc(dir / "surface.asc", 21, 7, 999, 4987, 2, [](int c, int) { return surface_at(2 * c) + 5; });
  e = ground(kSection);
  EXPECT_NE(e.find("surface.asc: at map (1000, 4995) on the section: point (0, 25) lies outside the grid"),
            std::string::npos)
      << e;
  write_slope(dir.path(), false);
  // A raster without a section; a section too short, or with a vertex repeated.
  e = ground("[ground]\nsurface = \"surface.asc\"\n");
  EXPECT_NE(e.find("key 'ground.surface': '" + (dir / "surface.asc").string() +
                   "' is a raster: a 2D scenario samples it along [ground] section"),
            std::string::npos)
      << e;
  EXPECT_NE(ground("[ground]\nsection = [[1000, 4995]]\nsurface = \"surface.asc\"\n")
                .find("key 'ground.section': a section needs at least 2 vertices, got 1"),
            std::string::npos);
  e = ground("[ground]\nsection = [[1000, 4995], [1000, 4995], [1040, 4995]]\nsurface = \"surface.asc\"\n");
  EXPECT_NE(e.find("key 'ground.section[1]': repeats the vertex before it"), std::string::npos) << e;
  // A layer's raster in another CRS than the surface's.
  write(dir / "surface.prj", test::wkt_of("EPSG:25833"));
  write(dir / "rock.prj", test::wkt_of("EPSG:32633"));
  e = ground(kSection);
  EXPECT_NE(
      e.find("rock.asc: its coordinate reference system \"WGS 84 / UTM zone 33N\" differs from \"ETRS89 / "
             "UTM zone 33N\" of surface.asc"),
      std::string::npos)
      << e;
  EXPECT_NE(e.find("(raster 'body[1].bottom' of "), std::string::npos) << e;
  // A section in 3D.
  write(toml,
        kHead + "[ground]\nsurface = \"surface.asc\"\norigin = [1000, 5000]\nsection = [[0, 0], [1, 1]]\n");
  EXPECT_NE(error_of(toml).find("key 'ground.section': 2D only"), std::string::npos) << error_of(toml);
}

// The 2D example is the 3D example's ground along the gully's axis (its z = 8 m): the same
// rasters, sampled along the section, give the 3D ground's heights at the section's points.
TEST(GroundSection, ValleySlopeExampleIsThe3DExamplesGroundAlongTheGully) {
  const std::string examples = std::string(SKRED_SOURCE_DIR) + "/examples/";
  const Scenario s2 = std::get<Scenario>(load_any_scenario(examples + "valley_slope_2d.toml"));
  const Scenario3 s3 = std::get<Scenario3>(load_any_scenario(examples + "valley_slope_3d.toml"));
  const Profile& p = *s2.ground_surface;
  EXPECT_EQ(p.points.front()[0], 0.0);
  EXPECT_NEAR(p.points.back()[0], 48.0, 1e-5);  // the section's vertices to 1e-6 m
  for (const Vec<2>& q : p.points) EXPECT_NEAR(q[1], s3.ground_raster->at(q[0], 8.0), 1e-5) << q[0];
  const Layer& clay = std::get<Layer>(s2.bodies[0].shape);
  const Layer3& clay3 = std::get<Layer3>(s3.bodies[0].shape);
  for (const Vec<2>& q : clay.bottom.points) EXPECT_NEAR(q[1], clay3.bottom->at(q[0], 8.0), 1e-5) << q[0];
}
