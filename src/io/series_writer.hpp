// The per-step time series of global quantities (series.csv).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace skred {

struct SeriesRow {
  long step;
  double time;
  double kinetic_energy;
  double strain_energy;
  double gravity_work;
  double plastic_dissipation;
  double friction_work;          // energy the walls took (EnergyTotals::friction_work)
  double transfer_dissipation;   // energy the velocity transfer took (EnergyTotals)
  double mean_speed;
  double max_speed;
  double momentum_x;
  double momentum_y;
  long num_particles;
  int stage;             // zero-based stage index
  double runout;         // front advance since the stage start [m] (StageTracker::runout)
  long yielding_points;  // points whose last stress update was plastic
  double momentum_z = 0.0;  // 3D runs only (last column)
};

// Collects rows in memory; flush() rewrites the whole file atomically, so the file on disk is
// always complete. Columns:
//   step,time,kinetic_energy,strain_energy,gravity_work,plastic_dissipation,friction_work,
//   transfer_dissipation,total_energy,mean_speed,max_speed,momentum_x,momentum_y,
//   num_particles,stage,runout,yielding_points
// with total_energy = kinetic_energy + strain_energy + plastic_dissipation + friction_work +
// transfer_dissipation - gravity_work (the energy balance; constant up to the time
// integration's error). Gravity work, strain energy
// (stored elastic) and the dissipations are measured from the start of the row's stage. Every real number is written as the
// shortest decimal that reads back to the identical double.
class SeriesWriter {
 public:
  // Nothing is written until the first flush().
  // With momentum_z (3D runs) the rows end with a momentum_z column.
  explicit SeriesWriter(const std::filesystem::path& file, bool momentum_z = false);
  // Flushes rows added since the last flush(); errors are swallowed here (call flush()
  // yourself to see them), so a run that ends by an exception still leaves its series.
  ~SeriesWriter();
  SeriesWriter(const SeriesWriter&) = delete;
  SeriesWriter& operator=(const SeriesWriter&) = delete;

  void add(const SeriesRow& row);
  // Rewrites the file atomically with the header and every row so far. Throws
  // std::runtime_error on I/O failure.
  void flush();

  const std::vector<SeriesRow>& rows() const { return rows_; }
  const std::filesystem::path& file() const { return file_; }

  static const char* header();

 private:
  std::filesystem::path file_;
  std::vector<SeriesRow> rows_;
  bool momentum_z_ = false;
  std::string text_;  // the formatted rows, kept so a flush does not reformat them
  bool dirty_ = false;
};

}  // namespace skred
