// The linear systems of a build without MPI and PETSc (CMake's SKRED_MPI=OFF; linear_system.hpp):
// there is no solver, and configuring one says so. The scenario parser refuses the implicit
// integrator in such a build first, naming the key (parser_implicit.cpp).
#include <string>
#include <vector>

#include "implicit/linear_system.hpp"

namespace skred {

struct LinearSystem::Petsc {};

namespace {
[[noreturn]] void no_solver() {
  throw LinearSolverError(
      "this build of skred has no linear solver: the implicit integrator's solves are PETSc's, and it "
      "was configured without MPI and PETSc (cmake -DSKRED_MPI=OFF); rebuild with the default "
      "(-DSKRED_MPI=ON, README)");
}
}  // namespace

LinearSystem::LinearSystem() = default;
LinearSystem::~LinearSystem() = default;

void LinearSystem::configure(LinearSolverKind, const std::string&, bool, int, const Processes&) {
  no_solver();
}
void LinearSystem::set_pattern(const SparsePattern&, const GlobalRows*) { no_solver(); }
void LinearSystem::set_coordinates(const std::vector<double>&) { no_solver(); }
void LinearSystem::set_needed_rows(std::vector<std::int32_t>) { no_solver(); }
void LinearSystem::factorise() { no_solver(); }
bool LinearSystem::solve(const std::vector<double>&, std::vector<double>&) { no_solver(); }
double LinearSystem::factor_bytes() const { return 0.0; }
std::string LinearSystem::description() const { return "none (built without PETSc)"; }

}  // namespace skred
