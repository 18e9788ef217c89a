// The phases of one implicit step (implicit_solver.hpp): the map at x^k, the out-of-balance
// force and the tangent of an iterate, Newton-Raphson with its line search, and the commit.
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

namespace skred {

namespace {

double norm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

}  // namespace

// The step's map (Acosta §2.1, eq. 43-44): the points' weights at x^k, the lumped masses
// m_i = sum_p N_ip m_p, the velocities v_i = sum_p N_ip m_p v_p / m_i and accelerations a_i
// likewise, the unknowns (every node with mass, D each) and the matrix pattern.
template <int D>
StepStatus ImplicitSolver<D>::map_step() {
  const GridGeometry<D>& g = model_.grid;
  long bad = -1;
  with_kernel<D>(model_.interpolation, model_.quadrature_points, [&](const auto& kernel) {
    width_ = std::decay_t<decltype(kernel)>::StencilT::width;
    bad = stencils_.build(kernel, g, P_, threads_);
  });
  if (bad >= 0) return {false, bad, "a point left the grid"};
  const std::size_t n = P_.size();
  const int K = stencils_.K;
  grid_mass_.assign(g.node_count(), 0.0);
  double* gm = grid_mass_.data();
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
#pragma omp atomic
      gm[stencils_.node[p * K + k]] += stencils_.N[p * K + k] * P_.mass[p];
    }
  // A node whose mass is round-off (a point's support ends on it) is no unknown: its equation
  // would balance round-off forces and pin the stress of the points around it.
  double m_max = 0.0;
  for (std::size_t p = 0; p < n; ++p) m_max = std::max(m_max, P_.mass[p]);
  for (double& m : grid_mass_)
    if (m < 1e-10 * m_max) m = 0.0;
  held_components();
  dofs_.build(stencils_, width_, g, grid_mass_, grid_held_, threads_);
  const std::size_t dofs = static_cast<std::size_t>(dofs_.dofs());
  totals_.max_unknowns = std::max(totals_.max_unknowns, static_cast<long>(dofs));
  mass_.resize(dofs);
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) mass_[a * D + c] = grid_mass_[static_cast<std::size_t>(dofs_.node(a))];
  volume_.resize(n);
  for (std::size_t p = 0; p < n; ++p) volume_[p] = P_.volume(p);
  inv_r_.clear();
  if (axisymmetric()) {
    inv_r_.resize(n);
    for (std::size_t p = 0; p < n; ++p) inv_r_[p] = 1.0 / P_.x[p][0];
  }
  system_.set_pattern(dofs_.pattern());
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
  if (P_.acceleration.size() != n) initial_acceleration();
  v_bar_.assign(dofs, 0.0);
  a_bar_.assign(dofs, 0.0);
  double *vb = v_bar_.data(), *ab = a_bar_.data();
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      const double wm = stencils_.N[p * K + k] * P_.mass[p];
      for (int c = 0; c < D; ++c) {
#pragma omp atomic
        vb[a * D + c] += wm * P_.v[p][c];
#pragma omp atomic
        ab[a * D + c] += wm * P_.acceleration[p][c];
      }
    }
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) {
      const std::size_t i = a * D + c;
      v_bar_[i] = dofs_.held(a, c) ? 0.0 : v_bar_[i] / mass_[i];
      a_bar_[i] = dofs_.held(a, c) ? 0.0 : a_bar_[i] / mass_[i];
    }
  return {};
}

// The components each node with mass has held (Dirichlet conditions, du = 0): every one on or
// beyond a fixed wall, the normal one on or beyond a roller wall (and a frictional one, which
// the implicit integrator does not model: the scenario refuses it), and in axisymmetric
// geometry the radial one on the axis r = 0.
template <int D>
void ImplicitSolver<D>::held_components() {
  const GridGeometry<D>& g = model_.grid;
  grid_held_.assign(g.node_count(), 0);
  const double tol = 1e-9 * g.h;
  const Vec<D> hi = g.origin + g.extent();
  for (std::size_t i = 0; i < grid_held_.size(); ++i) {
    if (grid_mass_[i] <= 0.0) continue;
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
    grid_held_[i] = bits;
  }
}

