#include "implicit/linear_system.hpp"

#include <fmt/core.h>
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "parallel/petsc_start.hpp"

namespace skred {

namespace {

// PETSc's calls return an error code; a failing one becomes a LinearSolverError.
void check(PetscErrorCode code, const char* call) {
  if (code != 0) throw LinearSolverError(petsc_failure(code, call));
}
#define SKRED_PETSC(call) check((call), #call)

}  // namespace

struct LinearSystem::Petsc {
  Mat matrix = nullptr;
  KSP ksp = nullptr;
  std::vector<PetscInt> rows, columns;
  // Across processes: the right-hand side and solution (owned rows), the rows of the solution
  // this process reads, and the scatter that fills them; the owned rows' entries in and beyond
  // their diagonal block (the exact preallocation).
  Vec b = nullptr, x = nullptr, x_needed = nullptr;
  VecScatter to_needed = nullptr;
  std::vector<PetscInt> in_diagonal, off_diagonal;
  void destroy_vectors() {
    if (to_needed) VecScatterDestroy(&to_needed);
    if (x_needed) VecDestroy(&x_needed);
    if (x) VecDestroy(&x);
    if (b) VecDestroy(&b);
  }
  ~Petsc() {
    destroy_vectors();
    if (ksp) KSPDestroy(&ksp);
    if (matrix) MatDestroy(&matrix);
  }
};

LinearSystem::LinearSystem() = default;
LinearSystem::~LinearSystem() = default;

void LinearSystem::configure(LinearSolverKind kind, const std::string& petsc_options, bool symmetric,
                             int block, const Processes& processes) {
  start_petsc();
  processes_ = processes;
  kind_ = kind;
  options_ = petsc_options;
  symmetric_ = symmetric;
  block_ = block;
  petsc_ = std::make_unique<Petsc>();
  if (!options_.empty()) SKRED_PETSC(PetscOptionsInsertString(nullptr, options_.c_str()));
  new_solver();
}

// A fresh KSP with its preconditioner, for each new pattern. (KSPReset keeps some of a
// multigrid's set-up: a run resumed from a checkpoint, whose solver is fresh, then differs from
// the run it continues in the last digits.)
void LinearSystem::new_solver() {
  Petsc& p = *petsc_;
  if (p.ksp) SKRED_PETSC(KSPDestroy(&p.ksp));
  SKRED_PETSC(KSPCreate(processes_.distributed() ? PETSC_COMM_WORLD : PETSC_COMM_SELF, &p.ksp));
  PC pc = nullptr;
  SKRED_PETSC(KSPGetPC(p.ksp, &pc));
  if (kind_ == LinearSolverKind::Direct) {
    SKRED_PETSC(KSPSetType(p.ksp, KSPPREONLY));
    SKRED_PETSC(PCSetType(pc, symmetric_ ? PCCHOLESKY : PCLU));
    SKRED_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  } else {
    SKRED_PETSC(KSPSetType(p.ksp, symmetric_ ? KSPCG : KSPGMRES));
    SKRED_PETSC(PCSetType(pc, PCGAMG));
    SKRED_PETSC(KSPSetTolerances(p.ksp, 1e-10, 1e-300, PETSC_DEFAULT, 5000));
  }
  SKRED_PETSC(KSPSetFromOptions(p.ksp));
}

void LinearSystem::set_pattern(const SparsePattern& pattern, const GlobalRows* global) {
  if (!petsc_) configure(kind_, options_, symmetric_, block_, processes_);
  Petsc& p = *petsc_;
  pattern_ = pattern;
  values_.assign(pattern_.column.size(), 0.0);
  owned_ = pattern_.size();
  if (processes_.distributed()) {
    if (!global || global->row.size() != static_cast<std::size_t>(pattern_.size()))
      throw LinearSolverError("a pattern across processes without its rows in the whole system");
    global_ = *global;
    owned_ = global_.owned;
    set_parallel_pattern();
    return;
  }
  p.rows.assign(pattern_.row_start.begin(), pattern_.row_start.end());
  p.columns.assign(pattern_.column.begin(), pattern_.column.end());
  if (p.matrix) {  // a new size: a new solver, without the old operator and its factor
    new_solver();
    SKRED_PETSC(MatDestroy(&p.matrix));
  }
  const PetscInt n = pattern_.size();
  SKRED_PETSC(MatCreate(PETSC_COMM_SELF, &p.matrix));
  SKRED_PETSC(MatSetSizes(p.matrix, n, n, n, n));
  SKRED_PETSC(MatSetType(p.matrix, MATSEQAIJ));
  if (block_ > 1 && n % block_ == 0) SKRED_PETSC(MatSetBlockSize(p.matrix, block_));
  // Exact preallocation: the pattern and zero values in one call.
  SKRED_PETSC(MatSeqAIJSetPreallocationCSR(p.matrix, p.rows.data(), p.columns.data(), values_.data()));
  SKRED_PETSC(MatSetOption(p.matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  if (symmetric_) SKRED_PETSC(MatSetOption(p.matrix, MAT_SYMMETRIC, PETSC_TRUE));
}

void LinearSystem::set_coordinates(const std::vector<double>& xyz) {
  if (kind_ == LinearSolverKind::Iterative) coordinates_.assign(xyz.begin(), xyz.end());
}

void LinearSystem::factorise() {
  Petsc& p = *petsc_;
  if (processes_.distributed()) {
    add_parallel_values();
  } else {
    PetscScalar* a = nullptr;
    SKRED_PETSC(MatSeqAIJGetArray(p.matrix, &a));
    std::copy(values_.begin(), values_.end(), a);
    SKRED_PETSC(MatSeqAIJRestoreArray(p.matrix, &a));
  }
  SKRED_PETSC(MatAssemblyBegin(p.matrix, MAT_FINAL_ASSEMBLY));
  SKRED_PETSC(MatAssemblyEnd(p.matrix, MAT_FINAL_ASSEMBLY));
  SKRED_PETSC(KSPSetOperators(p.ksp, p.matrix, p.matrix));
  if (!coordinates_.empty()) {  // GAMG's near null space (after the operator: it reads its blocks)
    PC pc = nullptr;
    SKRED_PETSC(KSPGetPC(p.ksp, &pc));
    PetscBool gamg = PETSC_FALSE;
    SKRED_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
    if (gamg)  // the owned nodes' coordinates
      SKRED_PETSC(PCSetCoordinates(pc, block_, static_cast<PetscInt>(owned_) / block_, coordinates_.data()));
  }
  SKRED_PETSC(KSPSetUp(p.ksp));
}

bool LinearSystem::solve(const std::vector<double>& b, std::vector<double>& x) {
  Petsc& p = *petsc_;
  const PetscInt n = pattern_.size();
  x.assign(static_cast<std::size_t>(n), 0.0);
  PetscErrorCode code = 0;
  if (processes_.distributed()) {
    code = parallel_solve(b, x);
  } else {
    Vec vb = nullptr, vx = nullptr;
    SKRED_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, b.data(), &vb));
    SKRED_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, x.data(), &vx));
    code = KSPSolve(p.ksp, vb, vx);
    VecDestroy(&vb);
    VecDestroy(&vx);
  }
  KSPConvergedReason why = KSP_CONVERGED_ITERATING;
  KSPGetConvergedReason(p.ksp, &why);
  PetscInt its = 0;
  KSPGetIterationNumber(p.ksp, &its);
  iterations_ = static_cast<int>(its);
  if (code != 0 || why < 0) {
    // A failed factorisation leaves the preconditioner failed: the next factorise() starts afresh
    // (a Krylov solver's multigrid is set up again from the next operator anyway; reset, it would
    // lose the near null space's block layout).
    if (kind_ == LinearSolverKind::Direct) KSPReset(p.ksp);
    const char* name = nullptr;
    if (why < 0) name = KSPConvergedReasons[why];
    reason_ = code != 0 ? fmt::format("PETSc error {} in KSPSolve", static_cast<int>(code))
                        : fmt::format("the linear solver failed ({})", name ? name : "?");
    return false;
  }
  bool finite = true;
  for (double v : x) finite = finite && std::isfinite(v);
  if (!processes_.any(!finite)) return true;  // (every process alike: they read other rows)
  reason_ = "the linear solve gave a non-finite displacement (a singular stiffness matrix?)";
  return false;
}

