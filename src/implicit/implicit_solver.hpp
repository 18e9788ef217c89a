// The implicit MPM of González Acosta et al. 2020 (seed 001, §2 and App. B): each step maps the
// points' mass, velocity and acceleration to a fresh grid at x^k, keeps the points' weights
// through the step's iterations, and solves the equilibrium equation (eq. 3, with Newmark's
// inertia, eq. 8-10, 47) for the nodal displacement increment du by Newton-Raphson; the points
// move and their stresses commit only once it has converged. The quasi-static analysis is the
// same without inertia, in load steps.
//
// One step (step()):
//   map_step        stencils N_ip, dN_ip at x^k; lumped m_i; v_i, a_i (eq. 43-44); the unknowns
//                   and the matrix pattern (dof_map.hpp); the loads at t + dt (loads.cpp)
//   solve_step      Newton-Raphson on R(du) = F_ext - F_int(du) - M (4 du / dt^2 - 4 v / dt - a)
//                   (eq. 47-48) with the consistent tangent K + 4 M / dt^2 (eq. 10-11), or
//                   Acosta's iteration (§2: the elastic matrix, factorised once per step); a line
//                   search; a step that does not converge is halved and tried again
//   commit_step     the laws' stresses and states, F, Fe, x_p, and Newmark's update of the
//                   points' acceleration and velocity (eq. 41-42)
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <omp.h>
#include "core/huge_pages.hpp"
#include "implicit/cell_boxes.hpp"
#include "implicit/dof_map.hpp"
#include "implicit/linear_system.hpp"
#include "implicit/mapped_stencils.hpp"
#include "implicit/point_stencils.hpp"
#include "material/law_result.hpp"
#include "shape/interpolation.hpp"
#include "solver/boundary_side.hpp"
#include "solver/integrator.hpp"
#include "solver/mpm_state.hpp"
#include "transfer/box_exchange.hpp"
#include "transfer/node_box.hpp"

namespace skred {

// What the implicit integrator takes from a scenario besides its points and materials.
template <int D>
struct ImplicitModel {
  GridGeometry<D> grid;
  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;
  Vec<D> gravity = Vec<D>::Zero();
  std::array<BoundarySide, 2 * D> boundaries{};
  Geometry geometry = Geometry::PlaneStrain;  // 2D only
  std::vector<BoundaryPressure> pressures;
  bool volumetric_averaging = false;  // the cell-averaged volumetric strain (cell_boxes.hpp)
  std::vector<PrescribedVelocity> prescribed;
  // The processes the points are split among (issue 55): each process works on the box of grid
  // nodes its points reach (box_exchange.hpp) and holds the unknowns there (dof_map.hpp); the
  // grid's sums over the points (m_i, v_i, a_i, F_ext, F_int, the cells' point counts of
  // Acosta's W* and DM) are completed between the processes whose boxes meet, the residual's
  // between a row's owner and the processes that touch it, and the cell-averaged volumetric
  // strain's sums between the processes whose points share a cell (cell_boxes.hpp); the linear
  // solves run on PETSc's parallel matrices.
  Processes processes;
};

// The phases of an implicit step whose wall time summary.json reports ("implicit_" + name).
enum class ImplicitPhase { Map, Assembly, Factorisation, Solve, StressUpdate, Commit, Count };

class ImplicitPhaseTimer {
 public:
  template <class Fn>
  decltype(auto) time(ImplicitPhase p, Fn&& fn) {
    struct Add {
      double& s;
      double t0;
      ~Add() { s += omp_get_wtime() - t0; }
    } add{seconds_[static_cast<std::size_t>(p)], omp_get_wtime()};
    return fn();
  }
  std::vector<std::pair<std::string, double>> report() const {
    static constexpr const char* names[] = {"implicit_map",           "implicit_assembly",
                                            "implicit_factorisation", "implicit_solve",
                                            "implicit_stress_update", "implicit_commit"};
    std::vector<std::pair<std::string, double>> r;
    for (std::size_t k = 0; k < seconds_.size(); ++k)
      if (seconds_[k] > 0.0) r.emplace_back(names[k], seconds_[k]);
    return r;
  }

 private:
  std::array<double, static_cast<std::size_t>(ImplicitPhase::Count)> seconds_{};
};

// Totals over the implicit steps of a run (summary.json).
struct ImplicitTotals {
  long steps = 0;       // converged steps
  long iterations = 0;  // linear solves of the converged steps
  long cut_steps = 0;   // steps that were halved at least once
  long factorisations = 0;
  long elastic_fallbacks = 0;  // Newton iterations that took the elastic matrix (a singular tangent)
  long max_unknowns = 0;
  double max_factor_bytes = 0.0;
  std::string linear_solver;  // PETSc's KSP + PC (+ factor package)
};

template <int D>
class ImplicitSolver final : public Integrator<D> {
 public:
  ImplicitSolver(ImplicitModel<D> model, Particles<D>& particles, std::vector<Material> materials,
                 int threads);

