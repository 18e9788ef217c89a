// The phases of one implicit step (implicit_solver.hpp): the map at x^k, Newton-Raphson with its
// line search, and the commit. The out-of-balance force and the tangent of an iterate are in
// equilibrium.cpp, the box a process holds across processes in across_processes.cpp.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/SVD>
#include <type_traits>

#include "implicit/implicit_solver.hpp"
#include "implicit/strain_matrix.hpp"
#include "material/law.hpp"
#include "solver/gravity.hpp"
#include "solver/process_sums.hpp"

namespace skred {

// m_i = sum_p N_ip m_p (eq. 43) on the step's grid.
template <int D>
void ImplicitSolver<D>::lumped_masses() {
  const std::size_t n = state_.points.size();
  const int K = stencils_.K;
  if (!state_.processes.distributed()) grid_mass_.assign(state_.grid.node_count(), 0.0);
  double* gm = grid_mass_.data();
  if (state_.processes.distributed())  // (the box: its nodes alone are written; clear_scratch)
    for_box(state_.grid, boxes_.own_box(), state_.threads, [&](std::size_t i) { gm[i] = 0.0; });
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
#pragma omp atomic
      gm[stencils_.node[p * K + k]] += stencils_.N[p * K + k] * state_.points.mass[p];
    }
  if (state_.processes.distributed())  // every process's points, in the box
    boxes_.sum(
        1, [&](std::size_t i, double* at) { at[0] = gm[i]; },
        [&](std::size_t i, const double* at) { gm[i] = at[0]; });
}

