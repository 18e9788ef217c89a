// Grid node fields as a VTK XML RectilinearGrid (.vtr) for ParaView (Post §7.1): the
// background grid of one output step with its nodal mass, velocity and stress.
#pragma once
#include <filesystem>
#include <span>

#include "core/grid.hpp"
#include "core/types.hpp"

namespace skred {

// Nodal arrays, flat-indexed like GridGeometry (axis 0 fastest), each grid.node_count() long.
template <int D>
struct GridNodeFieldsOf {
  std::span<const double> mass;      // m_i = sum_p N_ip m_p
  std::span<const Vec<D>> velocity;  // v_i = sum_p N_ip m_p v_p / m_i (0 where m_i = 0)
  std::span<const Sym3> stress;      // sigma_i = sum_p N_ip m_p sigma_p / m_i (Post eq. 57)
  // The implicit integrator's stiffness magnitude K_mag and internal force |F_int| (Acosta eq.
  // 25-26); empty: not written.
  std::span<const double> stiffness_magnitude = {}, internal_force_magnitude = {};
};
using GridNodeFields = GridNodeFieldsOf<2>;

// Writes every node of `grid`, ghost nodes included, as a point of a rectilinear grid (one
// coordinate array per axis, from GridGeometry::node_coordinate, so the uneven spacing of
// the cubic B-spline's Greville abscissae is kept; z = 0; Float64). Point data (Float32):
// mass,
// velocity (3, z = 0), stress (6, Voigt xx,yy,zz,xy,yz,xz), mean_stress_p and
// deviatoric_stress_q of the nodal stress, stiffness_magnitude and internal_force_magnitude
// when given, and has_material (UInt8: 1 where mass > 0, 0 at an
// empty node, whose zero stress is no material's; threshold on it in ParaView to hide empty
// nodes). Binary appended data, zlib-compressed if `compress` (vtk_appended.hpp),
// header_type UInt64, written atomically. Throws std::invalid_argument if an array does not have
// grid.node_count() entries, std::runtime_error on I/O failure.
void write_grid_vtr(const std::filesystem::path& file, const GridGeometry<2>& grid,
                    const GridNodeFields& fields, bool compress = true);
// The same in 3D (z coordinates from the grid, velocity with its z component).
void write_grid_vtr(const std::filesystem::path& file, const GridGeometry<3>& grid,
                    const GridNodeFieldsOf<3>& fields, bool compress = true);

}  // namespace skred
