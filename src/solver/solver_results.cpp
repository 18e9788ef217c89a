// What the solver reports between steps: particle totals (Thesis eq. 4.15, 5.12), the
// grid-smoothed stresses (eq. 4.18-4.19), and the start of a stage.
#include <omp.h>

#include <cmath>
#include <type_traits>

#include "solver/explicit_solver.hpp"
#include "transfer/velocity_filters.hpp"

namespace skred {

template <int D>
ParticleTotals<D> ExplicitSolver<D>::totals() const {
  const auto& P = particles_;
  const long n = static_cast<long>(P.size());
  double mass = 0.0, ke = 0.0, speed_mass = 0.0, vmax = 0.0;
  long yielding = 0;
  Vec<D> mom = Vec<D>::Zero();
#pragma omp parallel for num_threads(threads()) reduction(+ : mass, ke, speed_mass, yielding) \
    reduction(max : vmax) reduction(vsum : mom)
  for (long p = 0; p < n; ++p) {
    const double m = P.mass[p], s = P.v[p].norm();
    mass += m;
    ke += 0.5 * m * s * s;  // eq. 4.15
    speed_mass += m * s;    // eq. 5.12
    vmax = std::max(vmax, s);
    mom += m * P.v[p];
    yielding += P.state[p].yielding;
  }
  ParticleTotals<D> t;
  t.mass = mass;
  t.kinetic_energy = ke + affine_kinetic_energy();
  t.momentum = mom;
  t.mean_speed = mass > 0.0 ? speed_mass / mass : 0.0;
  t.max_speed = vmax;
  t.yielding = yielding;
  return t;
}

// APIC: the kinetic energy the points' affine velocities carry besides 1/2 m_p |v_p|^2,
// sum_p 1/2 m_p sum_i N_ip |C_p (x_i - x_p)|^2 (affine_energy), at the points' current positions.
template <int D>
double ExplicitSolver<D>::affine_kinetic_energy() const {
  const auto& P = particles_;
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
  const auto& P = particles_;
  if (P.size() == 0) return 0.0;
  if (mapped_points_ != P.size()) grid_mapped_ = false;
  if (!grid_mapped_ && !map_grid().ok) return INFINITY;
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
    return m > 0.0 ? speed_mass / m : 0.0;
  });
}

template <int D>
void ExplicitSolver<D>::smoothed_stress(std::vector<Sym3>& out) {
  dispatch([&](const auto& kernel) { smoothed_stress_with(kernel, out); });
}

// Thesis eq. 4.18: sigma_i = sum sigma_p N_ip m_p / m_i; eq. 4.19: sigma_p = sum sigma_i N_ip.
template <int D>
template <class K>
void ExplicitSolver<D>::smoothed_stress_with(const K& kernel, std::vector<Sym3>& out) {
  const NodeStrides<D> strides(grid());
  const auto& P = particles_;
  const long n = static_cast<long>(P.size());
  node_stress_.assign(fields_.size(), Sym3::Zero());
  node_velocity_.assign(fields_.size(), Vec<D>::Zero());
  node_mass_.assign(fields_.size(), 0.0);
  std::vector<double>& mass = node_mass_;
  for (long p = 0; p < n; ++p) {  // serial scatter: run only when results are written
    typename K::Shape sh;
    if (!kernel.shape(grid(), P.x[p], P.half0[p], P.F[p], sh)) continue;
    const double m = P.mass[p];
    for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) {
      mass[i] += w * m;
      node_stress_[i] += (w * m) * full_stress<D>(P.stress[p]);
      node_velocity_[i] += (w * m) * P.v[p];
    });
  }
  for (std::size_t i = 0; i < mass.size(); ++i)
    if (mass[i] > 0.0) {
      node_stress_[i] /= mass[i];
      node_velocity_[i] /= mass[i];
    }
  out.resize(P.size());
#pragma omp parallel for num_threads(threads()) schedule(static)
  for (long p = 0; p < n; ++p) {
    typename K::Shape sh;
    Sym3 acc = Sym3::Zero();
    if (kernel.shape(grid(), P.x[p], P.half0[p], P.F[p], sh))
      for_each_node(sh, strides, [&](std::size_t i, double w, const Vec<D>&) { acc += w * node_stress_[i]; });
    out[p] = acc;
  }
}

template <int D>
void ExplicitSolver<D>::reset_reference() {
  particles_.x_ref = particles_.x;
  energy_ = EnergyTotals{};
}

template <int D>
void ExplicitSolver<D>::begin_stage(std::vector<Material> materials, double gravity_ramp_time) {
  materials_ = std::move(materials);
  for (Material& m : materials_) m.prepare();
  gravity_ramp_time_ = gravity_ramp_time;
  ramp_start_ = time_;
  reset_reference();
  // Plastic state that a stage held elastic did not track: the volume strain is ln det F, and
  // no point is yielding at the start of a stage.
  auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    P.state[p].volume_strain = std::log(P.F[p].determinant());
    P.state[p].yielding = 0;
  }
}

#define SKRED_RESULTS(D)                                                \
  template ParticleTotals<D> ExplicitSolver<D>::totals() const;         \
  template double ExplicitSolver<D>::affine_kinetic_energy() const;     \
  template double ExplicitSolver<D>::material_mean_speed();             \
  template void ExplicitSolver<D>::smoothed_stress(std::vector<Sym3>&); \
  template void ExplicitSolver<D>::reset_reference();                   \
  template void ExplicitSolver<D>::begin_stage(std::vector<Material>, double);
SKRED_RESULTS(2)
SKRED_RESULTS(3)
#undef SKRED_RESULTS

}  // namespace skred
