// The particle velocity update (grid-to-particle velocity transfer) of the explicit step, as one
// type beside the schemes (scheme.hpp): which transfer, its parameters, the steps on which XPIC
// filters and how its booked loss pairs with the scheme. The phases ask the rule, not the
// settings or the scheme, what to form on the grid and what the points take.
#pragma once
#include <cmath>

#include "solver/scheme.hpp"

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

class VelocityTransferRule {
 public:
  VelocityTransferRule() = default;
  // xpic_period in seconds (0: XPIC filters every step); dt the solver's time step.
  VelocityTransferRule(VelocityTransfer kind, double pic_fraction, int xpic_order, double xpic_period,
                       double dt, StressScheme scheme)
      : kind_(kind),
        pic_fraction_(kind == VelocityTransfer::Flip ? pic_fraction : 0.0),
        xpic_order_(xpic_order),
        period_(xpic_period),
        dt_(dt),
        scheme_(scheme) {}

  // The step from t to t + dt begins. XPIC filters on it every step without a period, else on the
  // steps that cross a multiple of it (NairnMPM's PeriodicXPIC), taken from the time alone, so a
  // restart filters on the same steps.
  void begin_step(double t) {
    filters_ = kind_ == VelocityTransfer::Xpic &&
               (period_ <= 0.0 || std::floor((t + dt_) / period_) > std::floor(t / period_));
  }
  VelocityTransfer kind() const { return kind_; }
  // XPIC filters the velocity on this step (xpic_grid_velocity).
  bool filters() const { return filters_; }
  int xpic_order() const { return xpic_order_; }
  // The PIC share alpha of the particle update (particle_velocity): pic_fraction for FLIP, 1 for
  // APIC and for XPIC on its filter steps, 0 on XPIC's other steps and for the affine FLIP.
  double pic_share() const {
    switch (kind_) {
      case VelocityTransfer::Flip: return pic_fraction_;
      case VelocityTransfer::Xpic: return filters_ ? 1.0 : 0.0;
      case VelocityTransfer::Apic: return 1.0;
      case VelocityTransfer::Aflip: return 0.0;
    }
    return 0.0;
  }
  // The points carry an affine velocity C_p that the maps scatter (APIC, the affine FLIP).
  bool carries_affine() const { return kind_ == VelocityTransfer::Apic || kind_ == VelocityTransfer::Aflip; }
  // The grid update forms v_i^{k+1} = p_i / m_i + dt a_i (velocity_next): for a PIC share of FLIP
  // and for the C_p of APIC and the affine FLIP (XPIC forms its own, xpic_grid_velocity).
  bool forms_velocity_next() const { return pic_fraction_ > 0.0 || carries_affine(); }
  // The booked loss is taken from the FLIP update (FLIP without a PIC share, APIC and the affine
  // FLIP, XPIC between its filter steps), or from the new velocity (the PIC share, XPIC's filter):
  // which form of the walls' share of the lumped mass's loss pairs with it (wall_update_loss).
  bool update_from_flip() const {
    return carries_affine() || (kind_ == VelocityTransfer::Flip && pic_fraction_ <= 0.0) ||
           (kind_ == VelocityTransfer::Xpic && !filters_);
  }
  // w of particle_velocity's booked loss: the work of the velocity change over the step's mean
  // velocity (1/2) for USF and USL, over the new velocity (1) for the averaged scheme
  // (docs/method.md, "The PIC share's and XPIC's booked loss").
  double loss_weight() const { return scheme_ == StressScheme::Averaged ? 1.0 : 0.5; }
  // The walls' share of the lumped mass's loss has a nodal half booked by the grid update (USF;
  // the other schemes' second map takes it with the points).
  bool walls_share_at_nodes() const { return scheme_ == StressScheme::USF; }

 private:
  VelocityTransfer kind_ = VelocityTransfer::Flip;
  double pic_fraction_ = 0.0;
  int xpic_order_ = 2;
  double period_ = 0.0, dt_ = 0.0;
  StressScheme scheme_ = StressScheme::USF;
  bool filters_ = false;
};

}  // namespace skred