// The step's map (Acosta §2.1, eq. 43-44): the points' weights at x^k, the lumped masses
// m_i = sum_p N_ip m_p, the velocities v_i = sum_p N_ip m_p v_p / m_i and accelerations a_i
// likewise, the unknowns (every node with mass, D each) and the matrix pattern.
template <int D>
StepStatus ImplicitSolver<D>::map_step() {
  const GridGeometry<D>& g = state_.grid;
  long bad = -1;
  with_kernel<D>(state_.interpolation, state_.quadrature_points, [&](const auto& kernel) {
    width_ = std::decay_t<decltype(kernel)>::StencilT::width;
    bad = stencils_.build(kernel, g, state_.points, state_.threads);
  });
  bad = agreed_point(bad);
  if (bad >= 0) return {false, bad, "a point left the grid"};
  const std::size_t n = state_.points.size();
  BoxExchange<D>* boxes = nullptr;
  if (state_.processes.distributed()) {
    set_box();
    clear_scratch();
    boxes = &boxes_;
  }
  lumped_masses();
  // A node with a sliver of mass (below min_node_fill of a full node's, rho h^D; axisymmetric,
  // per radian, times r_i, h / 6 on the axis), which a point's domain grown with det F or moved
  // across a cell lends it, hands its weights to its neighbours (point_stencils.hpp).
  double rho_max = 0.0;
  for (std::size_t p = 0; p < n; ++p)
    rho_max = std::max(rho_max, state_.points.mass[p] / state_.points.volume(p));
  state_.processes.max(&rho_max, 1);
  const double m_min = settings_.min_node_fill * rho_max * std::pow(g.h, D);
  bool any = false;
  const auto mark_sliver = [&](std::size_t i) {
    const double r = axisymmetric() ? std::max(g.node_position(i)[0], g.h / 6.0) : 1.0;
    sliver_[i] = grid_mass_[i] > 0.0 && grid_mass_[i] < m_min * r;
    any = any || sliver_[i];
  };
  const auto drop_sliver = [&](std::size_t i) {
    if (sliver_[i]) grid_mass_[i] = 0.0;
  };
  if (state_.processes.distributed()) {  // (in the box; one thread: `any`)
    for_box(g, boxes_.own_box(), 1, mark_sliver);
    any = state_.processes.any(any);  // (the masses are collective)
  } else {
    sliver_.assign(g.node_count(), 0);
    for (std::size_t i = 0; i < grid_mass_.size(); ++i) mark_sliver(i);
  }
  if (any) {
    stencils_.aggregate_slivers(g, state_.points, sliver_, state_.threads);
    lumped_masses();
    // What is left on a sliver (a point whose nodes are all slivers) is no unknown.
    if (state_.processes.distributed())
      for_box(g, boxes_.own_box(), state_.threads, drop_sliver);
    else
      for (std::size_t i = 0; i < grid_mass_.size(); ++i) drop_sliver(i);
  }
  volume_.resize(n);
  for (std::size_t p = 0; p < n; ++p) volume_[p] = state_.points.volume(p);
  inv_r_.clear();
  if (axisymmetric()) {
    inv_r_.resize(n);
    for (std::size_t p = 0; p < n; ++p) inv_r_[p] = 1.0 / state_.points.x[p][0];
  }
  held_components();
  if (!settings_.at_points()) {
    const long wide =
        agreed_point(mapped_.build(settings_.integration, settings_.stress_recovery, stencils_, g,
                                   state_.points, volume_, inv_r_, grid_mass_, state_.threads, boxes));
    if (wide >= 0) return {false, wide, "its stencil spreads beyond the 4 nodes per axis around its cell"};
    mapped_.trim(g, state_.threads, state_.processes);
    // Acosta's stiffness (eq. 19-20) couples the corners of a cell only: its pattern is the
    // cells' (as narrow as linear MPM's), unless a node with mass lies in no mapped cell (of any
    // process: the pattern is their union).
    cell_pattern_ = settings_.iteration != ImplicitIteration::Newton && mapped_.gauss_points;
    if (cell_pattern_) {
      mapped_cells(cell_blocks_);
      dofs_.build(cell_blocks_.data(), cell_blocks_.size() / MappedStencils<D>::KG, 2, 2, g, grid_mass_,
                  grid_held_, state_.threads, boxes);
      cell_pattern_ = dofs_.every_node_coupled_to_itself();
    }
    if (!cell_pattern_)
      dofs_.build(mapped_.box.data(), n, mapped_.width, mapped_.width, g, grid_mass_, grid_held_,
                  state_.threads, boxes);
  } else if (averaging()) {
    const long wide = agreed_point(
        cells_.build(stencils_, width_, g, state_.points, volume_, inv_r_, state_.threads, boxes));
    if (wide >= 0)
      return {false, wide, "its stencil spreads beyond its cell's box (cell-averaged volumetric strain)"};
    // (across processes: the boxes of the cells this process's points are in)
    dofs_.build(cells_.node.data(), static_cast<std::size_t>(cells_.cells()), cells_.S, width_, g, grid_mass_,
                grid_held_, state_.threads, boxes);
  } else {
    dofs_.build(stencils_.node.data(), n, width_, width_, g, grid_mass_, grid_held_, state_.threads, boxes);
  }
  const std::size_t dofs = static_cast<std::size_t>(dofs_.dofs());
  totals_.max_unknowns = std::max(totals_.max_unknowns, D * dofs_.global_nodes());
  mass_.resize(dofs);
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) mass_[a * D + c] = grid_mass_[static_cast<std::size_t>(dofs_.node(a))];
  held_force_.assign(dofs, 0.0);
  prescribed_id_.assign(grid_prescribed_.empty() ? 0 : dofs_.active_nodes(), -1);
  driven_.assign(prescribed_id_.size(), 0);
  for (std::size_t a = 0; a < prescribed_id_.size(); ++a) {
    prescribed_id_[a] =
        static_cast<std::int8_t>(grid_prescribed_[static_cast<std::size_t>(dofs_.node(a))] - 1);
    driven_[a] = grid_driven_[static_cast<std::size_t>(dofs_.node(a))];
  }
  if (state_.processes.distributed()) {
    const GlobalRows rows = dofs_.global_rows();
    system_.set_pattern(dofs_.pattern(), &rows);
    needed_rows();
  } else {
    system_.set_pattern(dofs_.pattern());
  }
  if (settings_.linear_solver == LinearSolverKind::Iterative) {
    std::vector<double>& xyz = trial_du_;  // (scratch until the iterations start)
    xyz.resize(dofs);
    for (std::size_t a = 0; a < dofs_.active_nodes(); ++a) {
      const Vec<D> x = g.node_position(static_cast<std::size_t>(dofs_.node(a)));
      for (int c = 0; c < D; ++c) xyz[a * D + c] = x[c];
    }
    system_.set_coordinates(xyz);
  }
  if (!dynamic()) return {};
  bool start = state_.points.acceleration.size() != n;
  if (state_.processes.distributed()) start = state_.processes.any(start);  // (collective sums)
  if (start) initial_acceleration();
  v_bar_.assign(dofs, 0.0);
  a_bar_.assign(dofs, 0.0);
  double *vb = v_bar_.data(), *ab = a_bar_.data();
  const int K = stencils_.K;
