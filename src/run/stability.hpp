// The run-time instability detector (docs/method.md, "Instability"): an unstable run stops
// with status "unstable" naming the step, the time and a point, never "completed". Checked
// at every row of series.csv from the sums computed for it, and at every frame.
#pragma once
#include <cmath>
#include <string>

#include "parallel/processes.hpp"
#include "scenario/scenario.hpp"
#include "solver/explicit_solver.hpp"

namespace skred {

// Energy gained beyond what was supplied, as a fraction of the supply, above which a stage
// is unstable (see StabilityWatch::check). Sound runs stay below 0.02 (shipped examples) and
// 0.18 (the first steps of a release at c dt/h = 1.5); blow-ups pass 5 within two steps.
inline constexpr double kEnergyGrowthTolerance = 0.5;
// The largest stable (c + v0) dt / h, the bound the scenario key solver.cfl has.
inline constexpr double kStableCourant = 1.0;

template <int D>
class StabilityWatch {
 public:
  // Over the points of all of `procs` (parallel/processes.hpp): observe_dilation is collective.
  StabilityWatch(const ScenarioOf<D>& s, double dt, double total_mass, const Processes& procs = {});

  // Empty, or why the time step is not usable: zero or non-finite (e.g. from a non-finite
  // initial speed).
  std::string unusable_step() const;
  // Empty, or why the time step is above the stable limit: (c + v0) dt / h > 1 (a scenario
  // that insists on such a step skips this check; the run is then watched as any other).
  std::string step_above_limit() const;
  bool initial_speed_finite() const { return std::isfinite(v0_); }
  // Energies are measured from the stage start (EnergyTotals; kinetic energy K0 then);
  // `stored` is the elastic energy of the stresses the points start the stage with (a K0
  // initial stress, a previous stage's), which the stage may release: stored_stress_energy.
  void begin_stage(double kinetic_energy, double stored = 0.0);
  // Empty, or why the run is unstable, after a series row with these sums:
  //  - a sum is not finite (a non-finite speed or energy at some point);
  //  - the largest speed exceeds speed_bound();
  //  - energy grows beyond the supply: K - K0 + W_stored + D_plastic - W_gravity >
  //    tolerance * (K0 + max |W_gravity| + the larger of the stored energy released so far and
  //    the stored energy at the start) + floor, the floor
  //    1e-9 M c^2 (the stored energy of all the material at a uniform strain of ~5e-5).
  std::string check(const ParticleTotals<D>& t, const EnergyTotals& e);
  // c_max + v0 + sqrt(2 |g| H): wave speed, initial speed and free fall over the grid height.
  double speed_bound() const { return speed_bound_; }

  // Dilated material. A point's stiffness acts on its volume V = det(F) V0 while its mass is
  // fixed, so its elastic wave speed is c sqrt(det F), and the step's limit there is
  // c sqrt(det F) dt / h <= 1, i.e. det F <= (h / (c dt))^2. Past it a
  // point that unloads (a dilated point at the apex of its yield surface that is compressed
  // again) rings and blows up. observe_dilation records the largest det F at a series row and
  // returns true the first time it passes the limit; dilation_note() is then the explanation
  // (for the warning, and for an instability's message: the value of the last sound row, since
  // a row that fails the check is not observed, so the dilation of a blow-up itself is not
  // taken for its cause).
  bool observe_dilation(const Particles<D>& P);
  std::string dilation_note() const;

 private:
  double c_ = 0.0, v0_ = 0.0, dt_ = 0.0, h_ = 0.0, floor_ = 0.0, speed_bound_ = 0.0;
  std::string fastest_material_;
  double k0_ = 0.0, max_gravity_work_ = 0.0, max_released_ = 0.0, stored0_ = 0.0;
  double dilation_limit_ = INFINITY;
  Processes procs_;
  double det_max_ = 1.0;  // the largest det F at the last series row observed, and where (global index)
  long det_point_ = -1;
  bool dilation_warned_ = false;
};

// The elastic energy of the points' stresses, sum V_p sigma : C^-1 : sigma / 2 with each point's
// material's E and nu: what a stage that starts from them can release (a K0 column whose walls
// go: its first series row holds the kinetic energy the release gave before the stress update
// books the release, so the watch must not call it created).
template <int D>
double stored_stress_energy(const Particles<D>& P, const std::vector<Material>& materials,
                            const Processes& procs = {});

// The functions below name a point by its global index: its index among the points of all of
// `procs` in rank order (its own index when the run is not distributed). All are collective.
// The first point with a non-finite position, velocity, F or stress, or -1 (a frame of it
// would hold non-finite output).
template <int D>
long first_non_finite_point(const Particles<D>& P, const Processes& procs = {});
// The point to name for an instability: the first non-finite one, else the fastest.
template <int D>
long offending_point(const Particles<D>& P, const Processes& procs = {});
// Whether point p, sound otherwise (finite state, det F > 0, speed within `speed_bound`),
// lies outside the grid or within a cell of its edge: it left the grid.
template <int D>
bool left_the_grid(const Particles<D>& P, long p, const GridGeometry<D>& grid, double speed_bound,
                   const Processes& procs = {});
// Where point p is, for a message: its body and position (on every process).
template <int D>
struct PointPlace {
  int body = -1;
  Vec<D> x = Vec<D>::Zero();
};
template <int D>
PointPlace<D> point_place(const Particles<D>& P, long p, const Processes& procs = {});

}  // namespace skred
