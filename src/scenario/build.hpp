// Material point generation from a parsed scenario, and a human summary of it.
#pragma once
#include <cstddef>
#include <string>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// Fills every body with n x n material points per grid cell (n = particles_per_cell): each
// cell is split into n x n sub-squares of side h/n and a sub-square's centre becomes a point
// if it lies inside the body's shape. Mass = density (h/n)^2 (plane strain, per unit
// thickness), volume0 = (h/n)^2, half0 = (h/2n, h/2n). Bodies are filled in order, cells in
// row-major order (x fastest). Throws ScenarioError if a body receives no point.
Particles<2> build_particles(const Scenario& s);

// Number of material points build_particles gives body `b` on the grid of `s`.
std::size_t count_points(const Scenario& s, const Body& b);
// True if body `b` receives at least one point (cheaper than count_points).
bool has_points(const Scenario& s, const Body& b);

// Point-in-shape test with half-open rules: a point on a rectangle's or polygon's low (left,
// bottom) edge is inside and on its high edge is outside, so shapes sharing an edge never
// both claim a point. Discs use the strict test |x - c| < r.
bool shape_contains(const Shape& shape, const Vec<2>& x);

// Signed area of a polygon (positive when counter-clockwise).
double polygon_area(const Polygon& p);

// Short multi-line human summary (grid, materials, bodies, gravity, boundaries, solver and
// output settings), as printed by `skred check`. Ends with a newline.
std::string describe(const Scenario& s);

}  // namespace skred