#pragma omp parallel for num_threads(state_.threads) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const double wm = stencils_.N[p * K + k] * state_.points.mass[p];
      for (int c = 0; c < D; ++c) {
#pragma omp atomic
        vb[a * D + c] += wm * state_.points.v[p][c];
#pragma omp atomic
        ab[a * D + c] += wm * state_.points.acceleration[p][c];
      }
    }
  sum_in_boxes(v_bar_);
  sum_in_boxes(a_bar_);
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) {
      const std::size_t i = a * D + c;
      v_bar_[i] = dofs_.held(a, c) ? 0.0 : v_bar_[i] / mass_[i];
      a_bar_[i] = dofs_.held(a, c) ? 0.0 : a_bar_[i] / mass_[i];
    }
  return {};
}

// The components each node with mass has held (Dirichlet conditions): every one on or beyond a
// fixed wall, the normal one on or beyond a roller wall (and a frictional one, which the
// implicit integrator does not model: the scenario refuses it), in axisymmetric geometry the
// radial one on the axis r = 0 (all these with du = 0), and those of a [[prescribed_velocity]]
// box (du = v dt).
template <int D>
void ImplicitSolver<D>::held_components() {
  const GridGeometry<D>& g = state_.grid;
  if (!state_.processes.distributed()) {  // (across processes: clear_scratch)
    grid_held_.assign(g.node_count(), 0);
    grid_prescribed_.assign(model_.prescribed.empty() ? 0 : g.node_count(), 0);
    grid_driven_.assign(grid_prescribed_.size(), 0);
  }
  const double tol = 1e-9 * g.h;
  const Vec<D> hi = g.origin + g.extent();
  const auto hold = [&](std::size_t i) {
    if (grid_mass_[i] <= 0.0) return;
    const Vec<D> x = g.node_position(i);
    std::uint8_t bits = 0;
    for (int d = 0; d < D; ++d)
      for (int side = 0; side < 2; ++side) {
        const BoundaryKind kind = model_.boundaries[static_cast<std::size_t>(2 * d + side)].kind;
        if (kind == BoundaryKind::Free) continue;
        const bool beyond = side == 0 ? x[d] <= g.origin[d] + tol : x[d] >= hi[d] - tol;
        if (!beyond) continue;
        bits |= kind == BoundaryKind::Fixed ? std::uint8_t((1u << D) - 1) : std::uint8_t(1u << d);
      }
    if (axisymmetric() && x[0] <= tol) bits |= 1u;
    // The first [[prescribed_velocity]] box that holds the node drives its components that no
    // wall holds.
    for (std::size_t b = 0; b < model_.prescribed.size(); ++b) {
      const PrescribedVelocity& pv = model_.prescribed[b];
      bool in = true;
      for (int d = 0; d < D; ++d)
        in = in && x[d] >= pv.min[static_cast<std::size_t>(d)] - tol &&
             x[d] <= pv.max[static_cast<std::size_t>(d)] + tol;
      if (!in) continue;
      grid_prescribed_[i] = static_cast<std::int8_t>(b + 1);
      grid_driven_[i] = static_cast<std::uint8_t>(pv.components & ~bits);
      bits |= pv.components;
      break;
    }
    grid_held_[i] = bits;
  };
  if (state_.processes.distributed())
    for_box(g, boxes_.own_box(), state_.threads, hold);
  else
    for (std::size_t i = 0; i < grid_held_.size(); ++i) hold(i);
}

