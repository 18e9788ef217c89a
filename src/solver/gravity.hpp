// Gravity, applied at once or ramped by the incremental-gravity sine law.
#pragma once
#include <cmath>
#include <numbers>

#include "core/types.hpp"

namespace skred {

// Thesis eq. 4.13: g(t) = g/2 (sin(2 pi t / T - pi/2) + 1) for t <= T/2, g afterwards.
// A ramp time T = 0 applies the full gravity from the start.
template <int D>
inline Vec<D> gravity_at(const Vec<D>& g, double ramp_time, double t) {
  if (ramp_time <= 0.0 || t > 0.5 * ramp_time) return g;
  return 0.5 * g * (std::sin(2.0 * std::numbers::pi * t / ramp_time - 0.5 * std::numbers::pi) + 1.0);
}

}  // namespace skred