// The points' strain increments d_eps = sum_i B_i du_i and the laws' update at the iterate du
// (eq. 5-6), then R = F_ext - F_int - M (4 du / dt^2 - 4 v / dt - a) (eq. 47; without the last
// term when quasi-static or `inertia` is false), zero on held components. Returns |R|.
template <int D>
double ImplicitSolver<D>::residual(const std::vector<double>& du, double dt, bool tangent) {
  const std::size_t n = P_.size();
  const int K = stencils_.K;
  deps_.resize(n);
  trial_stress_.resize(n);
  trial_plastic_.resize(n);
  trial_state_.resize(n);
  if (tangent) tangent_.resize(n);
  r_ = f_ext_;
  double* r = r_.data();
  const bool axi = axisymmetric();
  timer_.time(ImplicitPhase::StressUpdate, [&] {
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (std::size_t p = 0; p < n; ++p) {
      const double inv_r = axi ? inv_r_[p] : 0.0;
      Sym3 de = Sym3::Zero();
      for (int k = 0; k < K; ++k) {
        const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
        if (a < 0) continue;
        const Eigen::Map<const Vec<D>> u(&du[static_cast<std::size_t>(a) * D]);
        de += strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r) * u;
      }
      const Material& mat = materials_[static_cast<std::size_t>(P_.material[p])];
      LawResult res = evaluate(mat, full_stress<D>(P_.stress[p]), de, P_.state[p], tangent);
      deps_[p] = de;
      trial_stress_[p] = res.stress;
      trial_plastic_[p] = res.plastic_strain;
      trial_state_[p] = res.state;
      if (tangent) tangent_[p] = res.tangent;
      // F_int on the step's nodes: V B_i^T W sigma (eq. 4).
      const Sym3 ws = volume_[p] * voigt_weighted(res.stress);
      for (int k = 0; k < K; ++k) {
        const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
        if (a < 0) continue;
        const Vec<D> f =
            strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r).transpose() * ws;
        for (int c = 0; c < D; ++c) {
#pragma omp atomic
          r[static_cast<std::size_t>(a) * D + c] -= f[c];
        }
      }
    }
  });
  const bool inertia = dynamic() && !v_bar_.empty();
  const double c0 = 4.0 / (dt * dt), c1 = 4.0 / dt;
  double s = 0.0;
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int c = 0; c < D; ++c) {
      const std::size_t i = a * D + c;
      if (dofs_.held(a, c)) {
        r_[i] = 0.0;
        continue;
      }
      if (inertia) r_[i] -= mass_[i] * (c0 * du[i] - c1 * v_bar_[i] - a_bar_[i]);  // eq. 9-10, 47
      s += r_[i] * r_[i];
    }
  return std::sqrt(s);
}

