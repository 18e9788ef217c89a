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
  CriticalCircle critical;
};

// 2D scenarios under gravity along -y whose deformable bodies have a material that can yield.
// The ground is the bodies' initial surface in columns of one cell (each point as its domain
// x_p +- l_p), down to the lowest material edge; of several materials, each cell of the grid
// holds the one with the most mass there, and a material that does not yield is firm ground
// that a slip surface may not cut.
SlopeStability slope_stability(const Scenario& s);

// One line for `skred check`: the factor, the circle and what it means.
std::string slope_stability_line(const SlopeStability& r);

}  // namespace skred
