// The explicit MPM/GIMP time step and its particle phases. The scheme types (scheme.hpp)
// call the phases in the order of Thesis §4.4; each phase is one member function with one
// tight, OpenMP-parallel loop. Phases that would read the points twice in a row are fused
// point by point (the stress update with the force map, the position update with the next
// step's map); their transfers are the transfer layer's (src/transfer), lock-free. Grid
// phases: grid_phases.cpp; the stress phase: stress_phase_impl.hpp; totals, smoothing and
// stage starts: solver_results.cpp.
// Included only by explicit_solver_2d.cpp and explicit_solver_3d.cpp, which instantiate the
// solver for one dimension each: two smaller translation units that build in parallel.
#pragma once
#include "solver/explicit_solver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <type_traits>

#include "core/inline.hpp"
#include "solver/gravity.hpp"
#include "solver/stress_arrays.hpp"
#include "solver/stress_update.hpp"
#include "solver/wall_share.hpp"
#include "transfer/size_ahead.hpp"
#include "transfer/transfers.hpp"

namespace skred {

namespace {

// How far ahead the 3D move phase asks for a point's weights, position and velocity.
inline constexpr long kMoveAhead = 16;

// End of a point's step: x^{k+1} = x^k + dx (eq. 2.55); F^{k+1} was formed by the stress
// update (eq. 3.2). A point that would cross a fixed, roller or frictional wall is stopped at
// the wall (the walls are impenetrable; interpolated velocities next to a wall can overshoot
// it by a fraction of a step). False if the point left the grid through a free side or its
// velocity is not finite.
template <int D>
SKRED_INLINE bool move_point(const GridGeometry<D>& grid, const WallBox<D>& walls, Vec<D>& x,
                             const Vec<D>& dx, const Vec<D>& v) {
  x += dx;
  for (int d = 0; d < D; ++d) x[d] = std::min(std::max(x[d], walls.lo[d]), walls.hi[d]);
  return grid.inside(x) && std::isfinite(v.sum());
}

// The particle velocity update (velocity_transfer.hpp). FLIP, Thesis eq. 2.56: v_p + dt sum
// N_ip a_i (acc_p = sum N_ip a_i, gathered by the caller), blended with a PIC share alpha of sum N_ip
// v_i^{k+1}: v_p <- (1 - alpha) v_p^FLIP + alpha v_p^PIC. XPIC and APIC are alpha = 1 with their nodal
// velocity in vnext; APIC also takes the affine velocity C_p = sum_i v_i^{k+1} (x) grad N_ip, the gradient
// form of Jiang et al. (2015)'s B_p D_p^-1 (equal to it for the linear kernel); the affine FLIP (Fei et
// al. 2021) is FLIP (alpha = 0) with that C_p, and books only its affine part. `lost` gains what the
// transfer took from the FLIP update. Under the PIC share and XPIC, whose change dv = v_p - v_p^FLIP
// removes grid-scale motion that the time step's own energy error feeds, the energy it takes from the
// scheme: (1/2) m_p (|v_p^FLIP|^2 - |v_p|^2) + w dt m_p dv . acc_p, with w = 1/2 for USF and USL (the
// work of the change over the step's mean velocity, (1/2) m_p (v_p^FLIP - v_p) . (v_p^k + v_p)) and
// w = 1 for the averaged scheme (docs/method.md, "The PIC share's and XPIC's booked loss"). Under APIC
// (w = 0): (1/2) m_p (|v_p^FLIP|^2 - |v_p|^2) and the affine velocity's share of the FLIP-updated
// kinetic energy (affine_trial_energy; the new C_p's share is taken off where the point is next
// mapped, at its new position).
template <class K, class Shape, int D>
SKRED_INLINE Vec<D> particle_velocity(const Shape& sh, const GridGeometry<D>& g,
                                      const NodeStrides<D>& strides, const Vec<D>& x, const Vec<D>& v,
                                      double dt, const Vec<D>& acc_p, const Vec<D>* __restrict vnext,
                                      double alpha, Mat<D>* affine, double m, double w, double& lost) {
  const Vec<D> flip = v + dt * acc_p;
  if (affine) *affine = apic_affine_velocity<K>(sh, g, strides, x, vnext);  // APIC and the affine FLIP
  if (alpha <= 0.0) return flip;
  Vec<D> vp;
  if (alpha >= 1.0) {
    vp = gather(sh, strides, vnext);
  } else {
    vp = (1.0 - alpha) * flip + alpha * gather(sh, strides, vnext);
  }
  if (affine)
    lost += 0.5 * m * (flip.squaredNorm() - vp.squaredNorm());
  else
    lost += 0.5 * m * (flip - vp).dot(vp + (2.0 * w) * v + (1.0 - 2.0 * w) * flip);  // dt acc_p = flip - v
  return vp;
}

}  // namespace

template <int D>
ExplicitSolver<D>::ExplicitSolver(GridGeometry<D> grid, Particles<D>& particles,
                                  std::vector<Material> materials, SolverSettings<D> settings, int threads)
    : state_(particles, grid, settings.interpolation, settings.quadrature_points, std::move(materials),
             threads),
      transfer_(state_.grid, threads),
      settings_(settings) {
  state_.processes = settings.processes;
  transfer_.set_processes(settings.processes);
  state_.clock.gravity_ramp_time = settings.gravity_ramp_time;
  for (Material& m : state_.materials) {
    m.hyperelastic = settings_.hyperelastic;
    m.prepare();
  }
  const GridGeometry<D>& g = transfer_.grid();
  boundaries_ = Boundaries<D>(g, settings_.boundaries, transfer_.threads());
  for (int d = 0; d < D; ++d) {
    const double lo = g.origin[d], hi = g.origin[d] + g.h * g.cells[d];
    const bool closed_lo = settings_.boundaries[2 * d].kind != BoundaryKind::Free;
    const bool closed_hi = settings_.boundaries[2 * d + 1].kind != BoundaryKind::Free;
    walls_.lo[d] = closed_lo ? lo : -INFINITY;
    walls_.hi[d] = closed_hi ? hi : INFINITY;
  }
  // Axisymmetric geometry: every point carries its hoop stretch (from 1 if no stage set it), and
  // the cell-averaged volumetric strain takes the hoop axis.
  if (axisymmetric()) {
    if (state_.points.hoop.size() != state_.points.size())
      state_.points.hoop.assign(state_.points.size(), 1.0);
    volumetric_.axes = 3;
  }
  transfer_rule_ =
      VelocityTransferRule(settings_.velocity_transfer, settings_.pic_fraction, settings_.xpic_order,
                           settings_.xpic_period, settings_.dt, settings_.scheme);
  const bool pic = transfer_rule_.forms_velocity_next(),
             xpic = transfer_rule_.kind() == VelocityTransfer::Xpic;
  fields_.resize(g.node_count(), pic, settings_.scheme != StressScheme::USF, xpic);
  // APIC's and the affine FLIP's affine velocities start at zero; other transfers carry none.
  if (transfer_rule_.carries_affine())
    state_.points.affine.resize(state_.points.size(), Mat<D>::Zero());
  else
    state_.points.affine.clear();
  if (contact_on()) {  // every body's fields, from zero pages (only where it reaches)
    bodies_.resize(static_cast<std::size_t>(settings_.contact.bodies()));
    for (auto& b : bodies_) b.resize(g.node_count(), pic || xpic, settings_.scheme != StressScheme::USF);
    contact_sums_.assign(static_cast<std::size_t>(16 * transfer_.threads()), 0.0);
    prepare_contact();
  }
}

template <int D>
StepStatus ExplicitSolver<D>::step() {
  return dispatch([this](const auto& kernel) {
    return with_scheme(settings_.scheme, [&](auto scheme) {
      return step_with<std::decay_t<decltype(kernel)>, decltype(scheme)>(kernel);
    });
  });
}

template <int D>
StepStatus ExplicitSolver<D>::map_grid() {
  status_ = StepStatus{};
  dispatch([this](const auto& kernel) {
    if (map_mass_momentum(kernel) && (settings_.body_fields || contact_on())) map_body_fields(kernel);
  });
  grid_mapped_ = status_.ok;
  mapped_points_ = state_.points.size();
  return status_;
}

// One step: the grid's mass and momentum of the step (mapped by the last step unless the
// points changed since), then the scheme's phases (Thesis §4.4), which end by mapping the
// next step's.
template <int D>
template <class K, class Scheme>
StepStatus ExplicitSolver<D>::step_with(const K& kernel) {
  gravity_now_ = state_.gravity(settings_.gravity);
  transfer_rule_.begin_step(state_.clock.time);
  status_ = StepStatus{};
  det_f_fresh_ = false;  // (written by this step's stress phase, if at all)
  if (transfer_rule_.carries_affine() && state_.points.affine.size() != state_.points.size())
    state_.points.affine.resize(state_.points.size(), Mat<D>::Zero());
  const bool fresh = needs_map();
  if (fresh && !map_mass_momentum(kernel)) return status_;
  grid_mapped_ = false;
  // With contact the last step mapped each body's fields; otherwise they are mapped here.
  if (contact_on() ? fresh : settings_.body_fields) map_body_fields(kernel);
  if (contact_traction_) map_body_stress(kernel);       // the traction rule's sigma_i^b (Paper III §C.2.7)
  if (!Scheme::advance(*this, kernel)) return status_;  // the failing step is steps() + 1
  grid_mapped_ = true;
  mapped_points_ = state_.points.size();
  state_.clock.time += settings_.dt;
  ++state_.clock.steps;
  return status_;
}

// Thesis eq. 2.53-2.54: m_i = sum m_p N_ip, p_i = sum m_p v_p N_ip. The weighting functions
// evaluated here are kept for the rest of the step.
template <int D>
template <class K>
bool ExplicitSolver<D>::map_mass_momentum(const K& kernel) {
  return timer_.time(Phase::MapMassMomentum, [&] {
    clear_mass_momentum();  // outside the box they are zero already
    const long bad =
        p2g_mass_momentum(transfer_, kernel, state_.points, fields_.mass.data(), fields_.momentum.data());
    return phase_ok(bad < 0 ? LONG_MAX : bad, "material point left the grid");
  });
}

// Each body's m_i^b and p_i^b beside the centre-of-mass fields (Paper III §C.2.7), from the
// weighting functions of the step.
template <int D>
template <class K>
void ExplicitSolver<D>::map_body_fields(const K& kernel) {
  timer_.time(Phase::BodyFields, [&] {
    const auto& P = state_.points;
    int count = 0;
    for (std::size_t p = 0; p < P.size(); ++p) count = std::max(count, P.body[p] + 1);
    count = static_cast<int>(state_.processes.max(static_cast<long>(count)));  // every process's bodies
    if (!contact_on() && bodies_.size() < static_cast<std::size_t>(count)) {
      bodies_.resize(static_cast<std::size_t>(count));
      for (auto& b : bodies_)
        if (b.mass.empty()) {
          b.mass.resize(fields_.size());
          b.momentum.resize(fields_.size());
        }
    }
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      BodyFields<D>& f = bodies_[b];
      for_box(grid(), body_box_, threads(), [&](std::size_t i) {
        f.mass[i] = 0.0;
        f.momentum[i].setZero();
      });
      p2g_body_mass_momentum(transfer_, kernel, P, static_cast<int>(b), f.mass.data(), f.momentum.data());
    }
    body_box_ = transfer_.box();
    if (contact_on()) clear_mass_momentum();  // unused with contact; keep them zero
  });
}

