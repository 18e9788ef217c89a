// The layered slope of the raster tests (test_ground3.cpp in 3D, test_ground_section.cpp along a
// 2D section): its profiles, its rasters and the two soils it is made of.
#pragma once
#include <filesystem>
#include <string>
#include <utility>

#include "gdal_test_util.hpp"
#include "scenario/build.hpp"

namespace skred::test::slope {

// The slope of the tests, along x: the ground 20 m high to x = 10, falling at 0.75 to 5 m at
// x = 30; a clay base 12 - x / 4 below it; the rock's top at 1.1 m. Chosen so that no point
// (at odd multiples of 1/4) lies on a boundary: both builds are exact.
inline double surface_at(double x) { return x <= 10 ? 20.0 : x >= 30 ? 5.0 : 20.0 - 0.75 * (x - 10); }
inline double clay_base_at(double x) { return 12.0 - 0.25 * x; }

// Two elastic soils (a sand on rock, a clay above) on 1 m cells.
inline const std::string kHead = R"(
[grid]
size = [40.0, 24.0, 12.0]
cell_size = 1.0
[solver]
end_time = 1.0
[[material]]
name = "sand"
model = "linear-elastic"
density = 2000
young = 3e7
poisson = 0.25
[[material]]
name = "clay"
model = "linear-elastic"
density = 1700
young = 8e6
poisson = 0.35
)";

// kHead in 2D: the grid's x-y extent.
inline std::string flat_head() {
  std::string t = kHead;
  t.replace(t.find("[40.0, 24.0, 12.0]"), 18, "[40.0, 24.0]");
  return t;
}

// The slope's rasters at 2 m cells: x along easting (rotation 0: z = 5000 - northing) or, with
// `rotated`, along northing (rotation 90: x = northing - 5000, z = easting - 1000).
inline void write_slope(const std::filesystem::path& dir, bool rotated) {
  for (const auto& [name, f] : {std::pair<std::string, double (*)(double)>{"surface.asc", surface_at},
                                {"clay_base.asc", clay_base_at},
                                {"rock.asc", [](double) { return 1.1; }}}) {
    if (rotated)  // 7 columns over z = 0..12, 21 rows over x = 40 (upper) .. 0
      write_asc(dir / name, 7, 21, 999, 4999, 2, [&](int, int r) { return f(40 - 2 * r); });
    else  // 21 columns over x = 0..40, 7 rows over z = 0 (upper) .. 12
      write_asc(dir / name, 21, 7, 999, 4987, 2, [&](int c, int) { return f(2 * c); });
  }
}

// The error loading `file` gives ("" if none).
inline std::string error_of(const std::filesystem::path& file) {
  try {
    load_any_scenario(file.string());
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

// How many points of p lie elsewhere or in another body than q's (of as many points).
template <int D>
std::size_t differing_points(const Particles<D>& p, const Particles<D>& q) {
  std::size_t differ = 0;
  for (std::size_t i = 0; i < p.size(); ++i) differ += p.x[i] != q.x[i] || p.body[i] != q.body[i];
  return differ;
}

}  // namespace skred::test::slope
