// Von Mises plasticity with linear post-peak softening (Acosta §3.2, after Wang et al.):
//   f = sqrt(J2) - c(kappa),  c(kappa) = max(c_r, c_p + H_s kappa),
// kappa = PointState::plastic_shear_strain. Associated flow d_eps_p = dl s/(2 sqrt(J2)), so
// 2 sqrt(J2(d_eps_p)) = dl and d_kappa = dl. Radial return, exact in closed form on both sides of
// the kink where c reaches c_r. See von_mises.cpp.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/inline.hpp"
#include "material/elastic/elastic.hpp"
#include "material/state.hpp"
#include "material/von_mises/params.hpp"

namespace skred {

// c(kappa) = max(c_r, c_p + H_s kappa) (Acosta §3.2).
SKRED_INLINE double von_mises_cohesion(const VonMisesParams& vm, double kappa) {
  return std::max(vm.cohesion_residual, vm.cohesion_peak + vm.softening_modulus * kappa);
}

// J2 = s:s/2 of a symmetric tensor (tensor shear components).
SKRED_INLINE double second_invariant(const Sym3& s) {
  const double p = (s[0] + s[1] + s[2]) / 3.0;
  const double a = s[0] - p, b = s[1] - p, c = s[2] - p;
  return 0.5 * (a * a + b * b + c * c) + s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
}

// Relative tolerance of the elastic check: elastic when sqrt(J2) - c <= 1e-12 (c + sqrt(J2)).
inline constexpr double kVonMisesRelTol = 1e-12;

namespace detail {
Sym3 von_mises_plastic(const ElasticConstants& e, const VonMisesParams& vm, Sym3& stress, const Sym3& trial,
                       double q_trial, PointState& state);
}  // namespace detail

// Stress update: `stress` in = sigma^k, out = returned stress; `deps` = total strain increment
// (tensor components); returns the plastic strain increment (zero when elastic). State updates as
// mohr_coulomb_update: volume_strain += tr(d_eps); when plastic plastic_shear_strain += dl,
// plastic_volume_strain += tr(d_eps_p) (= 0 to round-off), yielding = 1; else yielding = 0.
SKRED_INLINE Sym3 von_mises_update(const ElasticConstants& e, const VonMisesParams& vm, Sym3& stress,
                                   const Sym3& deps, PointState& state) {
  state.volume_strain += deps[0] + deps[1] + deps[2];
  const Sym3 trial = stress + elastic_increment(e, deps);
  const double q = std::sqrt(second_invariant(trial));
  const double c = von_mises_cohesion(vm, state.plastic_shear_strain);
  if (q - c <= kVonMisesRelTol * (c + q)) {
    stress = trial;
    state.yielding = 0;
    return Sym3::Zero();
  }
  return detail::von_mises_plastic(e, vm, stress, trial, q, state);
}

}  // namespace skred
