// The stress update and internal force with cell-averaged volumetric strain (USF and the
// averaged scheme's first half; volumetric_averaging.hpp). Included by explicit_solver_impl.hpp.
#pragma once
#include "solver/volumetric_averaging.hpp"

namespace skred {

// Three loops over the points of each continuum in place of stress_update_and_internal_force's
// one: (1) each point's div_p = tr grad v (eq. 2.20) and its cell's sums of V div and V;
// (2) the stress update with grad v_p + (div_c - div_p)/d I (eq. 2.20, 4.1-4.4) and the cell's
// sums of V m and V; (3) f_i^int = -sum V_p (sigma_p + (m_c - m_p) I) grad N_ip (eq. 2.51).
template <int D>
template <class K>
bool ExplicitSolver<D>::stress_update_cell_volumetric(const K& kernel, double dt_stress) {
  return timer_.time(Phase::StressUpdateForce, [&] {
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = particles_;
    const long n = static_cast<long>(P.size());
    VolumetricAveraging<D>& A = volumetric_;
    A.resize(g, P.size());
    long first_bad = LONG_MAX;
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      const StressArrays<D> S(P, materials_);
      const Vec<D>* __restrict vel = f.velocity.data();
      transfer_.for_box([&](std::size_t i) {
        A.div_sum[i] = A.volume_sum[i] = A.mean_sum[i] = A.mean_volume_sum[i] = 0.0;
      });
      auto grad_v = [&](long p) {
        typename K::Shape sh;
        kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
        return gather_gradient(sh, strides, vel);
      };
#pragma omp parallel for num_threads(threads()) schedule(static)
      for (long p = 0; p < n; ++p) {
        if (!sel(p)) continue;
        A.cell[p] = VolumetricAveraging<D>::cell_of(g, P.x[p]);
        A.div[p] = grad_v(p).trace();
        A.volume[p] = P.volume(static_cast<std::size_t>(p));
      }
      // (the cell sums in point order, on one thread: the same sums for any thread count)
      for (long p = 0; p < n; ++p) {
        if (!sel(p)) continue;
        A.div_sum[A.cell[p]] += A.volume[p] * A.div[p];
        A.volume_sum[A.cell[p]] += A.volume[p];
      }
      double work = 0.0, dissipation = 0.0;
      long bad = LONG_MAX;
#pragma omp parallel for num_threads(threads()) schedule(static) reduction(+ : work, dissipation) \
    reduction(min : bad)
      for (long p = 0; p < n; ++p) {
        if (!sel(p)) continue;
        Mat<D> g_p = grad_v(p);
        g_p.diagonal().array() += A.correction(static_cast<std::size_t>(p));
        const auto r = S.update(p, g_p, dt_stress);
        work += r.strain_energy;
        dissipation += r.dissipation;
        if (!sound_point(r, S.stress[p])) bad = std::min(bad, p);
        A.mean[p] = sym_block<D>(S.stress[p]).trace() / D;
        A.volume[p] = r.volume;
      }
      for (long p = 0; p < n; ++p) {
        if (!sel(p)) continue;
        A.mean_sum[A.cell[p]] += A.volume[p] * A.mean[p];
        A.mean_volume_sum[A.cell[p]] += A.volume[p];
      }
      Vec<D>* const forces = f.internal_force.data();
      transfer_.for_box([&](std::size_t i) { forces[i].setZero(); });
      p2g_internal_force(transfer_, kernel, P, forces, sel,
                         [&](long q) { return A.pressure_correction(static_cast<std::size_t>(q)); });
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
