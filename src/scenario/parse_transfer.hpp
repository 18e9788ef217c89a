// The [solver] keys of the particle velocity update (velocity_transfer, xpic_order,
// xpic_period, pic_fraction) and of the volumetric strain.
#pragma once
#include "scenario/scenario.hpp"
#include "scenario/toml_reader.hpp"

namespace skred::scenario_detail {

// Reads solver.velocity_transfer ("auto", "flip", "xpic", "apic"), xpic_order, xpic_period,
// volumetric_strain ("auto", "point", "cell-average") and elastic_update from the [solver]
// table `t`. "auto", the default, decides by `slide`: whether a deformable body's material can
// yield (docs/method.md, "The defaults").
void parse_velocity_transfer(const TableReader& t, ScenarioCommon& s, bool slide);

}  // namespace skred::scenario_detail
