// The lifecycle of the material points (core/particles.hpp): every operation over every field
// of the field list, checked through the list itself, so a field added to it is covered; and
// a run whose points are split and removed while it goes (mass, momentum, output, measures).
// Run under AddressSanitizer by scripts/sanitize.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "run/simulation.hpp"
#include "scenario/scenario.hpp"
#include "temp_dir.hpp"

using namespace skred;
namespace fs = std::filesystem;

namespace {

// A value of each field type that depends on `seed`, and equality (PointState has none).
template <class T>
T value_of(int seed) {
  if constexpr (std::is_same_v<T, PointState>) {
    PointState s;
    s.plastic_shear_strain = seed;
    s.plastic_volume_strain = seed + 0.5;
    s.volume_strain = -seed;
    s.yielding = static_cast<std::uint8_t>(seed % 2);
    return s;
  } else if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<T>(seed % 30000);
  } else {
    T v;
    for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = seed + 0.25 * static_cast<double>(i);
    return v;
  }
}
template <class T>
bool same(const T& a, const T& b) {
  if constexpr (std::is_same_v<T, PointState>)
    return a.plastic_shear_strain == b.plastic_shear_strain &&
           a.plastic_volume_strain == b.plastic_volume_strain && a.volume_strain == b.volume_strain &&
           a.yielding == b.yielding;
  else
    return a == b;
}

// n points whose every field holds value_of(1000 * field + point), stress_ref included.
Particles<2> stamped(int n) {
  Particles<2> P;
  P.set_reference_stress();  // empty; filled below like every other field
  for (int p = 0; p < n; ++p) P.add(Vec<2>::Zero(), Vec<2>::Zero(), 1.0, 1.0, Vec<2>::Ones(), 0, 0);
  int field = 0;
  P.for_each_field([&](const auto&, auto& a) {
    using T = typename std::decay_t<decltype(a)>::value_type;
    a.resize(static_cast<std::size_t>(n));
    for (int p = 0; p < n; ++p) a[static_cast<std::size_t>(p)] = value_of<T>(1000 * field + p);
    ++field;
  });
  return P;
}

// True if point `p` of P holds in every field what point `q` held when stamped.
bool holds_stamp(const Particles<2>& P, std::size_t p, int q) {
  bool ok = true;
  int field = 0;
  P.for_each_field([&](const auto&, const auto& a) {
    using T = typename std::decay_t<decltype(a)>::value_type;
    ok = ok && p < a.size() && same(a[p], value_of<T>(1000 * field + q));
    ++field;
  });
  return ok;
}

}  // namespace

TEST(Lifecycle, FieldListNamesEveryArrayOnce) {
  Particles<2> P;
  P.add(Vec<2>(1, 2), Vec<2>(3, 4), 5.0, 6.0, Vec<2>(0.5, 0.5), 1, 2);
  std::set<std::string> names;
  P.for_each_field([&](const auto& f, const auto& a) {
    names.insert(f.name);
    if (!f.optional) {
      EXPECT_EQ(a.size(), P.size()) << f.name;
    }
  });
  EXPECT_EQ(names.size(), std::tuple_size_v<decltype(Particles<2>::fields())>);
  EXPECT_EQ(names.size(), 21u);
  EXPECT_TRUE(P.stress_ref.empty());  // optional: stays empty (zero) until set
}

TEST(Lifecycle, AddGivesEveryFieldItsInitialValue) {
  Particles<2> P = stamped(3);
  const std::size_t q = P.add_default();
  EXPECT_EQ(q, 3u);
  P.for_each_field([&](const auto& f, const auto& a) {
    ASSERT_EQ(a.size(), 4u) << f.name;
    EXPECT_TRUE(same(a[q], f.initial())) << f.name;
  });
  for (int p = 0; p < 3; ++p) EXPECT_TRUE(holds_stamp(P, p, p));
}

TEST(Lifecycle, DuplicateCopiesEveryField) {
  Particles<2> P = stamped(5);
  P.reserve(5);  // no spare room: the copy reallocates while reading its source
  const std::size_t q = P.duplicate(2);
  EXPECT_EQ(q, 5u);
  EXPECT_TRUE(holds_stamp(P, q, 2));
  for (int p = 0; p < 5; ++p) EXPECT_TRUE(holds_stamp(P, p, p));
}

