// [solver] velocity_transfer, xpic_order, xpic_period and volumetric_strain (docs/scenario.md):
// the particle velocity update and the volumetric strain.
#include "scenario/parse_transfer.hpp"

#include <fmt/format.h>

namespace skred::scenario_detail {

namespace {
enum class Pick { Auto, Flip, Xpic, Apic, Aflip };
}  // namespace

void parse_velocity_transfer(const TableReader& t, ScenarioCommon& s, bool slide) {
  const Pick pick = t.choice<Pick>("velocity_transfer",
                                   {{"auto", Pick::Auto},
                                    {"flip", Pick::Flip},
                                    {"xpic", Pick::Xpic},
                                    {"apic", Pick::Apic},
                                    {"aflip", Pick::Aflip}},
                                   Pick::Auto);
  // "auto" (docs/method.md, "The defaults"): a slide gets XPIC(m) once per 2 h/c, which comes to
  // rest and whose runout does not follow the time step; elastic dynamics FLIP, which keeps the
  // energy (R1-R4). A key of one transfer alone (pic_fraction; xpic_order or xpic_period) picks it.
  s.transfer_by_default = pick == Pick::Auto;
  if (pick == Pick::Auto) {
    if (t.has("pic_fraction"))
      s.velocity_transfer = VelocityTransfer::Flip;
    else if (t.has("xpic_order") || t.has("xpic_period"))
      s.velocity_transfer = VelocityTransfer::Xpic;
    else
      s.velocity_transfer = slide ? VelocityTransfer::Xpic : VelocityTransfer::Flip;
  } else {
    s.velocity_transfer = pick == Pick::Flip   ? VelocityTransfer::Flip
                          : pick == Pick::Xpic ? VelocityTransfer::Xpic
                          : pick == Pick::Apic ? VelocityTransfer::Apic
                                               : VelocityTransfer::Aflip;
  }
  // Measured (docs/method.md, "Velocity transfers"): APIC's gradient-form C_p with the linear
  // kernel's jumping gradients inverts points where they cross cell boundaries (R3 with USL,
  // R4's sliding block), and with quadrature GIMP the soil column blows up within 0.16 s.
  // The affine FLIP takes the same C_p.
  if ((s.velocity_transfer == VelocityTransfer::Apic || s.velocity_transfer == VelocityTransfer::Aflip) &&
      (s.interpolation == Interpolation::Linear || s.interpolation == Interpolation::GimpQuadrature))
    t.fail_at("velocity_transfer",
              fmt::format("\"{}\" with interpolation = \"{}\" goes unstable (docs/method.md, \"Velocity "
                          "transfers\"); use interpolation = \"gimp\" or \"bspline\", or velocity_transfer = "
                          "\"flip\" or \"xpic\"",
                          to_string(s.velocity_transfer), to_string(s.interpolation)));
  // Measured (docs/method.md, "The affine FLIP"): R3's discs as two bodies in contact gain 0.3 %
  // of their energy with the affine FLIP, so it is refused with [[contact]] until that is understood.
  if (s.velocity_transfer == VelocityTransfer::Aflip && !s.contacts.empty())
    t.fail_at("velocity_transfer",
              "\"aflip\" with [[contact]] gains energy in the collision of two bodies (docs/method.md, "
              "\"The affine FLIP\"); use velocity_transfer = \"apic\" or \"xpic\" with contact");
  s.xpic_order = static_cast<int>(t.integer("xpic_order"));
  if (t.has("xpic_order") && s.velocity_transfer != VelocityTransfer::Xpic)
    t.fail_at("xpic_order", "applies to velocity_transfer = \"xpic\" only");
  s.xpic_period = t.number_or("xpic_period", s.transfer_by_default ? kAutoXpicPeriod : 0.0);
  if (t.has("xpic_period") && s.velocity_transfer != VelocityTransfer::Xpic)
    t.fail_at("xpic_period", "applies to velocity_transfer = \"xpic\" only");
  // Cell-averaged volumetric strain (solver/volumetric_averaging.hpp), with every scheme.
  // "auto": the cell average for a slide (no volumetric locking in isochoric plastic flow).
  const int volumetric =
      t.choice<int>("volumetric_strain", {{"auto", -1}, {"point", 0}, {"cell-average", 1}}, -1);
  s.volumetric_averaging = volumetric < 0 ? slide : volumetric == 1;
  s.volumetric_by_default = volumetric < 0;
  // Selective integration of shear (Thesis §4.5; solver/selective_shear.hpp): USF's stress
  // phase only, and not beside the cell-averaged volumetric strain.
  s.centre_shear = t.choice<bool>("shear_strain", {{"point", false}, {"cell-centre", true}}, false);
  if (s.centre_shear && s.scheme != StressScheme::USF)
    t.fail_at("shear_strain",
              fmt::format("\"cell-centre\" is built for scheme = \"usf\" only (this scenario: "
                          "\"{}\")",
                          to_string(s.scheme)));
  if (s.centre_shear && s.volumetric_averaging)
    t.fail_at("shear_strain", volumetric < 0
                                  ? "\"cell-centre\" needs volumetric_strain = \"point\" (\"auto\" "
                                    "takes the cell average for this scenario's yielding material)"
                                  : "\"cell-centre\" needs volumetric_strain = \"point\"");
  s.hyperelastic = t.choice<bool>("elastic_update", {{"incremental", false}, {"hyperelastic", true}}, false);
  if (t.has("pic_fraction") && s.velocity_transfer != VelocityTransfer::Flip)
    t.fail_at("pic_fraction", "applies to velocity_transfer = \"flip\" only");
}

}  // namespace skred::scenario_detail
