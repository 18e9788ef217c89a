// The star forests of a build without MPI (CMake's SKRED_MPI=OFF; star_forest.hpp): one process,
// whose leaves are its own roots; a reduction adds them in leaf order, a broadcast copies.
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallel/star_forest.hpp"

namespace skred {

struct StarForest::Petsc {    // (the name of the MPI build's holder; here no PETSc)
  std::vector<long> root_of;  // leaf k: its root
};

StarForest::StarForest() = default;
StarForest::~StarForest() = default;
StarForest::StarForest(StarForest&&) noexcept = default;
StarForest& StarForest::operator=(StarForest&&) noexcept = default;

void StarForest::match_nodes(const Processes&, long, std::span<const long>, std::span<const long> leaves) {
  if (!leaves.empty())  // (a leaf is a node another process owns)
    throw std::runtime_error("a grid node held by process 0 has no owner among the processes");
  petsc_ = std::make_unique<Petsc>();
}

void StarForest::connect(const Processes&, long roots, std::span<const int> rank,
                         std::span<const long> index) {
  petsc_ = std::make_unique<Petsc>();
  for (std::size_t k = 0; k < rank.size(); ++k) {
    if (rank[k] != 0 || index[k] < 0 || index[k] >= roots)
      throw std::logic_error("StarForest::connect: a leaf's root is not among this process's " +
                             std::to_string(roots));
    petsc_->root_of.push_back(index[k]);
  }
}

void StarForest::reduce(int per, const double* leaf, double* root, Combine how) {
  if (how != Combine::Sum && per != 1)
    throw std::logic_error("StarForest::reduce: the least or greatest of one value a leaf");
  const std::vector<long>& to = petsc_->root_of;
  for (std::size_t k = 0; k < to.size(); ++k)
    for (int c = 0; c < per; ++c) {
      double& r = root[to[k] * per + c];
      const double l = leaf[k * static_cast<std::size_t>(per) + static_cast<std::size_t>(c)];
      r = how == Combine::Sum ? r + l : how == Combine::Min ? std::min(r, l) : std::max(r, l);
    }
}

void StarForest::reduce_bits(int per, const std::uint64_t* leaf, std::uint64_t* root) {
  const std::vector<long>& to = petsc_->root_of;
  for (std::size_t k = 0; k < to.size(); ++k)
    for (int c = 0; c < per; ++c) root[to[k] * per + c] |= leaf[k * static_cast<std::size_t>(per) + c];
}

void StarForest::broadcast(int per, const double* root, double* leaf) {
  broadcast_bytes(static_cast<std::size_t>(per) * sizeof(double), root, leaf);
}

void StarForest::broadcast_bytes(std::size_t bytes, const void* root, void* leaf) {
  const std::vector<long>& to = petsc_->root_of;
  for (std::size_t k = 0; k < to.size(); ++k)
    std::memcpy(static_cast<char*>(leaf) + k * bytes,
                static_cast<const char*>(root) + static_cast<std::size_t>(to[k]) * bytes, bytes);
}

}  // namespace skred
