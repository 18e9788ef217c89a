// Material points as a VTK XML UnstructuredGrid (.vtu) for ParaView (Post §3).
#pragma once
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "post/material_strength.hpp"

namespace skred {

// Optional inputs, written when present; default-constructed, only the always-present fields
// are written, so older callers keep working.
struct ParticleFields {
  // Grid-smoothed stress (Post eq. 57-58, Thesis eq. 4.18-4.19), one per particle.
  const std::vector<Sym3>* smoothed_stress = nullptr;
  // Strength of each material, indexed by P.material[p]: enables relative_yield (Post eq. 66).
  const std::vector<MaterialStrength>* strength = nullptr;
  // Elastic part Fe of F = Fe Fp (Post eq. 67-73), one per particle: enables Fe and Fp.
  const std::vector<Mat3>* elastic_F = nullptr;
  // Stress recomputed from Fe, sigma_initial + E : (Fe - I) (Post eq. 75-77), one per particle.
  const std::vector<Sym3>* stress_from_elastic_F = nullptr;
};

// What a particle frame holds and how.
struct VtuOptions {
  // The cell fields to write (names of output_fields::all(), scenario/output_fields.hpp);
  // empty: all of them. A field whose input (ParticleFields) is absent is left out.
  std::vector<std::string> fields;
  // zlib-compressed arrays (VTK's vtkZLibDataCompressor), else raw.
  bool compress = true;
  // Float32 corners (true) or Float64 (false); unset: as corners_fit_float32 finds for the points
  // written (the pieces of one frame must agree: a distributed run decides for all of them).
  std::optional<bool> corners_float32 = std::nullopt;
};

// How far the corners of the points reach from the origin (the largest |coordinate|) and the
// smallest half-size of a point: Float32 corners fit while rounding them moves them by at most
// 1e-3 of the smallest voxel.
struct CornerSpan {
  double reach = 0.0, half = INFINITY;
};
template <int D>
CornerSpan corner_span(const Particles<D>& P);
bool corners_fit_float32(const CornerSpan& c);

// Writes every material point as its deformed voxel: a VTK_QUAD whose corners, counter-
// clockwise, are x_p + F_p (+-l0x, +-l0y) with l0 = P.half0[p] (Thesis eq. 3.6-3.12), z = 0.
// Cell data (Float32 unless noted: computed in double, stored with 7 significant digits, far
// below what a stress, strain or speed of a soil model means; det F near 1 keeps volume
// changes down to 1e-7; symmetric tensors as 6 Voigt components xx,yy,zz,xy,yz,xz
// with tensor shear; full tensors as 9 components row by row xx,xy,xz,yx,...,zz):
//   always: velocity (3), speed, displacement x - x_ref (3), stress (6), mean_stress_p,
//   deviatoric_stress_q, principal_stress (3: s1 <= s2 <= s3, Post eq. 59), principal_angle
//   (degrees, Post eq. 60), volume (det F V0), det_F, F (9), engineering_strain (6, eq. 63),
//   green_strain (6, eq. 64), hencky_strain (6, eq. 65), plastic_shear_strain, yielding
//   (UInt8), material_id and body_id (Int16);
//   with strength: relative_yield (eq. 66; NaN for materials without strength);
//   with smoothed_stress: smoothed_stress (6), smoothed_p, smoothed_q,
//   smoothed_principal_stress (3), smoothed_principal_angle, and with strength also
//   smoothed_relative_yield;
//   with elastic_F: Fe (9) and Fp = Fe^-1 F (9, eq. 74), F embedded in 3D with F_zz = 1;
//   with stress_from_elastic_F: stress_from_Fe (6).
// docs/post-processing.md describes every field; `options.fields` chooses them. The corners
// are Float32 unless rounding them so would move them by more than 1e-3 of the smallest
// voxel (georeferenced coordinates), then Float64; connectivity and offsets Int32 (Int64
// beyond 2^31 corners). Binary appended data, zlib-compressed unless options.compress is
// false (vtk_appended.hpp), header_type UInt64, the machine's byte order. The file is written atomically
// (write_file_atomically). Throws std::invalid_argument if the particle arrays or an optional per-particle
// input do not all have P.size() entries, a material id has no strength entry or options.fields names an
// unknown field; std::runtime_error on
// I/O failure.
void write_particles_vtu(const std::filesystem::path& file, const Particles<2>& P,
                         const ParticleFields& extra = {}, const VtuOptions& options = {});
// The same in 3D: each point a VTK_HEXAHEDRON with the 8 corners x_p + F_p (+-l0x, +-l0y,
// +-l0z) (Thesis eq. 3.6-3.12; the z- face counter-clockwise seen from +z, then the z+
// face), vectors with their z components, the full 3D stress and F; the same fields.
void write_particles_vtu(const std::filesystem::path& file, const Particles<3>& P,
                         const ParticleFields& extra = {}, const VtuOptions& options = {});

// The index of one frame written in pieces, one .vtu per process of a distributed run: a VTK
// XML PUnstructuredGrid (.pvtu) naming the `pieces` (paths relative to its folder) and the
// arrays write_particles_vtu writes with the same `extra` and `options` (whose corners_float32
// must be set: the pieces' corner type). `P` is any of the pieces' points. Written atomically.
void write_particles_pvtu(const std::filesystem::path& file, const std::vector<std::string>& pieces,
                          const Particles<2>& P, const ParticleFields& extra, const VtuOptions& options);
void write_particles_pvtu(const std::filesystem::path& file, const std::vector<std::string>& pieces,
                          const Particles<3>& P, const ParticleFields& extra, const VtuOptions& options);

}  // namespace skred
