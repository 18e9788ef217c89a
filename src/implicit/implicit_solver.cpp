// The implicit integrator's life between steps (stages and restores over the shared state,
// solver/mpm_state.hpp) and the step with its cuts. The step's phases are in implicit_step.cpp
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
    : model_(std::move(model)),
      state_(particles, model_.grid, model_.interpolation, model_.quadrature_points, {}, threads) {
  state_.processes = model_.processes;
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
  for (const Material& m : state_.materials)
    if (m.model == Model::MohrCoulomb && m.mohr_coulomb.dilation != m.mohr_coulomb.friction &&
        settings_.iteration == ImplicitIteration::Newton)
      symmetric = false;
  // The remedies' tangent pairs the test functions with other trial ones (mapped_stencils.hpp):
  // symmetric only at the points (with or without W*) and recovered there.
  if (settings_.iteration == ImplicitIteration::Newton && !settings_.at_points() &&
      (settings_.stress_recovery == StressRecovery::Cmpm ||
       (settings_.integration != ForceIntegration::Points &&
        settings_.integration != ForceIntegration::ModifiedWeights)))
    symmetric = false;
  if (!configured_ || symmetric != symmetric_) {
    symmetric_ = symmetric;
    system_.configure(settings_.linear_solver, settings_.petsc_options, symmetric_, D, state_.processes);
    configured_ = true;
    totals_.linear_solver = system_.description();
  }
  if (dynamic() && state_.points.acceleration.size() != state_.points.size())
    state_.points.acceleration.assign(state_.points.size(), Vec<D>::Zero());
  if (!dynamic()) state_.points.acceleration.clear();
}

template <int D>
void ImplicitSolver<D>::restore(const SolverClock& c, std::vector<Material> materials) {
  skred::restore(state_, c, std::move(materials));
  elastic_matrices();
}

// D_p of each material: Acosta's iteration (§2) and the fall-back of a singular tangent.
template <int D>
void ImplicitSolver<D>::elastic_matrices() {
  elastic_tangent_.clear();
  for (const Material& m : state_.materials)
    elastic_tangent_.push_back(
        elastic_evaluate(m.elastic_constants, Sym3::Zero(), Sym3::Zero(), {}, true).tangent);
}

template <int D>
void ImplicitSolver<D>::begin_stage(std::vector<Material> materials, double gravity_ramp_time) {
  skred::begin_stage(state_, std::move(materials), gravity_ramp_time);
  elastic_matrices();
  if (dynamic()) state_.points.acceleration.clear();  // found again from the out-of-balance force
}

// One step of dt (the stage's last one shortened to its end). A step that does not converge
// is halved and tried again from the same state, at most max_cuts times; the step after a cut
// takes the stage's dt again.
template <int D>
StepStatus ImplicitSolver<D>::step() {
  double dt = dt_;
  if (end_time_ > state_.clock.time && end_time_ - state_.clock.time < dt * (1.0 + 1e-9))
    dt = end_time_ - state_.clock.time;
  if (!(dt > 0.0)) return {false, -1, "the implicit step has no time to cover (zero time step)"};
  if (StepStatus m = timer_.time(ImplicitPhase::Map, [&] { return map_step(); }); !m.ok) return m;
  if (dynamic() && state_.points.acceleration.size() != state_.points.size()) initial_acceleration();
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
                      state_.clock.time, cut, dt, why)};
    dt *= 0.5;
    report_.cuts = cut + 1;
  }
  timer_.time(ImplicitPhase::Commit, [&] { commit_step(dt); });
  state_.clock.time += dt;
  ++state_.clock.steps;
  ++totals_.steps;
  totals_.iterations += report_.iterations;
  if (report_.cuts > 0) ++totals_.cut_steps;
  return {};
}

template class ImplicitSolver<2>;
template class ImplicitSolver<3>;

}  // namespace skred
