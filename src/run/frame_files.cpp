#include "run/frame_files.hpp"

#include <fmt/format.h>

#include <vector>

#include "io/grid_writer.hpp"

namespace skred {

namespace fs = std::filesystem;

template <int D>
void write_grid_frame(const Integrator<D>& solver, const std::filesystem::path& outdir, int frame,
                      PvdWriter& index, bool compress, bool writes) {
  const std::string name = fmt::format("grid_{:06}.vtr", frame);
  index.add(solver.time(), name);
  std::vector<double> k_mag, f_mag;  // (every process: the implicit stiffness is a sum over them all)
  const bool magnitudes = solver.node_magnitudes(k_mag, f_mag);
  if (!writes) return;  // (the grid is whole in every process: the first writes it)
  GridNodeFieldsOf<D> fields{solver.node_mass(), solver.node_velocity(), solver.node_stress()};
  if (magnitudes) {
    fields.stiffness_magnitude = k_mag;
    fields.internal_force_magnitude = f_mag;
  }
  write_grid_vtr(outdir / name, solver.grid(), fields, compress);
}

template <int D>
std::string write_frame_pieces(const std::filesystem::path& outdir, int frame, const Particles<D>& P,
                               const ParticleFields& extra, VtuOptions options, const Processes& procs) {
  CornerSpan span = corner_span(P);
  procs.max(&span.reach, 1);
  procs.min(&span.half, 1);
  options.corners_float32 = corners_fit_float32(span);
  const std::string folder = fmt::format("particles_{:06}", frame);
  fs::create_directories(outdir / folder);
  const auto piece = [&](int r) { return fmt::format("{}/piece_{:04}.vtu", folder, r); };
  write_particles_vtu(outdir / piece(procs.rank()), P, extra, options);
  procs.barrier();
  const std::string index = folder + ".pvtu";
  if (procs.rank() == 0) {
    std::vector<std::string> pieces;
    for (int r = 0; r < procs.size(); ++r) pieces.push_back(piece(r));
    write_particles_pvtu(outdir / index, pieces, P, extra, options);
  }
  return index;
}

template void write_grid_frame<2>(const Integrator<2>&, const fs::path&, int, PvdWriter&, bool, bool);
template void write_grid_frame<3>(const Integrator<3>&, const fs::path&, int, PvdWriter&, bool, bool);
template std::string write_frame_pieces<2>(const fs::path&, int, const Particles<2>&, const ParticleFields&,
                                           VtuOptions, const Processes&);
template std::string write_frame_pieces<3>(const fs::path&, int, const Particles<3>&, const ParticleFields&,
                                           VtuOptions, const Processes&);

}  // namespace skred
