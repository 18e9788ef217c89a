#include "app/omp_wait.hpp"

#include <unistd.h>

#include <cstdlib>

namespace skred {

void apply_default_omp_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("GOMP_SPINCOUNT", kDefaultSpinCount, 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // not re-executed: libgomp keeps its default, say so honestly
}

}  // namespace skred
