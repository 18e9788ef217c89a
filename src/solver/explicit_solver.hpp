// The explicit dynamic MPM/GIMP solver (Thesis §2.2.1 and §4.4). One call to step()
// advances the particles by one time step; each phase of the step is one member function,
// and a scheme type (scheme.hpp) orders them. It advances the state shared with the implicit
// integrator (mpm_state.hpp: points, grid, materials, clock) and owns what only its step
// needs: the grid fields, the transfer with its stored weights, the velocity transfer rule, the
// walls and the contact. The maps between points and grid are the transfer layer's
// (src/transfer); the grid phases are functions of one continuum's fields (grid_phases.hpp).
#pragma once
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "core/grid.hpp"
#include "core/particles.hpp"
#include "material/material.hpp"
#include "shape/interpolation.hpp"
#include "solver/boundary.hpp"
#include "solver/contact.hpp"
#include "solver/grid_fields.hpp"
#include "solver/grid_phases.hpp"
#include "solver/implicit_settings.hpp"
#include "solver/mpm_state.hpp"
#include "solver/phase_timer.hpp"
#include "solver/process_sums.hpp"
#include "solver/scheme.hpp"
#include "solver/velocity_transfer.hpp"
#include "solver/volumetric_averaging.hpp"
#include "transfer/transfer.hpp"

namespace skred {

template <int D>
struct SolverSettings {
  Interpolation interpolation = Interpolation::Gimp;
  int quadrature_points = 2;
  StressScheme scheme = StressScheme::Averaged;
  bool hyperelastic = false;  // linear-elastic materials: the hyperelastic law (stress_update.hpp)
  double dt = 0.0;
  Vec<D> gravity = Vec<D>::Zero();
  double gravity_ramp_time = 0.0;
  std::array<BoundarySide, 2 * D> boundaries{};
  // Fraction of PIC in the particle velocity update (0: the pure force-based FLIP update of
  // Thesis eq. 2.56). A small value damps the velocity noise FLIP leaves on points that the
  // grid no longer moves (the null space of the particle-to-grid map).
  double pic_fraction = 0.0;
  // The particle velocity update (velocity_transfer.hpp); pic_fraction applies to flip only.
  VelocityTransfer velocity_transfer = VelocityTransfer::Flip;
  int xpic_order = 2;  // m of XPIC(m), >= 1
  // XPIC only: the filter's period in seconds. 0: every step. Above 0: FLIP at every step and
  // XPIC(m) on the steps that cross a multiple of it (NairnMPM's PeriodicXPIC), so the filter's
  // damping per second does not follow the time step (docs/method.md, "The filter per unit time").
  double xpic_period = 0.0;
  // Cell-averaged volumetric strain against volumetric locking (volumetric_averaging.hpp).
  bool volumetric_averaging = false;
  // Selective integration of shear, grad N at the cell's centre (Thesis §4.5; USF only;
  // selective_shear.hpp).
  bool centre_shear = false;
  // A 2D grid's geometry: plane strain, or axisymmetric with x the radius r and y the axis
  // (Acosta App. A1: masses and volumes per radian, the hoop strain v_r / r in the stress update and
  // -V sigma_theta N / r in the radial internal force; stress_phase_impl.hpp).
  Geometry geometry = Geometry::PlaneStrain;
  // Map each body's mass and momentum beside the centre-of-mass fields (for contact).
  bool body_fields = false;
  // Multi-continuum contact (Paper III §C.2.7; contact.hpp): empty, every body shares the
  // centre-of-mass velocity field; set, each body moves with its own fields and the contact
  // phase couples them. Rigid bodies need it.
  ContactSettings<D> contact;
  // The processes the points are split among (parallel/processes.hpp; default: this one alone).
  // Each holds its share of the points, in a block of the grid (repartition_in_blocks), and works on
  // the box of nodes they reach; the grid sums are completed where boxes overlap
  // (transfer/box_exchange.hpp) and the points' sums over every process.
  Processes processes;
};

// Positions of the closed (fixed, roller, frictional) walls; +-inf on free sides.
template <int D>
struct WallBox {
  Vec<D> lo = Vec<D>::Constant(-INFINITY), hi = Vec<D>::Constant(INFINITY);
};

template <int D>
class ExplicitSolver {
 public:
  ExplicitSolver(GridGeometry<D> grid, Particles<D>& particles, std::vector<Material> materials,
                 SolverSettings<D> settings, int threads);

