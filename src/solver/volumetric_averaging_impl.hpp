// The stress update and internal force with cell-averaged volumetric strain (USF and the
// averaged scheme's first half; volumetric_averaging.hpp), and the cell sums the other phases
// take it from (the second stress update of USL and the averaged scheme, USL's force).
// Included by explicit_solver_impl.hpp.
#pragma once
#include "solver/volumetric_averaging.hpp"

namespace skred {

// The cells' sums of V value and V over the selected points (cell and volume as the averaging
// holds them), into sum and weight: per chunk of points in parallel, the runs of points in one
// cell; then the runs into their cells in chunk order (volumetric_averaging.hpp).
template <int D>
template <class Sel>
void ExplicitSolver<D>::cell_sums(Sel sel, const double* value, double* sum, double* weight) {
  VolumetricAveraging<D>& A = volumetric_;
  const long n = static_cast<long>(state_.points.size());
  const long chunks = A.chunk_count(state_.points.size());
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long c = 0; c < chunks; ++c) A.sum_chunk(c, n, sel, value);
  // Split among processes, a cell's points may lie in two shares: every process's runs, with the
  // cells no point of this process reached zero (parallel/processes.hpp).
  if (state_.processes.distributed()) transfer_.for_box([&](std::size_t i) { sum[i] = weight[i] = 0.0; });
  A.add_runs(chunks, sum, weight);
  transfer_.sum_scalars(sum, weight);
}

// Each selected point's cell, its own grad v and div_p = tr grad v (eq. 2.20) from the nodal
// velocities vel, its volume, and the cells' sums of V div and V (by chunks of points: the same
// sums for any thread count; volumetric_averaging.hpp).
template <int D>
template <class K, class Sel>
void ExplicitSolver<D>::cell_divergence(const K& kernel, const Vec<D>* vel, Sel sel) {
  const GridGeometry<D>& g = grid();
  const NodeStrides<D> strides = transfer_.strides();
  auto& P = state_.points;
  const long n = static_cast<long>(P.size());
  VolumetricAveraging<D>& A = volumetric_;
  A.resize(g, P.size());
  const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
  const bool axi = axisymmetric();
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    typename K::Shape sh;
    kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
    A.cell[p] = VolumetricAveraging<D>::cell_of(g, P.x[p]);
    A.grad[p] = gather_gradient(sh, strides, vel);
    A.div[p] = A.grad[p].trace();
    if (axi) {  // the hoop rate v_r / r (Acosta App. A1, eq. 32)
      A.hoop_rate[p] = gather(sh, strides, vel)[0] / P.x[p][0];
      A.div[p] += A.hoop_rate[p];
    }
    A.volume[p] = P.volume(static_cast<std::size_t>(p));
  }
  cell_sums(sel, A.div.data(), A.div_sum.data(), A.volume_sum.data());
}

// Each selected point's cell and mean in-plane stress m_p as the stresses stand, and the cells'
// sums of V m and V: the pressure the internal force pairs with (USL's force, from sigma^k).
template <int D>
template <class Sel>
void ExplicitSolver<D>::cell_pressure(Sel sel) {
  const GridGeometry<D>& g = grid();
  auto& P = state_.points;
  const long n = static_cast<long>(P.size());
  VolumetricAveraging<D>& A = volumetric_;
  A.resize(g, P.size());
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    A.cell[p] = VolumetricAveraging<D>::cell_of(g, P.x[p]);
    A.volume[p] = P.volume(static_cast<std::size_t>(p));
    A.mean[p] = mean_stress(P.stress[p]);
  }
  cell_sums(sel, A.mean.data(), A.mean_sum.data(), A.mean_volume_sum.data());
}

// Three loops over the points of each continuum in place of stress_update_and_internal_force's
// one: (1) each point's grad v and div_p = tr grad v (eq. 2.20) and its cell's sums of V div and V;
// (2) the stress update with grad v_p + (div_c - div_p)/d I (eq. 2.20, 4.1-4.4) and the cell's
// sums of V m and V; (3) f_i^int = -sum V_p (sigma_p + (m_c - m_p) I) grad N_ip (eq. 2.51).
template <int D>
template <class K>
bool ExplicitSolver<D>::stress_update_cell_volumetric(const K& kernel, double dt_stress) {
  return timer_.time(Phase::StressUpdateForce, [&] {
    auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    VolumetricAveraging<D>& A = volumetric_;
    long first_bad = LONG_MAX;
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      const StressArrays<D> S(P, state_.materials);
      cell_divergence(kernel, f.velocity.data(), sel);
      double work = 0.0, dissipation = 0.0;
      long bad = LONG_MAX;
#pragma omp parallel for num_threads(threads()) schedule(static) reduction(+ : work, dissipation) \
    reduction(min : bad)
      for (long p = 0; p < n; ++p) {
        if (!sel(p)) continue;
        Mat<D> grad_v = A.grad[p];  // (cell_divergence's)
        const double corr = A.correction(static_cast<std::size_t>(p));
        grad_v.diagonal().array() += corr;
        StressUpdateResult r;
        if constexpr (D == 2)
          r = S.update_booked(p, grad_v, S.hoop ? A.hoop_rate[p] + corr : 0.0, dt_stress, work, dissipation,
                              bad);
        else
          r = S.update_booked(p, grad_v, dt_stress, work, dissipation, bad);
        A.mean[p] = mean_stress(S.stress[p]);
        A.volume[p] = r.volume;
      }
      cell_sums(sel, A.mean.data(), A.mean_sum.data(), A.mean_volume_sum.data());
      Vec<D>* const forces = f.acceleration.data();  // f_i^int (GridFields)
      transfer_.for_box([&](std::size_t i) { forces[i].setZero(); });
      p2g_internal_force(
          transfer_, kernel, P, forces, sel,
          [&](long q) { return A.pressure_correction(static_cast<std::size_t>(q)); }, axisymmetric());
      sum_points(work, dissipation);
      state_.clock.energy.strain_energy += work;
      state_.clock.energy.plastic_dissipation += dissipation;
      first_bad = std::min(first_bad, bad);
    });
    return phase_ok(first_bad, "material point became unstable (inverted or non-finite stress)");
  });
}

}  // namespace skred
