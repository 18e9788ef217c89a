// Internal to the VTU writer: one data array of the appended section per block. Every block
// holds a fixed number of bytes per material point (points: 4 corners (2D) or 8 (3D) x 3
// coordinates; connectivity: 4 or 8 ids; cell data: one tuple), so all blocks are filled chunk
// by chunk over the particles (in parallel: fill must only read the particles).
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

// Real values are computed in double and stored as Float32 (vtu_writer.hpp says why).
inline double* put(double* out, double value) {
  *out = value;
  return out + 1;
}

inline double* put_sym3(double* out, const Sym3& s) {
  for (int k = 0; k < 6; ++k) *out++ = s[k];
  return out;
}

// A 3 x 3 tensor, row by row: xx, xy, xz, yx, yy, yz, zx, zy, zz (ParaView's tensor order).
inline double* put_mat3(double* out, const Mat3& m) {
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

template <class T>
inline unsigned char* put_bytes(unsigned char* out, T value) {
  std::memcpy(out, &value, sizeof value);
  return out + sizeof value;
}

// A block of `values` (at most 24) reals per particle, computed in double by f(p, out) and
// stored as Float32 (`single`) or Float64.
template <class F>
Block real_block(const char* section, std::string name, int components, std::size_t values, bool single,
                 F f) {
  Block b{section, std::move(name), single ? "Float32" : "Float64", components, single ? 4u : 8u, values,
          {},      nullptr};
  b.fill = [f, values, single](std::size_t begin, std::size_t end, unsigned char* out) {
    double v[24];
    for (std::size_t p = begin; p < end; ++p) {
      f(p, v);
      for (std::size_t k = 0; k < values; ++k)
        out = single ? put_bytes(out, static_cast<float>(v[k])) : put_bytes(out, v[k]);
    }
  };
  return b;
}

// A cell-data block of `components` (at most 9) Float32 per particle from f(p, out) -> out.
template <class F>
Block reals(std::string name, int components, F f, std::vector<std::string> names = {}) {
  Block b =
      real_block("CellData", std::move(name), components, static_cast<std::size_t>(components), true, f);
  b.component_names = std::move(names);
  return b;
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
