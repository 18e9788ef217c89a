// The OpenMP wait policy skred runs with. libgomp's default lets an idle thread spin for
// about 300,000 iterations at every barrier; on a machine where another process holds a
// core, the spinning thread and the descheduled one then take turns and a 2-thread run
// becomes many times slower than 1 thread. skred defaults to a short spin instead.
#pragma once

namespace skred {

// The spin count skred sets (GOMP_SPINCOUNT) when the user has set neither OMP_WAIT_POLICY
// nor GOMP_SPINCOUNT (scripts/bench.sh --busy measures both sides).
inline constexpr const char* kDefaultSpinCount = "1000";

// libgomp reads its environment once, when it is loaded, before main: so when neither
// variable is set this sets GOMP_SPINCOUNT and re-executes the program (/proc/self/exe) with
// the same arguments. Returns (without changing anything the user set) if a variable is
// already set or the re-execution fails. Thread binding the user asked for is kept (the
// process gets back the CPUs of every place before it re-executes). Call first thing in
// main. (Setting either variable, e.g. under a debugger, avoids the re-execution.)
void apply_default_omp_wait_policy(char** argv);

}  // namespace skred
