#include "run/stability.hpp"

#include <fmt/format.h>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

#include "scenario/estimate.hpp"

namespace skred {

namespace {
// The global index of this process's point `local` (-1: none here) that comes first over all
// processes, or -1.
long global_first(long local, long n, const Processes& procs) {
  if (!procs.distributed()) return local;
  const long offset = procs.offset(n);
  const long first = procs.min(local >= 0 ? offset + local : std::numeric_limits<long>::max());
  return first == std::numeric_limits<long>::max() ? -1 : first;
}
}  // namespace

template <int D>
StabilityWatch<D>::StabilityWatch(const ScenarioOf<D>& s, double dt, double total_mass,
                                  const Processes& procs)
    : dt_(dt), h_(s.cell_size), procs_(procs) {
  for (const Material& m : s.materials)
    if (m.wave_speed() > c_) {
      c_ = m.wave_speed();
      fastest_material_ = m.name;
    }
  for (const BodyOf<D>& b : s.bodies)
    v0_ = std::max(v0_, b.velocity.norm() + b.velocity_sine.amplitude.norm());
  // Also every density a stage gives a material (scenario/estimate.hpp): h / dt_stable = c + v0.
  c_ = std::max(c_, s.cell_size / stable_time_step(s) - v0_);
  const double height = s.cells[1] * s.cell_size;
  speed_bound_ = c_ + v0_ + std::sqrt(2.0 * s.gravity.norm() * height);
  floor_ = 1e-9 * total_mass * c_ * c_;
  // (only where the undilated material is within its limit: else the step is the cause)
  if (c_ > 0.0 && dt_ > 0.0) dilation_limit_ = std::pow(kStableCourant * h_ / (c_ * dt_), 2);
  if (!(dilation_limit_ >= 1.0)) dilation_limit_ = INFINITY;
}

template <int D>
bool StabilityWatch<D>::observe_dilation(const Particles<D>& P) {
  const long n = static_cast<long>(P.size());
  double det_max = 1.0;
#pragma omp parallel for reduction(max : det_max)
  for (long p = 0; p < n; ++p) {
    const double J = P.F[p].determinant();
    if (std::isfinite(J)) det_max = std::max(det_max, J);
  }
  procs_.max(&det_max, 1);
  long at = -1;
  if (det_max > dilation_limit_) {
    for (long p = 0; p < n && at < 0; ++p)
      if (P.F[p].determinant() == det_max) at = p;
    at = global_first(at, n, procs_);
  }
  det_max_ = det_max;
  det_point_ = at;
  if (dilation_warned_ || !(det_max > dilation_limit_)) return false;
  dilation_warned_ = true;
  return true;
}

template <int D>
std::string StabilityWatch<D>::dilation_note() const {
  const double J = det_max_;
  if (!(J > dilation_limit_)) return {};
  return fmt::format(
      "points had dilated to det F = {:.3g} (point {}): the elastic wave speed of dilated material is c "
      "sqrt(det F), so c sqrt(det F) dt / h = {:.3f} > {:g} there (above det F = {:.3g}); bound the dilation "
      "(the material's max_void_ratio, Paper III C.3.2) or take a smaller time step",
      J, det_point_, c_ * std::sqrt(J) * dt_ / h_, kStableCourant, dilation_limit_);
}

template <int D>
std::string StabilityWatch<D>::unusable_step() const {
  if (std::isfinite((c_ + v0_) * dt_ / h_) && dt_ > 0.0) return {};
  return fmt::format(
      "time step {:.6g} s is not usable (c = {:.6g} m/s, initial speed v0 = {:.6g} m/s: "
      "not finite)",
      dt_, c_, v0_);
}

template <int D>
std::string StabilityWatch<D>::step_above_limit() const {
  const double courant = (c_ + v0_) * dt_ / h_;
  if (!(courant > kStableCourant * (1.0 + 1e-9))) return {};
  return fmt::format(
      "time step {:.6g} s is above the stable limit: (c + v0) dt / h = {:.3g} > {:g} (c = {:.6g} m/s, "
      "P-wave speed of material '{}'; v0 = {:.6g} m/s; h = {:.6g} m); the largest stable step is {:.6g} s",
      dt_, courant, kStableCourant, c_, fastest_material_, v0_, h_, kStableCourant * h_ / (c_ + v0_));
}

template <int D>
void StabilityWatch<D>::begin_stage(double kinetic_energy, double stored) {
  k0_ = kinetic_energy;
  max_gravity_work_ = 0.0;
  max_released_ = 0.0;
  stored0_ = stored;
}

template <int D>
double stored_stress_energy(const Particles<D>& P, const std::vector<Material>& materials,
                            const Processes& procs) {
  double w = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const ElasticParams& e = materials[static_cast<std::size_t>(P.material[p])].elastic;
    const Sym3 s = full_stress<D>(P.stress[p]);
    const double tr = s[0] + s[1] + s[2];
    const double ss = s.head<3>().squaredNorm() + 2.0 * s.tail<3>().squaredNorm();  // sigma : sigma
    // sigma : C^-1 : sigma = ((1 + nu) sigma : sigma - nu tr(sigma)^2) / E
    if (e.young > 0.0) w += 0.5 * P.volume(p) * ((1.0 + e.poisson) * ss - e.poisson * tr * tr) / e.young;
  }
  procs.sum(&w, 1);
  return w;
}