// Newton-Raphson on du for one step of dt (Acosta §2, App. B): false, with the reason, when it
// does not converge within max_iterations (the caller cuts the step).
template <int D>
bool ImplicitSolver<D>::solve_step(double dt, std::string& why) {
  const std::size_t dofs = static_cast<std::size_t>(dofs_.dofs());
  const bool single = settings_.iteration == ImplicitIteration::Single;
  const bool elastic = settings_.iteration == ImplicitIteration::Elastic || single;
  history_.clear();
  external_forces(state_.clock.time + dt, f_ext_);
  du_.assign(dofs, 0.0);
  for (std::size_t a = 0; a < prescribed_id_.size(); ++a)  // du = v dt on the driven components
    if (prescribed_id_[a] >= 0)
      for (int c = 0; c < D; ++c)
        if ((driven_[a] >> c) & 1u)
          du_[a * D + c] = model_.prescribed[static_cast<std::size_t>(prescribed_id_[a])].velocity[c] * dt;
  double rn = residual(du_, dt, !elastic);
  // The force scale: the largest of |F_ext|, |F_int(sigma^k)| with the supports' forces, and the
  // inertial force of du = 0.
  {  // (R and the supports' forces are right in the owned rows: sums over those, then the processes)
    double sums[2] = {0.0, 0.0};  // |F_int|^2 with the supports' forces, |inertia|^2
    const std::size_t first = D * dofs_.first_node(), end = D * dofs_.end_node();
    for (std::size_t i = first; i < end; ++i) sums[0] += held_force_[i] * held_force_[i];
    const double c1 = 4.0 / dt;
    for (std::size_t i = first; i < end; ++i) {
      const double in = dynamic() ? mass_[i] * (c1 * v_bar_[i] + a_bar_[i]) : 0.0;
      const double fi = f_ext_[i] - r_[i] + in;
      sums[0] += fi * fi;
      sums[1] += in * in;
    }
    state_.processes.sum(sums, 2);
    force_scale_ = std::max({owned_norm(f_ext_), std::sqrt(sums[0]), std::sqrt(sums[1])});
    if (!(force_scale_ > 0.0)) force_scale_ = 1.0;
  }
  const double tol = settings_.residual_tolerance * force_scale_;
  history_.push_back(rn / force_scale_);
  report_.iterations = 0;
  report_.residual = rn / force_scale_;
  if (rn <= tol) return true;
  if (elastic) {
    timer_.time(ImplicitPhase::Assembly, [&] { assemble(dt, true); });
    timer_.time(ImplicitPhase::Factorisation, [&] { system_.factorise(); });
    ++totals_.factorisations;
  }
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    if (!elastic) {
      timer_.time(ImplicitPhase::Assembly, [&] { assemble(dt, false); });
      timer_.time(ImplicitPhase::Factorisation, [&] { system_.factorise(); });
      ++totals_.factorisations;
    }
    totals_.max_factor_bytes = std::max(totals_.max_factor_bytes, system_.factor_bytes());
    bool solved = timer_.time(ImplicitPhase::Solve, [&] { return system_.solve(r_, ddu_); });
    if (!solved && !elastic) {
      // A singular consistent tangent (perfectly plastic points at a corner of their yield
      // surface keep only the volumetric stiffness, which the cell average shares out): this
      // iteration takes the elastic matrix, Acosta's, which is regular.
      timer_.time(ImplicitPhase::Assembly, [&] { assemble(dt, true); });
      timer_.time(ImplicitPhase::Factorisation, [&] { system_.factorise(); });
      ++totals_.factorisations;
      ++totals_.elastic_fallbacks;
      solved = timer_.time(ImplicitPhase::Solve, [&] { return system_.solve(r_, ddu_); });
    }
    if (!solved) {
      why = system_.reason();
      return false;
    }
    // Backtracking line search on |R| (Newton only): the first of 1, 1/2, ... 1/64 that lowers
    // |R| enough, else the full step.
    double alpha = 1.0, r_new = 0.0;
    const bool search = settings_.line_search && !elastic;
    for (int cut = 0;; ++cut) {
      trial_du_ = du_;
      for (std::size_t i = 0; i < dofs; ++i) trial_du_[i] += alpha * ddu_[i];
      r_new = residual(trial_du_, dt, !elastic);
      if (!search || r_new <= (1.0 - 1e-4 * alpha) * rn) break;
      if (cut == 6) {
        alpha = 1.0;
        for (std::size_t i = 0; i < dofs; ++i) trial_du_[i] = du_[i] + ddu_[i];
        r_new = residual(trial_du_, dt, !elastic);
        break;
      }
      alpha *= 0.5;
    }
    du_.swap(trial_du_);
    rn = r_new;
    history_.push_back(rn / force_scale_);
    report_.iterations = it;
    report_.residual = rn / force_scale_;
    if (!std::isfinite(rn)) {
      why = "the out-of-balance force became non-finite";
      return false;
    }
    if (single || rn <= tol || alpha * owned_norm(ddu_) <= settings_.displacement_tolerance * owned_norm(du_))
      return within_a_cell(why);
    if (rn > 1e12 * force_scale_) break;  // diverging
  }
  why = fmt::format("the out-of-balance force stayed at {:.3g} of the force scale after {} iterations",
                    rn / force_scale_, report_.iterations);
  return false;
}

