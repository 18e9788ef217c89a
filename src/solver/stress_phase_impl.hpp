// The stress phase of the explicit step (Thesis §4.4): each point's strain increment and
// stress update with the internal forces it maps (USF and the averaged scheme), and the map of
// the forces alone from the stresses as they are (USL). Included at the end of
// explicit_solver_impl.hpp, after the solver's other phases.
#pragma once

#include <omp.h>

#include <algorithm>
#include <climits>
#include <type_traits>

#include "solver/explicit_solver.hpp"
#include "solver/selective_shear.hpp"
#include "solver/stress_arrays.hpp"
#include "solver/stress_lanes_3d.hpp"
#include "transfer/size_ahead.hpp"
#include "transfer/transfers.hpp"

namespace skred {

// Strain increment and stress update at every point (eq. 2.20, 3.5, 4.1-4.4) from v_i^k,
// then the internal forces f_i^int = -sum sigma_p V_p grad N_ip (eq. 2.51); with contact,
// each body from and into its own fields.
// With solver.shear_strain = "cell-centre", the shear takes grad N_ic (selective_shear.hpp).
template <int D>
template <class K>
bool ExplicitSolver<D>::stress_update_and_internal_force(const K& kernel, double dt_stress) {
  if (settings_.volumetric_averaging) return stress_update_cell_volumetric(kernel, dt_stress);
  if (settings_.centre_shear) return stress_phase(kernel, dt_stress, std::true_type{});
  return stress_phase(kernel, dt_stress, std::false_type{});
}

template <int D>
template <class K, class CentreShear>
bool ExplicitSolver<D>::stress_phase(const K& kernel, double dt_stress, CentreShear) {
  constexpr bool centre_shear = CentreShear::value;
  return timer_.time(Phase::StressUpdateForce, [&] {
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    ScatterBuffers<D>& buffers = transfer_.scatter();
    long first_bad = LONG_MAX;
    if constexpr (kSizeAhead<D, K>)
      det_f_.resize(P.size());  // (the move phase's; its size changes with n only)
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      // (the point arrays declared here, in the loop's own scope, keep their __restrict)
      const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      StressArrays<D> S(P, state_.materials);
      if constexpr (kSizeAhead<D, K>) S.det_f = det_f_.data();
      [[maybe_unused]] const bool axisymmetric = S.hoop != nullptr;
      Vec<D>* const forces = f.acceleration.data();  // f_i^int (GridFields)
      transfer_.for_box([&](std::size_t i) { forces[i].setZero(); });
      const Vec<D>* __restrict vel = f.velocity.data();
      double work = 0.0, dissipation = 0.0;
      long bad = LONG_MAX;
#pragma omp parallel num_threads(threads()) reduction(+ : work, dissipation) reduction(min : bad)
      {
        const int t = omp_get_thread_num();
        Vec<D>* __restrict force = buffers.vec_target(t, forces);
        BaseSpan span;
        const PointBlocks blocks{n};
#pragma omp for schedule(static) nowait
        for (long b = 0; b < blocks.count(); ++b) {
          const long p0 = blocks.first(b), p1 = blocks.last(b);
          if constexpr (D == 3) prefetch_block(S, p0 + 2 * kPointBlock, n);
          typename K::Shape sh[kPointBlock];
          Mat<D> m[kPointBlock];
          [[maybe_unused]] typename K::Shape centre[centre_shear ? kPointBlock : 1];
          [[maybe_unused]] double hoop_rate[D == 2 ? kPointBlock : 1] = {};  // v_r / r (axisymmetric)
          for (long p = p0; p < p1; ++p) {
            if (!sel(p)) continue;
            kernel.load(shape[p], g, P.x[p], P.half0[p], sh[p - p0]);
            m[p - p0] = gather_gradient(sh[p - p0], strides, vel);
            if constexpr (D == 2)
              if (axisymmetric) hoop_rate[p - p0] = gather(sh[p - p0], strides, vel)[0] / P.x[p][0];
            if constexpr (centre_shear)
              if (!centre_shear_gradient(kernel, g, strides, P.x[p], P.half0[p], P.F[p], vel, centre[p - p0],
                                         m[p - p0]))
                bad = std::min(bad, p);
          }
          unsigned in_lanes = 0;  // 3D: the points whose update ran in lanes
          if constexpr (D == 3)
            if (p1 - p0 == kPointBlock)
              in_lanes = lanes3d::update_block(S, p0, sel, m, dt_stress, work, dissipation, bad);
          for (long p = p0; p < p1; ++p) {
            if (!sel(p) || ((in_lanes >> (p - p0)) & 1u)) continue;
            if constexpr (D == 2) {
              const auto r =
                  S.update_booked(p, m[p - p0], hoop_rate[p - p0], dt_stress, work, dissipation, bad);
              m[p - p0] = -r.volume * sym_block<D>(S.stress[p]);
              if (axisymmetric) hoop_rate[p - p0] = -r.volume * S.stress[p][2] / P.x[p][0];  // hoop force
            } else {
              const auto r = S.update_booked(p, m[p - p0], dt_stress, work, dissipation, bad);
              m[p - p0] = -r.volume * sym_block<D>(S.stress[p]);
            }
          }
          for (long p = p0; p < p1; ++p) {
            if (!sel(p)) continue;
            if constexpr (centre_shear) {
              const Mat<D> normal = m[p - p0].diagonal().asDiagonal();
              scatter_gradient(centre[p - p0], strides, Mat<D>(m[p - p0] - normal), force);
              span.add(centre[p - p0].base);
              m[p - p0] = normal;
            }
            scatter_gradient(sh[p - p0], strides, m[p - p0], force);
            if constexpr (D == 2)  // axisymmetric: -V sigma_theta N_i / r on the radial component (eq. 30)
              if (axisymmetric) scatter(sh[p - p0], strides, Vec<D>(hoop_rate[p - p0], 0.0), force);
            span.add(sh[p - p0].base);
          }
        }
        buffers.touched(t, span);
      }
      transfer_.reduce(nullptr, forces);
      sum_points(work, dissipation);
      state_.clock.energy.strain_energy += work;
      state_.clock.energy.plastic_dissipation += dissipation;
      first_bad = std::min(first_bad, bad);
    });
    det_f_fresh_ = kSizeAhead<D, K>;
    return phase_ok(first_bad, "material point became unstable (inverted or non-finite stress)");
  });
}

// f_i^int = -sum sigma_p V_p grad N_ip (eq. 2.51) from the stresses as they are (USL).
template <int D>
template <class K>
void ExplicitSolver<D>::internal_force(const K& kernel) {
  timer_.time(Phase::InternalForce, [&] {
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      Vec<D>* const forces = f.acceleration.data();  // f_i^int (GridFields)
      transfer_.for_box([&](std::size_t i) { forces[i].setZero(); });
      if (!settings_.volumetric_averaging)
        return p2g_internal_force(transfer_, kernel, state_.points, forces, sel, NoPressureShift{},
                                  axisymmetric());
      cell_pressure(sel);  // the cell's mean pressure in place of the point's (volumetric_averaging.hpp)
      p2g_internal_force(
          transfer_, kernel, state_.points, forces, sel,
          [&](long q) { return volumetric_.pressure_correction(static_cast<std::size_t>(q)); },
          axisymmetric());
    });
  });
}

}  // namespace skred
