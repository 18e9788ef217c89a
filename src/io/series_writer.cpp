#include "io/series_writer.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace skred {

const char* SeriesWriter::header() {
  return "step,time,kinetic_energy,strain_energy,gravity_work,plastic_dissipation,friction_work,"
         "transfer_dissipation,total_energy,"
         "mean_speed,max_speed,momentum_x,momentum_y,num_particles,stage,runout,yielding_points\n";
}

SeriesWriter::SeriesWriter(const std::filesystem::path& file, SeriesColumns extra)
    : file_(file), extra_(extra) {
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
  if (file_.empty()) return;  // (rows only)
  format_row(r, text_);
  dirty_ = true;
}

void SeriesWriter::format_row(const SeriesRow& r, std::string& out) const {
  const double total = r.kinetic_energy + r.strain_energy + r.plastic_dissipation + r.friction_work +
                       r.transfer_dissipation + r.contact_work + r.damping_work - r.gravity_work -
                       r.load_work;
  // "{}" is the shortest representation that reads back to the same double.
  fmt::format_to(std::back_inserter(out), "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", r.step,
                 r.time, r.kinetic_energy, r.strain_energy, r.gravity_work, r.plastic_dissipation,
                 r.friction_work, r.transfer_dissipation, total, r.mean_speed, r.max_speed, r.momentum_x,
                 r.momentum_y, r.num_particles, r.stage, r.runout, r.yielding_points);
  if (extra_.momentum_z) fmt::format_to(std::back_inserter(out), ",{}", r.momentum_z);
  if (extra_.contact_work) fmt::format_to(std::back_inserter(out), ",{}", r.contact_work);
  if (extra_.damping_work) fmt::format_to(std::back_inserter(out), ",{}", r.damping_work);
  if (extra_.material_speed) fmt::format_to(std::back_inserter(out), ",{}", r.material_speed);
  if (extra_.implicit)
    fmt::format_to(std::back_inserter(out), ",{},{},{}", r.iterations, r.residual, r.load_work);
  for (const auto& [name, k] : extra_.forces)
    fmt::format_to(std::back_inserter(out), ",{}", r.boundary_force[static_cast<std::size_t>(k)]);
  out += '\n';
}

namespace {

// Appends `text` to `file` with O_APPEND; false if the file is gone (it is then rewritten).
// On a failed or short write the file is cut back to its old length and this throws.
bool append(const std::filesystem::path& file, const std::string& text) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st {};
  ::fstat(fd, &st);
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      const int cut = ::ftruncate(fd, st.st_size);  // keep whole rows only (best effort)
      static_cast<void>(cut);
      ::close(fd);
      throw std::runtime_error(
          fmt::format("cannot write '{}': appending failed: {}", file.string(), std::strerror(err)));
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  return true;
}

}  // namespace

void SeriesWriter::flush() {
  if (file_.empty()) return;
  if (started_ && append(file_, text_)) {
    text_.clear();
    dirty_ = false;
    return;
  }
  if (started_) {  // the file went away: write it whole again
    text_.clear();
    for (const SeriesRow& r : rows_) format_row(r, text_);
  }
  write_file_atomically(file_, [&](std::ostream& os) {
    const std::string h = header();
    os << h.substr(0, h.size() - 1) << (extra_.momentum_z ? ",momentum_z" : "")
       << (extra_.contact_work ? ",contact_work" : "") << (extra_.damping_work ? ",damping_work" : "")
       << (extra_.material_speed ? ",material_speed" : "")
       << (extra_.implicit ? ",iterations,residual,load_work" : "");
    for (const auto& [name, k] : extra_.forces) os << ',' << name;
    os << '\n';
    os.write(text_.data(), static_cast<std::streamsize>(text_.size()));
  });
  started_ = true;
  text_.clear();
  dirty_ = false;
}

}  // namespace skred
