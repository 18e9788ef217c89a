// The particle velocity update (grid-to-particle velocity transfer) of the explicit step.
#pragma once

namespace skred {

// flip: v_p += dt sum N_ip a_i (Thesis eq. 2.56), optionally blended with a PIC share
//   (SolverSettings::pic_fraction).
// xpic: XPIC(m) of Hammerquist & Nairn (2017): FLIP without the part of v_p the grid cannot
//   represent, estimated to order m (SolverSettings::xpic_order; m = 1 is PIC).
// apic: the affine particle-in-cell transfer of Jiang et al. (2015): v_p = sum N_ip v_i^{k+1}
//   and an affine velocity C_p that the next map carries to the nodes.
// aflip: the affine FLIP of Fei et al. (2021): FLIP's update of v_p with APIC's C_p and map.
enum class VelocityTransfer { Flip, Xpic, Apic, Aflip };

inline const char* to_string(VelocityTransfer t) {
  switch (t) {
    case VelocityTransfer::Flip: return "flip";
    case VelocityTransfer::Xpic: return "xpic";
    case VelocityTransfer::Apic: return "apic";
    case VelocityTransfer::Aflip: return "aflip";
  }
  return "?";
}

}  // namespace skred
