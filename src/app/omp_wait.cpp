#include "app/omp_wait.hpp"

#include <omp.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <vector>

namespace skred {

namespace {

// libgomp binds the initial thread to the first place as it loads when the user asks for
// binding (OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY). The re-executed image would inherit
// that one-place mask, see no other CPU and run every thread there (on two threads, half the
// speed). So the process gets back every CPU of the places first: the new image then forms the
// same places and binds its threads to them as asked.
void unbind_initial_thread() {
  const int places = omp_get_num_places();
  if (places <= 0) return;  // no places: nothing was bound
  cpu_set_t all;
  CPU_ZERO(&all);
  std::vector<int> ids;
  for (int p = 0; p < places; ++p) {
    ids.resize(static_cast<std::size_t>(omp_get_place_num_procs(p)));
    omp_get_place_proc_ids(p, ids.data());
    for (const int id : ids)
      if (id >= 0 && id < CPU_SETSIZE) CPU_SET(id, &all);
  }
  if (CPU_COUNT(&all) > 0) sched_setaffinity(0, sizeof all, &all);
}

int usable_cpus() {
  cpu_set_t mine;
  if (sched_getaffinity(0, sizeof mine, &mine) != 0) return 1;
  return CPU_COUNT(&mine);
}

// A positive integer at the start of `text`, or 0.
int leading_count(std::string_view text) {
  int n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  return ec == std::errc() && n > 0 ? n : 0;
}

// The other processes' tasks running or ready to run: the median of `samples` reads of
// /proc/loadavg 2 ms apart. A process that computes is seen in every read; one that passes
// (a pipe's reader starting, a process exiting) in a few, and the median leaves it out.
// Negative if it cannot be read.
int other_runnable_tasks(int samples) {
  std::vector<int> others;
  for (int i = 0; i < samples; ++i) {
    if (i > 0) {
      const timespec pause{0, 2'000'000};
      nanosleep(&pause, nullptr);
    }
    std::ifstream in("/proc/loadavg");
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const int running = running_tasks_of(text);
    if (running < 1) return -1;
    others.push_back(running - 1);  // this process is running as it reads
  }
  std::nth_element(others.begin(), others.begin() + samples / 2, others.end());
  return others[static_cast<std::size_t>(samples / 2)];
}

}  // namespace

int running_tasks_of(std::string_view loadavg) {
  // Three load averages, then "running/total".
  std::size_t at = 0;
  for (int field = 0; field < 3; ++field) {
    at = loadavg.find(' ', at);
    if (at == std::string_view::npos) return -1;
    at = loadavg.find_first_not_of(' ', at);
    if (at == std::string_view::npos) return -1;
  }
  const std::string_view rest = loadavg.substr(at);
  const std::size_t slash = rest.find('/');
  if (slash == std::string_view::npos || slash == 0) return -1;
  int running = -1;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + slash, running);
  return ec == std::errc() && end == rest.data() + slash ? running : -1;
}

int requested_threads(char** argv, const char* omp_num_threads, int cpus) {
  for (int i = 1; argv[i]; ++i) {
    const std::string_view arg = argv[i];
    if (arg == "--threads" && argv[i + 1]) {
      if (const int n = leading_count(argv[i + 1])) return n;
    } else if (arg.starts_with("--threads=")) {
      if (const int n = leading_count(arg.substr(std::strlen("--threads=")))) return n;
    }
  }
  if (omp_num_threads)
    if (const int n = leading_count(omp_num_threads)) return n;
  return cpus;
}

bool machine_idle_for(int others, int cpus, int threads) {
  return threads > 1 && others >= 0 && threads + others <= cpus;
}

void apply_default_omp_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  unbind_initial_thread();  // first: the CPUs counted below are the places' CPUs
  const int cpus = usable_cpus();
  const int threads = requested_threads(argv, std::getenv("OMP_NUM_THREADS"), cpus);
  // The load is read (28 ms) only where it can decide: more than one thread, on enough CPUs.
  const bool idle =
      threads > 1 && threads <= cpus && machine_idle_for(other_runnable_tasks(15), cpus, threads);
  const char* spin = idle ? kLongSpinCount : kShortSpinCount;
  if (setenv("GOMP_SPINCOUNT", spin, 1) != 0) return;
  setenv(kWaitChoiceVariable, (std::string(idle ? "idle " : "busy ") + spin).c_str(), 1);
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // not re-executed: libgomp keeps its default, say so honestly
  unsetenv(kWaitChoiceVariable);
}

std::string omp_wait_description() {
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  const char* choice = std::getenv(kWaitChoiceVariable);
  if (const char* policy = std::getenv("OMP_WAIT_POLICY"))
    return std::string("OMP_WAIT_POLICY=") + policy + " (set by the user)";
  if (!spin) return "libgomp's default spin (skred could not re-execute itself to set its own)";
  // skred's own choice only if the marker names this spin (else the user set GOMP_SPINCOUNT).
  const std::string_view marker = choice ? choice : "";
  if (marker == std::string("idle ") + spin)
    return std::string("spin ") + spin + " (the machine was idle as the run started)";
  if (marker == std::string("busy ") + spin)
    return std::string("spin ") + spin +
           " (other processes held CPUs as the run started, or one thread, or more threads than CPUs)";
  return std::string("spin ") + spin + " (GOMP_SPINCOUNT set by the user)";
}

}  // namespace skred