  // Advances by one time step: the scheme of the settings orders the phases (scheme.hpp).
  // The last phase of a step already maps the particles' mass and momentum for the next one;
  // code that changes the particles between steps (their positions, velocities, masses or F,
  // or their number) calls particles_changed() first. A change in the number of points is
  // also detected by itself.
  StepStatus step();
  void particles_changed() { grid_mapped_ = false; }
  // The key of the periodic point sort (Particles::sort_by_cell; docs/method.md, "Point
  // order"): the node nearest each point for 3D GIMP, whose points of one key then update the
  // same rows of nodes one after another, so each row's read is served from the previous
  // point's write; the cell elsewhere.
  bool sort_by_nearest_node() const { return D == 3 && settings_.interpolation == Interpolation::Gimp; }
  // Maps the current points' mass and momentum (and, with body_fields, each body's) to the
  // grid as a step starts (eq. 2.53-2.54); step() does this itself when needed.
  StepStatus map_grid();

  // The points, grid, materials and clock it advances (mpm_state.hpp).
  const MpmState<D>& state() const { return state_; }
  const Processes& processes() const { return state_.processes; }
  double time() const { return state_.clock.time; }
  long steps() const { return state_.clock.steps; }
  double dt() const { return settings_.dt; }
  const EnergyTotals& energy() const { return state_.clock.energy; }
  ParticleTotals<D> totals() const;
  // The mean speed the material moves with: sum_p m_p |sum_i N_ip v_i| / sum_p m_p, v_i = p_i / m_i
  // under the velocity conditions (eq. 2.23), from the map the next step starts from (made here
  // if the points changed since the last step; with contact each body's own fields). Eq. 5.12
  // takes |v_p| instead; a FLIP point's
  // v_p also carries velocities the grid cannot see, while it moves with sum_i N_ip v_i
  // (eq. 2.55). Infinite if the map fails (the next step then reports the point).
  double material_mean_speed();
  double affine_kinetic_energy() const;  // APIC's share of the kinetic energy
  const GridGeometry<D>& grid() const { return transfer_.grid(); }
  const GridFields<D>& fields() const { return fields_; }
  // Per-body mass and momentum of the step's start (settings.body_fields, or contact), indexed
  // by body id; with contact also each body's velocities and forces.
  const std::vector<BodyFields<D>>& body_fields() const { return bodies_; }
  bool contact_on() const { return settings_.contact.enabled(); }
  // The contact work of the last step, normal and friction parts (ContactLoss).
  const ContactLoss& contact_step() const { return contact_step_; }
  // Per body id: reference volume per unit mass (1 / mean density of its points, prepare_contact),
  // which turns a nodal mass into the volume it fills.
  const std::vector<double>& volume_per_mass() const { return volume_per_mass_; }
  // What the walls took in the last step, over every continuum (WallEnergy's work, work_sum and
  // rule_dissipation; the rest of it is not summed).
  const WallEnergy& wall_step() const { return wall_step_; }
  const SolverSettings<D>& settings() const { return settings_; }
  int threads() const { return transfer_.threads(); }
  // Seconds spent in each phase since the solver was made.
  const PhaseTimer& phase_times() const { return timer_; }

  // Grid-smoothed particle stresses (Thesis eq. 4.18-4.19; mpm_state.hpp). `out` is resized to
  // the particle count; the nodal fields of the call are in state().smoothing.
  void smoothed_stress(std::vector<Sym3>& out) { skred::smoothed_stress(state_, out); }

  // Starts a new stage at the current time: the materials (the stage's strength, or held
  // elastic) and the gravity ramp (Thesis eq. 4.13, measured from now; 0: full gravity)
  // change, and displacements, gravity work, strain energy and plastic dissipation are
  // measured from here (mpm_state.hpp).
  void begin_stage(std::vector<Material> materials, double gravity_ramp_time) {
    skred::begin_stage(state_, std::move(materials), gravity_ramp_time);
  }
  const std::vector<Material>& materials() const { return state_.materials; }
  // Local (non-viscous, Cundall type) damping of the current stage, 0 <= alpha < 1 (0: off):
  // each node feels -alpha |f_i| sign(v_i^k) per component, f_i its unbalanced force
  // (grid_update). A stage setting: the run driver sets it as each stage begins or resumes.
  void set_local_damping(double alpha) { local_damping_ = alpha; }
  double local_damping() const { return local_damping_; }

  // Checkpoint and restart: the state to save, and restoring it with the current stage's
  // materials. The next step maps the grid afresh from the particles, which gives the same
  // points bit for bit as the fused map (test FusedMapEqualsAFreshMapEveryStep).
  // (The explicit solver prescribes no velocities: it reports no boundary force.)
  SolverClock clock() const { return state_.clock; }
  void restore(const SolverClock& c, std::vector<Material> materials) {
    skred::restore(state_, c, std::move(materials));
    state_.clock.boundary_force = {};
    grid_mapped_ = false;
  }

