#include "implicit/linear_system.hpp"

#include <fmt/core.h>
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <string>

namespace skred {

namespace {

// PETSc's calls return an error code; a failing one becomes a LinearSolverError.
void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw LinearSolverError(fmt::format("PETSc: {} failed: {}", call, text ? text : "unknown error"));
}
#define SKRED_PETSC(call) check((call), #call)

// PETSc (and MPI under it) start once per process, the first time an implicit stage needs
// them, and stop at exit; errors come back as codes instead of printed traces.
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
    check(PetscInitializeNoArguments(), "PetscInitialize");
    PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
    std::atexit([] { PetscFinalize(); });
  });
}

}  // namespace

struct LinearSystem::Petsc {
  Mat matrix = nullptr;
  KSP ksp = nullptr;
  std::vector<PetscInt> rows, columns;
  ~Petsc() {
    if (ksp) KSPDestroy(&ksp);
    if (matrix) MatDestroy(&matrix);
  }
};

LinearSystem::LinearSystem() = default;
LinearSystem::~LinearSystem() = default;

void LinearSystem::configure(LinearSolverKind kind, const std::string& petsc_options, bool symmetric,
                             int block) {
  start_petsc();
  kind_ = kind;
  options_ = petsc_options;
  symmetric_ = symmetric;
  block_ = block;
  petsc_ = std::make_unique<Petsc>();
  Petsc& p = *petsc_;
  SKRED_PETSC(KSPCreate(PETSC_COMM_SELF, &p.ksp));
  PC pc = nullptr;
  SKRED_PETSC(KSPGetPC(p.ksp, &pc));
  if (kind == LinearSolverKind::Direct) {
    SKRED_PETSC(KSPSetType(p.ksp, KSPPREONLY));
    SKRED_PETSC(PCSetType(pc, symmetric ? PCCHOLESKY : PCLU));
    SKRED_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  } else {
    SKRED_PETSC(KSPSetType(p.ksp, symmetric ? KSPCG : KSPGMRES));
    SKRED_PETSC(PCSetType(pc, PCGAMG));
    SKRED_PETSC(KSPSetTolerances(p.ksp, 1e-10, 1e-300, PETSC_DEFAULT, 5000));
  }
  if (!options_.empty()) SKRED_PETSC(PetscOptionsInsertString(nullptr, options_.c_str()));
  SKRED_PETSC(KSPSetFromOptions(p.ksp));
}

void LinearSystem::set_pattern(const SparsePattern& pattern) {
  if (!petsc_) configure(kind_, options_, symmetric_, block_);
  Petsc& p = *petsc_;
  pattern_ = pattern;
  values_.assign(pattern_.column.size(), 0.0);
  p.rows.assign(pattern_.row_start.begin(), pattern_.row_start.end());
  p.columns.assign(pattern_.column.begin(), pattern_.column.end());
  if (p.matrix) {  // a new size: the solver forgets the old operator and its factor
    SKRED_PETSC(KSPReset(p.ksp));
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
  PetscScalar* a = nullptr;
  SKRED_PETSC(MatSeqAIJGetArray(p.matrix, &a));
  std::copy(values_.begin(), values_.end(), a);
  SKRED_PETSC(MatSeqAIJRestoreArray(p.matrix, &a));
  SKRED_PETSC(MatAssemblyBegin(p.matrix, MAT_FINAL_ASSEMBLY));
  SKRED_PETSC(MatAssemblyEnd(p.matrix, MAT_FINAL_ASSEMBLY));
  SKRED_PETSC(KSPSetOperators(p.ksp, p.matrix, p.matrix));
  if (!coordinates_.empty()) {  // GAMG's near null space (after the operator: it reads its blocks)
    PC pc = nullptr;
    SKRED_PETSC(KSPGetPC(p.ksp, &pc));
    PetscBool gamg = PETSC_FALSE;
    SKRED_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCGAMG, &gamg));
    if (gamg)
      SKRED_PETSC(PCSetCoordinates(pc, block_, static_cast<PetscInt>(coordinates_.size()) / block_,
                                   coordinates_.data()));
  }
  SKRED_PETSC(KSPSetUp(p.ksp));
}

bool LinearSystem::solve(const std::vector<double>& b, std::vector<double>& x) {
  Petsc& p = *petsc_;
  const PetscInt n = pattern_.size();
  x.assign(static_cast<std::size_t>(n), 0.0);
  Vec vb = nullptr, vx = nullptr;
  SKRED_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, b.data(), &vb));
  SKRED_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, x.data(), &vx));
  const PetscErrorCode code = KSPSolve(p.ksp, vb, vx);
  VecDestroy(&vb);
  VecDestroy(&vx);
  KSPConvergedReason why = KSP_CONVERGED_ITERATING;
  KSPGetConvergedReason(p.ksp, &why);
  PetscInt its = 0;
  KSPGetIterationNumber(p.ksp, &its);
  iterations_ = static_cast<int>(its);
  if (code != 0 || why < 0) {
    // A failed factorisation leaves the preconditioner failed: the next factorise() starts afresh.
    KSPReset(p.ksp);
    const char* name = nullptr;
    if (why < 0) name = KSPConvergedReasons[why];
    reason_ = code != 0 ? fmt::format("PETSc error {} in KSPSolve", static_cast<int>(code))
                        : fmt::format("the linear solver failed ({})", name ? name : "?");
    return false;
  }
  for (double v : x)
    if (!std::isfinite(v)) {
      reason_ = "the linear solve gave a non-finite displacement (a singular stiffness matrix?)";
      return false;
    }
  return true;
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
  return fmt::format("{} + {}{}", kt ? kt : "?", pt ? pt : "?", st ? fmt::format(" ({})", st) : "");
}

}  // namespace skred
