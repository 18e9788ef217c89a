// Selective integration of shear (Thesis §4.5; solver.shear_strain = "cell-centre"): in the
// shear strain rate and in the shear stresses' internal force, grad N_ip is replaced by
// grad N_ic = grad N_i(x_c), x_c the centre of the cell holding point p. The normal strains and
// stresses keep grad N_ip. Against the parasitic shear of the bilinear cell (Thesis fig. 4.7: a
// bending beam's point shear stresses alternate within each cell) as reduced integration of
// the shear does for a Q4 element (Sandhu & Singh 1978); the normal terms keep the full
// integration, so no zero-energy mode appears. The point's stress power is the nodal forces'
// work: sum_ab sigma_ab L_ab with L_ab from grad N_ic where a != b, which is what the forces'
// shear part does work against. USF only (the scenario parser asks for it). The phase is USF's
// stress_phase (stress_phase_impl.hpp) with these pieces (its
// `centre_shear` branch): the point's block gathers L with centre_shear_gradient, and the force
// scatters the normal stresses with grad N_ip and the shear ones with grad N_ic.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/grid.hpp"
#include "core/inline.hpp"
#include "shape/separable.hpp"

namespace skred {

// The centre of the cell that holds x (a point on a wall belongs to the cell inside).
template <int D>
Vec<D> cell_centre(const GridGeometry<D>& g, const Vec<D>& x) {
  Vec<D> c;
  for (int d = 0; d < D; ++d) {
    const int k = std::clamp(static_cast<int>(std::floor((x[d] - g.origin[d]) / g.h)), 0, g.cells[d] - 1);
    c[d] = g.origin[d] + (k + 0.5) * g.h;
  }
  return c;
}

// The shape functions of a point moved to its cell's centre (its own size and start-of-step F,
// so GIMP keeps its domain), and the off-diagonal entries of L from them: L_ab = sum_i v_ia
// d_b N_ic for a != b. False if the centre has no functions (never for a point in the grid).
template <class K, int D>
SKRED_INLINE bool centre_shear_gradient(const K& kernel, const GridGeometry<D>& g,
                                        const NodeStrides<D>& strides, const Vec<D>& x, const Vec<D>& half0,
                                        const Mat<D>& F, const Vec<D>* __restrict vel,
                                        typename K::Shape& centre, Mat<D>& L) {
  if (!kernel.shape(g, cell_centre(g, x), half0, F, centre)) return false;
  const Mat<D> Lc = gather_gradient(centre, strides, vel);
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      if (a != b) L(a, b) = Lc(a, b);
  return true;
}

}  // namespace skred
