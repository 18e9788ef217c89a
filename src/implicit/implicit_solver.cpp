// The implicit integrator's life between steps: stages, clock, totals, smoothed stresses, and
// the step with its cuts. The step's phases are in implicit_step.cpp
// (map, Newton, commit) and equilibrium.cpp (residual, tangent), its loads in loads.cpp.
#include "implicit/implicit_solver.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "material/law.hpp"

namespace skred {

template <int D>
ImplicitSolver<D>::ImplicitSolver(ImplicitModel<D> model, Particles<D>& particles,
                                  std::vector<Material> materials, int threads)
    : model_(std::move(model)), P_(particles), threads_(std::max(1, threads)) {
  // The cubic B-spline's degrees of freedom sit at the Greville abscissae (core/grid.hpp).
  model_.grid.bspline_dofs = model_.interpolation == Interpolation::Bspline;
  restore(SolverClock{}, std::move(materials));
}

template <int D>
void ImplicitSolver<D>::set_stage(const ImplicitSettings& settings, double dt, double end_time) {
  settings_ = settings;
  dt_ = dt;
  end_time_ = end_time;
  // The tangent is symmetric unless a material's flow is non-associated (Mohr-Coulomb with
  // dilation != friction): Cholesky and CG then, LU and GMRES otherwise.
  bool symmetric = true;
  for (const Material& m : materials_)
    if (m.model == Model::MohrCoulomb && m.mohr_coulomb.dilation != m.mohr_coulomb.friction &&
        settings_.iteration == ImplicitIteration::Newton)
      symmetric = false;
  if (!configured_ || symmetric != symmetric_) {
    symmetric_ = symmetric;
    system_.configure(settings_.linear_solver, settings_.petsc_options, symmetric_, D);
    configured_ = true;
    totals_.linear_solver = system_.description();
  }
  if (dynamic() && P_.acceleration.size() != P_.size()) P_.acceleration.assign(P_.size(), Vec<D>::Zero());
  if (!dynamic()) P_.acceleration.clear();
}

template <int D>
void ImplicitSolver<D>::restore(const SolverClock& c, std::vector<Material> materials) {
  materials_ = std::move(materials);
  elastic_tangent_.clear();
  for (Material& m : materials_) {
    m.prepare();
    elastic_tangent_.push_back(
        elastic_evaluate(m.elastic_constants, Sym3::Zero(), Sym3::Zero(), {}, true).tangent);
  }
  time_ = c.time;
  steps_ = c.steps;
  ramp_start_ = c.ramp_start;
  gravity_ramp_time_ = c.gravity_ramp_time;
  energy_ = c.energy;
  boundary_force_ = c.boundary_force;
}

template <int D>
void ImplicitSolver<D>::begin_stage(std::vector<Material> materials, double gravity_ramp_time) {
  SolverClock c = clock();
  c.ramp_start = time_;
  c.gravity_ramp_time = gravity_ramp_time;
  c.energy = EnergyTotals{};
  restore(c, std::move(materials));
  P_.x_ref = P_.x;
  // As the explicit solver's begin_stage: the volume strain is ln det F, nothing yields yet.
  for (std::size_t p = 0; p < P_.size(); ++p) {
    P_.state[p].volume_strain = std::log(P_.F[p].determinant());
    P_.state[p].yielding = 0;
  }
  if (dynamic()) P_.acceleration.clear();  // found again from the out-of-balance force
}

template <int D>
ParticleTotals<D> ImplicitSolver<D>::totals() const {
  ParticleTotals<D> t;
  double speed_mass = 0.0;
  for (std::size_t p = 0; p < P_.size(); ++p) {
    const double m = P_.mass[p], s = P_.v[p].norm();
    t.mass += m;
    t.kinetic_energy += 0.5 * m * s * s;  // Thesis eq. 4.15
    speed_mass += m * s;
    t.max_speed = std::max(t.max_speed, s);
    t.momentum += m * P_.v[p];
    t.yielding += P_.state[p].yielding;
  }
  t.mean_speed = t.mass > 0.0 ? speed_mass / t.mass : 0.0;
  return t;
}

// Thesis eq. 4.18: sigma_i = sum sigma_p N_ip m_p / m_i; eq. 4.19: sigma_p = sum sigma_i N_ip.
template <int D>
void ImplicitSolver<D>::smoothed_stress(std::vector<Sym3>& out) {
  PointStencils<D> st;
  with_kernel<D>(model_.interpolation, model_.quadrature_points,
                 [&](const auto& kernel) { st.build(kernel, model_.grid, P_, threads_); });
  const std::size_t nodes = model_.grid.node_count();
  node_mass_.assign(nodes, 0.0);
  node_velocity_.assign(nodes, Vec<D>::Zero());
  node_stress_.assign(nodes, Sym3::Zero());
  const int K = st.K;
  for (std::size_t p = 0; p < P_.size(); ++p)
    for (int k = 0; k < K; ++k) {
      const std::size_t e = p * K + k, i = static_cast<std::size_t>(st.node[e]);
      const double wm = st.N[e] * P_.mass[p];
      node_mass_[i] += wm;
      node_velocity_[i] += wm * P_.v[p];
      node_stress_[i] += wm * full_stress<D>(P_.stress[p]);
    }
  for (std::size_t i = 0; i < nodes; ++i)
    if (node_mass_[i] > 0.0) {
      node_velocity_[i] /= node_mass_[i];
      node_stress_[i] /= node_mass_[i];
    }
  out.assign(P_.size(), Sym3::Zero());
  for (std::size_t p = 0; p < P_.size(); ++p)
    for (int k = 0; k < K; ++k)
      out[p] += st.N[p * K + k] * node_stress_[static_cast<std::size_t>(st.node[p * K + k])];
}

// One step of dt (the stage's last one shortened to its end). A step that does not converge
// is halved and tried again from the same state, at most max_cuts times; the step after a cut
// takes the stage's dt again.
template <int D>
StepStatus ImplicitSolver<D>::step() {
  double dt = dt_;
  if (end_time_ > time_ && end_time_ - time_ < dt * (1.0 + 1e-9)) dt = end_time_ - time_;
  if (!(dt > 0.0)) return {false, -1, "the implicit step has no time to cover (zero time step)"};
  if (StepStatus m = timer_.time(ImplicitPhase::Map, [&] { return map_step(); }); !m.ok) return m;
  if (dynamic() && P_.acceleration.size() != P_.size()) initial_acceleration();
  report_ = {};
  std::string why;
  for (int cut = 0;; ++cut) {
    bool converged = false;
    try {
      converged = solve_step(dt, why);
    } catch (const LinearSolverError& e) {  // PETSc failed (out of memory, a zero pivot, ...)
      why = e.what();
    }
    if (converged) break;
    if (cut >= settings_.max_cuts)
      return {
          false, -1,
          fmt::format("the implicit step from t = {:.6g} s did not converge after {} cuts to dt = {:.3g} s "
                      "({}); allow more cuts or iterations (implicit.max_cuts, implicit.max_iterations), "
                      "or take smaller steps",
                      time_, cut, dt, why)};
    dt *= 0.5;
    report_.cuts = cut + 1;
  }
  timer_.time(ImplicitPhase::Commit, [&] { commit_step(dt); });
  time_ += dt;
  ++steps_;
  ++totals_.steps;
  totals_.iterations += report_.iterations;
  if (report_.cuts > 0) ++totals_.cut_steps;
  return {};
}

template class ImplicitSolver<2>;
template class ImplicitSolver<3>;

}  // namespace skred