// A converged increment that moves a node by more than a cell is refused (the step is cut): the
// step's stencils, taken at x^k, no longer describe the points, and a perfectly plastic body can
// offer such a solution along a spurious mechanism of the discretisation.
template <int D>
bool ImplicitSolver<D>::within_a_cell(std::string& why) const {
  double largest = 0.0;  // (over the owned nodes, then the processes)
  for (std::size_t a = dofs_.first_node(); a < dofs_.end_node(); ++a) {
    const Eigen::Map<const Vec<D>> u(&du_[a * D]);
    largest = std::max(largest, u.norm());
  }
  state_.processes.max(&largest, 1);
  if (largest <= state_.grid.h) return true;
  why = fmt::format("the converged increment moves a node by {:.3g} m, more than a cell ({:.3g} m)", largest,
                    state_.grid.h);
  return false;
}

// The points' acceleration at the start of a dynamic stage, a_i = (F_ext - F_int) / m_i on
// the step's grid, so that Newmark starts from the equilibrium of eq. 3 at t.
template <int D>
void ImplicitSolver<D>::initial_acceleration() {
  const std::size_t n = state_.points.size();
  const int K = stencils_.K;
  v_bar_.clear();  // residual() without inertia
  external_forces(state_.clock.time, f_ext_);
  du_.assign(static_cast<std::size_t>(dofs_.dofs()), 0.0);
  residual(du_, 1.0, false);
  state_.points.acceleration.assign(n, Vec<D>::Zero());
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      for (int c = 0; c < D; ++c)
        state_.points.acceleration[p][c] += stencils_.N[p * K + k] * r_[static_cast<std::size_t>(a) * D + c] /
                                            mass_[static_cast<std::size_t>(a) * D + c];
    }
}

