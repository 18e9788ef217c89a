// Limit equilibrium of a slope: Bishop's simplified method of slices on circular slip surfaces
// (Bishop 1955), a check on a scenario's strength from outside the MPM (docs/method.md, "Limit
// equilibrium"). Plane strain, dry ground of one soil or of several in cells (layers), each
// with a Mohr-Coulomb envelope (c, phi) and a unit weight gamma; no pore pressure, no tension
// crack, no external load.
#pragma once
#include <vector>

namespace skred {

// The ground: its surface y = top[j] over the column [x0 + j width, x0 + (j + 1) width) (NaN
// where there is no ground), soil from there down to `base`, which a slip surface may not cut
// (the firm layer, or the grid's floor).
struct GroundProfile {
  double x0 = 0.0, width = 1.0;
  std::vector<double> top;
  double base = 0.0;
  // Layered ground (optional): the soil in each cell of the columns, in `rows` rows of
  // `row_height` from `row0` up, [column * rows + row]: an index into the soils given with the
  // ground or kNoSoil where there is none. rows = 0: the first soil throughout.
  static constexpr int kNoSoil = -1;
  double row0 = 0.0, row_height = 1.0;
  int rows = 0;
  std::vector<int> soil;
  // A circle whose sliding mass is nowhere deeper than this (below the surface) is not admissible.
  // A profile built from material points knows the surface to a step of the points' spacing,
  // and in a cohesionless soil the least factor is then a sliver on the steepest step.
  double min_depth = 0.0;
  // The surface height at x: the column tops joined by straight lines between column centres
  // (NaN outside the ground or beside a column without ground).
  double surface(double x) const;
  double x_end() const { return x0 + width * static_cast<double>(top.size()); }
};

struct SoilStrength {
  double cohesion = 0.0;     // c [Pa]
  double friction = 0.0;     // phi [rad]
  double unit_weight = 0.0;  // gamma = rho g [N/m^3]
  bool firm = false;         // does not yield: a slip surface may not cut it (its weight counts)
};

struct SlipCircle {
  double xc = 0.0, yc = 0.0, radius = 0.0;
};

// Bishop's simplified factor of safety of one circle, the soil sliding towards +x (direction
// +1) or -x (-1):
//   F = sum_i [c b_i + W_i tan(phi)] / m_i  /  sum_i W_i sin(alpha_i),
//   m_i = cos(alpha_i) + sin(alpha_i) tan(phi) / F,
// over `slices` slices of width b_i between the circle's two crossings of the surface, with
// W_i = gamma b_i h_i and alpha_i the inclination of the slice's base. In layered ground W_i
// sums gamma over the layers above the slice's base, and c, phi are the soil's at the base's
// midpoint (so tan(phi) is per slice in m_i). NaN when the circle is
// not admissible: it does not cut the ground in one piece, goes below the base, is nowhere
// deeper than the ground's min_depth, its sliding mass does not drive towards `direction`, or m_i <= 0.2 on a
// slice whose base rises in the direction of motion (the usual guard against Bishop's spurious solutions at
// steep toes), or it cuts firm material.
double bishop_factor(const GroundProfile& g, const std::vector<SoilStrength>& soils, const SlipCircle& c,
                     int direction, int slices = 60);
double bishop_factor(const GroundProfile& g, const SoilStrength& s, const SlipCircle& c, int direction,
                     int slices = 60);

struct CriticalCircle {
  double factor = 0.0;  // the least F found (+inf if no circle was admissible)
  SlipCircle circle;
  int direction = 1;                // +1: the slip mass moves towards +x, -1 towards -x
  double x_from = 0.0, x_to = 0.0;  // where the circle enters and leaves the ground
};

// The least Bishop factor over circles in both directions: a grid of centres above the ground
// and radii that reach from just under the surface to the base, then a pattern search from the
// best of them (step halved down to width / 200).
CriticalCircle critical_circle(const GroundProfile& g, const std::vector<SoilStrength>& soils);
CriticalCircle critical_circle(const GroundProfile& g, const SoilStrength& s);

}  // namespace skred
