#include "io/vtu_writer.hpp"

#include <fmt/format.h>
#include <Eigen/LU>  // determinant(); core/types.hpp includes only Eigen/Core

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"
#include "io/vtu_blocks.hpp"

namespace skred {

namespace {

using namespace vtu;

constexpr std::uint8_t kVtkQuad = 9;
constexpr std::uint8_t kVtkHexahedron = 12;

// Velocity-like vectors padded to three components (z = 0 in 2D).
template <int D>
unsigned char* put_vec3(unsigned char* o, const Vec<D>& v) {
  o = put(put(o, v[0]), v[1]);
  return put(o, D == 3 ? v[D - 1] : 0.0);
}

// The corners x_p + F_p (+-l0) of a deformed voxel (Thesis eq. 3.6-3.12), in VTK order:
// a quad counter-clockwise (2D, z = 0), or a hexahedron's z- face then its z+ face.
template <int D>
unsigned char* put_corners(unsigned char* out, const Particles<D>& P, std::size_t p) {
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
constexpr std::size_t kChunk = 1 << 15;  // particles converted per buffer fill

template <int D>
std::vector<Block> make_blocks(const Particles<D>& P, const ParticleFields& extra) {
  const std::vector<std::string>& voigt = voigt_names();
  std::vector<Block> blocks;
  constexpr std::size_t corners = 1 << D;

  blocks.push_back({"Points",
                    "",
                    "Float64",
                    3,
                    sizeof(double),
                    3 * corners,
                    {},
                    [&P](std::size_t b, std::size_t e, unsigned char* out) {
                      for (std::size_t p = b; p < e; ++p) out = put_corners<D>(out, P, p);
                    }});
  blocks.push_back({"Cells",
                    "connectivity",
                    "Int64",
                    1,
                    8,
                    corners,
                    {},
                    [](std::size_t b, std::size_t e, unsigned char* out) {
                      for (std::size_t i = corners * b; i < corners * e; ++i)
                        out = put(out, static_cast<std::int64_t>(i));
                    }});
  blocks.push_back(
      {"Cells", "offsets", "Int64", 1, 8, 1, {}, [](std::size_t b, std::size_t e, unsigned char* out) {
         for (std::size_t p = b; p < e; ++p) out = put(out, static_cast<std::int64_t>(corners * (p + 1)));
       }});
  blocks.push_back(
      {"Cells", "types", "UInt8", 1, 1, 1, {}, [](std::size_t b, std::size_t e, unsigned char* out) {
         std::fill(out, out + (e - b), D == 3 ? kVtkHexahedron : kVtkQuad);
       }});

  blocks.push_back(
      doubles("velocity", 3, [&P](std::size_t p, unsigned char* o) { return put_vec3<D>(o, P.v[p]); }));
  blocks.push_back(doubles("displacement", 3, [&P](std::size_t p, unsigned char* o) {
    return put_vec3<D>(o, Vec<D>(P.x[p] - P.x_ref[p]));
  }));
  blocks.push_back(doubles(
      "stress", 6, [&P](std::size_t p, unsigned char* o) { return put_sym3(o, full_stress<D>(P.stress[p])); },
      voigt));
  blocks.push_back(doubles("mean_stress_p", 1, [&P](std::size_t p, unsigned char* o) {
    return put(o, mean_stress(full_stress<D>(P.stress[p])));
  }));
  blocks.push_back(doubles("deviatoric_stress_q", 1, [&P](std::size_t p, unsigned char* o) {
    return put(o, deviatoric_stress(full_stress<D>(P.stress[p])));
  }));
  blocks.push_back(
      doubles("volume", 1, [&P](std::size_t p, unsigned char* o) { return put(o, P.volume(p)); }));
  blocks.push_back(
      doubles("det_F", 1, [&P](std::size_t p, unsigned char* o) { return put(o, P.F[p].determinant()); }));
  blocks.push_back(doubles("plastic_shear_strain", 1, [&P](std::size_t p, unsigned char* o) {
    return put(o, P.state[p].plastic_shear_strain);
  }));
  blocks.push_back(
      {"CellData", "yielding", "UInt8", 1, 1, 1, {}, [&P](std::size_t b, std::size_t e, unsigned char* out) {
         for (std::size_t p = b; p < e; ++p) *out++ = P.state[p].yielding;
       }});
  blocks.push_back(integers("material_id", "Int16", P.material));
  blocks.push_back(integers("body_id", "Int16", P.body));

  if (extra.smoothed_stress) {
    const std::vector<Sym3>& s = *extra.smoothed_stress;
    blocks.push_back(doubles(
        "smoothed_stress", 6, [&s](std::size_t p, unsigned char* o) { return put_sym3(o, s[p]); }, voigt));
    blocks.push_back(doubles("smoothed_p", 1,
                             [&s](std::size_t p, unsigned char* o) { return put(o, mean_stress(s[p])); }));
    blocks.push_back(doubles(
        "smoothed_q", 1, [&s](std::size_t p, unsigned char* o) { return put(o, deviatoric_stress(s[p])); }));
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

std::string xml_header(const std::vector<Block>& blocks, std::size_t n, std::size_t corners) {
  constexpr bool little = std::endian::native == std::endian::little;
  std::string h;
  auto out = std::back_inserter(h);
  fmt::format_to(out,
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
                 "header_type=\"UInt64\">\n"
                 "  <UnstructuredGrid>\n"
                 "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
                 little ? "LittleEndian" : "BigEndian", corners * n, n);
  std::size_t offset = 0;
  const char* open = nullptr;
  for (const Block& b : blocks) {
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
    fmt::format_to(out, " format=\"appended\" offset=\"{}\"/>\n", offset);
    offset += sizeof(std::uint64_t) + n * b.bytes_per_particle();
  }
  if (open) fmt::format_to(out, "      </{}>\n", open);
  h += "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n_";
  return h;
}

template <int D>
void write_vtu(const std::filesystem::path& file, const Particles<D>& P, const ParticleFields& extra) {
  check_sizes(P, extra);
  const std::size_t n = P.size();
  const std::vector<Block> blocks = make_blocks(P, extra);
  const std::string header = xml_header(blocks, n, std::size_t{1} << D);

  write_file_atomically(file, [&](std::ostream& os) {
    os.write(header.data(), static_cast<std::streamsize>(header.size()));
    std::vector<unsigned char> buffer;
    for (const Block& b : blocks) {
      const std::uint64_t bytes = n * b.bytes_per_particle();
      os.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
      buffer.resize(std::min(n, kChunk) * b.bytes_per_particle());
      for (std::size_t begin = 0; begin < n && os; begin += kChunk) {
        const std::size_t end = std::min(n, begin + kChunk);
        b.fill(begin, end, buffer.data());
        os.write(reinterpret_cast<const char*>(buffer.data()),
                 static_cast<std::streamsize>((end - begin) * b.bytes_per_particle()));
      }
    }
    os << "\n  </AppendedData>\n</VTKFile>\n";
  });
}

}  // namespace

void write_particles_vtu(const std::filesystem::path& file, const Particles<2>& P,
                         const ParticleFields& extra) {
  write_vtu(file, P, extra);
}

void write_particles_vtu(const std::filesystem::path& file, const Particles<3>& P,
                         const ParticleFields& extra) {
  write_vtu(file, P, extra);
}

}  // namespace skred