// After convergence (eq. 41-42 and the kinematics of the explicit update, Thesis eq. 3.2):
// the laws' stresses rotated by the rotation of dF = I + sum du_i (x) grad N_i, their states, F <- dF F,
// Fe <- (I + d_eps - d_eps_p) Fe, x_p += sum N_ip du_i; dynamic: a_i = 4 du / dt^2 - 4 v_i / dt
// - a_i (eq. 42), a_p = sum N_ip a_i, v_p += dt/2 (a_p^t + a_p^{t+dt}) (eq. 41, whose printed form
// omits the dt); quasi-static: v_p = 0. The energies follow Thesis eq. 4.16 and 5.13.
template <int D>
void ImplicitSolver<D>::commit_step(double dt) {
  const std::size_t n = state_.points.size();
  const int K = stencils_.K;
  const bool dyn = dynamic(), axi = axisymmetric();
  std::vector<double>& a_new = ddu_;  // (free after the last iteration)
  if (dyn) {
    a_new.assign(du_.size(), 0.0);
    for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
      for (int c = 0; c < D; ++c) {
        const std::size_t i = a * D + c;
        if (!dofs_.held(a, c)) a_new[i] = 4.0 / (dt * dt) * du_[i] - 4.0 / dt * v_bar_[i] - a_bar_[i];
      }
  }
  store_internal_force(dt);
  if (axi && state_.points.hoop.size() != n) state_.points.hoop.assign(n, 1.0);
  const Vec<D> g_mid = 0.5 * (gravity_at(model_.gravity, state_.clock.gravity_ramp_time,
                                         state_.clock.time - state_.clock.ramp_start) +
                              gravity_at(model_.gravity, state_.clock.gravity_ramp_time,
                                         state_.clock.time + dt - state_.clock.ramp_start));
  double strain = 0.0, plastic = 0.0, gravity = 0.0;
#pragma omp parallel for num_threads(state_.threads) schedule(static) reduction(+ : strain, plastic, gravity)
  for (std::size_t p = 0; p < n; ++p) {
    Vec<D> dx = Vec<D>::Zero(), acc = Vec<D>::Zero();
    Mat<D> grad = Mat<D>::Zero();
    double u_r = 0.0;
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const Eigen::Map<const Vec<D>> u(&du_[static_cast<std::size_t>(a) * D]);
      const double N = stencils_.N[p * K + k];
      dx += N * u;
      grad += u * stencils_.dN[p * K + k].transpose();
      u_r += N * u[0];
      if (dyn) acc += N * Eigen::Map<const Vec<D>>(&a_new[static_cast<std::size_t>(a) * D]);
    }
    const Sym3 before = full_stress<D>(state_.points.stress[p]);
    const Sym3& after = trial_stress_[p];
    const Sym3 mid = 0.5 * volume_[p] * (before + after);
    strain += contract(mid, deps_[p] - trial_plastic_[p]);
    plastic += contract(mid, trial_plastic_[p]);
    gravity += state_.points.mass[p] * g_mid.dot(dx);
    // With the cell-averaged volumetric strain, dF takes the strain's correction too.
    const double corr = averaging() ? vol_corr_[p] : 0.0;
    const Mat<D> dF = Mat<D>::Identity() + grad + corr * Mat<D>::Identity();
    Mat3 dF3 = embed3<D>(dF, 1.0);
    if constexpr (D == 2)
      if (axi) dF3(2, 2) = 1.0 + u_r * inv_r_[p] + corr;  // hoop stretch r^{k+1} / r^k
    // The law's stress rotated with the material, R S R^T, R the rotation of dF = R U (polar
    // decomposition): Acosta's incremental update made objective. (The explicit update, Thesis
    // eq. 4.4, pushes forward by all of dF, which also scales the stress by the stretch: an
    // O(strain) difference that the small-strain references, R6, would see.)
    const Eigen::JacobiSVD<Mat3> svd(dF3, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3 R = svd.matrixU() * svd.matrixV().transpose();
    state_.points.stress[p] = stored_stress<D>(to_voigt(R * to_matrix(after) * R.transpose()));
    state_.points.state[p] = trial_state_[p];
    state_.points.F[p] = dF * state_.points.F[p];
    if (!state_.points.Fe.empty())  // tracked for the frames that hold Fe, Fp or stress_from_Fe
      state_.points.Fe[p] =
          (Mat<D>::Identity() + sym_block<D>(Sym3(deps_[p] - trial_plastic_[p]))) * state_.points.Fe[p];
    if (axi) state_.points.hoop[p] *= dF3(2, 2);
    state_.points.x[p] += dx;
    if (dyn) {
      state_.points.v[p] += 0.5 * dt * (state_.points.acceleration[p] + acc);  // eq. 41
      state_.points.acceleration[p] = acc;
    } else {
      state_.points.v[p].setZero();
    }
  }
  // The pressures' work, trapezoidal over the step (their forces at t and t + dt).
  if (!model_.pressures.empty()) {
    std::vector<double> f0(du_.size(), 0.0), f1(du_.size(), 0.0);
    pressure_forces(state_.clock.time, f0);
    pressure_forces(state_.clock.time + dt, f1);
    sum_in_boxes(f0);
    sum_in_boxes(f1);
    double w = 0.0;  // (over the owned nodes, then the processes)
    for (std::size_t a = dofs_.first_node(); a < dofs_.end_node(); ++a)
      for (int c = 0; c < D; ++c)
        if (!dofs_.held(a, c)) w += 0.5 * (f0[a * D + c] + f1[a * D + c]) * du_[a * D + c];
    state_.processes.sum(&w, 1);
    state_.clock.energy.load_work += w;
  }
  sum_over_processes(state_.processes, strain, plastic, gravity);
  state_.clock.energy.strain_energy += strain;
  state_.clock.energy.plastic_dissipation += plastic;
  state_.clock.energy.gravity_work += gravity;
  commit_boundary_forces(dt);
}

