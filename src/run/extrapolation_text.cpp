#include "run/extrapolation_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "run/table_text.hpp"

namespace skred {

namespace {

// The apparent orders an extrapolation is believed within (Celik et al. 2008 ask for a check
// that p is reasonable, not a range; this one is skred's).
constexpr double kLowestOrder = 0.5, kHighestOrder = 4.0;

double parse_number(const std::string& pair, const std::string& text, const char* what) {
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || stop != end)
    throw std::invalid_argument(
        fmt::format("'{}': the {} '{}' is not a number (give CELL=VALUE, e.g. 0.25=4.12)", pair, what, text));
  return v;
}

}  // namespace

std::string extrapolation_line(const std::string& words, const std::string& unit, const ThreeGrids& v,
                               const GridConvergence& g, const std::string& cell_unit) {
  const std::string head =
      fmt::format("{} over h = {:.6g}, {:.6g}, {:.6g}{}:", words, v.h[2], v.h[1], v.h[0], cell_unit);
  const double r = v.h[1] / v.h[0];
  const bool halving = std::abs(r - 2.0) < 1e-6;  // (sizes given to 7 digits, e.g. 10/3 and 5/3)
  const double fine = v.phi[0], medium = v.phi[1], coarse = v.phi[2];
  switch (g.kind) {
    case ConvergenceKind::unchanged:
      return fmt::format("{} the two finest agree exactly ({:.6g}{})\n", head, fine, unit);
    case ConvergenceKind::diverging:
      return fmt::format(
          "{} the last {} moved it by {:+.4g}{}, the one before by {:+.4g}{} (R = {}): the changes do not "
          "shrink, so these cells are not yet in the asymptotic range and nothing is extrapolated; "
          "refine further\n",
          head, halving ? "halving" : "refinement", fine - medium, unit, medium - coarse, unit,
          std::isfinite(g.ratio) ? fmt::format("{:.3g}", g.ratio) : std::string("inf"));
    case ConvergenceKind::monotone:
    case ConvergenceKind::oscillatory: break;
  }
  const std::string how = g.kind == ConvergenceKind::monotone
                              ? std::string("converges monotonically")
                              : fmt::format("oscillates (R = {:.3g}; extrapolate with care)", g.ratio);
  if (!std::isfinite(g.extrapolated))
    return fmt::format("{} {}, but no apparent order could be found\n", head, how);
  const std::string next =
      halving ? std::string("one more halving") : fmt::format("one more refinement by {:.4g}", r);
  // An apparent order far from any scheme's (first order for MPM's transfers, second at best)
  // says the three values are not in the asymptotic range, or carry noise of their own: R near 1
  // gives p near 0 and an extrapolation far away, noise can give p of 5 and a GCI of nothing.
  const bool implausible = g.order < kLowestOrder || g.order > kHighestOrder;
  return fmt::format(
      "{} {} with apparent order p = {:.2f} towards {:.6g}{} as h -> 0; GCI of the finest {:.2f} %, and {} "
      "would move it by about {}{}\n",
      head, how, g.order, g.extrapolated, unit, 100.0 * g.gci_fine, next,
      fine != 0.0 ? fmt::format("{:+.1f} %", 100.0 * g.next_change / fine)
                  : fmt::format("{:+.3g}{}", g.next_change, unit),
      implausible
          ? fmt::format(" (an order outside {} to {} says these values are not in the asymptotic range, "
                        "or carry noise of their own: do not rely on this extrapolation)",
                        kLowestOrder, kHighestOrder)
          : std::string());
}

ThreeGrids three_finest(const std::vector<std::string>& pairs) {
  std::vector<std::pair<double, double>> hv;
  for (const std::string& p : pairs) {
    const auto eq = p.find('=');
    if (eq == std::string::npos)
      throw std::invalid_argument(fmt::format("'{}': give CELL=VALUE, e.g. 0.25=4.12", p));
    const double h = parse_number(p, p.substr(0, eq), "cell size");
    const double v = parse_number(p, p.substr(eq + 1), "value");
    if (!(h > 0.0) || !std::isfinite(h))
      throw std::invalid_argument(fmt::format("'{}': the cell size must be positive", p));
    if (!std::isfinite(v)) throw std::invalid_argument(fmt::format("'{}': the value must be finite", p));
    for (const auto& [h0, v0] : hv)
      if (h0 == h)
        throw std::invalid_argument(fmt::format("'{}': the cell size {:.12g} is given twice", p, h));
    hv.emplace_back(h, v);
  }
  if (hv.size() < 3)
    throw std::invalid_argument(fmt::format(
        "{} value(s) given: the extrapolation needs the value at three cell sizes or more", hv.size()));
  std::sort(hv.begin(), hv.end());  // the finest first
  ThreeGrids t;
  for (int k = 0; k < 3; ++k) t.h[k] = hv[k].first, t.phi[k] = hv[k].second;
  return t;
}

std::string extrapolate_text(const std::vector<std::string>& pairs, const std::string& name,
                             const std::string& unit) {
  const ThreeGrids v = three_finest(pairs);
  // Celik et al.'s step 2 onwards, on the three finest (grid_convergence.hpp).
  const GridConvergence g = grid_convergence(v.phi[0], v.phi[1], v.phi[2], v.h[1] / v.h[0], v.h[2] / v.h[1]);
  std::string text = extrapolation_line(name, unit.empty() ? unit : " " + unit, v, g);
  text += "quantity,h1,h2,h3,phi1,phi2,phi3,kind,ratio,order,extrapolated,gci_fine,next_change\n";
  text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}\n", table_text(name), table_number(v.h[0]),
                      table_number(v.h[1]), table_number(v.h[2]), table_number(v.phi[0]),
                      table_number(v.phi[1]), table_number(v.phi[2]), convergence_kind_name(g.kind),
                      table_number(g.ratio), table_number(g.order), table_number(g.extrapolated),
                      table_number(g.gci_fine), table_number(g.next_change));
  return text;
}

}  // namespace skred