// K = sum_p V B_i^T W T B_j (eq. 5, 10-11; T the laws' consistent tangent at the iterate, or
// the elastic matrix for Acosta's iteration) + 4 M / dt^2 (eq. 10, dynamic), held rows and
// columns replaced by the identity.
template <int D>
void ImplicitSolver<D>::assemble(double dt, bool elastic) {
  std::vector<double>& values = system_.values();
  std::fill(values.begin(), values.end(), 0.0);
  double* v = values.data();
  const std::size_t n = P_.size();
  const int K = stencils_.K;
  const bool axi = axisymmetric();
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (std::size_t p = 0; p < n; ++p) {
    Mat6 WT = elastic ? elastic_tangent_[static_cast<std::size_t>(P_.material[p])] : tangent_[p];
    WT.bottomRows<3>() *= 2.0;
    WT *= volume_[p];
    const double inv_r = axi ? inv_r_[p] : 0.0;
    for (int l = 0; l < K; ++l) {
      const std::int32_t b = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + l]));
      if (b < 0) continue;
      const StrainMatrix<D> C = WT * strain_matrix<D>(stencils_.N[p * K + l], stencils_.dN[p * K + l], inv_r);
      for (int k = 0; k < K; ++k) {
        const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
        if (a < 0) continue;
        const Mat<D> block =
            strain_matrix<D>(stencils_.N[p * K + k], stencils_.dN[p * K + k], inv_r).transpose() * C;
        const int o = dofs_.pair_offset(k, l, K);
        for (int r = 0; r < D; ++r) {
          if (dofs_.held(static_cast<std::size_t>(a), r)) continue;
          const std::int32_t e = dofs_.row_entry(static_cast<std::size_t>(a), r, o);
          for (int c = 0; c < D; ++c) {
            if (dofs_.held(static_cast<std::size_t>(b), c)) continue;
#pragma omp atomic
            v[e + c] += block(r, c);
          }
        }
      }
    }
  }
  const int centre = dofs_.pair_offset(0, 0, K);
  const double c0 = dynamic() ? 4.0 / (dt * dt) : 0.0;
  for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
    for (int r = 0; r < D; ++r) {
      const std::int32_t e = dofs_.row_entry(a, r, centre) + r;
      v[e] += dofs_.held(a, r) ? 1.0 : c0 * mass_[a * D + r];
    }
}

// Newton-Raphson on du for one step of dt (Acosta §2, App. B): false, with the reason, when it
// does not converge within max_iterations (the caller cuts the step).
template <int D>
bool ImplicitSolver<D>::solve_step(double dt, std::string& why) {
  const std::size_t dofs = static_cast<std::size_t>(dofs_.dofs());
  const bool elastic = settings_.iteration == ImplicitIteration::Elastic;
  history_.clear();
  external_forces(time_ + dt, f_ext_);
  du_.assign(dofs, 0.0);
  double rn = residual(du_, dt, !elastic);
  // The force scale: the largest of |F_ext|, |F_int(sigma^k)| and the inertial force of du = 0.
  {
    double fint = 0.0, inert = 0.0;
    const double c1 = 4.0 / dt;
    for (std::size_t i = 0; i < dofs; ++i) {
      const double in = dynamic() ? mass_[i] * (c1 * v_bar_[i] + a_bar_[i]) : 0.0;
      const double fi = f_ext_[i] - r_[i] + in;
      fint += fi * fi;
      inert += in * in;
    }
    force_scale_ = std::max({norm(f_ext_), std::sqrt(fint), std::sqrt(inert)});
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
    const bool solved = timer_.time(ImplicitPhase::Solve, [&] { return system_.solve(r_, ddu_); });
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
    if (rn <= tol) return true;
    if (alpha * norm(ddu_) <= settings_.displacement_tolerance * norm(du_)) return true;
    if (rn > 1e12 * force_scale_) break;  // diverging
  }
  why = fmt::format("the out-of-balance force stayed at {:.3g} of the force scale after {} iterations",
                    rn / force_scale_, report_.iterations);
  return false;
}