TEST(Lifecycle, EraseKeepsTheOrderOfTheRest) {
  Particles<2> P = stamped(7);
  P.erase({1, 0, 0, 1, 1, 0, 1});
  ASSERT_EQ(P.size(), 4u);
  const int kept[] = {0, 3, 4, 6};
  for (std::size_t p = 0; p < 4; ++p) EXPECT_TRUE(holds_stamp(P, p, kept[p])) << p;
  P.for_each_field([&](const auto& f, const auto& a) { EXPECT_EQ(a.size(), 4u) << f.name; });
  P.erase_points({3, 0});
  ASSERT_EQ(P.size(), 2u);
  EXPECT_TRUE(holds_stamp(P, 0, 3));
  EXPECT_TRUE(holds_stamp(P, 1, 4));
}

TEST(Lifecycle, ReorderPermutesEveryField) {
  Particles<2> P = stamped(6);
  const std::vector<std::uint32_t> order = {4, 0, 5, 1, 3, 2};  // cycles (0 4 3 1)(2 5)
  P.reorder(order);
  for (std::size_t p = 0; p < 6; ++p) EXPECT_TRUE(holds_stamp(P, p, static_cast<int>(order[p]))) << p;
  // with points that stay, and the fields shared among two threads
  Particles<2> Q = stamped(7);
  const std::vector<std::uint32_t> order2 = {2, 1, 6, 3, 0, 5, 4};  // cycles (0 2 6 4), 1, 3, 5 stay
  Q.reorder(order2, 2);
  for (std::size_t p = 0; p < 7; ++p) EXPECT_TRUE(holds_stamp(Q, p, static_cast<int>(order2[p]))) << p;
}

TEST(Lifecycle, SortByCellOrdersByFlatCellIndexStably) {
  GridGeometry<2> g;
  g.h = 1.0;
  g.cells = {3, 2};
  Particles<2> P = stamped(6);
  const Vec<2> at[] = {{2.5, 1.5}, {0.5, 1.5}, {2.2, 0.2}, {0.1, 0.9}, {0.7, 1.1}, {3.0, 2.0}};
  for (std::size_t p = 0; p < 6; ++p) P.x[p] = at[p];
  // Cells (axis 0 fastest): 5, 3, 2, 0, 3, 5 (a point on the far wall is in the last cell).
  EXPECT_TRUE(P.sort_by_cell(g));
  const int expect[] = {3, 2, 1, 4, 0, 5};
  for (std::size_t p = 0; p < 6; ++p) {
    EXPECT_EQ(P.x[p], at[expect[p]]) << p;
    P.x[p] = value_of<Vec<2>>(expect[p]);  // the rest of the stamp moved along
    EXPECT_TRUE(holds_stamp(P, p, expect[p])) << p;
    P.x[p] = at[expect[p]];
  }
  EXPECT_FALSE(P.sort_by_cell(g));  // sorted already
}

TEST(Lifecycle, SortByNearestNodeOrdersByTheNodeNearestEachPoint) {
  GridGeometry<2> g;
  g.h = 1.0;
  g.cells = {3, 2};  // 4 x 3 nodes
  Particles<2> P = stamped(6);
  const Vec<2> at[] = {{2.6, 1.4}, {0.4, 1.6}, {2.2, 0.2}, {0.1, 0.9}, {0.7, 0.4}, {3.0, 2.0}};
  for (std::size_t p = 0; p < 6; ++p) P.x[p] = at[p];
  // Nearest nodes (axis 0 fastest, 4 per row): 7, 8, 2, 4, 1, 11 (a point on the far wall
  // takes the last node). Points 3 and 4 share cell 0 but not their nearest node.
  EXPECT_TRUE(P.sort_by_cell(g, true));
  const int expect[] = {4, 2, 3, 0, 1, 5};
  for (std::size_t p = 0; p < 6; ++p) EXPECT_EQ(P.x[p], at[expect[p]]) << p;
  EXPECT_FALSE(P.sort_by_cell(g, true));  // sorted already
  EXPECT_TRUE(P.sort_by_cell(g));         // by cell (0, 2, 0, ...) they are not
}

