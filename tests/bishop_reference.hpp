// An independent reference for Bishop's simplified method (Bishop 1955), for the tests that set
// skred's limit equilibrium (post/limit_equilibrium.hpp, run/slope_stability.hpp) against it.
// It shares no code with skred: the textbook slice sum on a circle over ground given the way a
// slope is drawn (a surface polyline, horizontal layers, a firm base), the slices' weights
// integrated over the layers exactly at each slice's centre line, the circle's crossings of the
// surface found analytically segment by segment, and its own search for the critical circle (a
// grid of centres and depths, then a compass search from the best few).
//
//   F = sum_i [c_i b + W_i tan(phi_i)] / m_i  /  sum_i W_i sin(alpha_i),
//   m_i = cos(alpha_i) + sin(alpha_i) tan(phi_i) / F,
//
// slices of equal width b, W_i the slice's weight, alpha_i the inclination of its base (positive
// where the base descends in the direction of sliding), c_i and phi_i the soil's at the base's
// midpoint; dry ground, no external load. F is iterated from the ordinary method's (Fellenius)
// value. As is usual (Whitman & Bailey 1967; Duncan & Wright, "Soil strength and slope
// stability"), a circle with m_i < 0.2 on a slice whose base rises in the direction of sliding
// is not counted: Bishop's F is spurious there.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace skred::test::bishop {

struct Soil {
  double cohesion = 0.0;     // c [Pa]
  double friction = 0.0;     // phi [rad]
  double unit_weight = 0.0;  // gamma [N/m^3]
};

// The ground: its surface y(x) through `surface` (x strictly increasing; ground from the first
// x to the last), soil down to the firm `base` that no slip surface may cut, in horizontal
// layers: layers[k] = {y_k, soil}, y_0 = base < y_1 < ..., soil k between y_k and y_{k+1} (the
// last up to the surface). A circle leaving the ground through its first or last x (a wall
// where the ground goes on) is no mechanism and is not counted.
struct Ground {
  std::vector<std::array<double, 2>> surface;
  double base = 0.0;
  std::vector<std::pair<double, Soil>> layers;

  double x_first() const { return surface.front()[0]; }
  double x_last() const { return surface.back()[0]; }
  double top() const {
    double t = -std::numeric_limits<double>::infinity();
    for (const auto& p : surface) t = std::max(t, p[1]);
    return t;
  }
  double surface_at(double x) const {
    const auto it =
        std::upper_bound(surface.begin(), surface.end(), x, [](double v, const auto& p) { return v < p[0]; });
    if (it == surface.begin()) return surface.front()[1];
    if (it == surface.end()) return surface.back()[1];
    const auto& a = *(it - 1);
    const auto& b = *it;
    return a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0]);
  }
  const Soil& soil_at(double y) const {
    std::size_t k = 0;
    while (k + 1 < layers.size() && y >= layers[k + 1].first) ++k;
    return layers[k].second;
  }
  // The weight per unit width of the column between y0 and y1 (y0 < y1), layer by layer.
  double column_weight(double y0, double y1) const {
    double w = 0.0;
    for (std::size_t k = 0; k < layers.size(); ++k) {
      const double lo = std::max(y0, layers[k].first);
      const double hi = k + 1 < layers.size() ? std::min(y1, layers[k + 1].first) : y1;
      if (hi > lo) w += layers[k].second.unit_weight * (hi - lo);
    }
    return w;
  }
};

struct Circle {
  double xc = 0.0, yc = 0.0, radius = 0.0;
};

inline double lower_arc(const Circle& c, double x) {
  const double d = x - c.xc;
  return c.yc - std::sqrt(std::max(0.0, c.radius * c.radius - d * d));
}

// Where the circle's lower arc runs under the surface: [xa, xb], if it does so in one piece that
// comes up to the surface at both ends (both ends crossings of the surface, inside the ground).
inline bool slip_range(const Ground& g, const Circle& c, double& xa, double& xb) {
  const double lo = std::max(g.x_first(), c.xc - c.radius), hi = std::min(g.x_last(), c.xc + c.radius);
  if (!(hi > lo)) return false;
  std::vector<double> xs{lo, hi};
  std::vector<char> is_crossing{0, 0};
  // Each surface segment y = p + m x against (x - xc)^2 + (y - yc)^2 = R^2, roots on the lower arc.
  for (std::size_t k = 0; k + 1 < g.surface.size(); ++k) {
    const double x0 = g.surface[k][0], x1 = g.surface[k + 1][0];
    const double m = (g.surface[k + 1][1] - g.surface[k][1]) / (x1 - x0), p = g.surface[k][1] - m * x0;
    const double q = p - c.yc;
    const double A = 1.0 + m * m, B = 2.0 * (m * q - c.xc), C = c.xc * c.xc + q * q - c.radius * c.radius;
    const double disc = B * B - 4.0 * A * C;
    if (disc < 0.0) continue;
    for (const double s : {-1.0, 1.0}) {
      const double x = (-B + s * std::sqrt(disc)) / (2.0 * A);
      if (x >= x0 && x <= x1 && x > lo && x < hi && p + m * x <= c.yc) {
        xs.push_back(x);
        is_crossing.push_back(1);
      }
    }
  }
  std::vector<std::size_t> order(xs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return xs[a] < xs[b]; });
  int pieces = 0;
  for (std::size_t k = 0; k + 1 < order.size(); ++k) {
    const double a = xs[order[k]], b = xs[order[k + 1]];
    if (!(b > a)) continue;
    const double mid = 0.5 * (a + b);
    if (g.surface_at(mid) > lower_arc(c, mid)) {
      if (pieces > 0 && a == xb) {  // a root of multiplicity two: the same piece goes on
        xb = b;
      } else {
        ++pieces;
        xa = a, xb = b;
      }
    }
  }
  if (pieces != 1) return false;
  const auto crossing_at = [&](double x) {
    for (std::size_t k = 0; k < xs.size(); ++k)
      if (xs[k] == x && is_crossing[k]) return true;
    return false;
  };
  return crossing_at(xa) && crossing_at(xb);
}

