// The linear systems of the implicit integrator's Newton iterations, K du = r, on PETSc's KSP
// (Debian's libpetsc-real-dev). skred assembles the matrix itself, in compressed rows whose
// pattern comes from the points' stencils (exact preallocation, dof_map.hpp); this class hands
// it to PETSc, factorises it (direct: MUMPS' Cholesky where the matrix is symmetric, LU where
// not) or sets up a Krylov solver with algebraic multigrid (iterative), and solves. PETSc stays
// behind this header: nothing else in skred includes it.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/implicit_settings.hpp"

namespace skred {

// Compressed rows of a square sparse matrix with sorted column indices.
struct SparsePattern {
  std::vector<std::int32_t> row_start;  // n + 1 entries
  std::vector<std::int32_t> column;     // row_start[n] entries
  int size() const { return row_start.empty() ? 0 : static_cast<int>(row_start.size()) - 1; }
};

// Thrown when PETSc reports an error (its message and the call).
struct LinearSolverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class LinearSystem {
 public:
  LinearSystem();
  ~LinearSystem();
  LinearSystem(const LinearSystem&) = delete;
  LinearSystem& operator=(const LinearSystem&) = delete;

  // The solver's choice: direct or iterative, extra PETSc options, and whether the matrices
  // are symmetric (Cholesky, CG) or not (LU, GMRES). `block` is the unknowns per node (the
  // multigrid's near null space: the rigid-body modes need the nodes' coordinates, block_coords).
  void configure(LinearSolverKind kind, const std::string& petsc_options, bool symmetric, int block);
  // A new pattern (each step: the points moved); the values are zeroed.
  void set_pattern(const SparsePattern& pattern);
  // The nodes' coordinates (block values each, in the unknowns' order): the multigrid builds
  // the rigid-body modes of elasticity from them (its near null space). Iterative only.
  void set_coordinates(const std::vector<double>& xyz);
  // The values in the pattern's order, to assemble into.
  std::vector<double>& values() { return values_; }
  // Hands the assembled values to PETSc and factorises (direct) or sets the preconditioner up.
  void factorise();
  // x = K^-1 b with the last factorisation; false (with reason()) when the solve failed.
  bool solve(const std::vector<double>& b, std::vector<double>& x);
  std::string reason() const { return reason_; }
  int last_iterations() const { return iterations_; }
  // The factor's memory [bytes] of the last factorisation (direct), 0 when unknown.
  double factor_bytes() const;
  // What the solver is ("mumps cholesky", "cg + gamg", ...), for summary.json.
  std::string description() const;

 private:
  struct Petsc;  // PETSc's objects (linear_system.cpp)
  std::unique_ptr<Petsc> petsc_;
  SparsePattern pattern_;
  std::vector<double> values_;
  std::vector<double> coordinates_;  // set_coordinates
  std::string reason_;
  int iterations_ = 0;
  bool symmetric_ = true;
  LinearSolverKind kind_ = LinearSolverKind::Direct;
  std::string options_;
  int block_ = 2;
};

}  // namespace skred