// fn(fields, points) for each continuum whose points the phase updates: the centre-of-mass
// fields and every point without contact; with contact each deformable body's own fields
// and points (Paper III §C.2.7). Rigid bodies have phases of their own (contact.cpp).
template <int D>
template <class Fn>
void ExplicitSolver<D>::for_each_continuum(Fn&& fn) {
  if (!contact_on()) {
    fn(static_cast<GridFields<D>&>(fields_), AllPoints{});
    return;
  }
  for (int b = 0; b < settings_.contact.bodies(); ++b)
    if (!settings_.contact.rigid[static_cast<std::size_t>(b)])
      fn(static_cast<GridFields<D>&>(bodies_[static_cast<std::size_t>(b)]),
         BodyPoints{state_.points.body.data(), b});
}

// The local damping's work (damping_work, positive where it takes energy), booked where the
// points take it: their FLIP velocity change holds d_p = sum N_ip d_i of the nodes' damping
// accelerations, so over the step's mean velocity v_p + dt/2 a_p the damping takes -m_p dt d_p .
// (v_p + dt/2 a_p) from their kinetic energy. (Booked at the nodes, m_i d_i . (v_i^k + dt/2 a_i),
// it counted the lumped mass of nodes that a point's GIMP domain barely reaches, where d_i is as
// large as f_i / m_i: on the Thesis fig. 4.7 cantilever that overstated it by 89 % of the gravity
// work.) A pass of its own, before the particle velocity update, so that the undamped phases keep
// their loops; it runs only in a damped stage.
template <int D>
template <class K, class Sel>
double ExplicitSolver<D>::damping_work_at_points(const K& kernel, const GridFields<D>& f, Sel sel) {
  const GridGeometry<D>& g = grid();
  const NodeStrides<D> strides = transfer_.strides();
  const auto& P = state_.points;
  const long n = static_cast<long>(P.size());
  const double dt = settings_.dt;
  const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
  const Vec<D>* __restrict acc = f.acceleration.data();
  const Vec<D>* __restrict damp = f.damping_acceleration.data();
  double work = 0.0;
#pragma omp parallel for num_threads(threads()) schedule(static) reduction(+ : work)
  for (long p = 0; p < n; ++p) {
    if (!sel(p)) continue;
    typename K::Shape sh;
    kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
    const Vec<D> a_p = gather(sh, strides, acc);
    work -= P.mass[p] * dt * gather(sh, strides, damp).dot(P.v[p] + (0.5 * dt) * a_p);
  }
  sum_points(work);
  return work;
}

