// The output folder of a run: what in it is skred's, so that a new run never mixes with an
// earlier one (stale frames beside new ones) and --overwrite removes only skred's own files.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace skred {

// skred's files in `dir` (not recursive): particles_NNNNNN.vtu, grid_NNNNNN.vtr,
// particles.pvd, grid.pvd, series.csv, summary.json, scenario.toml, checkpoint.skc,
// report.html, the pictures/ that `skred render` wrote (PNG and GIF), a sweep's sweep.csv
// (a refinement study's refine.csv) and run_NNN/ folders, and the NAME.tmp of any of these left by a crash.
// Sorted.
std::vector<std::filesystem::path> run_files(const std::filesystem::path& dir);

// Makes `dir` ready for a new run: creates it if missing. If it holds an earlier run's
// files, throws std::runtime_error naming the folder and what it holds unless `overwrite`,
// in which case those files (only those) are removed first; `keep` (e.g. the scenario file
// being run, when it lies in `dir`) is never removed.
void prepare_output_folder(const std::filesystem::path& dir, bool overwrite,
                           const std::filesystem::path& keep = {});

}  // namespace skred
