#include "io/series_writer.hpp"

#include <fmt/format.h>

#include <iterator>

#include "io/atomic_file.hpp"

namespace skred {

const char* SeriesWriter::header() {
  return "step,time,kinetic_energy,strain_energy,gravity_work,plastic_dissipation,friction_work,"
         "transfer_dissipation,total_energy,"
         "mean_speed,max_speed,momentum_x,momentum_y,num_particles,stage,runout,yielding_points\n";
}

SeriesWriter::SeriesWriter(const std::filesystem::path& file, bool momentum_z)
    : file_(file), momentum_z_(momentum_z) {
  rows_.reserve(4096);
  text_.reserve(4096 * 160);
}

SeriesWriter::~SeriesWriter() {
  if (!dirty_) return;
  try {
    flush();
  } catch (...) {
  }
}

void SeriesWriter::add(const SeriesRow& r) {
  rows_.push_back(r);
  const double total = r.kinetic_energy + r.strain_energy + r.plastic_dissipation + r.friction_work +
                       r.transfer_dissipation - r.gravity_work;
  // "{}" is the shortest representation that reads back to the same double.
  fmt::format_to(std::back_inserter(text_), "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                 r.step, r.time, r.kinetic_energy, r.strain_energy, r.gravity_work,
                 r.plastic_dissipation, r.friction_work, r.transfer_dissipation, total, r.mean_speed, r.max_speed, r.momentum_x,
                 r.momentum_y, r.num_particles, r.stage, r.runout, r.yielding_points);
  if (momentum_z_) fmt::format_to(std::back_inserter(text_), ",{}", r.momentum_z);
  text_ += '\n';
  dirty_ = true;
}

void SeriesWriter::flush() {
  write_file_atomically(file_, [&](std::ostream& os) {
    if (momentum_z_) {
      const std::string h = header();
      os << h.substr(0, h.size() - 1) << ",momentum_z\n";
    } else {
      os << header();
    }
    os.write(text_.data(), static_cast<std::streamsize>(text_.size()));
  });
  dirty_ = false;
}

}  // namespace skred
