// The explicit MPM/GIMP time step and its particle phases. step() reads like the algorithm
// lists of Thesis §4.4; each phase is one member function with one tight, OpenMP-parallel
// loop. Particle-to-grid transfers are lock-free: thread 0 scatters into the grid, every other
// thread into its own buffer, which grid_phases.cpp adds up. Grid phases: grid_phases.cpp;
// totals, smoothing and stage starts: solver_results.cpp.
#include "solver/explicit_solver.hpp"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <cmath>

#include "solver/gravity.hpp"
#include "solver/stress_update.hpp"

namespace skred {

namespace {

// End of a point's step: x^{k+1} = x^k + dx (eq. 2.55); F^{k+1} was formed by the stress
// update (eq. 3.2). A point that would cross a fixed, roller or frictional wall is stopped at
// the wall (the walls are impenetrable; interpolated velocities next to a wall can overshoot
// it by a fraction of a step). False if the point left the grid through a free side or its
// velocity is not finite.
template <int D>
[[gnu::always_inline]] inline bool move_point(const GridGeometry<D>& grid, const WallBox<D>& walls,
                                              Vec<D>& x, const Vec<D>& dx, const Vec<D>& v) {
  x += dx;
  for (int d = 0; d < D; ++d) x[d] = std::min(std::max(x[d], walls.lo[d]), walls.hi[d]);
  return grid.inside(x) && std::isfinite(v.sum());
}

// After a stress update: false if the point's volume collapsed or inverted (det F <= 0) or its
// stress is not finite.
template <class V>
[[gnu::always_inline]] inline bool sound_point(const StressUpdateResult& r, const V& stress) {
  return r.volume > 0.0 && std::isfinite(stress.sum());
}

// The per-point arrays the stress update reads and writes (Thesis eq. 4.1-4.4, Post 72-73),
// for the two phases that update stresses.
template <int D> struct StressArrays {
  const double* __restrict volume0;
  const std::int16_t* __restrict material;
  Mat<D>* __restrict F;
  Mat<D>* __restrict Fe;
  PointStress<D>* __restrict stress;
  PointState* __restrict state;
  const Material* mats;
  bool single;  // one material: the ids need not be read

  StressArrays(Particles<D>& P, const std::vector<Material>& materials)
      : volume0(P.volume0.data()), material(P.material.data()), F(P.F.data()), Fe(P.Fe.data()),
        stress(P.stress.data()), state(P.state.data()), mats(materials.data()),
        single(materials.size() == 1) {}

  [[gnu::always_inline]] StressUpdateResult update(long p, const Mat<D>& grad_v, double dt) const {
    return update_point_stress<D>(mats[single ? 0 : material[p]], grad_v, dt, volume0[p], stress[p],
                                  state[p], F[p], Fe[p]);
  }
};

// The extent of the points, per axis the lowest and highest coordinate (for the box of
// nodes the next step can reach, see set_box). Kept in registers in the hot loops.
template <int D> struct Extent {
  Vec<D> lo = Vec<D>::Constant(INFINITY), hi = Vec<D>::Constant(-INFINITY);
  [[gnu::always_inline]] void add(const Vec<D>& x) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  void merge(const Extent& o) {
    lo = lo.cwiseMin(o.lo);
    hi = hi.cwiseMax(o.hi);
  }
};
#pragma omp declare reduction(merge : Extent<2>, Extent<3> : omp_out.merge(omp_in))

// Lowest and highest block base a thread scattered to (see ScatterBuffer).
struct BaseSpan {
  std::size_t lo = SIZE_MAX, hi = 0;
  [[gnu::always_inline]] void add(std::size_t base) {
    lo = std::min(lo, base);
    hi = std::max(hi, base);
  }
};

// Thesis eq. 2.53-2.54 for one point: its weighting functions are evaluated, stored for the
// rest of the step, and its mass and momentum mapped to the nodes. False if the point's
// stencil does not fit in the grid.
template <int D, class K>
[[gnu::always_inline]] inline bool map_point(const K& kernel, const GridGeometry<D>& grid,
                                             const NodeStrides<D>& strides, const Vec<D>& x,
                                             const Vec<D>& half0, const Mat<D>& F, double m,
                                             const Vec<D>& v, typename K::Packed& store,
                                             double* __restrict mass, Vec<D>* __restrict mom,
                                             BaseSpan& span) {
  typename K::Shape sh;
  if (!kernel.shape(grid, x, half0, F, sh)) return false;
  kernel.store(store, sh, F);
  span.add(sh.base);
  scatter(sh, strides, m, mass);
  scatter(sh, strides, Vec<D>(m * v), mom);
  return true;
}

}  // namespace

template <int D>
ExplicitSolver<D>::ExplicitSolver(GridGeometry<D> grid, Particles<D>& particles,
                                  std::vector<Material> materials, SolverSettings<D> settings,
                                  int threads)
    : grid_(grid), particles_(particles), materials_(std::move(materials)), settings_(settings),
      threads_(std::max(1, threads)) {
  for (Material& m : materials_) m.prepare();
  grid_.bspline_dofs = settings_.interpolation == Interpolation::Bspline;
  boundaries_ = Boundaries<D>(grid_, settings_.boundaries);
  for (int d = 0; d < D; ++d) {
    const double lo = grid_.origin[d], hi = grid_.origin[d] + grid_.h * grid_.cells[d];
    const bool closed_lo = settings_.boundaries[2 * d].kind != BoundaryKind::Free;
    const bool closed_hi = settings_.boundaries[2 * d + 1].kind != BoundaryKind::Free;
    walls_.lo[d] = closed_lo ? lo : -INFINITY;
    walls_.hi[d] = closed_hi ? hi : INFINITY;
  }
  const std::size_t n = grid_.node_count();
  fields_.resize(n);
  for (int d = 0; d < D; ++d) {  // the fields start zero: no box yet
    box_.lo[d] = 0;
    box_.hi[d] = -1;
  }
  buffers_.resize(static_cast<std::size_t>(threads_ - 1));
  for (auto& b : buffers_) b.resize(n);
}

template <int D> StepStatus ExplicitSolver<D>::step() {
  return dispatch([this](const auto& kernel) { return step_with(kernel); });
}

// Thesis §4.4: update-stress-first, update-stress-last, or the averaged scheme, which
// splits the stress update into two half steps around the momentum update. The mass and
// momentum maps that start a step (eq. 2.53-2.54) are done by the last phase of the step
// before, point by point as it moves the points, so a step reads the particles three times
// (averaged, USL) or twice (USF) plus once.
template <int D> template <class K> StepStatus ExplicitSolver<D>::step_with(const K& kernel) {
  const double dt = settings_.dt;
  gravity_now_ = gravity_at<D>(settings_.gravity, settings_.gravity_ramp_time, time_ - ramp_start_);
  status_ = StepStatus{};
  if (mapped_points_ != particles_.size()) grid_mapped_ = false;
  if (!grid_mapped_ && !map_mass_momentum(kernel)) return status_;
  grid_mapped_ = false;
  nodal_velocity(fields_.velocity, /*clear=*/false);
  switch (settings_.scheme) {
    case StressScheme::USF:
      update_stress_and_map_forces(kernel, dt);
      if (!status_.ok) return status_;
      update_grid();
      clear_mass_momentum();
      update_particle_velocity(kernel, /*remap=*/false, /*move=*/true);
      break;
    case StressScheme::USL:
    case StressScheme::Averaged: {
      const double dt_stress = settings_.scheme == StressScheme::USL ? dt : 0.5 * dt;
      update_stress_and_map_forces(kernel, settings_.scheme == StressScheme::USL ? 0.0 : dt_stress);
      if (!status_.ok) return status_;
      update_grid();
      update_particle_velocity(kernel, /*remap=*/true, /*move=*/false);
      nodal_velocity(fields_.velocity, /*clear=*/true);  // v^{k+1} from the remap
      update_stress_and_move(kernel, dt_stress);
      break;
    }
  }
  if (!status_.ok) return status_;  // the failing step is steps() + 1, starting at time()
  grid_mapped_ = true;
  mapped_points_ = particles_.size();
  time_ += dt;
  ++steps_;
  return status_;
}

template <int D> template <class K> std::vector<typename K::Packed>& ExplicitSolver<D>::shapes() {
  using Store = std::vector<typename K::Packed>;
  if (!std::holds_alternative<Store>(shapes_)) shapes_.template emplace<Store>();
  Store& store = std::get<Store>(shapes_);
  if (store.size() != particles_.size()) {  // only when the number of points changes
    reserve_huge(store, particles_.size());
    store.resize(particles_.size());
  }
  return store;
}

// Thesis eq. 2.53-2.54: m_i = sum m_p N_ip, m_i v_i = sum m_p v_p N_ip. The weighting
// functions evaluated here are kept for the rest of the step.
template <int D> template <class K> bool ExplicitSolver<D>::map_mass_momentum(const K& kernel) {
  const NodeStrides<D> strides(grid_);
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  typename K::Packed* __restrict shape = shapes<K>().data();
  const Vec<D>* __restrict x = P.x.data();
  const Vec<D>* __restrict v = P.v.data();
  const Vec<D>* __restrict half0 = P.half0.data();
  const Mat<D>* __restrict F = P.F.data();
  const double* __restrict pmass = P.mass.data();
  clear_mass_momentum();  // outside the box they are zero already
  long bad = LONG_MAX;
  Extent<D> extent;
#pragma omp parallel num_threads(threads_) reduction(min : bad) reduction(merge : extent)
  {
    const int t = omp_get_thread_num();
    double* __restrict mass = mass_target(t);
    Vec<D>* __restrict mom = vec_target(t, fields_.momentum);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      if (!map_point(kernel, grid_, strides, x[p], half0[p], F[p], pmass[p], v[p], shape[p], mass, mom, span))
        bad = std::min(bad, p);
      extent.add(x[p]);
    }
    if (t > 0) buffers_[t - 1].touched(span.lo, span.hi);
  }
  set_box(extent.lo, extent.hi);
  reduce_scatter(true, fields_.momentum);
  if (bad != LONG_MAX) {
    status_ = {false, bad, "material point left the grid"};
    return false;
  }
  return true;
}

