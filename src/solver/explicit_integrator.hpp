// The explicit solver (solver/explicit_solver.hpp) behind the run driver's integrator
// interface (solver/integrator.hpp). The solver itself stays a concrete type: the benches and
// the tests step it directly, and no virtual call sits inside its time step.
#pragma once
#include <utility>
#include <vector>

#include "solver/explicit_solver.hpp"
#include "solver/integrator.hpp"

namespace skred {

template <int D>
class ExplicitIntegrator final : public Integrator<D> {
 public:
  ExplicitIntegrator(GridGeometry<D> grid, Particles<D>& particles, std::vector<Material> materials,
                     SolverSettings<D> settings, int threads)
      : solver_(grid, particles, std::move(materials), std::move(settings), threads) {}

  ExplicitSolver<D>& solver() { return solver_; }
  const ExplicitSolver<D>& solver() const { return solver_; }

  IntegratorKind kind() const override { return IntegratorKind::Explicit; }
  const MpmState<D>& state() const override { return solver_.state(); }
  StepStatus step() override { return solver_.step(); }
  void particles_changed() override { solver_.particles_changed(); }
  double dt() const override { return solver_.dt(); }
  ParticleTotals<D> totals() const override { return solver_.totals(); }
  double material_mean_speed() override { return solver_.material_mean_speed(); }
  bool sort_by_nearest_node() const override { return solver_.sort_by_nearest_node(); }
  bool contact_on() const override { return solver_.contact_on(); }
  void begin_stage(std::vector<Material> materials, double gravity_ramp_time) override {
    solver_.begin_stage(std::move(materials), gravity_ramp_time);
  }
  void set_local_damping(double alpha) override { solver_.set_local_damping(alpha); }
  void smoothed_stress(std::vector<Sym3>& out) override { solver_.smoothed_stress(out); }
  void restore(const SolverClock& c, std::vector<Material> materials) override {
    solver_.restore(c, std::move(materials));
  }
  std::vector<std::pair<std::string, double>> phase_seconds() const override {
    return solver_.phase_times().report();
  }

 private:
  ExplicitSolver<D> solver_;
};

}  // namespace skred
