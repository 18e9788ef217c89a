// Material points as a VTK XML UnstructuredGrid (.vtu) for ParaView (Post §3).
#pragma once
#include <filesystem>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"

namespace skred {

// Optional per-particle fields computed by the solver, written when present.
struct ParticleFields {
  const std::vector<Sym3>* smoothed_stress = nullptr;  // grid-smoothed stress (Thesis eq. 4.18-4.19), may be null
};

// Writes every material point as its deformed voxel: a VTK_QUAD whose corners, counter-
// clockwise, are x_p + F_p (+-l0x, +-l0y) with l0 = P.half0[p] (Thesis eq. 3.6-3.12), z = 0.
// Cell data (Float64 unless noted): velocity (3), displacement x - x_ref (3), stress (6,
// Voigt xx,yy,zz,xy,yz,xz), mean_stress_p, deviatoric_stress_q, volume (det F V0), det_F,
// plastic_shear_strain, yielding (UInt8), material_id and body_id (Int32), and with
// extra.smoothed_stress: smoothed_stress (6), smoothed_p, smoothed_q.
// Binary appended raw encoding, header_type UInt64, the machine's byte order. The file is
// written atomically (write_file_atomically). Throws std::invalid_argument if the particle
// arrays or the smoothed stress do not all have P.size() entries, std::runtime_error on I/O
// failure.
void write_particles_vtu(const std::filesystem::path& file, const Particles<2>& P,
                         const ParticleFields& extra = {});

}  // namespace skred