// Strain increment and stress update at every point (eq. 2.20, 3.5, 4.1-4.4) when
// dt_stress > 0, then the internal forces f_i = -sum sigma_p V_p grad N_ip (eq. 2.51).
template <int D>
template <class K>
void ExplicitSolver<D>::update_stress_and_map_forces(const K& kernel, double dt_stress) {
  const NodeStrides<D> strides(grid_);
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  const typename K::Packed* __restrict shape = shapes<K>().data();
  const Vec<D>* __restrict x = P.x.data();
  const Vec<D>* __restrict half0 = P.half0.data();
  const StressArrays<D> S(P, materials_);
  Vec<D>* const forces = fields_.accel.data();  // f_i^int, until the grid update
  for_box([&](std::size_t i) { forces[i].setZero(); });
  const Vec<D>* __restrict vel = fields_.velocity.data();
  double work = 0.0, dissipation = 0.0;
  long bad = LONG_MAX;
#pragma omp parallel num_threads(threads_) reduction(+ : work, dissipation) reduction(min : bad)
  {
    const int t = omp_get_thread_num();
    Vec<D>* __restrict force = vec_target(t, fields_.accel);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      typename K::Shape sh;
      kernel.load(shape[p], grid_, x[p], half0[p], sh);
      double volume;
      if (dt_stress > 0.0) {
        const Mat<D> grad_v = gather_gradient(sh, strides, vel);
        const auto r = S.update(p, grad_v, dt_stress);
        work += r.strain_energy;
        dissipation += r.dissipation;
        volume = r.volume;
        if (!sound_point(r, S.stress[p])) bad = std::min(bad, p);
      } else {
        volume = S.volume0[p] * S.F[p].determinant();
      }
      const Mat<D> sv = -volume * sym_block<D>(S.stress[p]);
      scatter_gradient(sh, strides, sv, force);
      span.add(sh.base);
    }
    if (t > 0) buffers_[t - 1].touched(span.lo, span.hi);
  }
  reduce_scatter(false, fields_.accel);
  energy_.strain_energy += work;
  energy_.plastic_dissipation += dissipation;
  if (bad != LONG_MAX) status_ = {false, bad, "material point became unstable (inverted or non-finite stress)"};
}

