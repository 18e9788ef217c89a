// The files of one frame of a run (run/simulation.cpp): the grid's node fields, and a distributed
// run's particle frame in pieces, one per process.
#pragma once
#include <filesystem>
#include <string>

#include "core/particles.hpp"
#include "io/pvd_writer.hpp"
#include "io/vtu_writer.hpp"
#include "parallel/processes.hpp"
#include "solver/integrator.hpp"

namespace skred {

// The grid node file of one frame (grid_NNNNNN.vtr) from the nodal fields of the last
// smoothed_stress() call, and its entry in grid.pvd (post). Every process adds the entry; the
// one that `writes` (the first: the grid is whole in each) writes the file.
template <int D>
void write_grid_frame(const Integrator<D>& solver, const std::filesystem::path& outdir, int frame,
                      PvdWriter& index, bool compress, bool writes);

// One particle frame of a run split among processes: each writes its points as a piece,
// particles_NNNNNN/piece_RRRR.vtu, and the first the frame's index particles_NNNNNN.pvtu, once
// every piece is on disk. The pieces' corners share one type (vtu_writer.hpp). Returns the index's
// name. Collective.
template <int D>
std::string write_frame_pieces(const std::filesystem::path& outdir, int frame, const Particles<D>& P,
                               const ParticleFields& extra, VtuOptions options, const Processes& procs);

}  // namespace skred
