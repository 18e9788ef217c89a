// The OpenMP wait policy skred runs with. libgomp's default lets an idle thread spin for
// about 300,000 iterations at every barrier; on a machine where another process holds a
// core, the spinning thread and the descheduled one then take turns and a 2-thread run
// becomes many times slower than 1 thread. skred chooses the spin from the machine's load as
// it starts: a short spin when other processes hold CPUs the run needs, a longer one when the
// machine is idle, where a thread that sleeps at a barrier costs a wake-up (docs/method.md,
// "A wait chosen from the load").
#pragma once

#include <string>
#include <string_view>

namespace skred {

// The spin counts skred sets (GOMP_SPINCOUNT) when the user has set neither OMP_WAIT_POLICY
// nor GOMP_SPINCOUNT (scripts/bench.sh --busy measures them).
inline constexpr const char* kShortSpinCount = "1000";  // other processes hold CPUs
inline constexpr const char* kLongSpinCount = "10000";  // the machine is idle

// The environment variable that tells the re-executed image why its spin was chosen
// ("idle 10000", "busy 1000"; it names the spin, so a GOMP_SPINCOUNT the user set beneath an
// inherited marker is still reported as the user's).
inline constexpr const char* kWaitChoiceVariable = "SKRED_OMP_WAIT";

// The running count of /proc/loadavg's text ("0.10 0.80 1.40 2/345 6789" -> 2): the tasks of
// the whole machine running or ready to run, the reader among them; -1 if malformed.
int running_tasks_of(std::string_view loadavg);

// The threads a command line asks for (--threads N or --threads=N), else OMP_NUM_THREADS's
// first value, else `cpus`.
int requested_threads(char** argv, const char* omp_num_threads, int cpus);

// The long spin when the run's threads fit beside the other processes' tasks (`others`, the
// median of 15 reads over 28 ms) on the CPUs this process may use; the short spin otherwise,
// and for one thread, which never waits at a barrier.
bool machine_idle_for(int others, int cpus, int threads);

// libgomp reads its environment once, when it is loaded, before main: so when neither
// variable is set this chooses the spin, sets GOMP_SPINCOUNT and re-executes the program
// (/proc/self/exe) with the same arguments. Returns (without changing anything the user set)
// if a variable is already set or the re-execution fails. Thread binding the user asked for
// is kept (the process gets back the CPUs of every place before it re-executes). Call first
// thing in main. (Setting either variable, e.g. under a debugger, avoids the re-execution.)
void apply_default_omp_wait_policy(char** argv);

// One line for the bench's report: the spin in force and who chose it.
std::string omp_wait_description();

}  // namespace skred
