// The particle fields a frame may hold ([output] fields): the names of the cell arrays of
// particles_NNNNNN.vtu (docs/post-processing.md describes each). Declared here, below io, so
// the schema, the parser and the VTU writer share one list.
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skred::output_fields {

// Every field, in the order of the file ("all"), separated by '|'.
inline constexpr const char* kAll =
    "velocity|displacement|stress|mean_stress_p|deviatoric_stress_q|volume|det_F|plastic_shear_strain|"
    "yielding|material_id|body_id|smoothed_stress|smoothed_p|smoothed_q|speed|F|engineering_strain|"
    "green_strain|hencky_strain|principal_stress|principal_angle|relative_yield|smoothed_principal_stress|"
    "smoothed_principal_angle|smoothed_relative_yield|Fe|Fp|stress_from_Fe";

// What a geotechnical user opens first ("default"): motion, the stress and its invariants
// (also grid-smoothed p, the quieter one), how close to failure and how far it yielded,
// volume change, and which material and body a point belongs to.
inline constexpr const char* kDefault =
    "velocity|speed|displacement|stress|mean_stress_p|deviatoric_stress_q|smoothed_p|relative_yield|"
    "plastic_shear_strain|yielding|det_F|material_id|body_id";

inline std::vector<std::string> split(std::string_view list) {
  std::vector<std::string> names;
  for (std::size_t a = 0; a <= list.size();) {
    const std::size_t b = std::min(list.find('|', a), list.size());
    names.emplace_back(list.substr(a, b - a));
    a = b + 1;
  }
  return names;
}

// Whether a frame holds a field of the multiplicative split F = Fe Fp (Post eq. 67-77): only
// then do the points track Fe (Particles::track_elastic_F).
inline bool wants_elastic_split(const std::vector<std::string>& fields) {
  for (const std::string& f : fields)
    if (f == "Fe" || f == "Fp" || f == "stress_from_Fe") return true;
  return false;
}

inline const std::vector<std::string>& all() {
  static const std::vector<std::string> names = split(kAll);
  return names;
}

inline const std::vector<std::string>& defaults() {
  static const std::vector<std::string> names = split(kDefault);
  return names;
}

// Bytes per point of a field in an uncompressed frame (Float32 components, UInt8, Int16).
inline double field_bytes(std::string_view name) {
  static constexpr std::pair<std::string_view, int> sizes[] = {{"velocity", 12},
                                                               {"displacement", 12},
                                                               {"stress", 24},
                                                               {"smoothed_stress", 24},
                                                               {"F", 36},
                                                               {"engineering_strain", 24},
                                                               {"green_strain", 24},
                                                               {"hencky_strain", 24},
                                                               {"principal_stress", 12},
                                                               {"smoothed_principal_stress", 12},
                                                               {"Fe", 36},
                                                               {"Fp", 36},
                                                               {"stress_from_Fe", 24},
                                                               {"yielding", 1},
                                                               {"material_id", 2},
                                                               {"body_id", 2}};
  for (const auto& [n, b] : sizes)
    if (n == name) return b;
  return 4;  // a scalar
}

// Bytes per point of an uncompressed D-dimensional frame holding `fields`: the Float32
// corners of the voxel, its Int32 connectivity, offset and cell type, and the fields. The
// zlib-compressed frame is smaller (docs/post-processing.md).
inline double uncompressed_bytes_per_point(const std::vector<std::string>& fields, int D) {
  const double corners = D == 3 ? 8 : 4;
  double bytes = corners * 12 + corners * 4 + 4 + 1;
  for (const std::string& f : fields) bytes += field_bytes(f);
  return bytes;
}

}  // namespace skred::output_fields
