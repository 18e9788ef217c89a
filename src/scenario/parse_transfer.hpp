// The [solver] keys of the particle velocity update (velocity_transfer, xpic_order).
#pragma once
#include "scenario/scenario.hpp"
#include "scenario/toml_reader.hpp"

namespace skred::scenario_detail {

// Reads solver.velocity_transfer ("flip", "xpic", "apic"; default "flip") and
// solver.xpic_order (1 to 20, default 2; XPIC only) from the [solver] table `t`.
void parse_velocity_transfer(const TableReader& t, ScenarioCommon& s);

}  // namespace skred::scenario_detail
