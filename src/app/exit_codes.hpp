// The exit codes of the skred command (README, "Exit codes"); scripts may rely on them.
#pragma once

namespace skred::exit_code {

inline constexpr int kSuccess = 0;   // completed (run, resume, sweep), valid (check)
inline constexpr int kError = 1;     // I/O error, unusable checkpoint, OUTDIR holding a run
inline constexpr int kUnstable = 2;  // unstable, a point left the grid, or an implicit step did not converge
inline constexpr int kInterrupted = 3;      // SIGINT/SIGTERM: checkpoint written, resume it
inline constexpr int kUsage = 4;            // bad command line
inline constexpr int kInvalidScenario = 5;  // the scenario file is invalid (file:line:col: key)
inline constexpr int kMissingPython = 6;    // render/report/sweep picture: Python or its modules missing

}  // namespace skred::exit_code
