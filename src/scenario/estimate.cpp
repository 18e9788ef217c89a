// Time step and size estimates of a scenario (estimate.hpp).
#include "scenario/estimate.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

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
        else if constexpr (std::is_same_v<T, Layer3>)
          return layer_volume(sh);
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
  Particles<D>().for_each_field([&](const auto& f, const auto&) {  // optional fields: off by default
    if (!f.optional) bytes += sizeof(typename std::decay_t<decltype(f)>::value_type);
  });
  return static_cast<double>(bytes) + 64.0 * D;
}

// Grid fields per node (solver/grid_fields.hpp: the mass and six vectors, 104 B in 2D and
// 152 B in 3D with every scheme's arrays) plus one scatter buffer of the second thread.
template <int D>
constexpr double kBytesPerNode = D == 2 ? 136.0 : 184.0;

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

template <int D>
double implicit_time_step(const ScenarioOf<D>& s, const Stage& st) {
  if (st.implicit.time_step > 0.0) return st.implicit.time_step;
  return kAutoImplicitSteps * stable_time_step(s);
}

template <int D>
ImplicitSystemSize estimate_implicit_system(const ScenarioOf<D>& s) {
  // Each body's grid nodes as a half-open box of node indices [lo, hi) per axis: the nodes of
  // the cells its bounding box covers.
  using Box = std::array<std::array<long, 2>, D>;
  std::vector<Box> boxes;
  for (const BodyOf<D>& b : s.bodies) {
    if (b.dilated_from >= 0) continue;  // its points are its parent's
    const ShapeBox<D> bb = bounding_box(b.shape);
    Box box;
    for (int d = 0; d < D; ++d) {
      const double cells = s.cells[static_cast<std::size_t>(d)];
      const double lo = std::floor((bb.lo[d] - s.origin[d]) / s.cell_size);
      const double hi = std::ceil((bb.hi[d] - s.origin[d]) / s.cell_size);
      box[d] = {static_cast<long>(std::clamp(lo, 0.0, cells)),
                static_cast<long>(std::clamp(hi, 0.0, cells)) + 1};
    }
    boxes.push_back(box);
  }
  ImplicitSystemSize z;
  if (boxes.empty()) return z;
  // The union's nodes: the boxes' corners cut each axis into intervals, and each product of
  // intervals lies inside a box or outside all (exact; a bound above a few hundred bodies).
  const double k = static_cast<double>(boxes.size());
  if (std::pow(2.0 * k, D) * k <= 1e8) {
    std::array<std::vector<long>, D> cuts;
    for (const Box& b : boxes)
      for (int d = 0; d < D; ++d) cuts[d].insert(cuts[d].end(), {b[d][0], b[d][1]});
    std::array<std::size_t, D> n{};
    for (int d = 0; d < D; ++d) {
      std::sort(cuts[d].begin(), cuts[d].end());
      cuts[d].erase(std::unique(cuts[d].begin(), cuts[d].end()), cuts[d].end());
      n[d] = cuts[d].size() - 1;
    }
    std::size_t total = 1;
    for (int d = 0; d < D; ++d) total *= n[d];
    for (std::size_t flat = 0; flat < total; ++flat) {
      std::array<long, D> lo{};
      double volume = 1.0;
      std::size_t rest = flat;
      for (int d = 0; d < D; ++d) {
        const std::size_t i = rest % n[d];
        rest /= n[d];
        lo[d] = cuts[d][i];
        volume *= static_cast<double>(cuts[d][i + 1] - lo[d]);
      }
      for (const Box& b : boxes) {
        bool inside = true;
        for (int d = 0; d < D; ++d) inside = inside && b[d][0] <= lo[d] && lo[d] < b[d][1];
        if (inside) {
          z.nodes += volume;
          break;
        }
      }
    }
  } else {
    for (const Box& b : boxes) {
      double nodes = 1.0;
      for (int d = 0; d < D; ++d) nodes *= static_cast<double>(b[d][1] - b[d][0]);
      z.nodes += nodes;
    }
    double grid = 1.0;
    for (int c : s.cells) grid *= c + 1.0;
    z.nodes = std::min(z.nodes, grid);
  }
  z.unknowns = D * z.nodes;
  if constexpr (D == 2) {
    long lo = boxes[0][0][0], hi = boxes[0][0][1];
    for (const Box& b : boxes) lo = std::min(lo, b[0][0]), hi = std::max(hi, b[0][1]);
    z.row_nodes = static_cast<double>(hi - lo);
    z.bandwidth = 2.0 * z.row_nodes * D;
  }
  // MUMPS' memory as measured on GIMP blocks (docs/studies/2026-12-02-implicit-equilibrium.md):
  // 2D 24 MB / 352 MB / 4.4 GB at 1e4 / 1e5 / 1e6 unknowns, 3D 96 MB / 1.5 GB at 6.6e3 / 4.7e4.
  z.direct_bytes = D == 2 ? kDirectBytes2 * z.unknowns * std::log2(std::max(2.0, z.unknowns))
                          : kDirectBytes3 * std::pow(z.unknowns, 4.0 / 3.0);
  return z;
}

double available_memory_bytes() {
  double bytes = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  std::ifstream cg("/sys/fs/cgroup/memory.max");
  double limit = 0;
  if (cg >> limit && limit > 0) bytes = std::min(bytes, limit);  // "max" reads as no number
  // The address-space limit (ulimit -v), less the address space the process holds already.
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    double held = 0.0;
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("VmSize:", 0) == 0) held = 1024.0 * std::strtod(line.c_str() + 7, nullptr);
    bytes = std::min(bytes, std::max(0.0, static_cast<double>(as.rlim_cur) - held));
  }
  return bytes;
}

template double scenario_time_step<2>(const Scenario&);
template double scenario_time_step<3>(const Scenario3&);
template double stable_time_step<2>(const Scenario&);
template double stable_time_step<3>(const Scenario3&);
template ScenarioSize estimate_size<2>(const Scenario&);
template ScenarioSize estimate_size<3>(const Scenario3&);
template double implicit_time_step<2>(const Scenario&, const Stage&);
template double implicit_time_step<3>(const Scenario3&, const Stage&);
template ImplicitSystemSize estimate_implicit_system<2>(const Scenario&);
template ImplicitSystemSize estimate_implicit_system<3>(const Scenario3&);

}  // namespace skred
