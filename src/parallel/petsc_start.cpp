// PETSc's start and stop (petsc_start.hpp).
#include "parallel/petsc_start.hpp"

#include <petscsys.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include "parallel/processes.hpp"

namespace skred {

std::string petsc_failure(int code, const char* call) {
  const char* text = nullptr;
  PetscErrorMessage(static_cast<PetscErrorCode>(code), &text, nullptr);
  return std::string("PETSc: ") + call + " failed: " + (text ? text : "unknown error");
}

void start_petsc() {
  static std::once_flag once;
  std::call_once(once, [] {
    PetscBool started = PETSC_FALSE;
    PetscInitialized(&started);
    if (started) return;
    // A process that mpirun did not start is an MPI singleton: OpenMPI's isolated singleton
    // start, with no transport but to itself, takes 0.05 s instead of 0.4 s (measured
    // 2026-12-02). The user's own settings win (setenv does not overwrite).
    if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMIX_RANK")) {
      setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
      setenv("OMPI_MCA_btl", "self", 0);
      setenv("OMPI_MCA_pml", "ob1", 0);
    }
    // PETSc's own signal handlers would take SIGINT/SIGTERM from skred's checkpointing
    // (run/checkpointing.hpp) and turn a crash into an MPI abort: off.
    const char* given = std::getenv("PETSC_OPTIONS");
    setenv("PETSC_OPTIONS", (std::string(given ? given : "") + " -no_signal_handler").c_str(), 1);
    if (const PetscErrorCode code = PetscInitializeNoArguments(); code != 0)
      throw std::runtime_error(petsc_failure(code, "PetscInitialize"));
    // Errors come back as codes instead of printed traces.
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    const auto stop = [] {
      PetscBool stopped = PETSC_FALSE;
      PetscFinalized(&stopped);
      if (!stopped) PetscFinalize();
    };
    stop_before_finish(stop);
    std::atexit(stop);
  });
}

}  // namespace skred