TEST(Lifecycle, SerialiseRoundTripsEveryFieldAndRejectsAMismatch) {
  for (bool with_ref : {true, false}) {
    Particles<2> P = stamped(4);
    if (!with_ref) P.stress_ref.clear();
    std::stringstream s;
    P.serialise(s);
    Particles<2> Q;
    Q.deserialise(s);
    ASSERT_EQ(Q.size(), 4u);
    EXPECT_EQ(Q.stress_ref.size(), with_ref ? 4u : 0u);
    if (!with_ref)
      for (int p = 0; p < 4; ++p) Q.stress_ref.push_back(value_of<PointStress<2>>(12000 + p));
    for (int p = 0; p < 4; ++p) EXPECT_TRUE(holds_stamp(Q, p, p));
  }
  Particles<2> P = stamped(3);
  std::stringstream s;
  P.serialise(s);
  std::string bytes = s.str();
  Particles<2> Q;
  std::istringstream cut(bytes.substr(0, bytes.size() - 5));
  EXPECT_THROW(Q.deserialise(cut), std::runtime_error);
  bytes[3 * 8] = 'y';  // the first field's name
  std::istringstream renamed(bytes);
  EXPECT_THROW(Q.deserialise(renamed), std::runtime_error);
}

TEST(Lifecycle, SplitHalvesAPointConservingMassAndMomentum) {
  Particles<2> P;
  P.add(Vec<2>(1.0, 1.0), Vec<2>(0.3, -0.7), 0.625, 0.01, Vec<2>(0.05, 0.05), 0, 0);
  P.F[0] << 1.1, 0.2, 0.0, 0.9;
  const std::size_t q = P.split(0, 0);
  EXPECT_EQ(P.mass[0] + P.mass[q], 0.625);
  EXPECT_EQ(P.mass[0] * P.v[0] + P.mass[q] * P.v[q], 0.625 * Vec<2>(0.3, -0.7));
  EXPECT_EQ(P.volume0[0] + P.volume0[q], 0.01);
  EXPECT_EQ(P.half0[q], Vec<2>(0.025, 0.05));
  EXPECT_NEAR((0.5 * (P.x[0] + P.x[q]) - Vec<2>(1.0, 1.0)).norm(), 0.0, 1e-15);  // centred
  EXPECT_NEAR((P.x[q] - P.x[0] - Vec<2>(0.055, 0.0)).norm(), 0.0, 1e-15);        // F l0 e_x apart
  EXPECT_EQ(P.F[q], P.F[0]);
}

TEST(Lifecycle, ASplitMovesNoMaterialInTheRestTestsWindow) {
  // x_rest (the displacement rest test's window start) moves with the halves: each keeps the
  // parent's displacement since the window began, so a split is no motion to that test.
  Particles<2> P;
  P.add(Vec<2>(1.0, 1.0), Vec<2>::Zero(), 0.625, 0.01, Vec<2>(0.05, 0.05), 0, 0);
  P.F[0] << 1.1, 0.2, 0.0, 0.9;
  P.x_rest = {Vec<2>(0.97, 1.01)};
  const Vec<2> moved = P.x[0] - P.x_rest[0];
  const std::size_t q = P.split(0, 1);
  ASSERT_EQ(P.x_rest.size(), 2u);
  EXPECT_NEAR((P.x[0] - P.x_rest[0] - moved).norm(), 0.0, 1e-15);
  EXPECT_NEAR((P.x[q] - P.x_rest[q] - moved).norm(), 0.0, 1e-15);
  Particles<2> Q;  // without the field (no stage tests on displacement) it stays empty
  Q.add(Vec<2>(1.0, 1.0), Vec<2>::Zero(), 0.625, 0.01, Vec<2>(0.05, 0.05), 0, 0);
  (void)Q.split(0, 0);
  EXPECT_TRUE(Q.x_rest.empty());
}

