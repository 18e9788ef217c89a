#include "scenario/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace skred {
namespace {

// The sub-cell centres q = origin + (i + 1/2) h/n turned by the body's lattice_rotation about its
// lattice_centre c, x = c + R (q - c) (Acosta §6, fig. 19), that lie inside the shape, the grid and
// no later body, lattice rows in order (i fastest). Stops early when f returns false.
template <class Claimed, class F>
void for_each_turned_point(const Scenario& s, const Body& body, const ShapeBox<2>& box, CellColumns columns,
                           Claimed&& claimed_later, F&& f) {
  const double sub = s.cell_size / body.particles_per_cell, a = body.lattice_rotation;
  const double cs = std::cos(a), sn = std::sin(a);
  const Vec<2> c = body.lattice_centre;
  const auto turn = [&](const Vec<2>& q, double sign) {  // c + R(sign a)(q - c)
    const Vec<2> d = q - c;
    return Vec<2>(c[0] + cs * d[0] - sign * sn * d[1], c[1] + sign * sn * d[0] + cs * d[1]);
  };
  // The lattice indices whose points can reach the shape's box: its corners turned back.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int k = 0; k < 4; ++k) {
    const Vec<2> q = turn(Vec<2>(k & 1 ? box.hi[0] : box.lo[0], k & 2 ? box.hi[1] : box.lo[1]), -1.0);
    for (int d = 0; d < 2; ++d) lo[d] = std::min(lo[d], q[d]), hi[d] = std::max(hi[d], q[d]);
  }
  long first[2], last[2];
  for (int d = 0; d < 2; ++d) {
    first[d] = static_cast<long>(std::floor((lo[d] - s.origin[d]) / sub)) - 1;
    last[d] = static_cast<long>(std::ceil((hi[d] - s.origin[d]) / sub)) + 1;
  }
  Vec<2> top = s.origin;
  for (int d = 0; d < 2; ++d) top[d] += s.cells[static_cast<std::size_t>(d)] * s.cell_size;
  for (long j = first[1]; j <= last[1]; ++j)
    for (long i = first[0]; i <= last[0]; ++i) {
      const Vec<2> q(s.origin[0] + (static_cast<double>(i) + 0.5) * sub,
                     s.origin[1] + (static_cast<double>(j) + 0.5) * sub);
      const Vec<2> x = turn(q, 1.0);
      if ((x - s.origin).minCoeff() < 0.0 || (x - top).maxCoeff() >= 0.0) continue;  // off the grid
      if (!columns.holds(column_of(s, x))) continue;
      if (shape_contains(body.shape, x) && !claimed_later(x) && !f(x)) return;
    }
}

// Calls f(point) for every sub-cell centre of the body's bounding-box cells (in `columns`) that
// lies inside the shape, cells in row-major order (x fastest, then y, then z), then the
// sub-cells of a cell in the same order. Stops early when f returns false.
template <int D, class F>
void for_each_point(const ScenarioOf<D>& s, const BodyOf<D>& body, F&& f, CellColumns columns = {}) {
  // With body_overlap = "later-wins" a point a later body claims is that body's only.
  std::size_t later = s.bodies.size();
  if (s.later_body_wins && &body >= s.bodies.data() && &body < s.bodies.data() + s.bodies.size())
    later = static_cast<std::size_t>(&body - s.bodies.data()) + 1;
  const auto claimed_later = [&](const Vec<D>& x) {
    for (std::size_t k = later; k < s.bodies.size(); ++k)
      if (s.bodies[k].dilated_from < 0 && shape_contains(s.bodies[k].shape, x)) return true;
    return false;
  };
  const double h = s.cell_size;
  const int n = body.particles_per_cell;
  if (!(h > 0.0) || n < 1) return;
  for (int d = 0; d < D; ++d)
    if (s.cells[static_cast<std::size_t>(d)] < 1) return;
  const double sub = h / n;
  const ShapeBox<D> box = bounding_box(body.shape);
  int lo[D], hi[D];
  for (int d = 0; d < D; ++d) {
    const double cells = s.cells[static_cast<std::size_t>(d)];
    const double a = std::floor((box.lo[d] - s.origin[d]) / h);
    const double b = std::floor((box.hi[d] - s.origin[d]) / h);
    if (!(b >= 0.0) || !(a <= cells - 1.0)) return;  // entirely outside the grid
    lo[d] = static_cast<int>(std::max(a, 0.0));
    hi[d] = static_cast<int>(std::min(b, cells - 1.0));
  }
  if constexpr (D == 2)
    if (body.lattice_rotation != 0.0) return for_each_turned_point(s, body, box, columns, claimed_later, f);
  lo[0] = std::max(lo[0], columns.first);
  hi[0] = std::min(hi[0], columns.end - 1);
  // Cell index c and sub-cell index q per axis, the lowest axis fastest in both.
  const int k_lo = D == 3 ? lo[D - 1] : 0, k_hi = D == 3 ? hi[D - 1] : 0;
  const int nz = D == 3 ? n : 1;
  for (int k = k_lo; k <= k_hi; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (int c = 0; c < nz; ++c)
          for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
              Vec<D> x;
              x[0] = s.origin[0] + i * h + (a + 0.5) * sub;
              x[1] = s.origin[1] + j * h + (b + 0.5) * sub;
              if constexpr (D == 3) x[2] = s.origin[2] + k * h + (c + 0.5) * sub;
              if (shape_contains(body.shape, x) && !claimed_later(x) && !f(x)) return;
            }
}

}  // namespace