 private:
  friend struct UpdateStressFirst;
  friend struct UpdateStressLast;
  friend struct AveragedScheme;
  template <class K, class Scheme>
  StepStatus step_with(const K& kernel);
  template <class F>
  decltype(auto) dispatch(F&& f) {
    return with_kernel<D>(settings_.interpolation, settings_.quadrature_points, f);
  }

  // The end of a phase: true if no point failed (first_bad == LONG_MAX), else status_ names
  // the first failing point and why. Split among processes, every process learns of the failure
  // and status_ names the point by its index over all of them, in rank order.
  bool phase_ok(long first_bad, const char* why) {
    if (const Processes& procs = state_.processes; procs.distributed()) {
      const long offset = procs.offset(static_cast<long>(state_.points.size()));
      first_bad = procs.min(first_bad == LONG_MAX ? LONG_MAX : offset + first_bad);
    }
    if (first_bad == LONG_MAX) return true;
    status_ = {false, first_bad, why};
    return false;
  }

  // Phases of one step (Thesis §2.2.1, §4.4), called in order by the scheme types. Each is
  // one tight parallel loop over the points or over the box of grid nodes; a phase that
  // finds a failing point sets status_ (phase_ok) and returns false. What each reads and
  // writes (points: state_.points; grid: fields_, or each body's with contact; the grid
  // phases are functions of one continuum's fields, grid_phases.hpp):
  //   map_mass_momentum            x_p, m_p, v_p (, half0, F)  -> m_i, p_i; the stored N_ip
  //   nodal_velocity               m_i, p_i                   -> v_i^k
  //   stress_update_and_internal_force
  //                                v_i^k; x_p, F_p, sigma_p   -> sigma_p, F_p, state; f_i^int;
  //                                                              strain energy, plastic work
  //   internal_force               sigma_p, V_p               -> f_i^int
  //   grid_update                  m_i, p_i, v_i^k, f_i^int   -> a_i, v_move, v_i^{k+1}; wall work
  //   contact                      each body's v_i, a_i       -> a_i, v_move, v_i^{k+1}; contact work
  //   velocity_and_remap           a_i (, v_i^{k+1}); v_p     -> v_p (, C_p); p~_i
  //   remap_velocity               m_i, p~_i                  -> v~_i; m_i, p_i cleared
  //   stress_update_move_and_map   v~_i, v_move; x_p, F_p     -> sigma_p, F_p, x_p; next m_i, p_i
  //   velocity_move_and_map        a_i, v_move (, v_i^{k+1})  -> v_p (, C_p), x_p; next m_i, p_i;
  //                                                              gravity work
  template <class K>
  bool map_mass_momentum(const K& kernel);  // eq. 2.53-2.54
  template <class K>
  void map_body_fields(const K& kernel);  // Paper III §C.2.7
  void nodal_velocity();                  // eq. 2.23
  template <class K>
  bool stress_update_and_internal_force(const K& kernel, double dt_stress);
  template <class K>
  bool stress_update_cell_volumetric(const K& kernel, double dt_stress);  // volumetric_averaging.hpp
  template <class K, class Sel>
  double damping_work_at_points(const K& kernel, const GridFields<D>& f, Sel sel);
  template <class K, class CentreShear>
  bool stress_phase(const K& kernel, double dt_stress, CentreShear);  // (std::bool_constant)
  template <class K, class Sel>
  void cell_divergence(const K& kernel, const Vec<D>* vel, Sel sel);  // volumetric_averaging_impl.hpp
  template <class Sel>
  void cell_pressure(Sel sel);  // volumetric_averaging_impl.hpp
  template <class Sel>
  void cell_sums(Sel sel, const double* value, double* sum, double* weight);  // volumetric_averaging_impl.hpp
  template <class K>
  void internal_force(const K& kernel);          // eq. 2.51
  void grid_update();                            // eq. 2.49, 5.8-5.11
  void continuum_grid_update(GridFields<D>& f);  // grid_update of one continuum's fields
  GridStep<D> grid_step() const;                 // what the grid phases read (grid_phases.hpp)
  void contact();                                // Paper III §C.2.7, C.36
  template <class K>
  void velocity_and_remap(const K& kernel);  // eq. 2.56, §4.4 step 6
  void remap_velocity();                     // v~_i = p~_i / m_i
  template <class K>
  bool stress_update_move_and_map(const K& kernel, double dt_stress);
  template <class K>
  bool velocity_move_and_map(const K& kernel);  // eq. 2.55-2.56
  // XPIC(m): the nodal velocity the points take, into velocity_next (before m_i, p_i are cleared).
  template <class K>
  void xpic_grid_velocity(const K& kernel);
  bool axisymmetric() const { return D == 2 && settings_.geometry == Geometry::Axisymmetric; }
  // Whether the grid must be mapped afresh from the points (their number changed, or
  // particles_changed()): in any process, then in all.
  bool needs_map() {
    if (mapped_points_ != state_.points.size()) grid_mapped_ = false;
    return state_.processes.max(grid_mapped_ ? 0L : 1L) > 0;
  }
  // The points' sums over the processes (process_sums.hpp).
  template <class... T>
  void sum_points(T&... v) const {
    sum_over_processes(state_.processes, v...);
  }
  // The mean normal stress the cell-averaged volumetric strain pairs with: over the in-plane axes,
  // and the hoop axis too in axisymmetric geometry (volumetric_averaging.hpp).
  double mean_stress(const PointStress<D>& s) const {
    return axisymmetric() ? (s[0] + s[1] + s[2]) / 3.0 : sym_block<D>(s).trace() / D;
  }
  void clear_mass_momentum();
  // The grid phases per body in a run with contact (contact.cpp).
  void body_nodal_velocity();
  void body_grid_update();
  void body_remap_velocity();
  void clear_body_mass_momentum();
  void prepare_contact();  // per-body data of the contact phase (contact.cpp)
  template <class Get, class Set, class Start>
  ContactLoss couple_nodes(Get&& get, Set&& set, Start&& start);
  template <class Field>
  void couple_start(Field&& field, bool shift);
  // fn(fields, points, body) for each continuum: the centre-of-mass fields and every point
  // without contact; each deformable body's fields and points with it.
  template <class Fn>
  void for_each_continuum(Fn&& fn);
  // Rigid bodies' points: velocity set, moved (if their velocity is not zero) and mapped.
  void rigid_velocity();
  template <class K>
  long move_and_map_rigid(const K& kernel, Extent<D>& all);
  // The maps that end a step, into a continuum's fields: the threads' parts over its moved
  // points' reach, then the processes' (with contact, once every body's points are mapped, over
  // the whole box of the step: set_next_box; each process needs every body's fields on it).
  void reduce_moved(const Extent<D>& extent, GridFields<D>& f) {
    if (!contact_on()) {
      transfer_.set_box(extent);
      transfer_.reduce(f.mass.data(), f.momentum.data());
    } else {
      transfer_.reduce_threads(extent, f.mass.data(), f.momentum.data());
    }
  }
  // The next step's box, of every moved point (`all`; without contact reduce_moved set it, the
  // one continuum's extent being `all`).
  void set_next_box(const Extent<D>& all) {
    if (!contact_on()) return;
    transfer_.set_box(all);
    body_box_ = transfer_.box();
    for (auto& f : bodies_) transfer_.sum_processes(f.mass.data(), f.momentum.data());
  }
  // Each body's nodal stress sums for the traction rule of contact (contact_impl.hpp).
  template <class K>
  void map_body_stress(const K& kernel);