template <int D>
std::string StabilityWatch<D>::check(const ParticleTotals<D>& t, const EnergyTotals& e) {
  const double sums[] = {t.kinetic_energy, t.max_speed,    t.mean_speed,         t.momentum.norm(),
                         e.strain_energy,  e.gravity_work, e.plastic_dissipation};
  for (double x : sums)
    if (!std::isfinite(x)) return "non-finite speed or energy";
  if (t.max_speed > speed_bound_)
    return fmt::format("speed {:.4g} m/s above the bound {:.4g} m/s (wave speed + initial speed + free fall)",
                       t.max_speed, speed_bound_);
  max_gravity_work_ = std::max(max_gravity_work_, std::abs(e.gravity_work + e.load_work));
  max_released_ = std::max(max_released_, -e.strain_energy);
  const double gained =
      t.kinetic_energy - k0_ + e.strain_energy + e.plastic_dissipation - e.gravity_work - e.load_work;
  const double supplied = k0_ + max_gravity_work_ + std::max(max_released_, stored0_);
  if (gained <= kEnergyGrowthTolerance * supplied + floor_) return {};
  return fmt::format(
      "energy grew by {:.4g} J beyond the {:.4g} J supplied since the stage start "
      "(kinetic {:.4g} J, stored {:.4g} J, dissipated {:.4g} J, gravity work {:.4g} J)",
      gained, supplied, t.kinetic_energy, e.strain_energy, e.plastic_dissipation, e.gravity_work);
}

namespace {
template <class M>
bool finite(const M& m) {
  return m.allFinite();
}
}  // namespace

template <int D>
long first_non_finite_point(const Particles<D>& P, const Processes& procs) {
  const long n = static_cast<long>(P.size());
  long bad = n;
#pragma omp parallel for reduction(min : bad)
  for (long p = 0; p < n; ++p)
    if (!finite(P.x[p]) || !finite(P.v[p]) || !finite(P.F[p]) || !finite(P.stress[p])) bad = std::min(bad, p);
  return global_first(bad < n ? bad : -1, n, procs);
}

template <int D>
long offending_point(const Particles<D>& P, const Processes& procs) {
  const long bad = first_non_finite_point(P, procs);
  if (bad >= 0) return bad;
  const long n = static_cast<long>(P.size());
  long fastest = n > 0 ? 0 : -1;
  for (long p = 1; p < n; ++p)
    if (P.v[p].squaredNorm() > P.v[fastest].squaredNorm()) fastest = p;
  double top = fastest >= 0 ? P.v[fastest].squaredNorm() : -1.0;
  procs.max(&top, 1);
  return global_first(fastest >= 0 && P.v[fastest].squaredNorm() == top ? fastest : -1, n, procs);
}

template <int D>
PointPlace<D> point_place(const Particles<D>& P, long p, const Processes& procs) {
  const long local = p - procs.offset(static_cast<long>(P.size()));
  double v[D + 1];
  std::fill(v, v + D + 1, -INFINITY);  // (the process that holds p puts its values)
  if (local >= 0 && local < static_cast<long>(P.size())) {
    for (int d = 0; d < D; ++d) v[d] = P.x[local][d];
    v[D] = P.body[local];
  }
  procs.max(v, D + 1);
  PointPlace<D> r;
  for (int d = 0; d < D; ++d) r.x[d] = v[d];
  r.body = std::isfinite(v[D]) ? static_cast<int>(v[D]) : -1;
  return r;
}

template <int D>
bool left_the_grid(const Particles<D>& P, long p, const GridGeometry<D>& grid, double speed_bound,
                   const Processes& procs) {
  if (procs.distributed()) {  // the process that holds p answers
    const long local = p - procs.offset(static_cast<long>(P.size()));
    return procs.any(local >= 0 && left_the_grid(P, local, grid, speed_bound));
  }
  if (p < 0 || p >= static_cast<long>(P.size())) return false;
  if (!finite(P.x[p]) || !finite(P.v[p]) || !finite(P.F[p]) || !finite(P.stress[p])) return false;
  if (!(P.F[p].determinant() > 0.0) || P.v[p].norm() > speed_bound) return false;
  for (int d = 0; d < D; ++d) {
    const double lo = grid.origin[d] + grid.h, hi = grid.origin[d] + (grid.cells[d] - 1) * grid.h;
    if (P.x[p][d] < lo || P.x[p][d] > hi) return true;
  }
  return false;
}

template class StabilityWatch<2>;
template class StabilityWatch<3>;
template double stored_stress_energy<2>(const Particles<2>&, const std::vector<Material>&, const Processes&);
template double stored_stress_energy<3>(const Particles<3>&, const std::vector<Material>&, const Processes&);
template long first_non_finite_point<2>(const Particles<2>&, const Processes&);
template long first_non_finite_point<3>(const Particles<3>&, const Processes&);
template long offending_point<2>(const Particles<2>&, const Processes&);
template long offending_point<3>(const Particles<3>&, const Processes&);
template bool left_the_grid<2>(const Particles<2>&, long, const GridGeometry<2>&, double, const Processes&);
template bool left_the_grid<3>(const Particles<3>&, long, const GridGeometry<3>&, double, const Processes&);
template PointPlace<2> point_place<2>(const Particles<2>&, long, const Processes&);
template PointPlace<3> point_place<3>(const Particles<3>&, long, const Processes&);

}  // namespace skred