// PETSc's parallel matrix over the owned rows, preallocated exactly from their patterns: each
// row's entries in the diagonal block (columns this process owns) and beyond it.
void LinearSystem::set_parallel_pattern() {
  Petsc& p = *petsc_;
  const PetscInt local = owned_;
  p.in_diagonal.assign(static_cast<std::size_t>(local), 0);
  p.off_diagonal.assign(static_cast<std::size_t>(local), 0);
  for (PetscInt r = 0; r < local; ++r) {
    const std::size_t row = static_cast<std::size_t>(r);
    for (std::int32_t e = pattern_.row_start[row]; e < pattern_.row_start[row + 1]; ++e)
      ++(pattern_.column[static_cast<std::size_t>(e)] < owned_ ? p.in_diagonal : p.off_diagonal)[row];
  }
  if (p.matrix) {
    new_solver();
    SKRED_PETSC(MatDestroy(&p.matrix));
  }
  p.destroy_vectors();
  SKRED_PETSC(MatCreate(PETSC_COMM_WORLD, &p.matrix));
  SKRED_PETSC(MatSetSizes(p.matrix, local, local, global_.size, global_.size));
  SKRED_PETSC(MatSetType(p.matrix, MATMPIAIJ));
  if (block_ > 1) SKRED_PETSC(MatSetBlockSize(p.matrix, block_));
  SKRED_PETSC(MatMPIAIJSetPreallocation(p.matrix, 0, p.in_diagonal.data(), 0, p.off_diagonal.data()));
  SKRED_PETSC(MatSetOption(p.matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  if (symmetric_) SKRED_PETSC(MatSetOption(p.matrix, MAT_SYMMETRIC, PETSC_TRUE));
  SKRED_PETSC(MatCreateVecs(p.matrix, &p.x, &p.b));
  std::vector<std::int32_t> every(static_cast<std::size_t>(pattern_.size()));
  for (std::size_t r = 0; r < every.size(); ++r) every[r] = static_cast<std::int32_t>(r);
  set_needed_rows(std::move(every));  // (until the caller names fewer)
}

void LinearSystem::set_needed_rows(std::vector<std::int32_t> rows) {
  if (!processes_.distributed()) return;
  Petsc& p = *petsc_;
  needed_ = std::move(rows);
  if (p.to_needed) VecScatterDestroy(&p.to_needed);
  if (p.x_needed) VecDestroy(&p.x_needed);
  std::vector<PetscInt> from(needed_.size());
  for (std::size_t k = 0; k < needed_.size(); ++k)
    from[k] = global_.row[static_cast<std::size_t>(needed_[k])];
  IS is = nullptr;
  SKRED_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(from.size()), from.data(),
                              PETSC_COPY_VALUES, &is));
  SKRED_PETSC(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(from.size()), &p.x_needed));
  const PetscErrorCode made = VecScatterCreate(p.x, is, p.x_needed, nullptr, &p.to_needed);
  ISDestroy(&is);
  SKRED_PETSC(made);
}