  MpmState<D> state_;  // points, grid, materials, clock and energy totals (shared core)
  Transfer<D> transfer_;
  const SolverSettings<D> settings_;    // as constructed: the run's state is in the members below
  VelocityTransferRule transfer_rule_;  // the particle velocity update (velocity_transfer.hpp)
  Boundaries<D> boundaries_;
  WallBox<D> walls_;
  std::array<bool, 2 * D> stopping_walls_{};  // the sides that stopped a node this step (WallEnergy)
  GridFields<D> fields_;
  std::vector<BodyFields<D>> bodies_;
  NodeBox<D> body_box_;                  // where the body fields were last written
  std::vector<double> contact_sums_;     // per-thread work sums of the contact phase
  std::vector<double> volume_per_mass_;  // per body (volume_per_mass())
  bool contact_traction_ = false;        // some pair decides contact by the traction rule
  // Per body: the outline normal at each node of a fixed rigid body with an outline (else empty)
  std::vector<std::vector<Vec<D>>> outline_normals_;
  ContactLoss contact_step_;  // the last step's contact work
  WallEnergy wall_step_;      // the last step's wall work (wall_step)
  PhaseTimer timer_;
  // True when the grid's mass and momentum and the stored weighting functions are those of
  // the particles' current state: the last phase of a step maps the next step's.
  bool grid_mapped_ = false;
  std::size_t mapped_points_ = 0;        // the number of points the map was made for
  GridArray<Vec<D>> material_velocity_;  // v_i of material_mean_speed(), over the box
  // det F_p^{k+1} of every point, written by the stress phase (3D GIMP) for the move phase of the
  // same step, which then need not read F (docs/method.md, "det F from the stress phase"); fresh
  // from that phase to the end of the step (the move is the step's last phase).
  std::vector<double> det_f_;
  bool det_f_fresh_ = false;
  Vec<D> gravity_now_ = Vec<D>::Zero();
  double local_damping_ = 0.0;
  VolumetricAveraging<D> volumetric_;  // cell sums of the volumetric averaging
  StepStatus status_;
};

}  // namespace skred
