// A refinement study of the user's own scenario (issue 12; Thesis fig. 5.18): the scenario at
// its cell size h and at h/2, h/4, ... with the same points per cell, a fixed time step halved
// with the cell (so c dt / h stays) and a splitting cap given in the scenario raised with the
// points, once per velocity transfer asked for; one table row per
// run with the last stage's slide measures, and how much each halving moved the runout.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "io/summary_writer.hpp"
#include "post/grid_convergence.hpp"
#include "scenario/scenario.hpp"

namespace skred {

struct RefineOptions {
  int levels = 3;                      // h, h/2, ..., h / 2^(levels - 1); 2 to 5
  std::vector<std::string> transfers;  // solver.velocity_transfer per series; empty: the scenario's
  int threads = 1;
  bool progress = true;
  // Called on every run's scenario before the first run starts (`skred refine`: whether it fits
  // the machine's memory); it throws to refuse.
  std::function<void(const AnyScenario&)> check;
};

struct RefineRow {
  std::string transfer;  // as asked ("" for the scenario's own)
  int level = 0;         // 0 for h
  double cell_size = 0.0;
  double time_step = 0.0;  // the fixed step of the run; 0 when it comes from the CFL number
  long particles = 0;      // at the end of the run (splitting adds points)
  std::string status;      // "completed", "unstable" or "left_grid"
  std::string folder;      // run folder, relative to the study's folder
  double wall_seconds = 0.0;
  StageMeasures last;  // the last stage's slide measures
};

// The keys that make the scenario's level k of a refinement study (refine's and fos's): the cell
// h / 2^k, a fixed time step halved with it (so c dt / h stays), and a splitting cap given in the
// scenario times 2^(d k), as the points grow.
std::vector<std::pair<std::string, double>> refined_keys(const AnyScenario& base, int level);

// Throws std::invalid_argument unless 2 <= levels <= 5 and the transfers are distinct.
void check_refine_options(const RefineOptions& opt);

// Runs every level of every transfer into OUTDIR/run_NNN/ (in the table's order) and writes
// OUTDIR/refine.csv and OUTDIR/extrapolation.csv (both rewritten atomically after every run). Every run's
// scenario is validated before the first starts; a bad value throws ScenarioError naming the file and key.
std::vector<RefineRow> run_refine(const std::string& scenario_file, const std::filesystem::path& outdir,
                                  const RefineOptions& opt);

// The text of refine.csv: transfer, level, cell_size, time_step, particles, status, folder,
// wall_seconds, stage, ended_by, runout, runout_change (the relative change from the level
// before, of the same transfer; nan at level 0), max_displacement, height_end, gravity_work,
// plastic_dissipation, final_mean_speed.
std::string refine_table(const std::vector<RefineRow>& rows);

// (b - a) / a, or NaN when a is not positive (a runout of zero cannot be refined relative to).
double relative_change(double a, double b);

// Richardson's extrapolation of one measure over a transfer's last three levels (post/grid_convergence.hpp).
struct RefineExtrapolation {
  std::string transfer;
  std::string quantity;    // "runout" or "gravity_work"
  double cell_size = 0.0;  // the finest of the three
  double fine = 0.0, medium = 0.0, coarse = 0.0;
  GridConvergence estimate;
};

// The extrapolations of the runout and the gravity work (the energy the slide released) of every
// transfer with three levels or more whose last three runs completed, each from its last three
// levels (r = 2).
std::vector<RefineExtrapolation> refine_extrapolations(const std::vector<RefineRow>& rows);

// The text of extrapolation.csv: transfer, quantity, cell_size, fine, medium, coarse, kind, ratio,
// order, extrapolated, approximate_error, extrapolated_error, gci_fine, next_change.
std::string extrapolation_table(const std::vector<RefineExtrapolation>& ex);

// What the study shows, as lines for the terminal: per transfer the runout per level and the
// change per halving, the last halving against the 5 % of issue 12, Richardson's extrapolation of
// the runout and the gravity work (with three levels or more), and, with several transfers, how
// far apart they are at the finest level and, where both extrapolate, as h -> 0.
std::string refine_verdict(const std::vector<RefineRow>& rows);

}  // namespace skred