// Thesis eq. 2.56: v_p^{k+1} = v_p + dt sum N_ip a_i (with a PIC share, if set), and the
// updated particle momenta mapped back to the grid, p~_i = sum N_ip m_p v_p^{k+1} (the double
// mapping of USL and the averaged scheme, step 6 of §4.4). With contact, each body from and
// into its own fields.
template <int D>
template <class K>
void ExplicitSolver<D>::velocity_and_remap(const K& kernel) {
  timer_.time(Phase::VelocityRemap, [&] {
    xpic_grid_velocity(kernel);
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    const double dt = settings_.dt;
    const double alpha = transfer_rule_.pic_share();
    const double w = transfer_rule_.loss_weight();  // particle_velocity
    ScatterBuffers<D>& buffers = transfer_.scatter();
    double lost = 0.0;  // to the transfer
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      if (local_damping_ > 0.0) state_.clock.energy.damping_work += damping_work_at_points(kernel, f, sel);
      // (the point arrays declared here, in the loop's own scope, keep their __restrict)
      const typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      Vec<D>* __restrict v = P.v.data();
      const double* __restrict pmass = P.mass.data();
      const Vec<D>* __restrict acc = f.acceleration.data();
      const Vec<D>* __restrict vnext = f.velocity_next.data();
      Mat<D>* const affine = transfer_rule_.carries_affine() ? P.affine.data() : nullptr;
      Vec<D>* const remap = f.momentum_remap.data();  // zero: see remap_velocity
      // One loop per transfer kind (an affine velocity or not), so the FLIP loop carries no affine branch.
      const auto loop = [&](auto apic_tag) {
        constexpr bool apic = decltype(apic_tag)::value;
#pragma omp parallel num_threads(threads()) reduction(+ : lost)
        {
          const int t = omp_get_thread_num();
          Vec<D>* __restrict mom = buffers.vec_target(t, remap);
          BaseSpan span;
#pragma omp for schedule(static) nowait
          for (long p = 0; p < n; ++p) {
            if (!sel(p)) continue;
            typename K::Shape sh;
            kernel.load(shape[p], g, P.x[p], P.half0[p], sh);
            if constexpr (apic)
              lost += affine_trial_energy(sh, g, strides, P.x[p], affine[p], acc, dt, pmass[p]);
            const Vec<D> vp =
                particle_velocity<K>(sh, g, strides, P.x[p], v[p], dt, gather(sh, strides, acc), vnext, alpha,
                                     apic ? affine + p : nullptr, pmass[p], w, lost);
            v[p] = vp;
            if constexpr (apic)  // APIC: the remap carries the affine velocity too
              scatter_affine(sh, g, strides, P.x[p], pmass[p], vp, affine[p], mom);
            else
              scatter(sh, strides, Vec<D>(pmass[p] * vp), mom);
            span.add(sh.base);
          }
          buffers.touched(t, span);
        }
      };
      if (affine)
        loop(std::true_type{});
      else
        loop(std::false_type{});
      transfer_.reduce(nullptr, remap);
    });
    sum_points(lost);
    state_.clock.energy.transfer_dissipation += lost;
    if (contact_on()) rigid_velocity();
  });
}

