// Each process builds only its share of a run's points (run/point_setup.hpp, issue 55): together
// the shares are the one-process set point for point, with the same K0 stresses to the bit
// (Thesis eq. 5.6-5.7: each point's overburden sums the points above it in its column, some of
// which another process keeps), and no process holds more than its share and one cell column.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "../support.hpp"
#include "parallel/processes.hpp"
#include "run/point_setup.hpp"
#include "scenario/build.hpp"
#include "scenario/initial_stress.hpp"
#include "scenario/scenario.hpp"

namespace skred {
namespace {

// Per point: position, the stress's six components, mass, body.
template <int D>
std::vector<std::vector<double>> records(const Particles<D>& P) {
  std::vector<std::vector<double>> r;
  for (std::size_t p = 0; p < P.size(); ++p) {
    std::vector<double> q(P.x[p].data(), P.x[p].data() + D);
    const Sym3 s = full_stress<D>(P.stress[p]);
    q.insert(q.end(), s.data(), s.data() + 6);
    q.push_back(P.mass[p]);
    q.push_back(P.body[p]);
    r.push_back(q);
  }
  std::sort(r.begin(), r.end());
  return r;
}

template <int D>
void expect_shares_are_the_whole(const ScenarioOf<D>& s, const char* what) {
  const Processes world = Processes::world();
  const Particles<D> own = build_points(s, world);
  Particles<D> whole = build_particles(s);
  apply_initial_stress(s, whole);
  // Every process's records, gathered in rank order.
  const std::vector<std::vector<double>> mine = records(own);
  const std::size_t width = D + 8;
  std::vector<double> flat;
  for (const auto& q : mine) flat.insert(flat.end(), q.begin(), q.end());
  const long n = world.sum_of(static_cast<long>(own.size()));
  ASSERT_EQ(n, static_cast<long>(whole.size())) << what;
  std::vector<double> all(static_cast<std::size_t>(n) * width);
  world.gather(flat.data(), flat.size(), all.data(), all.size());
  std::vector<std::vector<double>> got;
  for (long p = 0; p < n; ++p)
    got.emplace_back(all.begin() + p * static_cast<long>(width),
                     all.begin() + (p + 1) * static_cast<long>(width));
  std::sort(got.begin(), got.end());
  EXPECT_TRUE(got == records(whole)) << what << ": not the one-process points and stresses, bit for bit";
  double top = 0.0;
  for (const auto& q : got) top = std::min(top, q[static_cast<std::size_t>(D) + 1]);
  EXPECT_LT(top, 0.0) << what << ": no K0 stress";
  // The largest cell column's count bounds each share's excess.
  const std::vector<long> columns = points_per_column(s, CellColumns{});
  const long widest = *std::max_element(columns.begin(), columns.end());
  EXPECT_LE(world.max(static_cast<long>(own.size())), n / world.size() + widest) << what;
}

// Two bodies of different point spacing (the K0 columns are the finer's, 1/12 m): a base layer
// with 3 x 3 points per cell under a block with 2 x 2 on a lattice turned by 20 degrees (Acosta
// §6), whose points, wider than a column and off the cells' lines, load columns across the
// cells' edges, and so across the shares' cuts.
TEST(PointSetup, TwoBodiesSharesAreTheWholeSetWithItsK0Stresses) {
  const std::string text = R"(
[grid]
size = [8.0, 4.0]
cell_size = 0.25
[[material]]
name = "soil"
model = "mohr-coulomb"
density = 1800.0
young = 1e7
poisson = 0.3
friction = 30.0
cohesion = 1000.0
[[body]]
name = "base"
material = "soil"
particles_per_cell = 3
shape = "rectangle"
min = [0.0, 0.0]
max = [8.0, 1.0]
[[body]]
name = "block"
material = "soil"
particles_per_cell = 2
shape = "rectangle"
min = [1.1, 1.0]
max = [6.3, 3.0]
lattice_rotation = 20.0
lattice_centre = [3.7, 2.0]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81]
[solver]
end_time = 0.1
)";
  expect_shares_are_the_whole<2>(parse_scenario(text, "two_bodies.toml"), "two bodies, 2D");
}

TEST(PointSetup, Column3DSharesAreTheWholeSetWithItsK0Stresses) {
  const std::string path = std::string(SKRED_SOURCE_DIR) + "/examples/column_3d.toml";
  expect_shares_are_the_whole<3>(std::get<Scenario3>(load_any_scenario(path)), "3D column");
}

}  // namespace
}  // namespace skred
