// The per-step time series of global quantities (series.csv).
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "solver/implicit_settings.hpp"

namespace skred {

struct SeriesRow {
  long step;
  double time;
  double kinetic_energy;
  double strain_energy;
  double gravity_work;
  double plastic_dissipation;
  double friction_work;         // energy the walls took (EnergyTotals::friction_work)
  double transfer_dissipation;  // energy the velocity transfer took (EnergyTotals)
  double mean_speed;
  double max_speed;
  double momentum_x;
  double momentum_y;
  long num_particles;
  int stage;                        // zero-based stage index
  double runout;                    // front advance since the stage start [m] (StageTracker::runout)
  long yielding_points;             // points whose last stress update was plastic
  double momentum_z = 0.0;          // 3D runs only
  double contact_work = 0.0;        // runs with contact only (Paper III §C.2.7)
  double damping_work = 0.0;        // runs with local damping only
  double material_speed = 0.0;      // runs with a stage that rests on it only (Stage::rest_measure)
  int iterations = 0;               // runs with an implicit stage only: Newton iterations of the step
  double residual = 0.0;            // ... and its final out-of-balance force over the force scale
  double load_work = 0.0;           // ... and the work of the boundary pressures (EnergyTotals)
  BoundaryForces boundary_force{};  // runs with [[prescribed_velocity]]: their forces
};

// The columns only some runs have, in their order after yielding_points.
struct SeriesColumns {
  bool momentum_z = false;      // 3D runs
  bool contact_work = false;    // runs with contact
  bool damping_work = false;    // runs with a locally damped stage
  bool material_speed = false;  // runs with a stage whose rest test reads the material's speed
  bool implicit = false;        // runs with an implicit stage: iterations, residual, load_work
  // Runs with [[prescribed_velocity]]: the force columns' names (force_<name>_<axis>) and their
  // index in SeriesRow::boundary_force.
  std::vector<std::pair<std::string, int>> forces;
};

// Collects rows in memory (for checkpoints). The first flush() writes the file atomically;
// later ones append the new rows with one write (a failed write is cut back), so the file on
// disk always holds the header and whole rows, and a long run's flushes cost only their own
// rows. Columns:
//   step,time,kinetic_energy,strain_energy,gravity_work,plastic_dissipation,friction_work,
//   transfer_dissipation,total_energy,mean_speed,max_speed,momentum_x,momentum_y,
//   num_particles,stage,runout,yielding_points
// with total_energy = kinetic_energy + strain_energy + plastic_dissipation + friction_work +
// transfer_dissipation + contact_work + damping_work - gravity_work - load_work (the energy balance;
// constant up to the time integration's error). 3D runs add a column momentum_z, runs with
// contact a column contact_work (the energy the contact phase took out: friction between
// bodies and the inelastic stop of approaching bodies), runs with a locally damped stage a
// column damping_work (the work of that damping), runs with a stage whose rest test reads
// the material's speed a column material_speed (ExplicitSolver::material_mean_speed), runs
// with an implicit stage the last columns iterations, residual (the Newton iterations of the
// row's step and its final out-of-balance force relative to the step's force scale; 0 in
// explicit stages) and load_work (the work of the boundary pressures and prescribed velocities,
// subtracted in total_energy like the gravity work), and runs with [[prescribed_velocity]] the
// forces of each on the material, force_<name>_x, force_<name>_y (, force_<name>_z).
// Gravity work, strain energy
// (stored elastic) and the dissipations are measured from the start of the row's stage. Every real number is
// written as the shortest decimal that reads back to the identical double.
class SeriesWriter {
 public:
  // Nothing is written until the first flush(). The rows end with the `extra` columns asked for.
  // An empty `file`: the rows are kept (for checkpoints) and nothing is written (the processes
  // of a distributed run besides the first).
  explicit SeriesWriter(const std::filesystem::path& file, SeriesColumns extra = {});
  // Flushes rows added since the last flush(); errors are swallowed here (call flush()
  // yourself to see them), so a run that ends by an exception still leaves its series.
  ~SeriesWriter();
  SeriesWriter(const SeriesWriter&) = delete;
  SeriesWriter& operator=(const SeriesWriter&) = delete;

  void add(const SeriesRow& row);
  // Writes the rows added since the last flush (the first time: the file with its header,
  // atomically). Throws std::runtime_error on I/O failure.
  void flush();

  const std::vector<SeriesRow>& rows() const { return rows_; }
  const std::filesystem::path& file() const { return file_; }

  static const char* header();

 private:
  std::filesystem::path file_;
  std::vector<SeriesRow> rows_;
  SeriesColumns extra_;
  std::string text_;  // the formatted rows not yet written
  bool dirty_ = false;
  bool started_ = false;  // the file was written once: later flushes append

  void format_row(const SeriesRow& r, std::string& out) const;
};

}  // namespace skred
