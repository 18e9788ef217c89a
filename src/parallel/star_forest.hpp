// PETSc's star forests (PetscSF; issue 55): the one engine of skred's point-to-point exchanges
// between processes. A forest joins roots, each owned by one process, to leaves in other (or the
// same) processes; PETSc then sends only between the processes that a root and its leaves join.
// - The grid nodes that several processes hold (transfer/box_exchange.hpp): a root in the one
//   process that owns the node, a leaf in every other that holds it, matched by the nodes' global
//   numbers (match_nodes). A grid sum reduces the leaves into their roots (the owner adds the
//   others' parts to its own) and broadcasts the roots back, so every holder has the same bits.
// - Points moving to another process (point_shares.hpp): a root per point given, a leaf per slot
//   it arrives in (connect); each field is a broadcast from the roots to the leaves.
// PETSc stays in star_forest.cpp.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "parallel/processes.hpp"

namespace skred {

class StarForest {
 public:
  StarForest();
  ~StarForest();
  StarForest(StarForest&&) noexcept;
  StarForest& operator=(StarForest&&) noexcept;

  // Collective. `nodes`: the grid's node count; `roots`: the nodes this process owns and others
  // hold; `leaves`: the nodes it holds and another owns (global node numbers, each list
  // ascending). Throws std::runtime_error if a leaf has no root (the callers' ownership rules
  // disagree) or the grid is beyond PETSc's index range.
  void match_nodes(const Processes& procs, long nodes, std::span<const long> roots,
                   std::span<const long> leaves);
  // Collective. This process has `roots` roots; its leaf k is root index[k] of process rank[k].
  void connect(const Processes& procs, long roots, std::span<const int> rank, std::span<const long> index);

  // How a reduction combines a root's value with its leaves'.
  enum class Combine { Sum, Min, Max };
  // Collective. root (roots × per doubles) += the leaves' parts (leaves × per), the leaves of
  // each root taken in one fixed order; or the least or greatest of the root's and leaves'.
  void reduce(int per, const double* leaf, double* root, Combine how = Combine::Sum);
  // Collective. root (roots × per words) |= the leaves' bits.
  void reduce_bits(int per, const std::uint64_t* leaf, std::uint64_t* root);
  // Collective. leaf (leaves × per doubles) <- its root's values.
  void broadcast(int per, const double* root, double* leaf);
  // Collective. leaf (leaves × `bytes`) <- its root's bytes (trivially copyable values).
  void broadcast_bytes(std::size_t bytes, const void* root, void* leaf);

 private:
  struct Petsc;
  std::unique_ptr<Petsc> petsc_;
};

}  // namespace skred
