#include "io/vtu_writer.hpp"

#include <fmt/format.h>
#include <Eigen/LU>  // determinant(); core/types.hpp includes only Eigen/Core

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"
#include "io/vtk_appended.hpp"
#include "io/vtu_blocks.hpp"
#include "scenario/output_fields.hpp"

namespace skred {

namespace {

using namespace vtu;

constexpr std::uint8_t kVtkQuad = 9;
constexpr std::uint8_t kVtkHexahedron = 12;

// Velocity-like vectors padded to three components (z = 0 in 2D).
template <int D>
double* put_vec3(double* o, const Vec<D>& v) {
  o = put(put(o, v[0]), v[1]);
  return put(o, D == 3 ? v[D - 1] : 0.0);
}

// The corners x_p + F_p (+-l0) of a deformed voxel (Thesis eq. 3.6-3.12), in VTK order:
// a quad counter-clockwise (2D, z = 0), or a hexahedron's z- face then its z+ face.
template <int D>
double* put_corners(double* out, const Particles<D>& P, std::size_t p) {
  static constexpr double sx[8] = {-1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0};
  static constexpr double sy[8] = {-1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0};
  static constexpr double sz[8] = {-1.0, -1.0, -1.0, -1.0, 1.0, 1.0, 1.0, 1.0};
  const Vec<D>& l0 = P.half0[p];
  for (int k = 0; k < (1 << D); ++k) {
    Vec<D> a;
    a[0] = sx[k] * l0[0];
    a[1] = sy[k] * l0[1];
    if constexpr (D == 3) a[2] = sz[k] * l0[2];
    out = put_vec3<D>(out, Vec<D>(P.x[p] + P.F[p] * a));
  }
  return out;
}

// Whether the voxel corners may be stored as Float32: its rounding, 2^-24 |x| at most, must
// stay below 1e-3 of the smallest voxel half-size. Local coordinates pass easily (a 1 km
// slope: 0.06 mm against voxels of centimetres or more); georeferenced ones (UTM, |x| ~ 5e5 m:
// 3 cm) fall back to Float64 rather than draw jagged voxels.
template <int D>
bool corners_fit_float32(const Particles<D>& P, const VtuOptions& options) {
  if (options.corners_float32) return *options.corners_float32;
  return corners_fit_float32(corner_span(P));
}

// Cell connectivity and offsets as Int32 while the point count allows, else Int64.
template <class Int, std::size_t corners>
void add_cells(std::vector<Block>& blocks, const char* type) {
  blocks.push_back({"Cells",
                    "connectivity",
                    type,
                    1,
                    sizeof(Int),
                    corners,
                    {},
                    [](std::size_t b, std::size_t e, unsigned char* out) {
                      for (std::size_t i = corners * b; i < corners * e; ++i)
                        out = put_bytes(out, static_cast<Int>(i));
                    }});
  blocks.push_back(
      {"Cells", "offsets", type, 1, sizeof(Int), 1, {}, [](std::size_t b, std::size_t e, unsigned char* out) {
         for (std::size_t p = b; p < e; ++p) out = put_bytes(out, static_cast<Int>(corners * (p + 1)));
       }});
}

template <int D>
std::vector<Block> make_blocks(const Particles<D>& P, const ParticleFields& extra,
                               const VtuOptions& options) {
  const std::vector<std::string>& voigt = voigt_names();
  std::vector<Block> blocks;
  constexpr std::size_t corners = 1 << D;

  blocks.push_back(real_block("Points", "", 3, 3 * corners, corners_fit_float32(P, options),
                              [&P](std::size_t p, double* o) { put_corners<D>(o, P, p); }));
  if (corners * P.size() <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    add_cells<std::int32_t, corners>(blocks, "Int32");
  else
    add_cells<std::int64_t, corners>(blocks, "Int64");
  blocks.push_back(
      {"Cells", "types", "UInt8", 1, 1, 1, {}, [](std::size_t b, std::size_t e, unsigned char* out) {
         std::fill(out, out + (e - b), D == 3 ? kVtkHexahedron : kVtkQuad);
       }});

  blocks.push_back(reals("velocity", 3, [&P](std::size_t p, double* o) { return put_vec3<D>(o, P.v[p]); }));
  blocks.push_back(reals("displacement", 3, [&P](std::size_t p, double* o) {
    return put_vec3<D>(o, Vec<D>(P.x[p] - P.x_ref[p]));
  }));
  blocks.push_back(reals(
      "stress", 6, [&P](std::size_t p, double* o) { return put_sym3(o, full_stress<D>(P.stress[p])); },
      voigt));
  blocks.push_back(reals("mean_stress_p", 1, [&P](std::size_t p, double* o) {
    return put(o, mean_stress(full_stress<D>(P.stress[p])));
  }));
  blocks.push_back(reals("deviatoric_stress_q", 1, [&P](std::size_t p, double* o) {
    return put(o, deviatoric_stress(full_stress<D>(P.stress[p])));
  }));
  blocks.push_back(reals("volume", 1, [&P](std::size_t p, double* o) { return put(o, P.volume(p)); }));
  blocks.push_back(
      reals("det_F", 1, [&P](std::size_t p, double* o) { return put(o, P.F[p].determinant()); }));
  blocks.push_back(reals("plastic_shear_strain", 1,
                         [&P](std::size_t p, double* o) { return put(o, P.state[p].plastic_shear_strain); }));
  blocks.push_back(
      {"CellData", "yielding", "UInt8", 1, 1, 1, {}, [&P](std::size_t b, std::size_t e, unsigned char* out) {
         for (std::size_t p = b; p < e; ++p) *out++ = P.state[p].yielding;
       }});
  blocks.push_back(integers("material_id", "Int16", P.material));
  blocks.push_back(integers("body_id", "Int16", P.body));

  if (extra.smoothed_stress) {
    const std::vector<Sym3>& s = *extra.smoothed_stress;
    blocks.push_back(reals(
        "smoothed_stress", 6, [&s](std::size_t p, double* o) { return put_sym3(o, s[p]); }, voigt));
    blocks.push_back(
        reals("smoothed_p", 1, [&s](std::size_t p, double* o) { return put(o, mean_stress(s[p])); }));
    blocks.push_back(
        reals("smoothed_q", 1, [&s](std::size_t p, double* o) { return put(o, deviatoric_stress(s[p])); }));
  }
  add_post_blocks<D>(blocks, P, extra);
  return blocks;
}

template <class T>
void check_optional(const std::vector<T>* v, const char* name, std::size_t n) {
  if (v && v->size() != n)
    throw std::invalid_argument(
        fmt::format("write_particles_vtu: {} has {} entries for {} particles", name, v->size(), n));
}

template <int D>
void check_sizes(const Particles<D>& P, const ParticleFields& extra) {
  const std::size_t n = P.size();
  P.for_each_field([&](const auto& f, const auto& a) {  // every field of the list
    if (a.size() != n && !(f.optional && a.empty()))
      throw std::invalid_argument(fmt::format(
          "write_particles_vtu: particle arrays differ in size ({} has {} entries for {} particles)", f.name,
          a.size(), n));
  });
  check_optional(extra.smoothed_stress, "smoothed_stress", n);
  check_optional(extra.elastic_F, "elastic_F", n);
  check_optional(extra.stress_from_elastic_F, "stress_from_elastic_F", n);
  if (extra.strength)
    for (std::size_t p = 0; p < n; ++p)
      if (P.material[p] < 0 || static_cast<std::size_t>(P.material[p]) >= extra.strength->size())
        throw std::invalid_argument(
            fmt::format("write_particles_vtu: particle {} has material {} but strength lists {} materials", p,
                        P.material[p], extra.strength->size()));
}

std::string xml_header(const std::vector<Block>& blocks, std::size_t n, std::size_t corners, bool compress,
                       const std::vector<std::uint64_t>& offsets) {
  std::string h = "<?xml version=\"1.0\"?>\n" + vtk::vtkfile_element("UnstructuredGrid", compress);
  auto out = std::back_inserter(h);
  fmt::format_to(out,
                 "  <UnstructuredGrid>\n"
                 "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                 corners * n, n);
  const char* open = nullptr;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const Block& b = blocks[i];
    if (!open || std::strcmp(open, b.section) != 0) {
      if (open) fmt::format_to(out, "      </{}>\n", open);
      open = b.section;
      fmt::format_to(out, "      <{}>\n", open);
    }
    fmt::format_to(out, "        <DataArray type=\"{}\"", b.type);
    if (!b.name.empty()) fmt::format_to(out, " Name=\"{}\"", b.name);
    if (b.components != 1) fmt::format_to(out, " NumberOfComponents=\"{}\"", b.components);
    for (std::size_t c = 0; c < b.component_names.size(); ++c)
      fmt::format_to(out, " ComponentName{}=\"{}\"", c, b.component_names[c]);
    fmt::format_to(out, " format=\"appended\"{}/>\n", vtk::offset_attribute(offsets[i]));
  }
  if (open) fmt::format_to(out, "      </{}>\n", open);
  h += "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_";
  return h;
}

// The blocks of `fields` (all when empty) besides the points and cells, in the file's order.
std::vector<Block> chosen(std::vector<Block> blocks, const std::vector<std::string>& fields) {
  const std::vector<std::string>& all = output_fields::all();
  for (const std::string& f : fields)
    if (std::find(all.begin(), all.end(), f) == all.end())
      throw std::invalid_argument(fmt::format("write_particles_vtu: no field is called '{}'", f));
  if (fields.empty()) return blocks;
  std::erase_if(blocks, [&](const Block& b) {
    return std::strcmp(b.section, "CellData") == 0 &&
           std::find(fields.begin(), fields.end(), b.name) == fields.end();
  });
  return blocks;
}

template <int D>
void write_vtu(const std::filesystem::path& file, const Particles<D>& P, const ParticleFields& extra,
               const VtuOptions& options) {
  check_sizes(P, extra);
  const std::size_t n = P.size();
  const std::vector<Block> blocks = chosen(make_blocks(P, extra, options), options.fields);
  std::vector<vtk::AppendedArray> arrays;
  for (const Block& b : blocks) arrays.push_back({n, b.bytes_per_particle(), b.fill});
  write_file_atomically(file, [&](std::ostream& os) {
    vtk::write_appended(
        os,
        [&](const std::vector<std::uint64_t>& offsets) {
          return xml_header(blocks, n, std::size_t{1} << D, options.compress, offsets);
        },
        arrays, options.compress, "\n  </AppendedData>\n</VTKFile>\n");
  });
}

// The index of a frame in pieces: the arrays of make_blocks without their data.
template <int D>
void write_pvtu(const std::filesystem::path& file, const std::vector<std::string>& pieces,
                const Particles<D>& P, const ParticleFields& extra, const VtuOptions& options) {
  const std::vector<Block> blocks = chosen(make_blocks(P, extra, options), options.fields);
  std::string h = "<?xml version=\"1.0\"?>\n" + vtk::vtkfile_element("PUnstructuredGrid", options.compress);
  auto out = std::back_inserter(h);
  fmt::format_to(out, "  <PUnstructuredGrid GhostLevel=\"0\">\n");
  for (const char* section : {"Points", "CellData"}) {
    fmt::format_to(out, "    <P{}>\n", section);
    for (const Block& b : blocks) {
      if (std::strcmp(b.section, section) != 0) continue;
      fmt::format_to(out, "      <PDataArray type=\"{}\"", b.type);
      if (!b.name.empty()) fmt::format_to(out, " Name=\"{}\"", b.name);
      if (b.components != 1) fmt::format_to(out, " NumberOfComponents=\"{}\"", b.components);
      for (std::size_t c = 0; c < b.component_names.size(); ++c)
        fmt::format_to(out, " ComponentName{}=\"{}\"", c, b.component_names[c]);
      h += "/>\n";
    }
    fmt::format_to(out, "    </P{}>\n", section);
  }
  for (const std::string& piece : pieces) fmt::format_to(out, "    <Piece Source=\"{}\"/>\n", piece);
  h += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_file_atomically(file, [&](std::ostream& os) { os << h; });
}

}  // namespace

template <int D>
CornerSpan corner_span(const Particles<D>& P) {
  CornerSpan c;
  for (std::size_t p = 0; p < P.size(); ++p) {
    c.reach = std::max(c.reach, P.x[p].cwiseAbs().maxCoeff() + (P.F[p] * P.half0[p]).cwiseAbs().maxCoeff() +
                                    P.half0[p].maxCoeff());
    c.half = std::min(c.half, P.half0[p].minCoeff());
  }
  return c;
}
template CornerSpan corner_span<2>(const Particles<2>&);
template CornerSpan corner_span<3>(const Particles<3>&);

bool corners_fit_float32(const CornerSpan& c) { return c.reach * std::ldexp(1.0, -24) <= 1e-3 * c.half; }

void write_particles_pvtu(const std::filesystem::path& file, const std::vector<std::string>& pieces,
                          const Particles<2>& P, const ParticleFields& extra, const VtuOptions& options) {
  write_pvtu(file, pieces, P, extra, options);
}

void write_particles_pvtu(const std::filesystem::path& file, const std::vector<std::string>& pieces,
                          const Particles<3>& P, const ParticleFields& extra, const VtuOptions& options) {
  write_pvtu(file, pieces, P, extra, options);
}

void write_particles_vtu(const std::filesystem::path& file, const Particles<2>& P,
                         const ParticleFields& extra, const VtuOptions& options) {
  write_vtu(file, P, extra, options);
}

void write_particles_vtu(const std::filesystem::path& file, const Particles<3>& P,
                         const ParticleFields& extra, const VtuOptions& options) {
  write_vtu(file, P, extra, options);
}

}  // namespace skred
