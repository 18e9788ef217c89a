// [solver] velocity_transfer and xpic_order (docs/scenario.md): the particle velocity update.
#include "scenario/parse_transfer.hpp"

#include <fmt/format.h>

namespace skred::scenario_detail {

void parse_velocity_transfer(const TableReader& t, ScenarioCommon& s) {
  const auto V = [](VelocityTransfer x) { return std::pair{to_string(x), x}; };
  s.velocity_transfer = t.choice<VelocityTransfer>(
      "velocity_transfer", {V(VelocityTransfer::Flip), V(VelocityTransfer::Xpic), V(VelocityTransfer::Apic)},
      VelocityTransfer::Flip);
  // Measured (docs/method.md, "Velocity transfers"): APIC's gradient-form C_p with the linear
  // kernel's jumping gradients inverts points where they cross cell boundaries (R3 with USL,
  // R4's sliding block), and with quadrature GIMP the soil column blows up within 0.16 s.
  if (s.velocity_transfer == VelocityTransfer::Apic &&
      (s.interpolation == Interpolation::Linear || s.interpolation == Interpolation::GimpQuadrature))
    t.fail_at("velocity_transfer",
              fmt::format("\"apic\" with interpolation = \"{}\" goes unstable (docs/method.md, \"Velocity "
                          "transfers\"); use interpolation = \"gimp\" or \"bspline\", or velocity_transfer = "
                          "\"flip\" or \"xpic\"",
                          to_string(s.interpolation)));
  s.xpic_order = static_cast<int>(t.integer("xpic_order"));
  if (t.has("xpic_order") && s.velocity_transfer != VelocityTransfer::Xpic)
    t.fail_at("xpic_order", "applies to velocity_transfer = \"xpic\" only");
  s.xpic_period = t.number("xpic_period");
  if (t.has("xpic_period") && s.velocity_transfer != VelocityTransfer::Xpic)
    t.fail_at("xpic_period", "applies to velocity_transfer = \"xpic\" only");
  // Cell-averaged volumetric strain (solver/volumetric_averaging.hpp), with every scheme.
  s.volumetric_averaging =
      t.choice<bool>("volumetric_strain", {{"point", false}, {"cell-average", true}}, false);
  s.hyperelastic = t.choice<bool>("elastic_update", {{"incremental", false}, {"hyperelastic", true}}, false);
  if (t.has("pic_fraction") && s.velocity_transfer != VelocityTransfer::Flip)
    t.fail_at("pic_fraction", "applies to velocity_transfer = \"flip\" only");
}

}  // namespace skred::scenario_detail
