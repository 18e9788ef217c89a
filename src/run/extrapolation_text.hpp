// Richardson's extrapolation (post/grid_convergence.hpp) told in words: the line `skred refine`
// prints per measure, and `skred extrapolate`, which applies the same procedure (Celik et al. 2008)
// to values a user measured at three cell sizes or more (docs/method.md, "Richardson's
// extrapolation").
#pragma once
#include <string>
#include <vector>

#include "post/grid_convergence.hpp"

namespace skred {

// A value measured at three cell sizes, the finest first: h[0] < h[1] < h[2].
struct ThreeGrids {
  double h[3] = {};
  double phi[3] = {};
};

// One line on the extrapolation of `words` (e.g. "runout") with `unit` (its leading space
// included, "" for none) over cell sizes in `cell_unit` (likewise): how it converges, its
// apparent order, its value as h -> 0, the GCI of the finest grid and what one more refinement by
// h[1] / h[0] would change; or why nothing is extrapolated.
std::string extrapolation_line(const std::string& words, const std::string& unit, const ThreeGrids& v,
                               const GridConvergence& g, const std::string& cell_unit = "");

// The three finest of `pairs`, each "CELL=VALUE" (e.g. "0.25=4.123"). Throws
// std::invalid_argument naming the pair when one does not parse, a cell size is not positive, a
// value is not finite, two cell sizes repeat, or there are fewer than three.
ThreeGrids three_finest(const std::vector<std::string>& pairs);

// `skred extrapolate`: the line above for the three finest of `pairs`, and a CSV row under its
// header (quantity, the cell sizes, the values, kind, ratio, order, extrapolated, GCI of the finest,
// next change). Throws as three_finest does.
std::string extrapolate_text(const std::vector<std::string>& pairs, const std::string& name,
                             const std::string& unit);

}  // namespace skred
