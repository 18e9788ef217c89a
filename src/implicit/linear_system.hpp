// The linear systems of the implicit integrator's Newton iterations, K du = r, on PETSc's KSP
// (Debian's libpetsc-real-dev). skred assembles the matrix itself, in compressed rows whose
// pattern comes from the points' stencils (exact preallocation, dof_map.hpp); this class hands
// it to PETSc, factorises it (direct: MUMPS' Cholesky where the matrix is symmetric, LU where
// not) or sets up a Krylov solver with algebraic multigrid (iterative), and solves. PETSc stays
// behind this header (and parallel/star_forest.hpp's, for the exchanges between processes).
//
// Across processes (issue 55) the matrix is PETSc's parallel one (MPIAIJ). A process's pattern
// and vectors are over its local unknowns (dof_map.hpp: those of its box), its own first; each
// has a row in the whole system, and the owned ones are one run of it, which dof_map.hpp numbers
// after the points' blocks of the grid. It keeps the pattern of its own rows and of the rows its
// points' terms fall in (the others are empty), and adds its values of both; PETSc sends those of
// the rows it does not own to their owners, and MUMPS or the multigrid factorise and solve on all
// processes together. The right-hand side is read in the owned rows, and the solution comes back
// to the rows each process reads (set_needed_rows).
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "parallel/processes.hpp"
#include "solver/implicit_settings.hpp"

namespace skred {

// Compressed rows of a square sparse matrix (one process: sorted column indices).
struct SparsePattern {
  std::vector<std::int32_t> row_start;  // n + 1 entries
  std::vector<std::int32_t> column;     // row_start[n] entries
  int size() const { return row_start.empty() ? 0 : static_cast<int>(row_start.size()) - 1; }
};

// Across processes: the whole system's row of each of a process's local rows (its own rows
// first, [0, owned), one run of the whole's), and the whole system's size.
struct GlobalRows {
  std::vector<std::int32_t> row;
  int owned = 0;
  int size = 0;
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
  // `processes`: those the matrix is split among (one alone: PETSc's sequential matrices).
  void configure(LinearSolverKind kind, const std::string& petsc_options, bool symmetric, int block,
                 const Processes& processes = {});
  // A new pattern (each step: the points moved); the values are zeroed. Across processes, its
  // rows and columns are the local unknowns, `global` their rows in the whole system.
  void set_pattern(const SparsePattern& pattern, const GlobalRows* global = nullptr);
  // The nodes' coordinates (block values each, in the unknowns' order): the multigrid builds
  // the rigid-body modes of elasticity from them (its near null space). Iterative only.
  void set_coordinates(const std::vector<double>& xyz);
  // The values in the pattern's order, to assemble into: across processes, this process's part
  // of the sums (its points' terms; terms that every process knows alike only in its own rows).
  std::vector<double>& values() { return values_; }
  // Whether this process owns local row `row` (one process: every row).
  bool owns(std::size_t row) const { return static_cast<int>(row) < owned_; }
  // Across processes: the local rows of the solution this process reads (ascending; after
  // set_pattern). solve() fills those, and leaves the others 0. Not called: every local row.
  void set_needed_rows(std::vector<std::int32_t> rows);
  // Hands the assembled values to PETSc and factorises (direct) or sets the preconditioner up.
  void factorise();
  // x = K^-1 b with the last factorisation; false (with reason()) when the solve failed (on
  // every process alike). b: the owned rows are read.
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
  std::vector<double> coordinates_;   // set_coordinates
  std::vector<std::int32_t> needed_;  // set_needed_rows
  GlobalRows global_;                 // across processes
  std::string reason_;
  int iterations_ = 0;
  bool symmetric_ = true;
  LinearSolverKind kind_ = LinearSolverKind::Direct;
  std::string options_;
  int block_ = 2;
  Processes processes_;
  int owned_ = 0;               // the rows this process owns, [0, owned_)
  void new_solver();            // KSP and PC afresh
  void set_parallel_pattern();  // set_pattern across processes
  void add_parallel_values();   // factorise across processes
  int parallel_solve(const std::vector<double>& b, std::vector<double>& x);  // PETSc's error code
};

}  // namespace skred
