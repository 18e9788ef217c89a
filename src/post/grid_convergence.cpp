#include "post/grid_convergence.hpp"

#include <cmath>
#include <stdexcept>

namespace skred {

const char* convergence_kind_name(ConvergenceKind k) {
  switch (k) {
    case ConvergenceKind::monotone: return "monotone";
    case ConvergenceKind::oscillatory: return "oscillatory";
    case ConvergenceKind::diverging: return "diverging";
    case ConvergenceKind::unchanged: return "unchanged";
  }
  return "?";
}

namespace {

// The apparent order p of Celik et al.'s step 3 by fixed-point iteration:
// p = |ln|ε32/ε21| + q(p)| / ln r21, q(p) = ln((r21^p − s) / (r32^p − s)), s = sgn(ε32/ε21);
// q = 0 for a constant ratio, so one pass is exact there. NaN if it does not settle.
double apparent_order(double e21, double e32, double r21, double r32) {
  const double s = (e32 / e21) > 0.0 ? 1.0 : -1.0;
  const double log_ratio = std::log(std::abs(e32 / e21));
  double p = std::abs(log_ratio) / std::log(r21);
  for (int it = 0; it < 200; ++it) {
    const double a = std::pow(r21, p) - s, b = std::pow(r32, p) - s;
    if (!(a > 0.0) || !(b > 0.0)) return NAN;
    const double next = std::abs(log_ratio + std::log(a / b)) / std::log(r21);
    if (std::abs(next - p) <= 1e-12 * std::max(1.0, p)) return next;
    p = next;
  }
  return NAN;
}

}  // namespace

GridConvergence grid_convergence(double phi1, double phi2, double phi3, double r21, double r32,
                                 double safety_factor) {
  if (!std::isfinite(phi1) || !std::isfinite(phi2) || !std::isfinite(phi3))
    throw std::invalid_argument("grid_convergence: the three values must be finite");
  if (!(r21 > 1.0) || !(r32 > 1.0) || !std::isfinite(r21) || !std::isfinite(r32))
    throw std::invalid_argument("grid_convergence: the refinement ratios must be finite and > 1");
  GridConvergence g;
  const double e21 = phi2 - phi1, e32 = phi3 - phi2;
  g.ratio = e32 != 0.0 ? e21 / e32 : NAN;
  g.approximate_error = phi1 != 0.0 ? std::abs(e21 / phi1) : NAN;  // step 5
  g.order = g.extrapolated = g.extrapolated_error = g.gci_fine = g.next_change = NAN;
  if (e21 == 0.0) {
    g.kind = ConvergenceKind::unchanged;
    g.extrapolated = phi1;
    g.extrapolated_error = g.gci_fine = g.next_change = 0.0;
    return g;
  }
  if (e32 == 0.0 || std::abs(g.ratio) >= 1.0) {
    g.kind = ConvergenceKind::diverging;
    return g;
  }
  g.kind = g.ratio > 0.0 ? ConvergenceKind::monotone : ConvergenceKind::oscillatory;
  g.order = apparent_order(e21, e32, r21, r32);
  if (!std::isfinite(g.order) || g.order <= 0.0) return g;
  const double rp = std::pow(r21, g.order);
  g.extrapolated = (rp * phi1 - phi2) / (rp - 1.0);  // step 4
  g.extrapolated_error = g.extrapolated != 0.0 ? std::abs((g.extrapolated - phi1) / g.extrapolated) : NAN;
  g.gci_fine = safety_factor * g.approximate_error / (rp - 1.0);  // step 5
  g.next_change = (g.extrapolated - phi1) * (1.0 - 1.0 / rp);
  return g;
}

}  // namespace skred