// Second half of USL / averaged (steps 7-8 of §4.4): strain increment from the remapped
// velocities v~_i, stress update (with F^{k+1} = dF F, eq. 3.2), then the position update
// x_p += dt sum N_ip (v_i^k + v_i^{k+1}) / 2 (eq. 2.55, Post eq. 31), and the next step's
// maps at x^{k+1} (eq. 2.53-2.54). With contact, each body from and into its own fields.
template <int D>
template <class K>
bool ExplicitSolver<D>::stress_update_move_and_map(const K& kernel, double dt_stress) {
  return timer_.time(Phase::StressUpdateMoveMap, [&] {
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    const double dt = settings_.dt;
    ScatterBuffers<D>& buffers = transfer_.scatter();
    long first_bad = LONG_MAX;
    Extent<D> all;  // of every moved point
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      // (the point arrays declared here, in the loop's own scope, keep their __restrict)
      typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      Vec<D>* __restrict x = P.x.data();
      const Vec<D>* __restrict v = P.v.data();
      const Vec<D>* __restrict half0 = P.half0.data();
      const double* __restrict pmass = P.mass.data();
      const StressArrays<D> S(P, state_.materials);
      const Vec<D>* __restrict vel = f.velocity_move.data();
      const Vec<D>* __restrict vnew = f.velocity_remap.data();  // v~_i
      const Mat<D>* const affine = transfer_rule_.carries_affine() ? P.affine.data() : nullptr;
      const bool averaging = settings_.volumetric_averaging;  // cell-averaged volumetric strain
      if (averaging) cell_divergence(kernel, vnew, sel);
      const VolumetricAveraging<D>& A = volumetric_;
      double work = 0.0, dissipation = 0.0, affine_ke = 0.0;
      Vec<D> mdx = Vec<D>::Zero();
      long bad = LONG_MAX;
      Extent<D> extent;  // of the moved points
#pragma omp parallel num_threads(threads()) reduction(+ : work, dissipation, affine_ke) reduction(vsum : mdx) \
    reduction(min : bad) reduction(merge : extent)
      {
        const int t = omp_get_thread_num();
        double* __restrict mass = buffers.mass_target(t, f.mass.data());
        Vec<D>* __restrict mom = buffers.vec_target(t, f.momentum.data());
        BaseSpan span;
#pragma omp for schedule(static) nowait
        for (long p = 0; p < n; ++p) {
          if (!sel(p)) continue;
          typename K::Shape sh;
          kernel.load(shape[p], g, x[p], half0[p], sh);
          Mat<D> grad_v = averaging ? A.grad[p] : gather_gradient(sh, strides, vnew);  // (cell_divergence's)
          const double corr = averaging ? A.correction(static_cast<std::size_t>(p)) : 0.0;
          if (averaging) grad_v.diagonal().array() += corr;
          const Vec<D> vmove = gather(sh, strides, vel);
          StressUpdateResult r;
          if constexpr (D == 2) {
            if (S.hoop)  // axisymmetric: with the hoop rate v_r / r at x^k
              r = S.update_axisymmetric(
                  p, grad_v, (averaging ? A.hoop_rate[p] : gather(sh, strides, vnew)[0] / x[p][0]) + corr,
                  dt_stress);
            else
              r = S.update(p, grad_v, dt_stress);
          } else {
            r = S.update(p, grad_v, dt_stress);
          }
          work += r.strain_energy;
          dissipation += r.dissipation;
          mdx += pmass[p] * dt * vmove;
          if (!sound_point(r, S.stress[p]) || !move_point<D>(g, walls_, x[p], Vec<D>(dt * vmove), v[p]) ||
              !map_point(kernel, g, strides, x[p], half0[p], S.F[p], pmass[p], v[p], shape[p], mass, mom,
                         span, affine ? affine + p : nullptr, affine ? &affine_ke : nullptr))
            bad = std::min(bad, p);
          extent.add(x[p]);
        }
        buffers.touched(t, span);
      }
      reduce_moved(extent, f);
      sum_points(work, dissipation, affine_ke, mdx);
      state_.clock.energy.strain_energy += work;
      state_.clock.energy.plastic_dissipation += dissipation;
      state_.clock.energy.transfer_dissipation -= affine_ke;  // the new C_p's share (particle_velocity)
      state_.clock.energy.gravity_work += gravity_now_.dot(mdx);
      first_bad = std::min(first_bad, bad);
      all.merge(extent);
    });
    if (contact_on()) first_bad = std::min(first_bad, move_and_map_rigid(kernel, all));
    set_next_box(all);
    return phase_ok(first_bad, "material point became unstable or left the grid");
  });
}

