// PETSc's star forests for skred's exchanges between processes (star_forest.hpp).
#include "parallel/star_forest.hpp"

#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <petscsf.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallel/petsc_start.hpp"

namespace skred {

namespace {

void check(PetscErrorCode code, const char* call) {
  if (code != 0) throw std::runtime_error(petsc_failure(code, call));
}
#define SKRED_PETSC(call) check((call), #call)

std::vector<PetscInt> petsc_indices(std::span<const long> v) {
  std::vector<PetscInt> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = static_cast<PetscInt>(v[k]);
  return out;
}

MPI_Comm comm_of(const Processes& procs) { return procs.distributed() ? PETSC_COMM_WORLD : PETSC_COMM_SELF; }

}  // namespace

struct StarForest::Petsc {
  PetscSF sf = nullptr;
  struct Unit {
    MPI_Datatype base;
    std::size_t count;
    MPI_Datatype type;
  };
  std::vector<Unit> units;  // `count` of `base` (MPI_Type_contiguous), made on first use
  // What this process sends to others (not itself): leaves in a reduction, the copies of its roots
  // in a broadcast, and to how many processes.
  long leaves_out = 0, roots_out = 0, root_ranks = 0, leaf_ranks = 0;

  MPI_Datatype unit(MPI_Datatype base, std::size_t count) {
    if (count == 1) return base;  // (one value: MPI's own type, which MIN and MAX take)
    for (const Unit& u : units)
      if (u.base == base && u.count == count) return u.type;
    MPI_Datatype t = MPI_DATATYPE_NULL;
    MPI_Type_contiguous(static_cast<int>(count), base, &t);
    MPI_Type_commit(&t);
    units.push_back({base, count, t});
    return t;
  }
  void reset() {
    if (sf) SKRED_PETSC(PetscSFDestroy(&sf));
  }
  // After the graph is set: the counts of what goes to other processes.
  void set_up(const Processes& procs) {
    SKRED_PETSC(PetscSFSetUp(sf));
    count_exchange(0, 0, 0.0, 1);
    const PetscMPIInt me = procs.rank();
    PetscInt n = 0;
    const PetscMPIInt* ranks = nullptr;
    const PetscInt* offset = nullptr;
    SKRED_PETSC(PetscSFGetRootRanks(sf, &n, &ranks, &offset, nullptr, nullptr));
    leaves_out = root_ranks = 0;
    for (PetscInt k = 0; k < n; ++k)
      if (ranks[k] != me) leaves_out += offset[k + 1] - offset[k], ++root_ranks;
    SKRED_PETSC(PetscSFGetLeafRanks(sf, &n, &ranks, &offset, nullptr));
    roots_out = leaf_ranks = 0;
    for (PetscInt k = 0; k < n; ++k)
      if (ranks[k] != me) roots_out += offset[k + 1] - offset[k], ++leaf_ranks;
  }
  // leaf <- root, in units of `bytes` bytes made of `base` values.
  void broadcast(MPI_Datatype base, std::size_t bytes, const void* root, void* leaf) {
    int size = 1;
    MPI_Type_size(base, &size);
    const MPI_Datatype u = unit(base, bytes / static_cast<std::size_t>(size));
    SKRED_PETSC(PetscSFBcastBegin(sf, u, root, leaf, MPI_REPLACE));
    SKRED_PETSC(PetscSFBcastEnd(sf, u, root, leaf, MPI_REPLACE));
    count_exchange(1, leaf_ranks, static_cast<double>(roots_out) * static_cast<double>(bytes));
  }
  ~Petsc() {
    PetscBool stopped = PETSC_FALSE;
    PetscFinalized(&stopped);
    if (stopped) return;  // (freed with PETSc and MPI at exit)
    if (sf) PetscSFDestroy(&sf);
    for (Unit& u : units) MPI_Type_free(&u.type);
  }
};

StarForest::StarForest() = default;
StarForest::~StarForest() = default;
StarForest::StarForest(StarForest&&) noexcept = default;
StarForest& StarForest::operator=(StarForest&&) noexcept = default;

void StarForest::match_nodes(const Processes& procs, long nodes, std::span<const long> roots,
                             std::span<const long> leaves) {
  start_petsc();
  if (nodes > std::numeric_limits<PetscInt>::max())
    throw std::runtime_error("the grid has " + std::to_string(nodes) +
                             " nodes, beyond this PETSc's 32-bit indices");
  if (!petsc_) petsc_ = std::make_unique<Petsc>();
  Petsc& p = *petsc_;
  p.reset();
  // The global node numbers, brokered in even runs over the processes.
  PetscLayout layout = nullptr;
  SKRED_PETSC(PetscLayoutCreate(comm_of(procs), &layout));
  SKRED_PETSC(PetscLayoutSetSize(layout, static_cast<PetscInt>(nodes)));
  SKRED_PETSC(PetscLayoutSetUp(layout));
  const auto r = petsc_indices(roots), l = petsc_indices(leaves);
  const PetscErrorCode made =
      PetscSFCreateByMatchingIndices(layout, static_cast<PetscInt>(r.size()), r.data(), nullptr, 0,
                                     static_cast<PetscInt>(l.size()), l.data(), nullptr, 0, nullptr, &p.sf);
  PetscLayoutDestroy(&layout);
  SKRED_PETSC(made);
  // Every leaf must have found its root (the owners' and holders' rules agree).
  PetscInt n_roots = 0, n_leaves = 0;
  SKRED_PETSC(PetscSFGetGraph(p.sf, &n_roots, &n_leaves, nullptr, nullptr));
  if (static_cast<std::size_t>(n_leaves) != leaves.size())
    throw std::runtime_error("a grid node held by process " + std::to_string(procs.rank()) +
                             " has no owner among the processes");
  p.set_up(procs);
}

void StarForest::connect(const Processes& procs, long roots, std::span<const int> rank,
                         std::span<const long> index) {
  start_petsc();
  if (roots > std::numeric_limits<PetscInt>::max() ||
      rank.size() > static_cast<std::size_t>(std::numeric_limits<PetscInt>::max()))
    throw std::runtime_error("more points in one process than this PETSc's 32-bit indices count");
  if (!petsc_) petsc_ = std::make_unique<Petsc>();
  Petsc& p = *petsc_;
  p.reset();
  std::vector<PetscSFNode> remote(rank.size());
  for (std::size_t k = 0; k < rank.size(); ++k)
    remote[k].rank = rank[k], remote[k].index = static_cast<PetscInt>(index[k]);
  SKRED_PETSC(PetscSFCreate(comm_of(procs), &p.sf));
  SKRED_PETSC(PetscSFSetGraph(p.sf, static_cast<PetscInt>(roots), static_cast<PetscInt>(remote.size()),
                              nullptr, PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  p.set_up(procs);
}

void StarForest::reduce(int per, const double* leaf, double* root, Combine how) {
  Petsc& p = *petsc_;
  // (MPI's own MIN and MAX take basic types only: one double a leaf)
  if (how != Combine::Sum && per != 1)
    throw std::logic_error("StarForest::reduce: the least or greatest of one value a leaf");
  const MPI_Op op = how == Combine::Sum ? MPI_SUM : how == Combine::Min ? MPI_MIN : MPI_MAX;
  const MPI_Datatype unit = p.unit(MPI_DOUBLE, static_cast<std::size_t>(per));
  SKRED_PETSC(PetscSFReduceBegin(p.sf, unit, leaf, root, op));
  SKRED_PETSC(PetscSFReduceEnd(p.sf, unit, leaf, root, op));
  count_exchange(1, p.root_ranks, static_cast<double>(p.leaves_out) * per * sizeof(double));
}

void StarForest::reduce_bits(int per, const std::uint64_t* leaf, std::uint64_t* root) {
  Petsc& p = *petsc_;
  // (bytes: PETSc's packing knows contiguous runs of chars, and a word's OR is its bytes')
  const std::size_t bytes = static_cast<std::size_t>(per) * sizeof(std::uint64_t);
  const MPI_Datatype unit = p.unit(MPI_UNSIGNED_CHAR, bytes);
  SKRED_PETSC(PetscSFReduceBegin(p.sf, unit, leaf, root, MPI_BOR));
  SKRED_PETSC(PetscSFReduceEnd(p.sf, unit, leaf, root, MPI_BOR));
  count_exchange(1, p.root_ranks, static_cast<double>(p.leaves_out) * static_cast<double>(bytes));
}

void StarForest::broadcast(int per, const double* root, double* leaf) {
  petsc_->broadcast(MPI_DOUBLE, static_cast<std::size_t>(per) * sizeof(double), root, leaf);
}

void StarForest::broadcast_bytes(std::size_t bytes, const void* root, void* leaf) {
  petsc_->broadcast(MPI_BYTE, bytes, root, leaf);
}

}  // namespace skred
