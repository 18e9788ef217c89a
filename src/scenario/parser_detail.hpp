// Internal to the scenario parser: the parts of a file that depend on the dimension (grid,
// bodies, gravity, boundaries; parser_geometry.cpp, 3D shapes in parser_shapes3.cpp) and the
// helpers they share with parser.cpp.
#pragma once
#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "scenario/scenario.hpp"
#include "scenario/toml_reader.hpp"

namespace skred::scenario_detail {

constexpr double kDeg = M_PI / 180.0;

inline const char* axis_name(int d) { return d == 0 ? "x" : d == 1 ? "y" : "z"; }

// Index of the material called `name`, or a message listing the defined ones.
int material_index(const TableReader& t, std::string_view key, const ScenarioCommon& s);

// High corner of the grid and the tolerance for "inside the grid" tests.
template <int D>
Vec<D> grid_high(const ScenarioOf<D>& s) {
  Vec<D> hi = s.origin;
  for (int d = 0; d < D; ++d) hi[d] += s.cell_size * s.cells[static_cast<std::size_t>(d)];
  return hi;
}
template <int D>
double grid_tolerance(const ScenarioOf<D>& s) {
  return 1e-9 * (grid_high(s) - s.origin).maxCoeff();
}
template <int D>
bool inside_grid(const ScenarioOf<D>& s, const Vec<D>& x) {
  const double tol = grid_tolerance(s);
  return (x.array() >= s.origin.array() - tol).all() && (x.array() <= grid_high(s).array() + tol).all();
}
template <int D>
std::string grid_bounds(const ScenarioOf<D>& s) {
  const Vec<D> hi = grid_high(s);
  std::string t;
  for (int d = 0; d < D; ++d) t += fmt::format("{}[{}, {}]", d ? " x " : "", s.origin[d], hi[d]);
  return t;
}
template <int D>
std::string point_text(const Vec<D>& x) {
  if constexpr (D == 2)
    return fmt::format("({}, {})", x[0], x[1]);
  else
    return fmt::format("({}, {}, {})", x[0], x[1], x[2]);
}
// Checks that point x lies within the grid; `what` names it in the message.
template <int D>
void check_inside(const TableReader& t, std::string_view key, const ScenarioOf<D>& s, const Vec<D>& x,
                  const std::string& what) {
  if (!inside_grid(s, x))
    t.fail_at(key, fmt::format("{} {} lies outside the grid {}", what, point_text<D>(x), grid_bounds(s)));
}

// The geometric tables, in the dimension of the scenario.
template <int D>
void parse_grid(const TableReader& root, ScenarioOf<D>& s);
template <int D>
void parse_bodies(const TableReader& root, ScenarioOf<D>& s);
template <int D>
void parse_gravity(const TableReader& root, ScenarioOf<D>& s);
template <int D>
void parse_boundary(const TableReader& root, ScenarioOf<D>& s);
// The [[contact]] tables (parser_contact.cpp), after the bodies.
template <int D>
void parse_contacts(const TableReader& root, ScenarioOf<D>& s);
// The dilated continua (Paper III §C.3.2; parser_dilation.cpp), after the contacts and the
// splitting: one more body per deformable body whose material has the dilation cut-off.
template <int D>
void add_dilation_continua(const TableReader& root, ScenarioOf<D>& s);

// The implicit integrator's tables (parser_implicit.cpp). The keys of an [implicit] or
// [stage.implicit] table over `settings` (keys it does not set keep their value).
void parse_implicit_settings(const TableReader& t, ImplicitSettings& settings);
// solver.integrator's stages and [implicit] (before the stages, which start from them).
void parse_integrator(const TableReader& root, const TableReader& solver, ScenarioCommon& s);
// After the stages: the [[pressure]] tables, and what the stages' integrators refuse (an
// [implicit] table no stage reads, axisymmetric explicit stages, contact, rigid bodies,
// frictional walls, splitting or dilated continua with an implicit stage, ...).
template <int D>
void check_integrators(const TableReader& root, ScenarioOf<D>& s);

// Layered ground (parser_ground.cpp): the [ground] surface, a "layer" body's profiles, and
// the check that no two bodies claim the same points (unless the later one wins).
void parse_ground(const TableReader& root, Scenario& s);
Layer parse_layer(const TableReader& b, const Scenario& s);
template <int D>
void check_overlaps(const TableReader& root, const ScenarioOf<D>& s);
// The same in 3D from elevation rasters (parser_ground3.cpp).
void parse_ground3(const TableReader& root, Scenario3& s);
Layer3 parse_layer3(const TableReader& b, const Scenario3& s);
// A raster laid on the map itself (x easting, z northing): at(e, n) is the bilinear height at
// map point (e, n); for the sections of a 2D [ground]. Throws RasterError.
ElevationRaster raster_on_map(const std::string& file);
// The fractional (column, row) of the cell centres at a raster's (x, z), and back.
Vec<2> cell_of(const ElevationRaster& r, double x, double z);
Vec<2> scenario_of(const ElevationRaster& r, double u, double v);

// The time step against the stable explicit step (Thesis §2.2) and the steps each stage takes
// (parser_time_step.cpp).
template <int D>
void check_time_step(const TableReader& root, const ScenarioOf<D>& s);

// A 3D body's shape (box, extruded polygon, cylinder, sphere, layer) from its [[body]] table.
Shape3 parse_shape3(const TableReader& b, const Scenario3& s);
// The [x, y] vertices of a polygon (2D body or the section of an extruded one), each checked
// against the grid's x-y extent `lo`-`hi`.
Polygon parse_vertices(const TableReader& b, const Vec<2>& lo, const Vec<2>& hi, double tol,
                       const std::string& bounds);

// Sets the value at a key path such as "material[0].friction" or "material[sand].friction"
// (an array element chosen by its name key) or "stage[1].material[0].cohesion".
void set_key(toml::table& doc, const std::string& path, double value, const std::string& source);
// The same with a text value. "solver.velocity_transfer" also removes the keys of one transfer
// (pic_fraction, xpic_order, xpic_period): the transfer set comes with its own defaults.
void set_key(toml::table& doc, const std::string& path, const std::string& value, const std::string& source);

// Empty, or why `path` cannot be read as an input file of at most `max_bytes`: it is not a
// regular file (a device such as /dev/zero, a pipe, a directory: reading it would not end) or
// it is larger (parser.cpp).
std::string input_file_problem(const std::string& path, std::uintmax_t max_bytes);
inline constexpr std::uintmax_t kMaxScenarioBytes = std::uintmax_t{16} << 20;  // 16 MiB
inline constexpr std::uintmax_t kMaxProfileBytes = std::uintmax_t{512} << 20;  // 512 MiB

}  // namespace skred::scenario_detail