// Thesis eq. 2.56: v_p += dt sum N_ip a_i. With remap, the updated particle momenta are
// mapped back to the grid (USL and averaged schemes, step 6 of §4.4). With move (USF), the
// point is also moved (eq. 2.55 / Post eq. 31) and the next step's maps done (eq. 2.53-2.54).
template <int D>
template <class K>
void ExplicitSolver<D>::update_particle_velocity(const K& kernel, bool remap, bool move) {
  const NodeStrides<D> strides(grid_);
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  const double dt = settings_.dt;
  typename K::Packed* __restrict shape = shapes<K>().data();
  Vec<D>* __restrict x = P.x.data();
  Vec<D>* __restrict v = P.v.data();
  const Vec<D>* __restrict half0 = P.half0.data();
  const double* __restrict pmass = P.mass.data();
  const Mat<D>* __restrict F = P.F.data();
  if (remap) for_box([&](std::size_t i) { fields_.momentum[i].setZero(); });
  const Vec<D>* __restrict acc = fields_.accel.data();
  const Vec<D>* __restrict vel = fields_.velocity_move.data();
  const Vec<D>* __restrict vnew = fields_.velocity.data();  // v^{k+1}
  const double alpha = settings_.pic_fraction;
  Vec<D> mdx = Vec<D>::Zero();
  long bad = LONG_MAX;
  Extent<D> extent;  // of the moved points
#pragma omp parallel num_threads(threads_) reduction(vsum : mdx) reduction(min : bad) \
    reduction(merge : extent)
  {
    const int t = omp_get_thread_num();
    double* __restrict mass = mass_target(t);
    Vec<D>* __restrict mom = vec_target(t, fields_.momentum);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      typename K::Shape sh;
      kernel.load(shape[p], grid_, x[p], half0[p], sh);
      Vec<D> vp = v[p] + dt * gather(sh, strides, acc);
      if (alpha > 0.0) {  // PIC/FLIP blend: v_p <- (1 - alpha) v_p^FLIP + alpha sum N_ip v_i^{k+1}
        vp = (1.0 - alpha) * vp + alpha * gather(sh, strides, vnew);
      }
      v[p] = vp;
      if (remap) {
        const Vec<D> mv = pmass[p] * vp;
        scatter(sh, strides, mv, mom);
        span.add(sh.base);
      }
      if (move) {
        const Vec<D> vmove = gather(sh, strides, vel);
        mdx += pmass[p] * dt * vmove;
        if (!move_point<D>(grid_, walls_, x[p], Vec<D>(dt * vmove), vp) ||
            !map_point(kernel, grid_, strides, x[p], half0[p], F[p], pmass[p], vp, shape[p], mass, mom, span))
          bad = std::min(bad, p);
        extent.add(x[p]);
      }
    }
    if (t > 0) buffers_[t - 1].touched(span.lo, span.hi);
  }
  if (remap) reduce_scatter(false, fields_.momentum);
  if (move) {
    set_box(extent.lo, extent.hi);  // the next step's box, which the reduction must cover now
    reduce_scatter(true, fields_.momentum);
    energy_.gravity_work += gravity_now_.dot(mdx);
    if (bad != LONG_MAX) status_ = {false, bad, "material point became unstable or left the grid"};
  }
}

