// Post-processing result files: the particle VTU's strain, invariant, yield and split fields,
// the grid node file (.vtr) and grid.pvd, read back with VTK's own readers; and what a run
// writes into its output folder.
#include <gtest/gtest.h>
#include <Eigen/LU>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "io/grid_writer.hpp"
#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"
#include "post/elastic_plastic_split.hpp"
#include "post/invariants.hpp"
#include "post/strain_measures.hpp"
#include "vtu_test_util.hpp"

using namespace skred;
using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

Particles<2> three_particles() {
  Particles<2> P;
  P.add(Vec<2>(1.0, 2.0), Vec<2>(0.3, -0.4), 3.0, 0.16, Vec<2>(0.2, 0.2), 0, 0);
  P.add(Vec<2>(2.0, 2.0), Vec<2>(0.0, 0.0), 2.0, 0.16, Vec<2>(0.2, 0.2), 1, 0);
  P.add(Vec<2>(3.0, 2.0), Vec<2>(1.0, 0.0), 2.0, 0.16, Vec<2>(0.2, 0.2), 1, 1);
  P.F[0] << 1.0, 0.5, 0.0, 1.0;
  P.F[1] << 1.3, 0.0, 0.0, 0.8;
  const double t = 0.4;
  P.F[2] << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  P.stress[0] << 50, -30, 5, 30;  // xx, yy, zz, xy (plane strain)
  P.stress[1] << -2e4, -5e4, -3e4, 4e3;
  P.stress[2] << -1e3, -1e3, -1e3, 0;
  return P;
}

void expect_sym(const VtuInfo& info, const std::string& name, int cell, const Sym3& s, double tol) {
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(info.arrays.at(name).values.at({cell, k}), f32(s[k]), tol)
        << name << " cell " << cell << " k " << k;
}

void expect_mat(const VtuInfo& info, const std::string& name, int cell, const Mat3& m, double tol) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(info.arrays.at(name).values.at({cell, 3 * i + j}), f32(m(i, j)), tol)
          << name << " " << i << j;
}

// (time, file) of every data set of a .pvd, read with tests/scripts/read_pvd.py.
std::vector<std::pair<std::string, std::string>> datasets(const fs::path& pvd) {
  const auto [status, out] = run_python("read_pvd.py", {pvd.string()});
  EXPECT_EQ(status, 0) << out;
  std::vector<std::pair<std::string, std::string>> sets;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream in(line);
    std::string word, time, file;
    if (in >> word >> time >> file && word == "dataset") sets.emplace_back(time, file);
  }
  return sets;
}

}  // namespace

