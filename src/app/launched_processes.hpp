// How many processes an MPI launcher started together with this one: MPI is started only then
// (parallel/processes.hpp). `run`, `resume` and `bench` split among them; the other commands run
// in one process, and N copies of them would write one output folder at once, so they refuse.
#pragma once
#include <cerrno>
#include <cstdlib>
#include <string>

namespace skred {

struct Launch {
  long processes = 1;
  std::string variable;  // the launcher's variable that gave the count ("" when started alone)
};

// The count from the variables the launchers set in each process: OpenMPI's
// OMPI_COMM_WORLD_SIZE, and PMI_SIZE (MPICH's Hydra, Intel MPI, srun with PMI).
inline Launch launched_processes() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* text = std::getenv(name);
    if (!text || !*text) continue;
    char* end = nullptr;
    errno = 0;
    const long n = std::strtol(text, &end, 10);
    if (errno == 0 && *end == '\0' && n > 1) return {n, name};
  }
  return {};
}

// This process's rank among them, from the same launchers' OMPI_COMM_WORLD_RANK or PMI_RANK
// (0 when started alone), for a message only the first should print before MPI starts.
inline long launched_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"})
    if (const char* text = std::getenv(name); text && *text) return std::strtol(text, nullptr, 10);
  return 0;
}

}  // namespace skred
