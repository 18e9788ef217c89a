// Time step and size estimates of a scenario (estimate.hpp).
#include "scenario/estimate.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <type_traits>
#include <variant>

#include "core/particles.hpp"
#include "scenario/build.hpp"

namespace skred {

namespace {

double measure(const Shape& shape) {
  return std::visit(
      [](const auto& sh) -> double {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Rectangle>)
          return (sh.max - sh.min).prod();
        else if constexpr (std::is_same_v<T, Disc>)
          return M_PI * sh.radius * sh.radius;
        else if constexpr (std::is_same_v<T, Layer>)
          return layer_area(sh);
        else
          return std::abs(polygon_area(sh));
      },
      shape);
}

double measure(const Shape3& shape) {
  return std::visit(
      [](const auto& sh) -> double {
        using T = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<T, Box>)
          return (sh.max - sh.min).prod();
        else if constexpr (std::is_same_v<T, Sphere>)
          return 4.0 / 3.0 * M_PI * std::pow(sh.radius, 3);
        else if constexpr (std::is_same_v<T, Cylinder>)
          return M_PI * sh.radius * sh.radius * sh.length;
        else
          return std::abs(polygon_area(sh.section)) * (sh.z_max - sh.z_min);
      },
      shape);
}

// Bytes a material point holds: its fields (core/particles.hpp) and its stored weighting
// functions (about 2 x 4 values per axis and node row).
template <int D>
double bytes_per_point() {
  std::size_t bytes = 0;
  Particles<D>().for_each_field(
      [&](const auto& f, const auto&) { bytes += sizeof(typename std::decay_t<decltype(f)>::value_type); });
  return static_cast<double>(bytes) + 64.0 * D;
}

// Grid fields per node (docs/method.md: 120 B in 2D, 176 B in 3D with every scheme's arrays)
// plus one scatter buffer of the second thread.
template <int D>
constexpr double kBytesPerNode = D == 2 ? 152.0 : 208.0;

}  // namespace

template <int D>
double stable_time_step(const ScenarioOf<D>& s) {
  double c = 0.0;  // the fastest P-wave speed of every density a stage gives a material
  for (std::size_t k = 0; k <= s.stages.size(); ++k)
    for (std::size_t m = 0; m < s.materials.size(); ++m) {
      Material mat = s.materials[m];
      mat.density = density_at_stage_start(s, k, static_cast<int>(m));
      c = std::max(c, mat.wave_speed());
    }
  double v = 0.0;
  for (const BodyOf<D>& b : s.bodies) v = std::max(v, b.velocity.norm() + b.velocity_sine.amplitude.norm());
  return s.cell_size / (c + v);
}

template <int D>
double scenario_time_step(const ScenarioOf<D>& s) {
  if (s.time_step > 0.0) return s.time_step;
  return s.cfl * stable_time_step(s);
}

template <int D>
ScenarioSize estimate_size(const ScenarioOf<D>& s) {
  ScenarioSize z;
  for (const BodyOf<D>& b : s.bodies)
    if (b.dilated_from < 0)  // a dilated continuum's points are its parent's
      z.points += measure(b.shape) * std::pow(b.particles_per_cell / s.cell_size, D);
  z.nodes = 1.0;
  for (int c : s.cells) z.nodes *= c + 1.0;
  z.steps = std::ceil(s.end_time / scenario_time_step(s));
  z.memory_bytes = z.points * bytes_per_point<D>() + z.nodes * kBytesPerNode<D>;
  z.frame_bytes = z.points * output_fields::uncompressed_bytes_per_point(s.output_fields, D);  // at most
  z.frames = s.output_interval > 0 ? std::floor(s.end_time / s.output_interval) + 1 : 1;
  return z;
}

double available_memory_bytes() {
  double bytes = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  std::ifstream cg("/sys/fs/cgroup/memory.max");
  double limit = 0;
  if (cg >> limit && limit > 0) bytes = std::min(bytes, limit);  // "max" reads as no number
  return bytes;
}

template double scenario_time_step<2>(const Scenario&);
template double scenario_time_step<3>(const Scenario3&);
template double stable_time_step<2>(const Scenario&);
template double stable_time_step<3>(const Scenario3&);
template ScenarioSize estimate_size<2>(const Scenario&);
template ScenarioSize estimate_size<3>(const Scenario3&);

}  // namespace skred