// F_int of the last residual (eq. 7), for the grid frames' |F_int| (eq. 26): F_ext - R with the
// held rows' support forces and, dynamic, the inertia of du.
// Across processes each forms its owned rows' and the processes whose boxes hold a node add them
// up (the grid frames read every node of a box).
template <int D>
void ImplicitSolver<D>::store_internal_force(double dt) {
  const bool inertia = dynamic() && !v_bar_.empty();
  f_int_.assign(du_.size(), 0.0);
  for (std::size_t a = dofs_.first_node(); a < dofs_.end_node(); ++a)
    for (int c = 0; c < D; ++c) {
      const std::size_t i = a * D + c;
      const double R = dofs_.held(a, c) ? -held_force_[i] : r_[i];
      const double m =
          inertia ? mass_[i] * (4.0 / (dt * dt) * du_[i] - 4.0 / dt * v_bar_[i] - a_bar_[i]) : 0.0;
      f_int_[i] = f_ext_[i] - R - m;
    }
  sum_in_boxes(f_int_);
}

// The prescribed velocities' forces on the material at t + dt (the sums of the supports' forces
// -R on their driven components) and their work, trapezoidal over the step, into load_work.
template <int D>
void ImplicitSolver<D>::commit_boundary_forces(double dt) {
  if (model_.prescribed.empty()) return;
  BoundaryForces f{};
  for (std::size_t a = dofs_.first_node(); a < std::min(dofs_.end_node(), prescribed_id_.size()); ++a)
    if (prescribed_id_[a] >= 0)  // (the owned nodes: there the supports' forces are right)
      for (int c = 0; c < D; ++c)
        if ((driven_[a] >> c) & 1u)
          f[static_cast<std::size_t>(3 * prescribed_id_[a] + c)] += held_force_[a * D + c];
  state_.processes.sum(f.data(), f.size());
  for (std::size_t b = 0; b < model_.prescribed.size(); ++b)
    for (int c = 0; c < D; ++c) {
      const std::size_t k = 3 * b + static_cast<std::size_t>(c);
      state_.clock.energy.load_work +=
          0.5 * (state_.clock.boundary_force[k] + f[k]) * model_.prescribed[b].velocity[c] * dt;
    }
  state_.clock.boundary_force = f;
}

#define SKRED_IMPLICIT_STEP(D)                                       \
  template StepStatus ImplicitSolver<D>::map_step();                 \
  template void ImplicitSolver<D>::held_components();                \
  template bool ImplicitSolver<D>::solve_step(double, std::string&); \
  template void ImplicitSolver<D>::initial_acceleration();           \
  template void ImplicitSolver<D>::commit_step(double);              \
  template void ImplicitSolver<D>::commit_boundary_forces(double);   \
  template void ImplicitSolver<D>::store_internal_force(double);     \
  template bool ImplicitSolver<D>::within_a_cell(std::string&) const;

SKRED_IMPLICIT_STEP(2)
SKRED_IMPLICIT_STEP(3)
#undef SKRED_IMPLICIT_STEP

}  // namespace skred