// The points' acceleration at the start of a dynamic stage, a_i = (F_ext - F_int) / m_i on
// the step's grid, so that Newmark starts from the equilibrium of eq. 3 at t.
template <int D>
void ImplicitSolver<D>::initial_acceleration() {
  const std::size_t n = P_.size();
  const int K = stencils_.K;
  v_bar_.clear();  // residual() without inertia
  external_forces(time_, f_ext_);
  du_.assign(static_cast<std::size_t>(dofs_.dofs()), 0.0);
  residual(du_, 1.0, false);
  P_.acceleration.assign(n, Vec<D>::Zero());
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < K; ++k) {
      const std::int32_t a = dofs_.active(static_cast<std::size_t>(stencils_.node[p * K + k]));
      if (a < 0) continue;
      for (int c = 0; c < D; ++c)
        P_.acceleration[p][c] += stencils_.N[p * K + k] * r_[static_cast<std::size_t>(a) * D + c] /
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
  const std::size_t n = P_.size();
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
  if (axi && P_.hoop.size() != n) P_.hoop.assign(n, 1.0);
  const Vec<D> g_mid = 0.5 * (gravity_at(model_.gravity, gravity_ramp_time_, time_ - ramp_start_) +
                              gravity_at(model_.gravity, gravity_ramp_time_, time_ + dt - ramp_start_));
  double strain = 0.0, plastic = 0.0, gravity = 0.0;
#pragma omp parallel for num_threads(threads_) schedule(static) reduction(+ : strain, plastic, gravity)
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
    const Sym3 before = full_stress<D>(P_.stress[p]);
    const Sym3& after = trial_stress_[p];
    const Sym3 mid = 0.5 * volume_[p] * (before + after);
    strain += contract(mid, deps_[p] - trial_plastic_[p]);
    plastic += contract(mid, trial_plastic_[p]);
    gravity += P_.mass[p] * g_mid.dot(dx);
    const Mat<D> dF = Mat<D>::Identity() + grad;
    Mat3 dF3 = embed3<D>(dF, 1.0);
    if constexpr (D == 2)
      if (axi) dF3(2, 2) = 1.0 + u_r * inv_r_[p];  // hoop stretch r^{k+1} / r^k
    // The law's stress rotated with the material, R S R^T, R the rotation of dF = R U (polar
    // decomposition): Acosta's incremental update made objective. (The explicit update, Thesis
    // eq. 4.4, pushes forward by all of dF, which also scales the stress by the stretch: an
    // O(strain) difference that the small-strain references, R6, would see.)
    const Eigen::JacobiSVD<Mat3> svd(dF3, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3 R = svd.matrixU() * svd.matrixV().transpose();
    P_.stress[p] = stored_stress<D>(to_voigt(R * to_matrix(after) * R.transpose()));
    P_.state[p] = trial_state_[p];
    P_.F[p] = dF * P_.F[p];
    P_.Fe[p] = (Mat<D>::Identity() + sym_block<D>(Sym3(deps_[p] - trial_plastic_[p]))) * P_.Fe[p];
    if (axi) P_.hoop[p] *= dF3(2, 2);
    P_.x[p] += dx;
    if (dyn) {
      P_.v[p] += 0.5 * dt * (P_.acceleration[p] + acc);  // eq. 41
      P_.acceleration[p] = acc;
    } else {
      P_.v[p].setZero();
    }
  }
  // The pressures' work, trapezoidal over the step (their forces at t and t + dt).
  if (!model_.pressures.empty()) {
    std::vector<double> f0(du_.size(), 0.0), f1(du_.size(), 0.0);
    pressure_forces(time_, f0);
    pressure_forces(time_ + dt, f1);
    double w = 0.0;
    for (std::size_t a = 0; a < dofs_.active_nodes(); ++a)
      for (int c = 0; c < D; ++c)
        if (!dofs_.held(a, c)) w += 0.5 * (f0[a * D + c] + f1[a * D + c]) * du_[a * D + c];
    energy_.load_work += w;
  }
  energy_.strain_energy += strain;
  energy_.plastic_dissipation += plastic;
  energy_.gravity_work += gravity;
}

#define SKRED_IMPLICIT_STEP(D)                                                           \
  template StepStatus ImplicitSolver<D>::map_step();                                     \
  template void ImplicitSolver<D>::held_components();                                    \
  template double ImplicitSolver<D>::residual(const std::vector<double>&, double, bool); \
  template void ImplicitSolver<D>::assemble(double, bool);                               \
  template bool ImplicitSolver<D>::solve_step(double, std::string&);                     \
  template void ImplicitSolver<D>::initial_acceleration();                               \
  template void ImplicitSolver<D>::commit_step(double);
SKRED_IMPLICIT_STEP(2)
SKRED_IMPLICIT_STEP(3)
#undef SKRED_IMPLICIT_STEP

}  // namespace skred
