// What summary.json says of the scenario a run took (its interpolation, scheme, velocity
// transfer, volumetric strain, Bishop's factor of safety at the start) and of its implicit
// integrator (the analysis, the linear solver and its totals, the prescribed velocities'
// forces). The run's own figures (status, steps, memory, processes) are filled by the driver.
#pragma once
#include "implicit/implicit_solver.hpp"
#include "io/summary_writer.hpp"
#include "scenario/scenario.hpp"

namespace skred {

// Fills the scenario's part of `sum`; returns Bishop's F of the bodies at the start (2D slopes of
// up to 2 million points, else NaN).
template <int D>
double describe_scenario(Summary& sum, const ScenarioOf<D>& s, long points);

// Fills sum.implicit from the implicit integrator that ran.
template <int D>
void describe_implicit(Summary& sum, const ScenarioOf<D>& s, const ImplicitSolver<D>& im);

}  // namespace skred
