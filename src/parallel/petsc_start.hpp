// PETSc (Debian's libpetsc-real-dev) starts once per process, the first time skred needs it: the
// implicit integrator's solves (implicit/linear_system.cpp) and, in a distributed run, the star
// forests of the grid sums and point migration (star_forest.hpp). It stops before MPI does
// (finish_processes) when skred started MPI, else at exit. Collective when distributed: every
// process starts it together.
#pragma once
#include <string>

namespace skred {

// "PETSc: <call> failed: <PETSc's message for code>" (code: a PetscErrorCode).
std::string petsc_failure(int code, const char* call);

// Throws std::runtime_error with PETSc's message if PETSc cannot start.
void start_petsc();

}  // namespace skred
