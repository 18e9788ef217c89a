// The fixed regular background grid. Every axis has `cells` cells of size h between the
// domain walls, plus one ghost node beyond each wall, so there are cells + 3 nodes per axis.
// For the nodal kernels (linear, GIMP) node j sits at origin + (j - 1) h: nodes 1 and
// cells + 1 lie on the walls, 0 and cells + 2 are ghosts. The clamped cubic B-spline has
// exactly cells + 3 basis functions per axis, so it uses the same storage: its degree of
// freedom j sits at the Greville abscissa of its basis function and DOFs 0 and cells + 2
// lie on the walls.
#pragma once
#include <array>
#include <cstddef>

#include "core/types.hpp"

namespace skred {

template <int D>
struct GridGeometry {
  Vec<D> origin = Vec<D>::Zero();  // position of the low wall corner
  double h = 1.0;                  // cell size (equal in every direction)
  std::array<int, D> cells{};      // cells between the walls, per axis
  bool bspline_dofs = false;       // node positions are Greville abscissae (cubic B-spline)

  static constexpr int pad = 1;  // ghost nodes beyond each wall

  int nodes(int d) const { return cells[d] + 3; }

  std::size_t node_count() const {
    std::size_t n = 1;
    for (int d = 0; d < D; ++d) n *= static_cast<std::size_t>(nodes(d));
    return n;
  }

  // Flat-index stride of axis d (axis 0 is contiguous).
  std::size_t stride(int d) const {
    std::size_t s = 1;
    for (int k = 0; k < d; ++k) s *= static_cast<std::size_t>(nodes(k));
    return s;
  }

  Vec<D> extent() const {
    Vec<D> e;
    for (int d = 0; d < D; ++d) e[d] = h * cells[d];
    return e;
  }

  // Coordinate along axis d of node (or B-spline DOF) j, measured from the origin.
  double node_coordinate(int d, int j) const {
    if (!bspline_dofs) return (j - pad) * h;
    const int n = cells[d];
    if (j <= 0) return 0.0;
    if (j == 1) return h / 3.0;
    if (j >= n + 2) return n * h;
    if (j == n + 1) return (n - 1.0 / 3.0) * h;
    return (j - 1) * h;
  }

  std::array<int, D> unflatten(std::size_t idx) const {
    std::array<int, D> ij{};
    for (int d = 0; d < D; ++d) {
      ij[d] = static_cast<int>(idx % static_cast<std::size_t>(nodes(d)));
      idx /= static_cast<std::size_t>(nodes(d));
    }
    return ij;
  }

  Vec<D> node_position(std::size_t idx) const {
    const auto ij = unflatten(idx);
    Vec<D> x;
    for (int d = 0; d < D; ++d) x[d] = origin[d] + node_coordinate(d, ij[d]);
    return x;
  }

  // True if x lies inside the domain between the walls (inclusive).
  bool inside(const Vec<D>& x) const {
    for (int d = 0; d < D; ++d) {
      const double r = x[d] - origin[d];
      if (!(r >= 0.0 && r <= h * cells[d])) return false;
    }
    return true;
  }
};

}  // namespace skred
