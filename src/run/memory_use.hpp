// The process's memory as the kernel counts it (/proc/self/status), for `skred bench` and
// summary.json: the peak resident set and the resident set now, whose difference over a run is
// what the run's points and grid cost beyond the idle process (code, libraries, PETSc).
#pragma once

namespace skred {

// Peak resident set size of this process in bytes (VmHWM), 0 if unknown.
double peak_rss_bytes();
// Resident set size of this process now in bytes (VmRSS), 0 if unknown.
double current_rss_bytes();
// Starts the peak over from the resident set now (/proc/self/clear_refs, "5"); false if the
// kernel does not allow it. A distributed run's set-up peaks once per process (in_turns).
bool reset_peak_rss();

}  // namespace skred
