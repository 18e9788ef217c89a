// The explicit dynamic MPM/GIMP solver (Thesis §2.2.1 and §4.4). One call to step()
// advances the particles by one time step; each phase of the step is one member function.
#pragma once
#include <algorithm>
#include <array>
#include <climits>
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "scenario/scenario.hpp"
#include "shape/bspline.hpp"
#include "shape/gimp.hpp"
#include "shape/gimp_quadrature.hpp"
#include "shape/linear.hpp"
#include "solver/boundary.hpp"
#include "solver/grid_fields.hpp"

namespace skred {

template <int D> struct SolverSettings {
  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;
  StressScheme scheme = StressScheme::Averaged;
  double dt = 0.0;
  Vec<D> gravity = Vec<D>::Zero();
  double gravity_ramp_time = 0.0;
  std::array<BoundarySide, 2 * D> boundaries{};
  // Fraction of PIC in the particle velocity update (0: the pure force-based FLIP update of
  // Thesis eq. 2.56). A small value damps the velocity noise FLIP leaves on points that the
  // grid no longer moves (the null space of the particle-to-grid map).
  double pic_fraction = 0.0;
};

// Running totals kept by the solver (energy bookkeeping, Thesis eq. 4.15-4.17, 5.13).
struct EnergyTotals {
  double strain_energy = 0.0;        // stored: sum of V (sigma^{k+1} + sigma^k)/2 : (d_eps - d_eps_p) (eq. 4.16)
  double gravity_work = 0.0;         // sum of m_p g . d_x_p (eq. 5.13, incremental form)
  double plastic_dissipation = 0.0;  // plastic work (zero for elastic materials)
};

// The solver's state between two steps beyond the particles and the scenario, for a
// checkpoint: clock, gravity ramp of the stage (what begin_stage set) and energy totals.
struct SolverClock {
  double time = 0.0;
  long steps = 0;
  double ramp_start = 0.0;
  double gravity_ramp_time = 0.0;
  EnergyTotals energy;
};

// Quantities summed over the particles on demand.
template <int D> struct ParticleTotals {
  double mass = 0.0;
  double kinetic_energy = 0.0;  // eq. 4.15
  Vec<D> momentum = Vec<D>::Zero();
  double mean_speed = 0.0;      // mass-weighted mean speed, eq. 5.12
  double max_speed = 0.0;
  long yielding = 0;            // points whose last stress update was plastic
};

// Outcome of one step. A step that fails names the first offending particle.
struct StepStatus {
  bool ok = true;
  long particle = -1;
  std::string reason;
};

// Positions of the closed (fixed, roller, frictional) walls; +-inf on free sides.
template <int D> struct WallBox {
  Vec<D> lo = Vec<D>::Constant(-INFINITY), hi = Vec<D>::Constant(INFINITY);
};

// A box of grid nodes, per axis the first and last index (empty when hi < lo).
template <int D> struct NodeBox {
  std::array<int, D> lo{}, hi{};
};

// Sum of vectors across OpenMP threads: reduction(vsum : v).
#pragma omp declare reduction(vsum : Vec<2> : omp_out += omp_in) initializer(omp_priv = Vec<2>::Zero())
#pragma omp declare reduction(vsum : Vec<3> : omp_out += omp_in) initializer(omp_priv = Vec<3>::Zero())
// Widest stencil of the kernels (B-spline and GIMP quadrature: four nodes per axis).
inline constexpr int kMaxStencil = 4;

template <int D> class ExplicitSolver {
 public:
  ExplicitSolver(GridGeometry<D> grid, Particles<D>& particles, std::vector<Material> materials,
                 SolverSettings<D> settings, int threads);

  // Advances by one time step. The last phase of a step already maps the particles' mass
  // and momentum for the next one; code that changes the particles between steps (their
  // positions, velocities, masses or F, or their number) calls particles_changed() first. A
  // change in the number of points is also detected by itself.
  StepStatus step();
  void particles_changed() { grid_mapped_ = false; }

  double time() const { return time_; }
  long steps() const { return steps_; }
  double dt() const { return settings_.dt; }
  const EnergyTotals& energy() const { return energy_; }
  ParticleTotals<D> totals() const;
  const GridGeometry<D>& grid() const { return grid_; }
  const GridFields<D>& fields() const { return fields_; }
  const SolverSettings<D>& settings() const { return settings_; }
  int threads() const { return threads_; }

  // Grid-smoothed particle stresses (Thesis eq. 4.18-4.19): stresses mapped to the nodes
  // weighted by mass, then interpolated back. `out` is resized to the particle count.
  void smoothed_stress(std::vector<Sym3>& out);

  // Nodal fields of the last smoothed_stress() call, flat-indexed like grid(), for the grid
  // output file: mass m_i, velocity sum N_ip m_p v_p / m_i and stress sigma_i (eq. 4.18).
  const std::vector<double>& node_mass() const { return node_mass_; }
  const std::vector<Vec<D>>& node_velocity() const { return node_velocity_; }
  const std::vector<Sym3>& node_stress() const { return node_stress_; }

  // Starts a new stage at the current time: the materials (the stage's strength, or held
  // elastic) and the gravity ramp (Thesis eq. 4.13, measured from now; 0: full gravity)
  // change, and displacements, gravity work, strain energy and plastic dissipation are
  // measured from here.
  void begin_stage(std::vector<Material> materials, double gravity_ramp_time);
  void reset_reference();
  const std::vector<Material>& materials() const { return materials_; }

  // Checkpoint and restart: the state to save, and restoring it with the current stage's
  // materials. The next step maps the grid afresh from the particles, which gives the same
  // points bit for bit as the fused map (test FusedMapEqualsAFreshMapEveryStep).
  SolverClock clock() const {
    return {time_, steps_, ramp_start_, settings_.gravity_ramp_time, energy_};
  }
  void restore(const SolverClock& c, std::vector<Material> materials) {
    materials_ = std::move(materials);
    for (Material& m : materials_) m.prepare();
    time_ = c.time;
    steps_ = c.steps;
    ramp_start_ = c.ramp_start;
    settings_.gravity_ramp_time = c.gravity_ramp_time;
    energy_ = c.energy;
    grid_mapped_ = false;
  }

 private:
  template <class K> StepStatus step_with(const K& kernel);
  // Phases of one step, in the order of Thesis §4.4.
  template <class K> bool map_mass_momentum(const K& kernel);            // eq. 2.53-2.54
  void nodal_velocity(GridArray<Vec<D>>& velocity, bool clear);       // eq. 2.23
  void clear_mass_momentum();
  template <class K> void update_stress_and_map_forces(const K& kernel, double dt_stress);  // eq. 2.20, 4.1-4.4, 2.51
  void update_grid();                                                    // eq. 2.49, 5.8-5.11
  template <class K> void update_particle_velocity(const K& kernel, bool remap, bool move);  // eq. 2.56
  template <class K> void update_stress_and_move(const K& kernel, double dt_stress);  // eq. 2.55, 3.2

  // Where thread t scatters: the grid itself for thread 0, its own buffer for the others.
  double* mass_target(int t) { return t == 0 ? fields_.mass.data() : buffers_[t - 1].mass.data(); }
  Vec<D>* vec_target(int t, GridArray<Vec<D>>& grid) {
    return t == 0 ? grid.data() : buffers_[t - 1].vec.data();
  }
  void reduce_scatter(bool mass, GridArray<Vec<D>>& target);
  void set_box(const Vec<D>& lo, const Vec<D>& hi);
  template <class Fn> void for_box(Fn&& fn, int last_lo = 0, int last_hi = INT_MAX);
  template <class K> std::vector<typename K::Packed>& shapes();
  template <class K> void smoothed_stress_with(const K& kernel, std::vector<Sym3>& out);
  template <class F> decltype(auto) dispatch(F&& f);

  GridGeometry<D> grid_;
  Particles<D>& particles_;
  std::vector<Material> materials_;
  SolverSettings<D> settings_;
  Boundaries<D> boundaries_;
  WallBox<D> walls_;
  GridFields<D> fields_;
  std::vector<ScatterBuffer<D>> buffers_;  // one per thread beyond the first
  // Every point's weighting functions, evaluated once per step by map_mass_momentum (x_p and
  // the F_p that sizes the GIMP domain are those of the start of the step) and read by the
  // later phases; the vector type follows the kernel.
  std::variant<std::monostate, std::vector<typename LinearKernel<D>::Packed>,
               std::vector<typename GimpKernel<D>::Packed>,
               std::vector<typename BsplineKernel<D>::Packed>,
               std::vector<QuadratureState<D>>>
      shapes_;
  // True when the grid's mass and momentum and the stored weighting functions are those of
  // the particles' current state: the last phase of a step maps the next step's.
  bool grid_mapped_ = false;
  std::size_t mapped_points_ = 0;  // the number of points the map was made for
  NodeBox<D> box_;  // the nodes the stencils of this step can reach (see set_box); empty at first
  std::vector<double> node_mass_;          // nodal mass of the smoothing (eq. 4.18)
  std::vector<Sym3> node_stress_;          // nodal stresses for smoothing (eq. 4.18)
  std::vector<Vec<D>> node_velocity_;      // nodal velocities mapped with the smoothing
  int threads_ = 1;
  double time_ = 0.0;
  double ramp_start_ = 0.0;  // time at which the gravity ramp starts
  long steps_ = 0;
  Vec<D> gravity_now_ = Vec<D>::Zero();
  EnergyTotals energy_;
  StepStatus status_;
};

// The kernel of the scenario, as a type: f(kernel).
template <int D> template <class F> decltype(auto) ExplicitSolver<D>::dispatch(F&& f) {
  switch (settings_.interpolation) {
    case Interpolation::Linear: return f(LinearKernel<D>{});
    case Interpolation::Gimp: return f(GimpKernel<D>{});
    case Interpolation::Bspline: return f(BsplineKernel<D>{});
    case Interpolation::GimpQuadrature:
      if (settings_.quadrature_points == 1) return f(GimpQuadratureKernel<D, 1>{});
      if (settings_.quadrature_points == 3) return f(GimpQuadratureKernel<D, 3>{});
      return f(GimpQuadratureKernel<D, 2>{});
  }
  return f(GimpKernel<D>{});
}

// fn(i) for every node i of the box (or of its part with last-axis index in [last_lo,
// last_hi]), in parallel over its rows.
template <int D>
template <class Fn>
void ExplicitSolver<D>::for_box(Fn&& fn, int last_lo, int last_hi) {
  NodeBox<D> b = box_;
  b.lo[D - 1] = std::max(b.lo[D - 1], last_lo);
  b.hi[D - 1] = std::min(b.hi[D - 1], last_hi);
  const long width = b.hi[0] - b.lo[0] + 1;
  long rows = 1;
  for (int d = 1; d < D; ++d) rows *= std::max(0, b.hi[d] - b.lo[d] + 1);
  if (width <= 0) return;
  std::size_t stride[D];
  for (int d = 0; d < D; ++d) stride[d] = grid_.stride(d);
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (long r = 0; r < rows; ++r) {
    std::size_t row = static_cast<std::size_t>(b.lo[0]);
    long rest = r;
    for (int d = 1; d < D; ++d) {
      const long n = b.hi[d] - b.lo[d] + 1;
      row += static_cast<std::size_t>(b.lo[d] + rest % n) * stride[d];
      rest /= n;
    }
    for (long i = 0; i < width; ++i) fn(row + static_cast<std::size_t>(i));
  }
}

}  // namespace skred
