#include "io/pvd_writer.hpp"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <stdexcept>

#include "io/atomic_file.hpp"

namespace skred {

namespace {

std::string xml_attribute_escape(const std::string& s) {
  std::string r;
  r.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      case '\'': r += "&apos;"; break;
      default: r += c;
    }
  }
  return r;
}

}  // namespace

PvdWriter::PvdWriter(const std::filesystem::path& folder, const std::string& name)
    : file_(folder.empty() ? folder : folder / name) {}

void PvdWriter::add(double time, const std::string& vtu_filename) {
  if (!std::isfinite(time))
    throw std::invalid_argument(fmt::format("PvdWriter: non-finite time for '{}'", vtu_filename));
  // "{}" is the shortest representation that reads back to the same double.
  entries_ += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time,
                          xml_attribute_escape(vtu_filename));
  ++count_;
  if (file_.empty()) return;
  constexpr bool little = std::endian::native == std::endian::little;
  write_file_atomically(file_, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\""
       << (little ? "LittleEndian" : "BigEndian") << "\">\n"
       << "  <Collection>\n"
       << entries_ << "  </Collection>\n"
       << "</VTKFile>\n";
  });
}

}  // namespace skred
