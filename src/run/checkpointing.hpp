// Checkpoint and restart of a run, and stopping on SIGINT/SIGTERM. run_simulation keeps the
// state of the run that is not in the solver or the particles in a RunProgress; Checkpointing
// saves it with the particles and the solver's clock (io/checkpoint.hpp), restores it, and
// watches for signals between steps.
#pragma once
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/checkpoint.hpp"
#include "io/pvd_writer.hpp"
#include "io/series_writer.hpp"
#include "run/hazard_maps.hpp"
#include "run/simulation.hpp"
#include "run/slide_measures.hpp"

namespace skred {

// Where a run stands between two steps, beyond the particles and the solver.
template <int D>
struct RunProgress {
  std::uint64_t stage = 0;    // the current stage (the number of stages once all are done)
  bool in_stage = false;      // the current stage has begun: stage_* and tracker are live
  long stage_first_step = 0;  // solver step at which the current stage began
  double stage_start = 0.0;   // and its time
  double next_output = 0.0, next_series = 0.0;
  std::vector<double> frame_times;      // time of every frame written so far
  std::vector<StageMeasures> finished;  // measures of the finished stages
  StageTracker<D> tracker;              // of the current stage
  long checkpoint_every = 0;            // as the run was started (a resume keeps it)
  HazardMaps maps;                      // 3D: the hazard maps so far (off in 2D)
  std::vector<std::string> map_files;   // the stages' map files written so far
};

// Catches SIGINT/SIGTERM from now on (for the command line, before the scenario is read and
// the points built): a run with RunOptions::handle_signals then stops at its first step.
void watch_stop_signals();

// The name of the checkpoint file in an output folder.
std::filesystem::path checkpoint_file(const std::filesystem::path& outdir);
// A run split among N processes checkpoints in pieces, one per process (its points and the run's
// state), checkpoint.<rank>-of-<N>.skc, and the first process then writes checkpoint.manifest
// naming the count, the step and each piece's points: the pieces it names are the newest
// checkpoint (the last written of checkpoint.skc and the manifest is; writing one removes the
// other).
std::filesystem::path checkpoint_piece(const std::filesystem::path& outdir, int rank, int processes);
std::filesystem::path checkpoint_manifest(const std::filesystem::path& outdir);
// What process `rank` of `processes` reads of a checkpoint in pieces of `points` points each, on
// another count: its share of the points in the pieces' order, [m rank / N, m (rank + 1) / N) of
// m, as runs [first, end) of the pieces that hold it. A process whose share is empty still reads
// one piece (none of its points), for the run's state.
struct PieceRun {
  long piece = 0, first = 0, end = 0;
};
std::vector<PieceRun> pieces_to_read(const std::vector<long>& points, int rank, int processes);
// The scenario hash a checkpoint is bound to: FNV-1a of the scenario file's text (of its
// source name when it is not a file).
std::uint64_t scenario_hash(const std::string& source);

// Reads checkpoint `file` of scenario `s`: the particles, the solver's clock, the progress and
// the series rows so far. Throws CheckpointError naming the file when it cannot be used.
template <int D>
void load_checkpoint(const std::filesystem::path& file, const ScenarioOf<D>& s, Particles<D>& P,
                     SolverClock& clock, RunProgress<D>& at, std::vector<SeriesRow>& series);

template <int D>
class Checkpointing {
 public:
  // Installs the SIGINT/SIGTERM handlers when opt.handle_signals (restored on destruction).
  Checkpointing(const ScenarioOf<D>& s, const std::filesystem::path& outdir, const RunOptions& opt);
  ~Checkpointing();
  Checkpointing(const Checkpointing&) = delete;
  Checkpointing& operator=(const Checkpointing&) = delete;

  // When opt.restart is set: reads it into the particles, the solver (clock and the current
  // stage's materials), the progress and the output indexes and series; returns true. Throws
  // CheckpointError for a checkpoint that cannot be used. Next to a checkpoint.manifest (a
  // checkpoint in pieces), a run on as many processes reads its own piece (and goes on bit for
  // bit); on another count, each process reads the pieces that hold its share (pieces_to_read),
  // and keeps its share of a single checkpoint.skc. Collective.
  bool restore(Particles<D>& P, Integrator<D>& solver, RunProgress<D>& at, SeriesWriter& series,
               PvdWriter& particles_pvd, PvdWriter& grid_pvd);
  // After a step: writes the periodic checkpoint when one is due; when a signal arrived (at any
  // of the processes) or the step is opt.stop_at_step, writes one and returns true: the run
  // stops. Collective.
  bool after_step(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
                  const SeriesWriter& series);
  // At the end of a completed run (when checkpoints are enabled).
  void at_end(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
              const SeriesWriter& series);
  // Writes the checkpoint now (recording the checkpoint period in `at`).
  void write(const Particles<D>& P, const Integrator<D>& solver, RunProgress<D>& at,
             const SeriesWriter& series);

 private:
  const ScenarioOf<D>& s_;
  Processes procs_;
  std::filesystem::path outdir_, file_, restart_;
  long every_ = 0, stop_at_ = -1;
  bool signals_ = false;
  struct sigaction old_int_ {
  }, old_term_{};
  void load_pieces(const std::filesystem::path& manifest, Particles<D>& P, SolverClock& c, RunProgress<D>& at,
                   std::vector<SeriesRow>& rows) const;
};

}  // namespace skred