// Second half of USL / averaged (steps 7-8 of §4.4): strain increment from the remapped
// velocities, stress update (with F^{k+1} = dF F, eq. 3.2), then the position update
// x_p += dt sum N_ip (v_i + dt/2 a_i) (eq. 2.55, Post eq. 31, with the velocity_move of
// update_grid), and the next step's maps at x^{k+1} (eq. 2.53-2.54).
template <int D>
template <class K>
void ExplicitSolver<D>::update_stress_and_move(const K& kernel, double dt_stress) {
  const NodeStrides<D> strides(grid_);
  auto& P = particles_;
  const long n = static_cast<long>(P.size());
  const double dt = settings_.dt;
  typename K::Packed* __restrict shape = shapes<K>().data();
  Vec<D>* __restrict x = P.x.data();
  const Vec<D>* __restrict v = P.v.data();
  const Vec<D>* __restrict half0 = P.half0.data();
  const double* __restrict pmass = P.mass.data();
  const StressArrays<D> S(P, materials_);
  const Vec<D>* __restrict vel = fields_.velocity_move.data();
  const Vec<D>* __restrict vnew = fields_.velocity.data();  // v^{k+1}
  double work = 0.0, dissipation = 0.0;
  Vec<D> mdx = Vec<D>::Zero();
  long bad = LONG_MAX;
  Extent<D> extent;  // of the moved points
#pragma omp parallel num_threads(threads_) reduction(+ : work, dissipation) reduction(vsum : mdx) \
    reduction(min : bad) reduction(merge : extent)
  {
    const int t = omp_get_thread_num();
    double* __restrict mass = mass_target(t);
    Vec<D>* __restrict mom = vec_target(t, fields_.momentum);
    BaseSpan span;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      typename K::Shape sh;
      kernel.load(shape[p], grid_, x[p], half0[p], sh);
      const Mat<D> grad_v = gather_gradient(sh, strides, vnew);
      const Vec<D> vmove = gather(sh, strides, vel);
      const auto r = S.update(p, grad_v, dt_stress);
      work += r.strain_energy;
      dissipation += r.dissipation;
      mdx += pmass[p] * dt * vmove;
      if (!sound_point(r, S.stress[p]) || !move_point<D>(grid_, walls_, x[p], Vec<D>(dt * vmove), v[p]) ||
          !map_point(kernel, grid_, strides, x[p], half0[p], S.F[p], pmass[p], v[p], shape[p], mass, mom, span))
        bad = std::min(bad, p);
      extent.add(x[p]);
    }
    if (t > 0) buffers_[t - 1].touched(span.lo, span.hi);
  }
  set_box(extent.lo, extent.hi);  // the next step's box, which the reduction must cover now
  reduce_scatter(true, fields_.momentum);
  energy_.strain_energy += work;
  energy_.plastic_dissipation += dissipation;
  energy_.gravity_work += gravity_now_.dot(mdx);
  if (bad != LONG_MAX) status_ = {false, bad, "material point became unstable or left the grid"};
}

template class ExplicitSolver<2>;
template class ExplicitSolver<3>;

}  // namespace skred
