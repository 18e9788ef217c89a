// Wall-clock seconds spent in each phase of the explicit time step, summed over the run;
// summary.json and `skred bench` report them.
#pragma once
#include <omp.h>

#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace skred {

enum class Phase {
  MapMassMomentum,      // p2g of m_i, p_i (eq. 2.53-2.54), when not done by the last step
  BodyFields,           // p2g per body (Paper III §C.2.7)
  NodalVelocity,        // v_i^k (eq. 2.23)
  StressUpdateForce,    // stress update, then p2g of f_i^int (USF, averaged first half)
  InternalForce,        // p2g of f_i^int from the current stresses (USL)
  GridUpdate,           // a_i, v_i^{k+1}, boundaries (eq. 2.49, 5.8-5.11)
  Contact,              // contact between bodies (Paper III §C.2.7; runs with contact only)
  VelocityRemap,        // g2p of v_p, p2g of p~_i (USL, averaged)
  RemapVelocity,        // v~_i = p~_i / m_i (USL, averaged)
  StressUpdateMoveMap,  // stress update, g2p of x_p, next step's p2g (USL, averaged)
  VelocityMoveMap,      // g2p of v_p and x_p, next step's p2g (USF)
  Count
};

inline const char* phase_name(Phase p) {
  static constexpr const char* names[] = {
      "map_mass_momentum", "body_fields", "nodal_velocity", "stress_update_force", "internal_force",
      "grid_update",       "contact",     "velocity_remap", "remap_velocity",      "stress_update_move_map",
      "velocity_move_map"};
  return names[static_cast<std::size_t>(p)];
}

class PhaseTimer {
 public:
  static constexpr std::size_t kCount = static_cast<std::size_t>(Phase::Count);
  // fn(), its wall time added to phase p.
  template <class Fn>
  decltype(auto) time(Phase p, Fn&& fn) {
    const double t0 = omp_get_wtime();
    struct Add {
      double& s;
      double t0;
      ~Add() { s += omp_get_wtime() - t0; }
    } add{seconds_[static_cast<std::size_t>(p)], t0};
    return fn();
  }
  double seconds(Phase p) const { return seconds_[static_cast<std::size_t>(p)]; }
  void reset() { seconds_.fill(0.0); }
  // (name, seconds) of every phase that ran, in step order.
  std::vector<std::pair<std::string, double>> report() const {
    std::vector<std::pair<std::string, double>> r;
    for (std::size_t k = 0; k < kCount; ++k)
      if (seconds_[k] > 0.0) r.emplace_back(phase_name(static_cast<Phase>(k)), seconds_[k]);
    return r;
  }

 private:
  std::array<double, kCount> seconds_{};
};

}  // namespace skred