// USF's last phase: v_p^{k+1} (eq. 2.56), x_p^{k+1} (eq. 2.55, Post eq. 31) and the next
// step's maps at x^{k+1} (eq. 2.53-2.54). With contact, each body from and into its own
// fields.
template <int D>
template <class K>
bool ExplicitSolver<D>::velocity_move_and_map(const K& kernel) {
  return timer_.time(Phase::VelocityMoveMap, [&] {
    // m_i and p_i of this step are used up: the next step's map (XPIC first reads them)
    xpic_grid_velocity(kernel);
    if (contact_on())
      clear_body_mass_momentum();
    else
      clear_mass_momentum();
    const GridGeometry<D>& g = grid();
    const NodeStrides<D> strides = transfer_.strides();
    auto& P = state_.points;
    const long n = static_cast<long>(P.size());
    const double dt = settings_.dt;
    const double alpha = transfer_rule_.pic_share(), w = transfer_rule_.loss_weight();  // particle_velocity
    ScatterBuffers<D>& buffers = transfer_.scatter();
    long first_bad = LONG_MAX;
    double lost = 0.0;  // to the transfer
    Extent<D> all;      // of every moved point
    for_each_continuum([&](GridFields<D>& f, auto sel) {
      if (local_damping_ > 0.0) state_.clock.energy.damping_work += damping_work_at_points(kernel, f, sel);
      // (the point arrays declared here, in the loop's own scope, keep their __restrict)
      typename K::Packed* __restrict shape = transfer_.weights().template get<K>(P.size());
      Vec<D>* __restrict x = P.x.data();
      Vec<D>* __restrict v = P.v.data();
      const Vec<D>* __restrict half0 = P.half0.data();
      const double* __restrict pmass = P.mass.data();
      const Mat<D>* __restrict F = P.F.data();
      const Vec<D>* __restrict acc = f.acceleration.data();
      const Vec<D>* __restrict vel = f.velocity_move.data();
      const Vec<D>* __restrict vnext = f.velocity_next.data();
      const Vec<D>* __restrict stopped = f.stopped_acceleration.data();
      const bool from_flip = transfer_rule_.update_from_flip();
      const std::array<bool, 2 * D> stopping = stopping_walls_;
      Mat<D>* const affine = transfer_rule_.carries_affine() ? P.affine.data() : nullptr;
      Vec<D> mdx = Vec<D>::Zero();
      long bad = LONG_MAX;
      double affine_ke = 0.0;  // the new C_p's share of the kinetic energy (particle_velocity)
      Extent<D> extent;        // of the moved points
#pragma omp parallel num_threads(threads()) reduction(vsum : mdx) reduction(min : bad) \
    reduction(merge : extent) reduction(+ : lost, affine_ke)
      {
        const int t = omp_get_thread_num();
        double* __restrict mass = buffers.mass_target(t, f.mass.data());
        Vec<D>* __restrict mom = buffers.vec_target(t, f.momentum.data());
        BaseSpan span;
        SizeAhead<D, K> ahead;  // F is not changed here: the next point's size is formed ahead
        const double* const det_f = det_f_fresh_ ? det_f_.data() : nullptr;
#pragma omp for schedule(static) nowait
        for (long p = 0; p < n; ++p) {
          if (!sel(p)) continue;
          const auto size = ahead.take(kernel, g, half0, F, det_f, p, n);
          if constexpr (D == 3)  // the cache lines of a point 16 ahead (docs/method.md, "Prefetches")
            if (p + kMoveAhead < n) {
              const char* w = reinterpret_cast<const char*>(shape + p + kMoveAhead);
              __builtin_prefetch(w);
              __builtin_prefetch(w + 64);
              __builtin_prefetch(x + p + kMoveAhead);
              __builtin_prefetch(v + p + kMoveAhead);
            }
          typename K::Shape sh;
          kernel.load(shape[p], g, x[p], half0[p], sh);
          Vec<D> acc_p, vmove;
          gather_pair(sh, strides, acc, vel, acc_p, vmove);
          if (affine) lost += affine_trial_energy(sh, g, strides, x[p], affine[p], acc, dt, pmass[p]);
          const Vec<D> vp = particle_velocity<K>(sh, g, strides, x[p], v[p], dt, acc_p, vnext, alpha,
                                                 affine ? affine + p : nullptr, pmass[p], w, lost);
          if (std::array<unsigned, D> layers;
              const unsigned near = near_stopping_sides<K::S>(g.h, walls_, stopping, x[p]))
            if (boundaries_.template block_layers<K::S>(sh.base, near, layers))
              lost += wall_update_loss(sh, strides, stopped, layers, dt, pmass[p], from_flip, acc_p, vp);
          v[p] = vp;
          mdx += pmass[p] * dt * vmove;
          if (!move_point<D>(g, walls_, x[p], Vec<D>(dt * vmove), vp) ||
              !map_point(kernel, g, strides, x[p], size, F[p], pmass[p], vp, shape[p], mass, mom, span,
                         affine ? affine + p : nullptr, affine ? &affine_ke : nullptr))
            bad = std::min(bad, p);
          extent.add(x[p]);
        }
        buffers.touched(t, span);
      }
      reduce_moved(extent, f);
      sum_points(mdx);  // (lost, with affine_ke, is summed after the loop)
      state_.clock.energy.gravity_work += gravity_now_.dot(mdx);
      lost -= affine_ke;
      first_bad = std::min(first_bad, bad);
      all.merge(extent);
    });
    sum_points(lost);
    state_.clock.energy.transfer_dissipation += lost;
    if (contact_on()) {
      rigid_velocity();
      first_bad = std::min(first_bad, move_and_map_rigid(kernel, all));
    }
    set_next_box(all);
    return phase_ok(first_bad, "material point became unstable or left the grid");
  });
}

