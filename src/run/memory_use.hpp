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
// kernel does not allow it. A distributed run's set-up peaks before its points are cut in blocks.
bool reset_peak_rss();
// Gives the allocator's free pages back to the kernel (glibc's malloc_trim): after a process of a
// distributed run has dropped points (its set-up's margins, points moved to other blocks), glibc
// keeps their pages for reuse, and the process would hold them for the rest of the run.
void release_free_memory();

}  // namespace skred
