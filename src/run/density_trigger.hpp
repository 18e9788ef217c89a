// A stage's density trigger (Paper III §C.3: rainfall makes the clay heavier): the masses of
// a material's points follow its density from the stage-start value to the stage's, over
// the ramp time. Volumes, velocities and stresses are kept, so the added mass arrives with
// the points' velocity; the heavier soil then loads the ground through gravity.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/particles.hpp"
#include "scenario/scenario.hpp"

namespace skred {

class DensityTrigger {
 public:
  DensityTrigger(const ScenarioCommon& s, std::size_t stage) {
    for (const MaterialOverride& o : s.stages.at(stage).overrides)
      if (o.density)
        changes_.push_back(
            {o.material, density_at_stage_start(s, stage, o.material), *o.density, o.density_ramp_time});
  }

  bool empty() const { return changes_.empty(); }
  // Stage time at which every density has reached its target.
  double ramp_end() const {
    double t = 0.0;
    for (const Change& c : changes_) t = std::max(t, c.ramp);
    return t;
  }

  // Sets the masses for time tau into the stage: rho0 + (rho1 - rho0) (1 - cos(pi tau / T))
  // / 2, rho1 from tau = T on. True if a mass changed (the grid must be mapped afresh).
  template <int D>
  bool apply(Particles<D>& p, double tau) {
    bool changed = false;
    for (Change& c : changes_) {
      if (c.done) continue;
      const double r =
          c.ramp > 0 && tau < c.ramp ? 0.5 * (1.0 - std::cos(std::numbers::pi * tau / c.ramp)) : 1.0;
      const double rho = c.from + (c.to - c.from) * r;
      const long n = static_cast<long>(p.size());
#pragma omp parallel for schedule(static)
      for (long i = 0; i < n; ++i)
        if (p.material[static_cast<std::size_t>(i)] == c.material)
          p.mass[static_cast<std::size_t>(i)] = rho * p.volume0[static_cast<std::size_t>(i)];
      c.done = r == 1.0;
      changed = true;
    }
    return changed;
  }

 private:
  struct Change {
    int material;
    double from, to, ramp;
    bool done = false;
  };
  std::vector<Change> changes_;
};

}  // namespace skred