// The colliding discs of R3 (examples/colliding_discs.toml) with points split and removed
// while they move: at step 100 every third point of the lower disc is split in two, at step
// 200 every fifth point is removed. Splitting conserves mass exactly and momentum to the
// round-off of the sum; removal takes away the removed points' mass and momentum. The run
// goes on, its series, frames and measures follow the point count, and total momentum stays
// constant between the changes.
TEST(Lifecycle, PointsSplitAndRemovedMidRun) {
  std::ifstream in(fs::path(SKRED_SOURCE_DIR) / "examples" / "colliding_discs.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  t.replace(t.find("end_time = 3.0"), 14, "end_time = 0.4");
  const Scenario s = parse_scenario(t, "lifecycle-discs.toml");
  const fs::path out = skred::test::fresh_temp_dir();
  RunOptions opt;
  opt.progress = false;
  opt.sort_every = 50;
  std::size_t n0 = 0, n1 = 0, n2 = 0;
  double mass0 = 0, mass1 = 0, mass2 = 0, removed = 0;
  Vec<2> mom_split = Vec<2>::Zero(), mom_before = Vec<2>::Zero(), mom_removed = Vec<2>::Zero(),
         mom_after = Vec<2>::Zero();
  opt.edit_points = [&](Particles<2>& P, const ExplicitSolver<2>& solver) {
    if (solver.steps() == 100) {
      n0 = P.size();
      mass0 = solver.totals().mass;
      mom_split = solver.totals().momentum;
      for (std::size_t p = 0; p < n0; p += 3)
        if (P.body[p] == 0) P.split(p, static_cast<int>(p / 3 % 2));
      n1 = P.size();
      mass1 = solver.totals().mass;
      mom_split -= solver.totals().momentum;
      return true;
    }
    if (solver.steps() == 200) {
      std::vector<std::uint8_t> keep(P.size(), 1);
      for (std::size_t p = 0; p < P.size(); p += 5) {
        keep[p] = 0;
        removed += P.mass[p];
        mom_removed += P.mass[p] * P.v[p];
      }
      mass2 = solver.totals().mass;
      mom_before = solver.totals().momentum;
      P.erase(keep);
      n2 = P.size();
      mass2 -= solver.totals().mass;
      mom_after = mom_before - solver.totals().momentum;
      return true;
    }
    return false;
  };
  const RunResult r = run_simulation(s, out, opt);
  ASSERT_TRUE(r.completed) << r.message;
  EXPECT_GT(n1, n0);
  EXPECT_EQ(mass1, mass0);                     // splitting conserves mass exactly
  EXPECT_LT(mom_split.norm(), 1e-14);          // and momentum (to the order of the sum)
  EXPECT_NEAR(mass2, removed, 1e-13 * mass0);  // removal takes away the removed points' mass
  EXPECT_NEAR((mom_after - mom_removed).norm(), 0.0, 1e-14);
  EXPECT_EQ(n2, n1 - (n1 + 4) / 5);
  EXPECT_EQ(r.particles, static_cast<long>(n2));
  // series.csv: the point count column follows; total momentum stays zero.
  std::ifstream series(out / "series.csv");
  std::string line;
  std::getline(series, line);
  std::set<long> counts;
  double worst = 0.0;
  for (Vec<2> m; std::getline(series, line);) {
    std::vector<std::string> c;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 18u);  // (the last, material_speed: a FLIP stage's stop time reads it)
    m = Vec<2>(std::stod(c[11]), std::stod(c[12]));
    worst = std::max(worst, (std::stol(c[0]) <= 200 ? m : Vec<2>(m + mom_removed)).norm());
    counts.insert(std::stol(c[13]));
  }
  EXPECT_EQ(counts, (std::set<long>{static_cast<long>(n0), static_cast<long>(n1), static_cast<long>(n2)}));
  EXPECT_LT(worst, 1e-12);  // eq. 2.53-2.56 conserve momentum whatever the points
  ASSERT_EQ(r.stages.size(), 1u);
  EXPECT_GT(r.stages[0].peak_mean_speed, 0.1);
  EXPECT_TRUE(fs::exists(out / "particles_000004.vtu"));
  fs::remove_all(out);
}