// XPIC(m) (Hammerquist & Nairn 2017): the points take sum N_ip (v_i^{k+1} - p_i / m_i + v*_i),
// i.e. FLIP without the part of v_p^k the grid cannot represent; under the velocity conditions.
// With contact, each deformable body's v* from its own m_i^b, p_i^b and points, and its
// accelerations after the contact phase (Paper III §C.2.7).
template <int D>
template <class K>
void ExplicitSolver<D>::xpic_grid_velocity(const K& kernel) {
  if (!transfer_rule_.filters()) return;
  const double dt = settings_.dt;
  for_each_continuum([&](GridFields<D>& f, auto sel) {
    Vec<D>* const star = f.velocity_next.data();  // v*_i, then v_i^{k+1} - p_i / m_i + v*_i in place
    xpic_velocity(transfer_, kernel, state_.points, f.mass.data(), f.momentum.data(),
                  transfer_rule_.xpic_order(), star, fields_.xpic_work.data(), sel);
    const Vec<D>* __restrict acc = f.acceleration.data();
    transfer_.for_box([&](std::size_t i) { star[i] += dt * acc[i]; });
    boundaries_.constrain_velocity(f.velocity_next, transfer_.box());
  });
}

}  // namespace skred

#include "solver/contact_impl.hpp"       // the kernel-templated phases of contact runs
#include "solver/stress_phase_impl.hpp"  // the stress phase and the USL force map
#include "solver/volumetric_averaging_impl.hpp"
