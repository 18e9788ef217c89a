// The MPM's own factor of safety of a slope by strength reduction (`skred fos`): the scenario's
// slide stage (its last stage that lets the soil yield) is run with c, tan(phi) and tan(psi)
// divided by a factor f (`[[stage]] strength_reduction`, times the stage's own), bracketing the
// f at which the slope starts to fail by bisection. "Fails" means some point moved more than a
// share of the material's height within the stage, which runs its whole duration (the rest
// test would end a slowly starting failure as standing) unless it fails: the run ends there. The factor found
// is set beside Bishop's limit equilibrium (run/slope_stability.hpp; docs/method.md, "Limit equilibrium").
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/summary_writer.hpp"
#include "post/grid_convergence.hpp"
#include "scenario/scenario.hpp"

namespace skred {

struct FosOptions {
  double low = 0.5, high = 2.0;  // the bracket: the slope must stand at `low` and fail at `high`
  int steps = 5;                 // bisections after the two ends (the bracket shrinks by 2^steps)
  double moved = 0.01;           // fails: a displacement above this share of the height
  int levels = 1;                // cell sizes h, h/2, ..., each bisected alike (1 to 4; as `skred refine`'s)
  int threads = 1;
  bool progress = true;
  // Called on every run's scenario before it starts (`skred fos`: whether it fits the
  // machine's memory); it throws to refuse.
  std::function<void(const AnyScenario&)> check;
};

struct FosRun {
  double factor = 1.0;  // the strength-reduction factor f
  int level = 0;        // 0 for the scenario's cell size h, k for h / 2^k
  double cell_size = 0.0;
  std::string status;  // "completed", "unstable" or "left_grid"
  std::string folder;  // run folder, relative to the study's folder
  bool fails = false;
  double threshold = NAN;  // the displacement above which it fails [m]
  StageMeasures stage;     // the slide stage's measures
};

// One cell size's bracket.
struct FosLevel {
  double cell_size = 0.0;
  double stands = NAN, fails = NAN;  // NaN: the ends did not bracket the onset
  bool fails_at_low = false;         // the slope failed already at --range's LOW
  double midpoint() const { return 0.5 * (stands + fails); }
};

struct FosResult {
  std::vector<FosRun> runs;          // in the order run
  std::string stage;                 // the slide stage's name
  std::vector<FosLevel> levels;      // one per cell size, coarsest first
  double stands = NAN, fails = NAN;  // the finest level's bracket (NaN: the ends did not bracket)
  double limit_equilibrium = NAN;    // Bishop's F, where computed
};

// Richardson's extrapolation (post/grid_convergence.hpp) of the brackets' midpoints of the last
// three levels, or nullopt when fewer than three levels bracketed the onset.
std::optional<GridConvergence> fos_extrapolation(const FosResult& r);

// Throws std::invalid_argument unless 0 < low < high, 0 <= steps <= 12, 0 < moved < 1 and
// 1 <= levels <= 4.
void check_fos_options(const FosOptions& opt);

// Per level (the cell h, then h/2, ... as `skred refine` makes them), runs the ends of the bracket,
// then bisects while they bracket the onset, into OUTDIR/run_NNN/, rewriting OUTDIR/fos.csv after
// every run. Throws ScenarioError for a
// scenario without a stage that lets the soil yield.
FosResult run_strength_reduction(const std::string& scenario_file, const std::filesystem::path& outdir,
                                 const FosOptions& opt);

// fos.csv: factor, status, folder, fails, max_displacement, height_start, threshold, runout,
// ended_by, stage_time (how long the stage ran: a failing run's time to fail), gravity_work,
// plastic_dissipation, limit_equilibrium (Bishop's F, nan where not computed), level, cell_size;
// one row per run, in the order run.
std::string fos_table(const FosResult& r);

// What the study shows, for the terminal: the bracket per cell size, or which end failed to
// bracket, with three levels or more the onset extrapolated to h -> 0, and Bishop's F beside it.
std::string fos_verdict(const FosResult& r, const FosOptions& opt);

}  // namespace skred