TEST_F(IoTest, PostFieldsInParticleVtu) {
  const Particles<2> P = three_particles();
  const auto S = [&P](int p) { return full_stress<2>(P.stress[p]); };
  std::vector<Sym3> smoothed = {S(0) * 0.5, S(1) * 0.9, S(2)};
  const std::vector<MaterialStrength> strength = {{}, {30.0 * std::numbers::pi / 180, 10e3}};
  std::vector<Mat3> Fe(3, Mat3::Identity());
  Fe[1] = deformation3<2>(P.F[1]);
  Fe[1](2, 2) = 1.01;
  std::vector<Sym3> from_fe = {S(0), S(1) * 1.1, S(2) * 1.2};
  ParticleFields extra{&smoothed, &strength, &Fe, &from_fe};
  const fs::path file = dir / "p.vtu";
  write_particles_vtu(file, P, extra);
  const VtuInfo info = read_vtu(file);
  ASSERT_EQ(info.cells, 3);
  const std::map<std::string, int> components = {{"speed", 1},
                                                 {"F", 9},
                                                 {"engineering_strain", 6},
                                                 {"green_strain", 6},
                                                 {"hencky_strain", 6},
                                                 {"principal_stress", 3},
                                                 {"principal_angle", 1},
                                                 {"relative_yield", 1},
                                                 {"smoothed_principal_stress", 3},
                                                 {"smoothed_principal_angle", 1},
                                                 {"smoothed_relative_yield", 1},
                                                 {"Fe", 9},
                                                 {"Fp", 9},
                                                 {"stress_from_Fe", 6}};
  for (const auto& [name, k] : components) {
    ASSERT_TRUE(info.arrays.count(name)) << name;
    EXPECT_EQ(info.arrays.at(name).components, k) << name;
    EXPECT_EQ(info.arrays.at(name).vtk_class, "float32") << name;
  }
  EXPECT_EQ(info.arrays.size(), 14u + 14u);  // the 14 of test_io plus these
  EXPECT_EQ(info.arrays.at("hencky_strain").component_names.at(3), "xy");
  EXPECT_EQ(info.arrays.at("Fe").component_names.at(1), "xy");
  EXPECT_EQ(info.arrays.at("principal_stress").component_names.at(2), "s3");

  for (int c = 0; c < 3; ++c) {
    auto value = [&](const std::string& name, int k = 0) { return info.arrays.at(name).values.at({c, k}); };
    const Mat3 F = deformation3<2>(P.F[c]);
    EXPECT_EQ(value("speed"), f32(P.v[c].norm()));
    expect_mat(info, "F", c, F, 0.0);
    expect_sym(info, "engineering_strain", c, engineering_strain(F), 0.0);
    expect_sym(info, "green_strain", c, green_lagrange_strain(F), 0.0);
    expect_sym(info, "hencky_strain", c, hencky_strain(F), 0.0);
    for (const auto& [prefix, s] : {std::pair<std::string, Sym3>{"", S(c)}, {"smoothed_", smoothed[c]}}) {
      const PrincipalStresses ps = principal_stresses(s);
      EXPECT_EQ(value(prefix + "principal_stress", 0), f32(ps.s1));
      EXPECT_EQ(value(prefix + "principal_stress", 1), f32(ps.s2));
      EXPECT_EQ(value(prefix + "principal_stress", 2), f32(ps.s3));
      EXPECT_EQ(value(prefix + "principal_angle"), f32(principal_angle_degrees(s)));
      const double fr = value(prefix + "relative_yield");
      if (P.material[c] == 0)
        EXPECT_TRUE(std::isnan(fr)) << "material 0 has no strength";
      else
        EXPECT_EQ(fr, f32(relative_yield(s, strength[1].friction, strength[1].cohesion)));
    }
    expect_mat(info, "Fe", c, Fe[c], 0.0);
    expect_mat(info, "Fp", c, plastic_F(Fe[c], F), 0.0);
    expect_sym(info, "stress_from_Fe", c, from_fe[c], 0.0);
  }
  // Cell 0: sigma = (50, -30, 5, xy 30) -> principal (-40, 5, 60) at 18.43 degrees.
  EXPECT_NEAR(info.arrays.at("principal_stress").values.at({0, 0}), -40, f32_tolerance(40));
  EXPECT_NEAR(info.arrays.at("principal_angle").values.at({0, 0}), 18.434948822922010, f32_tolerance(18.5));
  // Cell 2 is a rigid rotation: zero Green and Hencky strain.
  expect_sym(info, "hencky_strain", 2, Sym3::Zero(), 1e-15);
  expect_sym(info, "green_strain", 2, Sym3::Zero(), 1e-15);
  // Cell 1: Fe = F in plane, so Fp = diag(1, 1, 1/1.01).
  EXPECT_NEAR(info.arrays.at("Fp").values.at({1, 8}), 1 / 1.01, f32_tolerance(1.0));
  EXPECT_NEAR(info.arrays.at("Fp").values.at({1, 0}), 1.0, f32_tolerance(1.0));
}

TEST_F(IoTest, PostInputsOfWrongSizeAreRejected) {
  const Particles<2> P = three_particles();
  std::vector<Mat3> Fe(2, Mat3::Identity());
  std::vector<Sym3> s(2, Sym3::Zero());
  const std::vector<MaterialStrength> one = {{}};  // material 1 has no entry
  ParticleFields a, b, c;
  a.elastic_F = &Fe;
  b.stress_from_elastic_F = &s;
  c.strength = &one;
  for (const ParticleFields* f : {&a, &b, &c})
    EXPECT_THROW(write_particles_vtu(dir / "x.vtu", P, *f), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "x.vtu"));
  expect_no_tmp_files();
}

