// The end-of-run summary (summary.json).
#pragma once
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace skred {

// The slide measures of one stage (filled by run/slide_measures).
struct StageMeasures {
  std::string name;
  double start_time = 0.0, end_time = 0.0;  // [s], simulation time
  long steps = 0;
  std::string ended_by;  // "duration", "rest", "unstable" or "moved" (skred fos: it failed)
  // Runout: how far the front of the moving mass (points displaced more than half a cell)
  // has advanced beyond its start position, towards -x and +x, and the larger of the two.
  double runout_x_min = 0.0, runout_x_max = 0.0, runout = 0.0;
  // 3D only (NaN in 2D, not written): the same towards -z and +z.
  double runout_z_min = NAN, runout_z_max = NAN;
  double max_displacement = 0.0;                // largest point displacement in the stage [m]
  double height_start = 0.0, height_end = 0.0;  // top of the material above its lowest point
  double peak_mean_speed = 0.0, peak_time = 0.0, final_mean_speed = 0.0;  // eq. 5.12
  double gravity_work = 0.0;                                              // eq. 5.13, from the stage start
  double kinetic_energy_change = 0.0;
  double strain_energy = 0.0;  // stored elastic energy change
  double plastic_dissipation = 0.0;
  double plastic_volume = 0.0;  // volume of the points that yielded during the stage
  long plastic_points = 0;
  // Stage time after which the mean speed stayed below the rest speed (or, without a rest
  // criterion, below 1 % of its peak); empty if the material was still moving at the end.
  std::optional<double> stop_time;
  // The speed the rest test and the stop time read (Stage::rest_measure): "points" (eq. 5.12),
  // "material" (sum_i N_ip v_i at the points) or "displacement" (over windows of rest_time).
  std::string rest_measure = "points";
  // Dilation cut-off as a new continuum (Paper III §C.3.2): the points that joined a dilated
  // continuum during the stage, and the stage times of the first and the last move.
  long dilated_points = 0;
  std::optional<double> dilated_first_time, dilated_last_time;
};

struct Summary {
  std::string status;  // "completed", "unstable", "left_grid", "not_converged" (an implicit step),
                       // "interrupted" (SIGINT/SIGTERM) or "error"
  std::string message;
  long steps;
  double simulated_time;
  double end_time;
  long particles;
  long cells;  // product over the axes
  double wall_seconds;
  double particle_updates_per_second;
  int threads;
  std::string scenario;
  std::string interpolation;
  std::string scheme;
  double time_step;
  std::vector<StageMeasures> stages = {};
  // Wall seconds spent in each phase of the time step over the run, in step order.
  std::vector<std::pair<std::string, double>> phase_seconds = {};
  int dimension = 2;                          // written (after cells) only when 3
  std::string version = {}, git_commit = {};  // of the skred that ran (written last)
  // The process's peak resident memory, and that peak less the resident memory before the points
  // were made, per point (the points' and the grid's cost; run/memory_use.hpp). NaN: unknown.
  double peak_memory_bytes = NAN, memory_bytes_per_point = NAN;
  // A run split among processes (written after threads when more than one): their count and the
  // fewest and most points one held at the end; the imbalance is most / mean. The memory is then
  // the sum of the processes' peaks after the set-up, where each built all the points in turn.
  int processes = 1;
  long share_min = 0, share_max = 0;
  double setup_peak_bytes = 0.0;  // the largest peak of a process in the set-up (0: not apart)
  long rebalances = 0;            // how often the shares were evened out (splitting)
  // The most bytes and the most messages (to single processes) any process sent the others per
  // step of this run (parallel/processes.hpp: skred's own exchanges, not PETSc's solves).
  double bytes_per_step = NAN, messages_per_step = NAN;
  // The velocity transfer and volumetric strain the run used (written after the scheme when
  // set; "auto" resolved): xpic_order and xpic_period [h/c] for "xpic", pic_fraction for "flip".
  std::string velocity_transfer = {}, volumetric_strain = {};
  int xpic_order = 0;
  double xpic_period = 0.0, pic_fraction = 0.0;
  // Bishop's factor of safety of the bodies at the start and its critical circle (centre x, y,
  // radius, and the x where it enters and leaves the ground; run/slope_stability.hpp), written
  // after the transfer as "limit_equilibrium" and "slip_circle" when finite: 2D slopes of one soil.
  double limit_equilibrium = NAN;
  std::array<double, 5> slip_circle = {NAN, NAN, NAN, NAN, NAN};
  // Runs with an implicit stage (written after time_step as the object "implicit"): the geometry,
  // the analysis and iteration of the last implicit stage, its linear solver (PETSc's KSP + PC),
  // and the totals over the implicit steps: steps, Newton iterations (linear solves),
  // factorisations, steps that were cut, the largest number of unknowns and the largest factor's
  // memory [bytes] (0 when unknown).
  struct Implicit {
    std::string geometry, analysis, iteration, linear_solver;
    long steps = 0, iterations = 0, factorisations = 0, cut_steps = 0, max_unknowns = 0;
    double max_factor_bytes = 0.0;
    long elastic_fallbacks = 0;  // Newton iterations on the elastic matrix (a singular tangent)
    // [[prescribed_velocity]]: each one's name and force on the material at the end [N/m, N].
    std::vector<std::pair<std::string, std::vector<double>>> forces = {};
  };
  std::optional<Implicit> implicit = {};
  // 3D: the hazard maps' files relative to the output folder (written after "stages" as "maps"
  // when there are any; run/map_files.hpp).
  std::vector<std::string> maps = {};
};

// Writes `s` as one JSON object (keys named as the fields, in field order; "stages" is an
// array of objects keyed like StageMeasures, stop_time null when unset; "phase_seconds" an
// object of phase name to seconds) atomically.
// Strings are escaped (quotes, backslashes, control characters; invalid UTF-8 bytes become
// U+FFFD); real numbers are written as the shortest decimal that reads back to the same
// double, and as null when not finite. Throws std::runtime_error on I/O failure.
void write_summary_json(const std::filesystem::path& file, const Summary& s);

// The JSON string literal (with the surrounding quotes) for `s`.
std::string json_string(const std::string& s);

}  // namespace skred
