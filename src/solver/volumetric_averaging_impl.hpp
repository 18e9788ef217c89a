// The stress update and internal force with cell-averaged volumetric strain (USF and the
// averaged scheme's first half; volumetric_averaging.hpp), and the cell sums the other phases
// take it from (the second stress update of USL and the averaged scheme, USL's force).
// Included by explicit_solver_impl.hpp.
#pragma once
#include "solver/volumetric_averaging.hpp"

namespace skred {

// Each selected point's cell, its own div_p = tr grad v (eq. 2.20) from the nodal velocities
// vel, its volume, and the cells' sums of V div and V (in point order, on one thread: the same
// sums for any thread count).
template <int D>
template <class K, class Sel>
void ExplicitSolver<D>::cell_divergence(const K& kernel, const Vec<D>* vel, Sel sel) {
  const GridGeometry<D>& g = grid();
  const NodeStrides<D> strides = transfer_.strides();
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  VolumetricAveraging<D>& A = volumetric_;
  A.resize(g, P.size());
  const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
  transfer_.for_box([&](std::size_t i) { A.div_sum[i] = A.volume_sum[i] = 0.0; });
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    typename K::Shape sh;
    kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
    A.cell[p] = VolumetricAveraging<D>::cell_of(g, P.x[p]);
    A.div[p] = gather_gradient(sh, strides, vel).trace();
    A.volume[p] = P.volume(static_cast<std::size_t>(p));
  }
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    A.div_sum[A.cell[p]] += A.volume[p] * A.div[p];
    A.volume_sum[A.cell[p]] += A.volume[p];
  }
}

// Each selected point's cell and mean in-plane stress m_p as the stresses stand, and the cells'
// sums of V m and V: the pressure the internal force pairs with (USL's force, from sigma^k).
template <int D>
template <class Sel>
void ExplicitSolver<D>::cell_pressure(Sel sel) {
  const GridGeometry<D>& g = grid();
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  VolumetricAveraging<D>& A = volumetric_;
  A.resize(g, P.size());
  transfer_.for_box([&](std::size_t i) { A.mean_sum[i] = A.mean_volume_sum[i] = 0.0; });
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    const std::uint32_t c = VolumetricAveraging<D>::cell_of(g, P.x[p]);
    const double V = P.volume(static_cast<std::size_t>(p));
    A.cell[p] = c;
    A.mean[p] = sym_block<D>(P.stress[p]).trace() / D;
    A.mean_sum[c] += V * A.mean[p];
    A.mean_volume_sum[c] += V;
  }
}

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
    long first_bad = LONG_MAX;
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      const StressArrays<D> S(P, materials_);
      const Vec<D>* __restrict vel = f.velocity.data();
      cell_divergence(kernel, vel, sel);
      transfer_.for_box([&](std::size_t i) { A.mean_sum[i] = A.mean_volume_sum[i] = 0.0; });
      auto grad_v = [&](long p) {
        typename K::Shape sh;
        kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
        return gather_gradient(sh, strides, vel);
      };
      double work = 0.0, dissipation = 0.0;
      long bad = LONG_MAX;
      const PointBlocks blocks{n};  // a block's gradients first, then its updates
#pragma omp parallel for num_threads(threads()) schedule(static) reduction(+ : work, dissipation) \
    reduction(min : bad)
      for (long b = 0; b < blocks.count(); ++b) {
        const long p0 = blocks.first(b), p1 = blocks.last(b);
        Mat<D> g_p[kPointBlock];
        for (long p = p0; p < p1; ++p) {
          if (!sel(p)) continue;
          g_p[p - p0] = grad_v(p);
          g_p[p - p0].diagonal().array() += A.correction(static_cast<std::size_t>(p));
        }
        for (long p = p0; p < p1; ++p) {
          if (!sel(p)) continue;
          const auto r = S.update_booked(p, g_p[p - p0], dt_stress, work, dissipation, bad);
          A.mean[p] = sym_block<D>(S.stress[p]).trace() / D;
          A.volume[p] = r.volume;
        }
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
    return phase_ok(first_bad, "material point became unstable (inverted or non-finite stress)");
  });
}

}  // namespace skred