TEST_F(IoTest, GridNodeFileReadsBackWithVtk) {
  for (bool bspline : {false, true}) {
    GridGeometry<2> g;
    g.origin = Vec<2>(-1.0, 0.5);
    g.h = 0.25;
    g.cells = {4, 3};
    g.bspline_dofs = bspline;
    const std::size_t n = g.node_count();
    std::vector<double> mass(n);
    std::vector<Vec<2>> vel(n);
    std::vector<Sym3> stress(n);
    for (std::size_t i = 0; i < n; ++i) {
      mass[i] = 0.5 * i;
      vel[i] = Vec<2>(i, -2.0 * i);
      stress[i] << -1.0 * i, -2.0 * i, -3.0 * i, 0.25 * i, 0, 0;
    }
    const fs::path file = dir / "grid_000003.vtr";
    write_grid_vtr(file, g, {mass, vel, stress});
    require_python_vtk();
    const auto [status, out] = run_python("read_vtr.py", {file.string()});
    ASSERT_EQ(status, 0) << out;
    std::istringstream lines(out);
    std::string line;
    std::map<std::string, std::map<std::pair<int, int>, double>> values;
    std::map<std::string, int> comps;
    std::vector<double> xs, ys;
    int dims[3] = {0, 0, 0};
    while (std::getline(lines, line)) {
      std::istringstream in(line);
      std::string key;
      in >> key;
      if (key == "dims")
        in >> dims[0] >> dims[1] >> dims[2];
      else if (key == "xcoord" || key == "ycoord") {
        int i;
        std::string v;
        in >> i >> v;
        (key == "xcoord" ? xs : ys).push_back(to_double(v));
      } else if (key == "array") {
        std::string name, cls;
        in >> name;
        in >> comps[name] >> cls;
        EXPECT_EQ(cls, name == "has_material" ? "uint8" : "float32") << name;
      } else if (key == "value") {
        std::string name, v;
        int i, k;
        in >> name >> i >> k >> v;
        values[name][{i, k}] = to_double(v);
      }
    }
    EXPECT_EQ(dims[0], g.nodes(0));
    EXPECT_EQ(dims[1], g.nodes(1));
    EXPECT_EQ(dims[2], 1);
    ASSERT_EQ(xs.size(), 7u);
    for (int j = 0; j < g.nodes(0); ++j) EXPECT_EQ(xs[j], g.origin[0] + g.node_coordinate(0, j));
    for (int j = 0; j < g.nodes(1); ++j) EXPECT_EQ(ys[j], g.origin[1] + g.node_coordinate(1, j));
    EXPECT_EQ(comps, (std::map<std::string, int>{{"mass", 1},
                                                 {"velocity", 3},
                                                 {"stress", 6},
                                                 {"mean_stress_p", 1},
                                                 {"deviatoric_stress_q", 1},
                                                 {"has_material", 1}}));
    auto at = [&values](const std::string& name, std::size_t i, int k) {
      return values[name][std::make_pair(static_cast<int>(i), k)];
    };
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(at("mass", i, 0), f32(mass[i]));
      EXPECT_EQ(at("velocity", i, 1), f32(vel[i][1]));
      EXPECT_EQ(at("velocity", i, 2), 0.0);
      for (int k = 0; k < 6; ++k) EXPECT_EQ(at("stress", i, k), f32(stress[i][k]));
      EXPECT_EQ(at("mean_stress_p", i, 0), f32(mean_stress(stress[i])));
      EXPECT_EQ(at("has_material", i, 0), i == 0 ? 0.0 : 1.0);  // node 0 has no mass
    }
    // VTK's point order is x fastest, like GridGeometry's flat index.
    EXPECT_EQ(g.node_position(8)[0], xs[1]);
    EXPECT_EQ(g.node_position(8)[1], ys[1]);
  }
  std::vector<double> short_mass(3);
  GridGeometry<2> g;
  g.cells = {2, 2};
  EXPECT_THROW(write_grid_vtr(dir / "bad.vtr", g, {short_mass, {}, {}}), std::invalid_argument);
  expect_no_tmp_files();
}

TEST_F(IoTest, RunWritesGridFilesScenarioCopyAndPostFields) {
  const fs::path scenario = dir / "all_fields.toml";  // minimal.toml writing every field
  {
    std::ofstream f(scenario);
    f << read_text(fs::path(SKRED_SOURCE_DIR) / "tests" / "data" / "minimal.toml")
      << "\n[output]\nfields = \"all\"\ncompression = false\n";
  }
  const auto [status, out] =
      run_command(std::string(SKRED_BINARY) + " run " + shell_quote(scenario.string()) + " -o " +
                  shell_quote((dir / "out").string()) + " --threads 1");
  ASSERT_EQ(status, 0) << out;
  const fs::path o = dir / "out";
  EXPECT_EQ(read_text(o / "scenario.toml"), read_text(scenario));
  const auto grid = datasets(o / "grid.pvd");
  const auto parts = datasets(o / "particles.pvd");
  ASSERT_GT(parts.size(), 1u);
  ASSERT_EQ(grid.size(), parts.size());  // one grid file per particle frame, same times
  for (std::size_t f = 0; f < parts.size(); ++f) {
    EXPECT_EQ(grid[f].first, parts[f].first);
    char name[32];
    std::snprintf(name, sizeof name, "grid_%06zu.vtr", f);
    EXPECT_EQ(grid[f].second, name);
    EXPECT_TRUE(fs::exists(o / name)) << name;
  }
  const VtuInfo info = read_vtu(o / "particles_000000.vtu", "0");
  ASSERT_TRUE(info.arrays.count("relative_yield"));
  EXPECT_TRUE(std::isnan(info.arrays.at("relative_yield").values.at({0, 0})))
      << "linear elastic material: no strength";
  EXPECT_TRUE(info.arrays.count("smoothed_relative_yield"));
  // The solver keeps Fe (Post eq. 72-73); at the reference state Fe = Fp = I and the stress
  // recomputed from Fe is the reference stress (zero here).
  ASSERT_TRUE(info.arrays.count("Fe"));
  ASSERT_TRUE(info.arrays.count("Fp"));
  ASSERT_TRUE(info.arrays.count("stress_from_Fe"));
  for (int k = 0; k < 9; ++k) {
    EXPECT_EQ(info.arrays.at("Fe").values.at({0, k}), k % 4 == 0 ? 1.0 : 0.0) << k;
    EXPECT_EQ(info.arrays.at("Fp").values.at({0, k}), k % 4 == 0 ? 1.0 : 0.0) << k;
  }
  for (int k = 0; k < 6; ++k) EXPECT_EQ(info.arrays.at("stress_from_Fe").values.at({0, k}), 0.0);
}
