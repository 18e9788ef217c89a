#include "app/omp_wait.hpp"

#include <omp.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
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

}  // namespace

void apply_default_omp_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("GOMP_SPINCOUNT", kDefaultSpinCount, 1) != 0) return;
  unbind_initial_thread();
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // not re-executed: libgomp keeps its default, say so honestly
}

}  // namespace skred