// Bishop's simplified F of one circle, the soil sliding towards +x (direction +1) or -x (-1);
// NaN if the circle is not admissible (see slip_range, the base, the m_i guard) or drives
// nothing towards `direction`.
inline double factor(const Ground& g, const Circle& c, int direction, int slices = 1000) {
  double xa = 0.0, xb = 0.0;
  if (!(c.radius > 0.0) || !slip_range(g, c, xa, xb)) return NAN;
  if (c.xc > xa && c.xc < xb && c.yc - c.radius < g.base) return NAN;
  const double b = (xb - xa) / slices;
  std::vector<double> W(slices), sin_a(slices), cos_a(slices), cb(slices), tan_phi(slices);
  double driving = 0.0;
  for (int i = 0; i < slices; ++i) {
    const double x = xa + (i + 0.5) * b, y_base = lower_arc(c, x), y_top = g.surface_at(x);
    if (y_base < g.base) return NAN;
    const Soil& s = g.soil_at(y_base);
    W[i] = b * g.column_weight(y_base, std::max(y_top, y_base));
    sin_a[i] = direction * (c.xc - x) / c.radius;
    cos_a[i] = (c.yc - y_base) / c.radius;
    cb[i] = s.cohesion * b;
    tan_phi[i] = std::tan(s.friction);
    driving += W[i] * sin_a[i];
  }
  if (!(driving > 0.0)) return NAN;
  double F = 0.0;  // the ordinary method's: sum (c b / cos + W cos tan phi) / driving
  for (int i = 0; i < slices; ++i) F += cb[i] / cos_a[i] + W[i] * cos_a[i] * tan_phi[i];
  F /= driving;
  for (int it = 0; it < 500; ++it) {
    double resisting = 0.0;
    for (int i = 0; i < slices; ++i)
      resisting += (cb[i] + W[i] * tan_phi[i]) / (cos_a[i] + sin_a[i] * tan_phi[i] / F);
    const double next = resisting / driving;
    const bool done = std::abs(next - F) <= 1e-13 * F;
    F = next;
    if (done) break;
  }
  for (int i = 0; i < slices; ++i)
    if (sin_a[i] < 0.0 && cos_a[i] + sin_a[i] * tan_phi[i] / F < 0.2) return NAN;
  return F;
}

struct Critical {
  double factor = std::numeric_limits<double>::infinity();
  Circle circle;
};

// The least F over circles sliding towards `direction`: centres on an n x n grid over
// [x_first, x_last] x [y0, y0 + 3 (top - base)] with y0 = (base + top) / 2, and n heights of the
// circle's lowest point from the base to the top; then a compass search over (centre, height of
// the lowest point) from the best `starts` circles of the grid, each step halved until it is
// below `tolerance` (so the firm base, which the critical circle often touches, bounds one
// coordinate alone).
inline Critical critical_circle(const Ground& g, int direction, int n = 24, int starts = 6,
                                double tolerance = 1e-4) {
  const double top = g.top(), height = top - g.base;
  const double x0 = g.x_first(), x1 = g.x_last(), y0 = 0.5 * (g.base + top), y1 = y0 + 3.0 * height;
  const std::array<double, 3> spacing{(x1 - x0) / (n - 1), (y1 - y0) / (n - 1), height / (n - 1)};
  // (xc, yc, lowest point) -> F, +inf where not admissible
  const auto value = [&](const std::array<double, 3>& p) {
    const double f = factor(g, Circle{p[0], p[1], p[1] - p[2]}, direction);
    return std::isfinite(f) ? f : std::numeric_limits<double>::infinity();
  };
  std::vector<std::pair<double, std::array<double, 3>>> grid;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const std::array<double, 3> p{x0 + i * spacing[0], y0 + j * spacing[1], g.base + k * spacing[2]};
        const double f = value(p);
        if (std::isfinite(f)) grid.emplace_back(f, p);
      }
  std::sort(grid.begin(), grid.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Critical best;
  for (std::size_t s = 0; s < grid.size() && s < static_cast<std::size_t>(starts); ++s) {
    auto [f, p] = grid[s];
    std::array<double, 3> step = spacing;
    while (std::max({step[0], step[1], step[2]}) > tolerance) {
      bool moved = false;
      for (int axis = 0; axis < 3; ++axis)
        for (const double sign : {-1.0, 1.0}) {
          std::array<double, 3> t = p;
          t[axis] += sign * step[axis];
          const double ft = value(t);
          if (ft < f) f = ft, p = t, moved = true;
        }
      if (!moved)
        for (double& h : step) h *= 0.5;
    }
    if (f < best.factor) best.factor = f, best.circle = Circle{p[0], p[1], p[1] - p[2]};
  }
  return best;
}

}  // namespace skred::test::bishop