template <int D>
std::size_t count_points(const ScenarioOf<D>& s, const BodyOf<D>& b, CellColumns columns) {
  std::size_t n = 0;
  for_each_point(
      s, b, [&](const Vec<D>&) { return ++n, true; }, columns);
  return n;
}

template <int D>
std::vector<long> points_per_column(const ScenarioOf<D>& s, CellColumns columns) {
  std::vector<long> n(static_cast<std::size_t>(std::max(0, s.cells[0])), 0);
  for (const BodyOf<D>& b : s.bodies)
    if (b.dilated_from < 0)
      for_each_point(
          s, b,
          [&](const Vec<D>& x) {
            ++n[static_cast<std::size_t>(std::clamp(column_of(s, x), 0, s.cells[0] - 1))];
            return true;
          },
          columns);
  return n;
}

template <int D>
bool has_points(const ScenarioOf<D>& s, const BodyOf<D>& b) {
  bool any = false;
  for_each_point(s, b, [&](const Vec<D>&) { return any = true, false; });
  return any;
}

template <int D>
Particles<D> build_particles(const ScenarioOf<D>& s, CellColumns columns) {
  if (s.bodies.size() > static_cast<std::size_t>(kMaxIds) ||
      s.materials.size() > static_cast<std::size_t>(kMaxIds))
    throw ScenarioError(
        fmt::format("{}: at most {} bodies and {} materials are supported", s.source, kMaxIds, kMaxIds));
  std::vector<std::size_t> counts;
  std::size_t total = 0;
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    counts.push_back(s.bodies[i].dilated_from >= 0 ? 0 : count_points(s, s.bodies[i], columns));
    if (s.bodies[i].dilated_from < 0 && (columns.whole() ? counts.back() == 0 : !has_points(s, s.bodies[i])))
      throw ScenarioError(
          fmt::format("{}: key 'body[{}].shape': body '{}' contains no material point on this grid "
                      "(cell size {} m, {} points per cell); enlarge the shape or refine the grid",
                      s.source, i, s.bodies[i].name, s.cell_size, s.bodies[i].particles_per_cell));
    total += counts.back();
  }
  Particles<D> p;
  p.reserve(total);
  for (std::size_t i = 0; i < s.bodies.size(); ++i) {
    const BodyOf<D>& b = s.bodies[i];
    if (b.dilated_from >= 0) continue;  // a dilated continuum starts empty (Paper III §C.3.2)
    const Material& mat = s.materials.at(static_cast<std::size_t>(b.material));
    const double sub = s.cell_size / b.particles_per_cell;
    double volume = sub;
    for (int d = 1; d < D; ++d) volume *= sub;
    const Vec<D> half = Vec<D>::Constant(0.5 * sub);
    for_each_point(
        s, b,
        [&](const Vec<D>& x) {
          Vec<D> v = b.velocity;
          const SineVelocityOf<D>& sv = b.velocity_sine;
          if (sv.wavelength > 0.0)
            v += sv.amplitude * std::sin(2.0 * M_PI * (x[sv.axis] - sv.origin) / sv.wavelength);
          // Axisymmetric (2D): per radian, the sub-cell's area times its radius r_p = x_p.
          double vol = volume;
          if constexpr (D == 2)
            if (s.geometry == Geometry::Axisymmetric) vol *= x[0];
          p.add(x, v, mat.density * vol, vol, half, b.material, static_cast<int>(i));
          return true;
        },
        columns);
  }
  if (output_fields::wants_elastic_split(s.output_fields)) p.track_elastic_F();  // Post eq. 67-77
  return p;
}

template std::size_t count_points<2>(const Scenario&, const Body&, CellColumns);
template std::size_t count_points<3>(const Scenario3&, const Body3&, CellColumns);
template std::vector<long> points_per_column<2>(const Scenario&, CellColumns);
template std::vector<long> points_per_column<3>(const Scenario3&, CellColumns);
template bool has_points<2>(const Scenario&, const Body&);
template bool has_points<3>(const Scenario3&, const Body3&);
template Particles<2> build_particles<2>(const Scenario&, CellColumns);
template Particles<3> build_particles<3>(const Scenario3&, CellColumns);

}  // namespace skred
