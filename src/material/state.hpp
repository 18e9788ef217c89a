// Per-material-point constitutive state. Every model reads and writes this typed struct, so
// plastic models drop in without changing the particle storage.
#pragma once
#include <cstdint>

namespace skred {

struct PointState {
  double plastic_shear_strain = 0.0;  // accumulated plastic shear strain (deviatoric norm)
  double plastic_volume_strain = 0.0; // accumulated plastic volumetric strain
  std::uint8_t yielding = 0;          // 1 if the last update was plastic
};

}  // namespace skred