// This process's values into the parallel matrix, every row its pattern holds (its own rows,
// each with every entry, and those its points' terms fall in), by their rows and columns in the
// whole system; PETSc adds them up in the rows' owners (MatAssembly).
void LinearSystem::add_parallel_values() {
  Petsc& p = *petsc_;
  SKRED_PETSC(MatZeroEntries(p.matrix));
  const int n = pattern_.size();
  p.columns.resize(0);
  for (int row = 0; row < n; ++row) {
    const std::int32_t e0 = pattern_.row_start[static_cast<std::size_t>(row)];
    const PetscInt len = pattern_.row_start[static_cast<std::size_t>(row) + 1] - e0;
    if (len == 0) continue;
    p.columns.resize(static_cast<std::size_t>(len));
    for (PetscInt e = 0; e < len; ++e)
      p.columns[static_cast<std::size_t>(e)] =
          global_.row[static_cast<std::size_t>(pattern_.column[static_cast<std::size_t>(e0 + e)])];
    const PetscInt r = global_.row[static_cast<std::size_t>(row)];
    SKRED_PETSC(MatSetValues(p.matrix, 1, &r, len, p.columns.data(), values_.data() + e0, ADD_VALUES));
  }
}

// Solves with the owned rows of b and brings the solution's rows this process reads back.
int LinearSystem::parallel_solve(const std::vector<double>& b, std::vector<double>& x) {
  Petsc& p = *petsc_;
  PetscScalar* a = nullptr;
  SKRED_PETSC(VecGetArray(p.b, &a));
  std::copy(b.begin(), b.begin() + owned_, a);
  SKRED_PETSC(VecRestoreArray(p.b, &a));
  const PetscErrorCode code = KSPSolve(p.ksp, p.b, p.x);
  if (code != 0) return static_cast<int>(code);
  SKRED_PETSC(VecScatterBegin(p.to_needed, p.x, p.x_needed, INSERT_VALUES, SCATTER_FORWARD));
  SKRED_PETSC(VecScatterEnd(p.to_needed, p.x, p.x_needed, INSERT_VALUES, SCATTER_FORWARD));
  const PetscScalar* got = nullptr;
  SKRED_PETSC(VecGetArrayRead(p.x_needed, &got));
  for (std::size_t k = 0; k < needed_.size(); ++k) x[static_cast<std::size_t>(needed_[k])] = got[k];
  SKRED_PETSC(VecRestoreArrayRead(p.x_needed, &got));
  return 0;
}

double LinearSystem::factor_bytes() const {
  if (!petsc_ || kind_ != LinearSolverKind::Direct) return 0.0;
  PC pc = nullptr;
  if (KSPGetPC(petsc_->ksp, &pc)) return 0.0;
  Mat factor = nullptr;
  if (PCFactorGetMatrix(pc, &factor) || !factor) return 0.0;
  PetscInt mb = 0;
  if (MatMumpsGetInfog(factor, 17, &mb)) return 0.0;  // INFOG(17): MB used by the factorisation
  return 1e6 * static_cast<double>(mb);
}

std::string LinearSystem::description() const {
  if (!petsc_) return "none";
  KSPType kt = nullptr;
  KSPGetType(petsc_->ksp, &kt);
  PC pc = nullptr;
  KSPGetPC(petsc_->ksp, &pc);
  PCType pt = nullptr;
  PCGetType(pc, &pt);
  MatSolverType st = nullptr;
  if (kind_ == LinearSolverKind::Direct) PCFactorGetMatSolverType(pc, &st);
  return fmt::format(
      "{} + {}{}{}", kt ? kt : "?", pt ? pt : "?", st ? fmt::format(" ({})", st) : "",
      processes_.distributed() ? fmt::format(", parallel over {} processes", processes_.size()) : "");
}

}  // namespace skred
