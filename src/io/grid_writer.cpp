#include "io/grid_writer.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/vtk_appended.hpp"

namespace skred {

namespace {

// One appended array: its XML attributes and its values (Float32 for the nodal fields, Float64
// for the coordinates, UInt8 in `bytes`).
struct Array {
  std::string name;
  int components;
  std::vector<std::string> component_names;
  std::vector<double> values;
  std::vector<std::uint8_t> bytes = {};
  bool single = true;

  bool is_bytes() const { return values.empty() && !bytes.empty(); }
  const char* type() const { return is_bytes() ? "UInt8" : single ? "Float32" : "Float64"; }
  vtk::AppendedArray appended() const {
    if (is_bytes())
      return {bytes.size(), 1, [this](std::size_t b, std::size_t e, unsigned char* out) {
                std::memcpy(out, bytes.data() + b, e - b);
              }};
    return {values.size(), single ? sizeof(float) : sizeof(double),
            [this](std::size_t b, std::size_t e, unsigned char* out) {
              for (std::size_t i = b; i < e; ++i) {
                if (single) {
                  const float x = static_cast<float>(values[i]);
                  std::memcpy(out, &x, sizeof x);
                  out += sizeof x;
                } else {
                  std::memcpy(out, &values[i], sizeof(double));
                  out += sizeof(double);
                }
              }
            }};
  }
};

template <int D>
std::string header(const GridGeometry<D>& g, const std::vector<Array>& coords,
                   const std::vector<Array>& point_data, bool compress,
                   const std::vector<std::uint64_t>& offsets) {
  std::string h = "<?xml version=\"1.0\"?>\n" + vtk::vtkfile_element("RectilinearGrid", compress);
  auto out = std::back_inserter(h);
  const int nx = g.nodes(0) - 1, ny = g.nodes(1) - 1, nz = D == 3 ? g.nodes(D - 1) - 1 : 0;
  fmt::format_to(out,
                 "  <RectilinearGrid WholeExtent=\"0 {} 0 {} 0 {}\">\n"
                 "    <Piece Extent=\"0 {} 0 {} 0 {}\">\n",
                 nx, ny, nz, nx, ny, nz);
  std::size_t i = 0;
  auto arrays = [&](const char* section, const std::vector<Array>& list) {
    fmt::format_to(out, "      <{}>\n", section);
    for (const Array& a : list) {
      fmt::format_to(out, "        <DataArray type=\"{}\" Name=\"{}\"", a.type(), a.name);
      if (a.components != 1) fmt::format_to(out, " NumberOfComponents=\"{}\"", a.components);
      for (std::size_t c = 0; c < a.component_names.size(); ++c)
        fmt::format_to(out, " ComponentName{}=\"{}\"", c, a.component_names[c]);
      fmt::format_to(out, " format=\"appended\"{}/>\n", vtk::offset_attribute(offsets[i++]));
    }
    fmt::format_to(out, "      </{}>\n", section);
  };
  arrays("PointData", point_data);
  arrays("Coordinates", coords);
  h += "    </Piece>\n  </RectilinearGrid>\n  <AppendedData encoding=\"raw\">\n_";
  return h;
}

template <int D>
void write_vtr(const std::filesystem::path& file, const GridGeometry<D>& grid, const GridNodeFieldsOf<D>& f,
               bool compress) {
  const std::size_t n = grid.node_count();
  if (f.mass.size() != n || f.velocity.size() != n || f.stress.size() != n)
    throw std::invalid_argument(
        fmt::format("write_grid_vtr: {} nodes but mass/velocity/stress have {}/{}/{} entries", n,
                    f.mass.size(), f.velocity.size(), f.stress.size()));

  std::vector<Array> coords;  // Float64: node coordinates may be georeferenced
  for (int d = 0; d < D; ++d) {
    Array a{d == 0 ? "x" : d == 1 ? "y" : "z", 1, {}, {}, {}, false};
    for (int j = 0; j < grid.nodes(d); ++j) a.values.push_back(grid.origin[d] + grid.node_coordinate(d, j));
    coords.push_back(std::move(a));
  }
  if (D == 2) coords.push_back({"z", 1, {}, {0.0}, {}, false});

  std::vector<Array> data = {{"mass", 1, {}, {}},
                             {"velocity", 3, {}, {}},
                             {"stress", 6, {"xx", "yy", "zz", "xy", "yz", "xz"}, {}},
                             {"mean_stress_p", 1, {}, {}},
                             {"deviatoric_stress_q", 1, {}, {}}};
  for (Array& a : data) a.values.reserve(n * static_cast<std::size_t>(a.components));
  Array mask{"has_material", 1, {}, {}, std::vector<std::uint8_t>(n)};  // 0: an empty node
  for (std::size_t i = 0; i < n; ++i) {
    data[0].values.push_back(f.mass[i]);
    data[1].values.insert(data[1].values.end(),
                          {f.velocity[i][0], f.velocity[i][1], D == 3 ? f.velocity[i][D - 1] : 0.0});
    data[2].values.insert(data[2].values.end(), f.stress[i].data(), f.stress[i].data() + 6);
    data[3].values.push_back(mean_stress(f.stress[i]));        // Post eq. 61
    data[4].values.push_back(deviatoric_stress(f.stress[i]));  // Post eq. 62
    mask.bytes[i] = f.mass[i] > 0.0;
  }
  data.push_back(std::move(mask));
  const std::pair<const char*, std::span<const double>> magnitudes[] = {
      {"stiffness_magnitude", f.stiffness_magnitude},
      {"internal_force_magnitude", f.internal_force_magnitude}};
  for (const auto& [name, values] : magnitudes) {
    if (values.empty()) continue;
    if (values.size() != n)
      throw std::invalid_argument(
          fmt::format("write_grid_vtr: {} nodes but {} has {} entries", n, name, values.size()));
    data.push_back({name, 1, {}, std::vector<double>(values.begin(), values.end())});
  }

  std::vector<vtk::AppendedArray> arrays;
  for (const auto* list : {&data, &coords})
    for (const Array& a : *list) arrays.push_back(a.appended());
  write_file_atomically(file, [&](std::ostream& os) {
    vtk::write_appended(
        os,
        [&](const std::vector<std::uint64_t>& offsets) {
          return header(grid, coords, data, compress, offsets);
        },
        arrays, compress, "\n  </AppendedData>\n</VTKFile>\n");
  });
}

}  // namespace

void write_grid_vtr(const std::filesystem::path& file, const GridGeometry<2>& grid, const GridNodeFields& f,
                    bool compress) {
  write_vtr(file, grid, f, compress);
}

void write_grid_vtr(const std::filesystem::path& file, const GridGeometry<3>& grid,
                    const GridNodeFieldsOf<3>& f, bool compress) {
  write_vtr(file, grid, f, compress);
}

}  // namespace skred
