// A slope's limit equilibrium before any run (`skred check`): Bishop's simplified factor of
// safety (post/limit_equilibrium.hpp) of the scenario's bodies as they stand at the start,
// with the soil's strength in its last stage that lets it yield, an answer from outside the MPM
// to set a slide's result against (docs/method.md, "Limit equilibrium").
#pragma once
#include <string>
#include <vector>

#include "post/limit_equilibrium.hpp"
#include "scenario/scenario.hpp"

namespace skred {

struct SlopeStability {
  bool computed = false;
  std::string why_not;  // when not computed: why (no soil that yields, gravity not along -y, ...)
  std::string stage;    // the stage whose strength was taken
  std::vector<std::string> materials;  // the ground's materials that yield
  std::string note;                    // what the factor does not count (a contact in the ground)
  std::string section;                 // 3D: the section the circles lie in
  char axis = 'x';                     // the axis the section runs along (3D: x or z)
  CriticalCircle critical;
};

// 2D scenarios under gravity along -y whose deformable bodies have a material that can yield.
// The ground is the bodies' initial surface in columns of one cell (each point as its domain
// x_p +- l_p), down to the lowest material edge; of several materials, each cell of the grid
// holds the one with the most mass there, and a material that does not yield is firm ground
// that a slip surface may not cut.
SlopeStability slope_stability(const Scenario& s);
// 3D: the same on the steepest 2D section through the slope, as plane strain: of the rows of
// cells along x (one cell across z) and the columns along z (one cell across x), the one whose
// ground tops have the largest mean gradient along it, its points taken as a 2D section
// (`section` says which, `axis` along which). A check on the section only: the 3D slide's
// sides add strength, and a fall line oblique to both axes is seen less steep than it is.
SlopeStability slope_stability(const Scenario3& s);

// One line for `skred check`: the factor, the circle and what it means.
std::string slope_stability_line(const SlopeStability& r);

}  // namespace skred
