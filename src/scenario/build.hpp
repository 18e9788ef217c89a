// Material point generation from a parsed scenario, and a human summary of it.
#pragma once
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// A run of the grid's cell columns along x, [first, end).
struct CellColumns {
  int first = 0, end = std::numeric_limits<int>::max();
  bool holds(int i) const { return i >= first && i < end; }
  bool whole() const { return first <= 0 && end == std::numeric_limits<int>::max(); }
};
// The cell column along x that holds point x (may be outside [0, cells[0]) off the grid).
template <class S, class V>
int column_of(const S& s, const V& x) {
  return static_cast<int>(std::floor((x[0] - s.origin[0]) / s.cell_size));
}

// Fills every body with n^D material points per grid cell (n = particles_per_cell): each
// cell is split into n^D sub-cells of side h/n and a sub-cell's centre becomes a point if it
// lies inside the body's shape. Mass = density (h/n)^D (in 2D plane strain, per unit
// thickness), volume0 = (h/n)^D, half0 = h/2n on every axis. In axisymmetric geometry
// (2D) mass and volume0 are per radian: (h/n)^2 times the point's radius x_p. Bodies are filled in order,
// cells in row-major order (x fastest, then y, then z), and the sub-cells of a cell in the
// same order. Throws ScenarioError if a body receives no point. With `columns`, only the points in
// those cell columns along x (a process's part of the set-up, run/point_setup.hpp).
template <int D>
Particles<D> build_particles(const ScenarioOf<D>& s, CellColumns columns = {});

// Number of material points build_particles gives body `b` on the grid of `s` (in `columns`).
template <int D>
std::size_t count_points(const ScenarioOf<D>& s, const BodyOf<D>& b, CellColumns columns = {});
// The points build_particles gives each cell column along x (cells[0] counts), counted in
// `columns` only (zero elsewhere).
template <int D>
std::vector<long> points_per_column(const ScenarioOf<D>& s, CellColumns columns);
// True if body `b` receives at least one point (cheaper than count_points).
template <int D>
bool has_points(const ScenarioOf<D>& s, const BodyOf<D>& b);

// Point-in-shape test with half-open rules: a point on a rectangle's or polygon's low (left,
// bottom) edge is inside and on its high edge is outside, so shapes sharing an edge never
// both claim a point. Discs use the strict test |x - c| < r. In 3D: boxes and extruded
// polygons (also z_min <= z < z_max) likewise; spheres and cylinders strictly.
bool shape_contains(const Shape& shape, const Vec<2>& x);
bool shape_contains(const Shape3& shape, const Vec<3>& x);

// The outward unit normal of a shape at x (shape_normal.cpp): the gradient of the signed
// distance to its outline (round a corner outside it, the nearest face's inside). Rectangles,
// polygons, discs; boxes, spheres. Zero for the other shapes (layers, cylinders, extruded
// polygons; 3D layers), which have no outline normal here.
Vec<2> shape_normal(const Shape& shape, const Vec<2>& x);
Vec<3> shape_normal(const Shape3& shape, const Vec<3>& x);

// Axis-aligned bounding box of a shape.
template <int D>
struct ShapeBox {
  Vec<D> lo, hi;
};
ShapeBox<2> bounding_box(const Shape& shape);
ShapeBox<3> bounding_box(const Shape3& shape);

// Signed area of a polygon (positive when counter-clockwise).
double polygon_area(const Polygon& p);
// Area of a layer: the integral of max(0, min(top, surface) - bottom) over its x range
// (exact: the integrand is linear between the profiles' points and their crossings).
double layer_area(const Layer& l);
// Volume of a 3D layer: the integral of max(0, min(top, surface) - bottom) over its extent (the
// midpoint rule on 1024 x 1024 columns).
double layer_volume(const Layer3& l);

// Short multi-line human summary (grid, materials, bodies, gravity, boundaries, solver and
// output settings), as printed by `skred check`. Ends with a newline.
template <int D>
std::string describe(const ScenarioOf<D>& s);

}  // namespace skred
