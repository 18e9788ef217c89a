// Von Mises radial return with linear softening (Acosta §3.2). See von_mises.hpp.
//
// With n = s^tr/(2 q^tr), q = sqrt(J2), the return s = s^tr - 2G dl n is radial, so
// q = q^tr - G dl, and consistency f = 0 reads
//   h(dl) = q^tr - G dl - max(c_r, c_p + H_s (kappa + dl)) = 0.
// h = min(h_r, h_s) with h_r = q^tr - c_r - G dl and h_s = q^tr - c_p - H_s kappa - (G + H_s) dl.
// For G + H_s > 0 both are strictly decreasing, so the unique root is
//   dl = min(dl_r, dl_s),  dl_r = (q^tr - c_r)/G,  dl_s = (q^tr - c_p - H_s kappa)/(G + H_s),
// i.e. the softening-branch root when it still has c >= c_r, else the residual-branch root.
// Both are exact, so a step that crosses the kink lands on f = 0 with c = c_r. If G + H_s <= 0
// (snap-back) h_s stays positive for a yielding trial and the root is dl_r: the point softens to
// c_r at once.
#include "material/von_mises/von_mises.hpp"

namespace skred {

namespace detail {

Sym3 von_mises_plastic(const ElasticConstants& e, const VonMisesParams& vm, Sym3& stress, const Sym3& trial,
                       double q_trial, PointState& state) {
  const double G = 0.5 * e.two_g, H = vm.softening_modulus;
  const double kappa = state.plastic_shear_strain;
  // h(dl) = min(q^tr - G dl - c_r, q^tr - G dl - (c_p + H_s (kappa + dl))) is the minimum of
  // two decreasing lines (for G + H_s > 0), so its root is the smaller of their roots.
  const double dl_residual = (q_trial - vm.cohesion_residual) / G;
  double dl = dl_residual;
  if (G + H > 0.0) dl = std::min(dl, (q_trial - vm.cohesion_peak - H * kappa) / (G + H));
  // d_eps_p = dl s^tr/(2 q^tr) (deviatoric, tensor components).
  const double p = (trial[0] + trial[1] + trial[2]) / 3.0;
  Sym3 n = trial;
  n[0] -= p;
  n[1] -= p;
  n[2] -= p;
  const Sym3 deps_p = (dl / (2.0 * q_trial)) * n;
  stress = trial - elastic_increment(e, deps_p);
  state.plastic_shear_strain += dl;
  state.plastic_volume_strain += deps_p[0] + deps_p[1] + deps_p[2];
  state.yielding = 1;
  return deps_p;
}

}  // namespace detail

}  // namespace skred
