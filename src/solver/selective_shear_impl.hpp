// Selective integration of shear (Thesis §4.5; solver.shear_strain = "cell-centre"): in the
// shear strain rate and in the shear stresses' internal force, grad N_ip is replaced by
// grad N_ic = grad N_i(x_c), x_c the centre of the cell holding point p. The normal strains and
// stresses keep grad N_ip. Against the parasitic shear of the bilinear cell (Thesis fig. 4.7: a
// bending beam's point shear stresses alternate within each cell) as reduced integration of
// the shear does for a Q4 element (Sandhu & Singh 1978); the normal terms keep the full
// integration, so no zero-energy mode appears. The point's stress power is the nodal forces'
// work: sum_ab sigma_ab L_ab with L_ab from grad N_ic where a != b, which is what the forces'
// shear part does work against. Included at the end of explicit_solver_impl.hpp; USF only (the
// scenario parser asks for it).
#pragma once
#include <climits>
#include <cmath>

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

template <int D>
template <class K>
bool ExplicitSolver<D>::stress_update_centre_shear(const K& kernel, double dt_stress) {
  return timer_.time(Phase::StressUpdateForce, [&] {
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = particles_;
    const long n = static_cast<long>(P.size());
    ScatterBuffers<D>& buffers = transfer_.scatter();
    long first_bad = LONG_MAX;
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      const StressArrays<D> S(P, materials_);
      Vec<D>* const forces = f.internal_force.data();
      transfer_.for_box([&](std::size_t i) { forces[i].setZero(); });
      const Vec<D>* __restrict vel = f.velocity.data();
      double work = 0.0, dissipation = 0.0;
      long bad = LONG_MAX;
#pragma omp parallel num_threads(threads()) reduction(+ : work, dissipation) reduction(min : bad)
      {
        const int t = omp_get_thread_num();
        Vec<D>* __restrict force = buffers.vec_target(t, forces);
        BaseSpan span;
#pragma omp for schedule(static) nowait
        for (long p = 0; p < n; ++p) {
          if (!sel(p)) continue;
          typename K::Shape sh, centre;
          kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
          // The point's own functions moved to its cell's centre (its size, its F of the step's start).
          if (!kernel.shape(g, cell_centre(g, P.x[p]), P.half0[p], P.F[p], centre)) {
            bad = std::min(bad, p);
            continue;
          }
          Mat<D> L = gather_gradient(sh, strides, vel);
          const Mat<D> Lc = gather_gradient(centre, strides, vel);
          for (int a = 0; a < D; ++a)
            for (int b = 0; b < D; ++b)
              if (a != b) L(a, b) = Lc(a, b);
          const auto r = S.update_booked(p, L, dt_stress, work, dissipation, bad);
          const Mat<D> sigma = -r.volume * sym_block<D>(S.stress[p]);
          const Mat<D> normal = sigma.diagonal().asDiagonal();
          scatter_gradient(sh, strides, normal, force);
          scatter_gradient(centre, strides, Mat<D>(sigma - normal), force);
          span.add(sh.base);
          span.add(centre.base);
        }
        buffers.touched(t, span);
      }
      transfer_.reduce(nullptr, forces);
      energy_.strain_energy += work;
      energy_.plastic_dissipation += dissipation;
      first_bad = std::min(first_bad, bad);
    });
    if (first_bad != LONG_MAX)
      status_ = {false, first_bad, "material point became unstable (inverted or non-finite stress)"};
    return first_bad == LONG_MAX;
  });
}

}  // namespace skred