  // The settings of the stage that begins or resumes, its step dt [s] (dynamic: the time step;
  // quasi-static: duration / load_steps) and its end time; call before begin_stage.
  void set_stage(const ImplicitSettings& settings, double dt, double end_time);
  const ImplicitTotals& implicit_totals() const { return totals_; }

  IntegratorKind kind() const override { return IntegratorKind::Implicit; }
  StepStatus step() override;
  const MpmState<D>& state() const override { return state_; }
  void particles_changed() override {}
  double dt() const override { return dt_; }
  ParticleTotals<D> totals() const override {
    return particle_totals(state_.points, state_.threads, state_.processes);
  }
  double material_mean_speed() override { return totals().mean_speed; }
  bool sort_by_nearest_node() const override { return false; }
  bool contact_on() const override { return false; }
  void begin_stage(std::vector<Material> materials, double gravity_ramp_time) override;
  void set_local_damping(double) override {}
  void smoothed_stress(std::vector<Sym3>& out) override { skred::smoothed_stress(state_, out); }
  void restore(const SolverClock& c, std::vector<Material> materials) override;
  std::vector<std::pair<std::string, double>> phase_seconds() const override { return timer_.report(); }
  StepReport last_step() const override { return report_; }

  // The residual norms of the last step's iterations, relative to its force scale (tests:
  // Newton's quadratic convergence).
  const std::vector<double>& residual_history() const { return history_; }
  bool node_magnitudes(std::vector<double>& k_mag, std::vector<double>& f_mag) const override;
  // Maps the points where they are and evaluates the internal force of their stresses at du = 0
  // without stepping (quasi-static): node_magnitudes() and node_internal_force() then describe
  // that state (Acosta fig. 11, 20-21).
  StepStatus evaluate_at_rest();
  // Sets pressure k ([[pressure]] tables in order) to `value` [Pa] from now on, without a ramp:
  // a load re-evaluated between steps from the body's position (Acosta §3.1, fig. 3).
  void set_pressure(std::size_t k, double value) {
    model_.pressures.at(k).pressure = value;
    model_.pressures.at(k).ramp_time = 0.0;
  }
  // F_int per grid node of the last evaluation (zero at nodes without mass; across processes,
  // at the nodes of this process's box).
  void node_internal_force(std::vector<Vec<D>>& f) const;

 private:
  bool dynamic() const { return settings_.analysis == ImplicitAnalysis::Dynamic; }
  bool axisymmetric() const { return D == 2 && model_.geometry == Geometry::Axisymmetric; }
  bool averaging() const { return model_.volumetric_averaging; }
  // m, the volumetric axes: the in-plane normal strains in plane strain, all three in 3D and in
  // axisymmetric geometry (with the hoop strain).
  Sym3 volumetric_axes() const {
    Sym3 m = Sym3::Zero();
    m.head<3>().setOnes();
    if (D == 2 && !axisymmetric()) m[2] = 0.0;
    return m;
  }
  static constexpr int kMaxStencil = D == 3 ? 64 : 16;  // 4^D (cubic B-spline, GIMP quadrature)
  static constexpr int kMaxBox = D == 3 ? 125 : 25;     // (4 + 1)^D
  // implicit_step.cpp (and equilibrium.cpp: point_strain to assemble)
  StepStatus map_step();
  long agreed_point(long bad) const;  // the first failing point over the processes (-1: none)
  void needed_rows();                 // across processes: the rows of du this one reads
  double owned_norm(const std::vector<double>& v) const;  // |v| over the processes' owned rows
  void held_components();
  void lumped_masses();
  void set_box();                                   // across processes: the box of nodes this one holds
  void sum_in_boxes(std::vector<double>& v) const;  // per-unknown values, over the processes
  void external_forces(double t, std::vector<double>& f) const;  // loads.cpp
  void pressure_forces(double t, std::vector<double>& f) const;  // loads.cpp
  void keep_outermost_over_processes(std::unordered_map<std::int64_t, std::size_t>& outermost, int axis,
                                     bool hi) const;
  Sym3 point_strain(std::size_t p, const std::vector<double>& du) const;
  const Sym3& update_point(std::size_t p, const Sym3& de, bool tangent);
  void subtract_internal_force(std::size_t p, const Sym3& ws, double* r) const;
  double residual(const std::vector<double>& du, double dt, bool tangent);
  void add_point_block(std::size_t p, const Mat6& WT, bool project, Vec<D>* g, Vec<D>* h, double* v) const;
  void add_block(std::size_t a, std::size_t b, int o, const Mat<D>& block, double* v) const;
  void add_inertia_and_held(double dt, int centre, double* v) const;
  void assemble(double dt, bool elastic);
  // mapped_equilibrium.cpp: Acosta's remedies (mapped_stencils.hpp)
  void mapped_internal_forces(const std::vector<double>& du, bool tangent, double* r);
  template <class F>
  void mapped_point_blocks(std::size_t p, const Mat6& WT, bool acosta, F&& f) const;
  Mat6 weighted_tangent(std::size_t p, bool elastic) const;
  void assemble_mapped(double dt, bool elastic);
  void assemble_by_cells(double* v);
  bool solve_step(double dt, std::string& why);
  bool within_a_cell(std::string& why) const;
  void commit_step(double dt);
  void commit_boundary_forces(double dt);
  void store_internal_force(double dt);
  void initial_acceleration();
  void elastic_matrices();

