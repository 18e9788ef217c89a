// What the explicit solver reports between steps beyond the shared state's (mpm_state.cpp): the
// particle totals with APIC's affine kinetic energy, and the material's mean speed.
#include <omp.h>

#include <cmath>
#include <type_traits>

#include "solver/explicit_solver.hpp"
#include "transfer/velocity_filters.hpp"

namespace skred {

template <int D>
ParticleTotals<D> ExplicitSolver<D>::totals() const {
  ParticleTotals<D> t = particle_totals(state_.points, threads(), state_.processes);
  double affine = affine_kinetic_energy();
  sum_points(affine);
  t.kinetic_energy += affine;
  return t;
}

// APIC: the kinetic energy the points' affine velocities carry besides 1/2 m_p |v_p|^2,
// sum_p 1/2 m_p sum_i N_ip |C_p (x_i - x_p)|^2 (affine_energy), at the points' current positions.
template <int D>
double ExplicitSolver<D>::affine_kinetic_energy() const {
  const auto& P = state_.points;
  if (!transfer_rule_.carries_affine() || P.affine.size() != P.size()) return 0.0;
  return with_kernel<D>(settings_.interpolation, settings_.quadrature_points, [&](const auto& kernel) {
    using K = std::decay_t<decltype(kernel)>;
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides(g);
    const long n = static_cast<long>(P.size());
    double e = 0.0;
#pragma omp parallel for num_threads(threads()) reduction(+ : e)
    for (long p = 0; p < n; ++p) {
      typename K::Shape sh;
      if (kernel.shape(g, P.x[p], P.half0[p], P.F[p], sh))
        e += 0.5 * P.mass[p] * affine_energy(sh, g, strides, P.x[p], P.affine[p]);
    }
    return e;
  });
}

template <int D>
double ExplicitSolver<D>::material_mean_speed() {
  const auto& P = state_.points;
  if (!state_.processes.distributed() && P.size() == 0) return 0.0;
  if (needs_map() && !map_grid().ok) return INFINITY;
  material_velocity_.resize(fields_.size());  // zero pages, once
  return dispatch([&](const auto& kernel) {
    using K = std::decay_t<decltype(kernel)>;
    const long n = static_cast<long>(P.size());
    const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
    double m = 0.0, speed_mass = 0.0;
    // sum_p m_p |sum_i N_ip v_i| over the points of `body` (-1: every point) from the fields m_i, p_i.
    const auto add = [&](const GridFields<D>& f, int body) {
      const double* __restrict mass = f.mass.data();
      const Vec<D>* __restrict mom = f.momentum.data();
      Vec<D>* __restrict vel = material_velocity_.data();
      transfer_.for_box(
          [&](std::size_t i) { vel[i] = mass[i] > 0.0 ? Vec<D>(mom[i] / mass[i]) : Vec<D>::Zero(); });
      boundaries_.constrain_velocity(material_velocity_, transfer_.box());
#pragma omp parallel for num_threads(threads()) schedule(static) reduction(+ : m, speed_mass)
      for (long q = 0; q < n; ++q) {
        if (body >= 0 && P.body[q] != body) continue;
        typename K::Shape sh;
        kernel.load(shape[q], transfer_.grid(), P.x[q], P.half0[q], sh);
        m += P.mass[q];
        speed_mass += P.mass[q] * gather(sh, transfer_.strides(), vel).norm();
      }
    };
    if (!contact_on())
      add(fields_, -1);
    else  // each body moves with its own fields (Paper III §C.2.7)
      for (std::size_t b = 0; b < bodies_.size(); ++b) add(bodies_[b], static_cast<int>(b));
    sum_points(m, speed_mass);
    return m > 0.0 ? speed_mass / m : 0.0;
  });
}

#define SKRED_RESULTS(D)                                            \
  template ParticleTotals<D> ExplicitSolver<D>::totals() const;     \
  template double ExplicitSolver<D>::affine_kinetic_energy() const; \
  template double ExplicitSolver<D>::material_mean_speed();
SKRED_RESULTS(2)
SKRED_RESULTS(3)
#undef SKRED_RESULTS

}  // namespace skred
