// The axisymmetric point update (stress_arrays.hpp), compiled once.
#include "solver/stress_arrays.hpp"

namespace skred {

StressUpdateResult update_point_axisymmetric(const Material& mat, const Mat<2>& grad_v, double hoop_rate,
                                             double dt, double volume0, PointStress<2>& stress,
                                             PointState& state, Mat<2>& F, Mat<2>* Fe, double& hoop) {
  Mat3 g3 = Mat3::Zero();
  g3.topLeftCorner<2, 2>() = grad_v;
  g3(2, 2) = hoop_rate;
  Mat3 F3 = embed3<2>(F, hoop);
  Mat3 Fe3 = embed3<2>(Fe ? *Fe : Mat<2>(Mat<2>::Identity()), 1.0);  // (in-plane Fe only)
  Sym3 s = full_stress<2>(stress);
  const StressUpdateResult r = update_point_stress<3>(mat, g3, dt, volume0, s, state, F3, Fe3);
  stress = s.head<4>();
  F = F3.topLeftCorner<2, 2>();
  hoop = F3(2, 2);
  if (Fe) *Fe = Fe3.topLeftCorner<2, 2>();
  return r;
}

}  // namespace skred