  ImplicitModel<D> model_;
  MpmState<D> state_;  // points, grid, materials, clock and energy totals (shared core)
  ImplicitSettings settings_;
  double dt_ = 0.0, end_time_ = 0.0;
  ImplicitTotals totals_;
  StepReport report_;
  std::vector<double> history_;
  ImplicitPhaseTimer timer_;
  LinearSystem system_;
  bool configured_ = false;
  bool symmetric_ = true;

  // The step's map (kept through its iterations and cuts).
  PointStencils<D> stencils_;
  MappedStencils<D> mapped_;  // with Acosta's remedies (settings_.at_points() false)
  // Acosta's stiffness cell by cell (assemble_by_cells): per grid node the slot of the cell whose
  // lower corner it is, and per cell its corner, lower radius and W D_g A_g per Gauss point.
  std::vector<std::int32_t> cell_slot_;
  std::vector<std::int64_t> cell_slots_set_;  // the nodes whose cell_slot_ is set (clear_cell_slots)
  void clear_cell_slots();
  std::vector<std::int64_t> cell_node_;
  std::vector<double> cell_r0_;
  std::vector<std::array<Mat6, MappedStencils<D>::KG>> cell_D_;
  // The pattern of Acosta's stiffness: per mapped cell its 2^D corner nodes (mapped_cells).
  bool cell_pattern_ = false;
  std::vector<std::int64_t> cell_blocks_;
  void mapped_cells(std::vector<std::int64_t>& blocks);
  int width_ = 2;  // S, nodes per axis of a point's stencil
  DofMap<D> dofs_;
  mutable BoxExchange<D> boxes_;  // across processes: the grid's sums between the boxes that meet
  CellBoxes<D> cells_;            // with the cell-averaged volumetric strain
  // Per grid node, map_step's scratch. Across processes each is written in the step's box only
  // and cleared there at the next step (clear_scratch): the pages of nodes no box reaches stay
  // untouched (GridArray), and a step costs O(the box), not O(the grid).
  GridArray<double> grid_mass_;
  GridArray<std::uint8_t> grid_held_;  // the components held (held_components)
  GridArray<std::uint8_t> sliver_;     // its mass a sliver
  NodeBox<D> scratch_box_;             // across processes: the box the scratch was written in
  void clear_scratch();
  // The prescribed velocities: per grid node (scratch: the table's index + 1, 0: none) and per
  // active node (the index, -1: none), and the bits of the components it drives (not held by a
  // wall).
  GridArray<std::int8_t> grid_prescribed_;
  std::vector<std::int8_t> prescribed_id_;
  GridArray<std::uint8_t> grid_driven_;
  std::vector<std::uint8_t> driven_;
  std::vector<double> mass_;                 // m_i per unknown (lumped, eq. 43)
  std::vector<double> v_bar_, a_bar_;        // v_i^t, a_i^t per unknown (eq. 43-44)
  std::vector<double> f_ext_, f_ext_start_;  // F_ext at t + dt and at t
  std::vector<double> inv_r_;                // 1 / r_p (axisymmetric), else empty
  std::vector<double> volume_;               // V_p at x^k
  // Newton's iterates.
  std::vector<double> du_, ddu_, r_, trial_du_;
  std::vector<double> held_force_;  // per unknown: a held component's support force (-R)
  std::vector<double> f_int_;       // per unknown: F_int of the last converged step (eq. 7)
  double force_scale_ = 0.0;
  // The points' trial update at the current iterate.
  std::vector<Sym3> deps_, trial_stress_, trial_plastic_;
  std::vector<PointState> trial_state_;
  std::vector<Mat6> tangent_;
  std::vector<double> vol_corr_, mean_;         // (theta_c - theta_p) / d and q_p (cell averaging)
  std::vector<double> cell_theta_, cell_mean_;  // per cell: V_c theta_c and V_c q_c
  std::vector<Mat6> elastic_tangent_;           // per material
};

}  // namespace skred
