// Per-material-point constitutive state. Every model reads and writes this typed struct, so
// plastic models drop in without changing the particle storage.
#pragma once
#include <cstdint>

namespace skred {

struct PointState {
  // Accumulated plastic engineering shear strain, gamma_p = sum 2 sqrt(J2(d_eps_p)) (so that
  // simple shear gives gamma_p = 2 eps_p_xy). Softening laws are written in terms of it.
  double plastic_shear_strain = 0.0;
  double plastic_volume_strain = 0.0;  // accumulated tr(d_eps_p), dilation positive
  // Accumulated tr(d_eps) ~ ln det F, for the void ratio of the dilation cut-off. Plastic
  // models accumulate it; the solver sets it to ln det F at the start of every stage, so a
  // stage held elastic (which leaves the state untouched) does not lose it.
  double volume_strain = 0.0;
  std::uint8_t yielding = 0;  // 1 if the last update was plastic
};

}  // namespace skred
