// What a scenario will cost before anything is allocated: its time step and number of steps,
// material points, grid nodes, memory and output size, from the shapes' areas (volumes) and
// the grid alone, in microseconds, so `skred check` can refuse a run that cannot fit the
// machine before it hangs or runs out of memory.
#pragma once
#include <cstdint>

#include "scenario/scenario.hpp"

namespace skred {

// The time step of a scenario: the fixed one, or cfl * h / (fastest P-wave speed + fastest
// initial particle speed).
template <int D>
double scenario_time_step(const ScenarioOf<D>& s);
// The largest stable explicit step, h / (c + v0): the CFL limit (cfl = 1) of every kernel.
template <int D>
double stable_time_step(const ScenarioOf<D>& s);

struct ScenarioSize {
  double points = 0;        // material points (shape area or volume times points per unit)
  double nodes = 0;         // grid nodes
  double steps = 0;         // time steps to the end time
  double memory_bytes = 0;  // particles, their stored weights and the grid fields
  double frame_bytes = 0;   // one particle frame (VTU) uncompressed: an upper bound
  double frames = 0;        // particle frames written
  double output_bytes() const { return frame_bytes * frames; }
};
template <int D>
ScenarioSize estimate_size(const ScenarioOf<D>& s);

// The time step of a dynamic implicit stage: its implicit.time_step, or 0 there:
// kAutoImplicitSteps times the stable explicit step (ImplicitSettings::time_step).
inline constexpr double kAutoImplicitSteps = 10.0;
template <int D>
double implicit_time_step(const ScenarioOf<D>& s, const Stage& st);

// The implicit integrator's linear system, estimated from the grid and the bodies' bounding
// boxes (the active nodes are those the points weight, numbered row by row): D unknowns per
// grid node of the cells the bounding boxes cover, and what a direct factorisation stores.
inline constexpr double kDirectBytes2 = 230.0, kDirectBytes3 = 1000.0;
struct ImplicitSystemSize {
  double nodes = 0;      // grid nodes of the cells the bodies' bounding boxes cover (their union)
  double unknowns = 0;   // D per such node
  double row_nodes = 0;  // 2D: nodes per grid row across those boxes (at most the grid's row)
  double bandwidth = 0;  // 2D: 2 x row_nodes x D, the band of a row-by-row numbering
  // What MUMPS' factorisation takes (nested dissection), fitted to measurements: 2D
  // kDirectBytes2 x N log2 N, 3D kDirectBytes3 x N^(4/3), N the unknowns.
  double direct_bytes = 0;
};
template <int D>
ImplicitSystemSize estimate_implicit_system(const ScenarioOf<D>& s);

// Memory this machine offers a process: physical memory, or the cgroup limit when lower, or
// the address-space limit (ulimit -v) less the address space the process holds, when lower.
double available_memory_bytes();

}  // namespace skred
