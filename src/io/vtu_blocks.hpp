// Internal to the VTU writer: one binary block of the appended section per data array.
// Every block holds a fixed number of bytes per material point (points: 4 corners (2D) or 8
// (3D) x 3 coordinates; connectivity: 4 or 8 ids; cell data: one tuple), so all blocks are filled chunk by
// chunk over the particles.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/types.hpp"

namespace skred::vtu {

struct Block {
  const char* section;  // "Points", "Cells" or "CellData"
  std::string name;
  const char* type;
  int components;
  std::size_t value_bytes;
  std::size_t values_per_particle;
  std::vector<std::string> component_names;
  std::function<void(std::size_t begin, std::size_t end, unsigned char* out)> fill;

  std::size_t bytes_per_particle() const { return value_bytes * values_per_particle; }
};

template <class T>
inline unsigned char* put(unsigned char* out, T value) {
  std::memcpy(out, &value, sizeof value);
  return out + sizeof value;
}

inline unsigned char* put_sym3(unsigned char* out, const Sym3& s) {
  std::memcpy(out, s.data(), 6 * sizeof(double));
  return out + 6 * sizeof(double);
}

// A 3 x 3 tensor, row by row: xx, xy, xz, yx, yy, yz, zx, zy, zz (ParaView's tensor order).
inline unsigned char* put_mat3(unsigned char* out, const Mat3& m) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out = put(out, m(i, j));
  return out;
}

inline const std::vector<std::string>& voigt_names() {
  static const std::vector<std::string> n = {"xx", "yy", "zz", "xy", "yz", "xz"};
  return n;
}

inline const std::vector<std::string>& tensor_names() {
  static const std::vector<std::string> n = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  return n;
}

// A cell-data block of `components` doubles per particle computed by f(p, out) -> out.
template <class F>
Block doubles(std::string name, int components, F f, std::vector<std::string> names = {}) {
  return Block{"CellData",
               std::move(name),
               "Float64",
               components,
               sizeof(double),
               static_cast<std::size_t>(components),
               std::move(names),
               [f](std::size_t b, std::size_t e, unsigned char* out) {
                 for (std::size_t p = b; p < e; ++p) out = f(p, out);
               }};
}

template <class T>
Block integers(std::string name, const char* type, const std::vector<T>& values) {
  return Block{"CellData",
               std::move(name),
               type,
               1,
               sizeof(T),
               1,
               {},
               [&values](std::size_t b, std::size_t e, unsigned char* out) {
                 std::memcpy(out, values.data() + b, (e - b) * sizeof(T));
               }};
}

}  // namespace skred::vtu

namespace skred {
struct ParticleFields;
namespace vtu {
// Appends the post-processing cell fields of Post §5-7 (vtu_post_fields.cpp).
template <int D>
void add_post_blocks(std::vector<Block>& blocks, const Particles<D>& P, const ParticleFields& extra);
}  // namespace vtu
}  // namespace skred
