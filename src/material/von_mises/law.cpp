// Consistent tangent of the von Mises radial return with linear softening (see law.hpp).
#include "material/von_mises/law.hpp"

#include "material/elastic/law.hpp"

namespace skred {

LawResult von_mises_evaluate(const ElasticConstants& e, const VonMisesParams& vm, const Sym3& stress,
                             const Sym3& deps, const PointState& state, bool want_tangent,
                             VonMisesBranch* branch) {
  LawResult r;
  r.stress = stress;
  r.state = state;
  r.plastic_strain = von_mises_update(e, vm, r.stress, deps, r.state);
  if (!r.state.yielding) {
    if (branch) *branch = VonMisesBranch::Elastic;
    if (want_tangent) {
      r.tangent = elastic_stiffness(e);
      r.has_tangent = true;
    }
    return r;
  }
  // The trial of the update (eq. 5.2 form: sigma^tr = sigma^k + C : d_eps) and its deviator.
  const Sym3 trial = stress + elastic_increment(e, deps);
  const double q = std::sqrt(second_invariant(trial));
  const double G = 0.5 * e.two_g, H = vm.softening_modulus;
  // The branch of von_mises.cpp: dl = min(dl_r, dl_s); dl_s only when G + H_s > 0.
  const double dl_residual = (q - vm.cohesion_residual) / G;
  const double dl_softening = (q - vm.cohesion_peak - H * state.plastic_shear_strain) / (G + H);
  const bool softening = G + H > 0.0 && dl_softening < dl_residual;
  if (branch) *branch = softening ? VonMisesBranch::Softening : VonMisesBranch::Residual;
  if (!want_tangent) return r;
  const double dl = softening ? dl_softening : dl_residual;
  const double beta = 1.0 - G * dl / q;
  const double ddl_dq = softening ? 1.0 / (G + H) : 1.0 / G;
  Sym3 dev = trial;
  const double p = (trial[0] + trial[1] + trial[2]) / 3.0;
  for (int i = 0; i < 3; ++i) dev[i] -= p;
  Sym3 dq = (G / q) * dev;  // d q / d deps[j] (factor 2 on shear, tensor-strain Voigt)
  dq.tail<3>() *= 2.0;
  const double K = e.lambda + e.two_g / 3.0;
  Mat6 Pdev = Mat6::Identity();  // d dev(eps) / d deps
  Pdev.topLeftCorner<3, 3>().array() -= 1.0 / 3.0;
  Mat6 D = e.two_g * beta * Pdev;
  D.topLeftCorner<3, 3>().array() += K;
  D += dev * (((1.0 - beta) - G * ddl_dq) / q * dq).transpose();
  r.tangent = D;
  r.has_tangent = true;
  return r;
}

}  // namespace skred
