#include "run/point_setup.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"

namespace skred {

template <int D>
Particles<D> build_points(const ScenarioOf<D>& s, const Processes& procs,
                          const std::function<void(const std::string&)>& report) {
  const auto initial_stress = [&](Particles<D>& P) {
    if (s.initial_stress.rule == K0Rule::None) return;
    if (report) report("the initial stress");
    apply_initial_stress(s, P);
  };
  if (!procs.distributed()) {
    Particles<D> P = build_particles(s);
    initial_stress(P);
    return P;
  }
  const int C = s.cells[0];
  const long r = procs.rank(), N = procs.size();
  // The points per cell column, every process's count of an even run of them.
  std::vector<long> counts =
      points_per_column(s, CellColumns{static_cast<int>(C * r / N), static_cast<int>(C * (r + 1) / N)});
  procs.sum(counts.data(), counts.size());
  const long total = std::accumulate(counts.begin(), counts.end(), 0L);
  // Process q's columns begin at the first column before which total q / N points lie.
  const auto cut = [&](long q) {
    if (q <= 0) return 0;
    if (q >= N) return C;
    long before = 0;
    int c = 0;
    while (c < C && before < total * q / N) before += counts[static_cast<std::size_t>(c++)];
    return c;
  };
  const CellColumns own{cut(r), cut(r + 1)};
  const int margin = s.initial_stress.rule == K0Rule::None ? 0 : 2;
  Particles<D> P = build_particles(s, CellColumns{own.first - margin, own.end + margin});
  initial_stress(P);
  if (margin > 0) {
    std::vector<std::uint8_t> keep(P.size());
    for (std::size_t p = 0; p < P.size(); ++p)
      keep[p] = own.holds(std::clamp(column_of(s, P.x[p]), 0, C - 1));
    P.erase(keep);
    P.shrink();  // (the margins' memory goes back)
  }
  return P;
}

template Particles<2> build_points<2>(const Scenario&, const Processes&,
                                      const std::function<void(const std::string&)>&);
template Particles<3> build_points<3>(const Scenario3&, const Processes&,
                                      const std::function<void(const std::string&)>&);

}  // namespace skred
