// Result files: VTU particles (read back with VTK's own reader), PVD index, series.csv,
// summary.json and the atomic-write layer underneath them all.
#include <gtest/gtest.h>
#include <Eigen/LU>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"
#include "vtu_test_util.hpp"

using namespace skred;
using namespace skred::iotest;

namespace {

Particles<2> two_particles() {
  Particles<2> P;
  P.add(Vec<2>(1.0, 2.0), Vec<2>(0.5, -0.25), 3.0, 0.16, Vec<2>(0.2, 0.2), 1, 0);
  P.add(Vec<2>(-3.5, 0.125), Vec<2>(1.0 / 3.0, 7e-9), 2.0, 0.08, Vec<2>(0.2, 0.1), 0, 4);
  P.F[0] << 1.0, 0.5, 0.0, 1.0;  // simple shear
  P.F[1] << 1.2, 0.0, 0.0, 0.9;  // stretch
  P.x[0] += Vec<2>(0.1, -0.2);
  P.x[1] += Vec<2>(1.0 / 7.0, 0.0);
  P.stress[0] << -1.0e5 / 3.0, -2.5e4, -3.14159e4, 1234.5678;  // xx, yy, zz, xy (plane strain)
  P.stress[1] << 7.25, -1.0 / 9.0, 2.0e-300, -5.5;
  P.state[1].plastic_shear_strain = 0.0123;
  P.state[1].yielding = 1;
  return P;
}

}  // namespace

TEST_F(IoTest, VtuRoundTripsThroughVtkReader) {
  const Particles<2> P = two_particles();
  std::vector<Sym3> smoothed = {full_stress<2>(P.stress[0]) * 0.5, full_stress<2>(P.stress[1]) * 2.0};
  smoothed[1][4] = 1.0e-7;  // a general Sym3 field keeps all six components
  smoothed[1][5] = -3.0;
  const auto file = dir / "particles_000001.vtu";
  write_particles_vtu(file, P, ParticleFields{&smoothed});
  expect_no_tmp_files();

  const VtuInfo info = read_vtu(file);
  ASSERT_EQ(info.cells, 2);
  ASSERT_EQ(info.points, 8);
  EXPECT_EQ(info.point_type, "float32");
  EXPECT_EQ(info.point_arrays, 0);
  const std::map<std::string, std::pair<int, std::string>> expected = {
      {"velocity", {3, "float32"}},
      {"displacement", {3, "float32"}},
      {"stress", {6, "float32"}},
      {"mean_stress_p", {1, "float32"}},
      {"deviatoric_stress_q", {1, "float32"}},
      {"volume", {1, "float32"}},
      {"det_F", {1, "float32"}},
      {"plastic_shear_strain", {1, "float32"}},
      {"yielding", {1, "uint8"}},
      {"material_id", {1, "int16"}},
      {"body_id", {1, "int16"}},
      {"smoothed_stress", {6, "float32"}},
      {"smoothed_p", {1, "float32"}},
      {"smoothed_q", {1, "float32"}},
      // post-processing fields (test_post_files.cpp checks their values)
      {"speed", {1, "float32"}},
      {"F", {9, "float32"}},
      {"engineering_strain", {6, "float32"}},
      {"green_strain", {6, "float32"}},
      {"hencky_strain", {6, "float32"}},
      {"principal_stress", {3, "float32"}},
      {"principal_angle", {1, "float32"}},
      {"smoothed_principal_stress", {3, "float32"}},
      {"smoothed_principal_angle", {1, "float32"}}};
  ASSERT_EQ(info.arrays.size(), expected.size());
  for (const auto& [name, spec] : expected) {
    ASSERT_TRUE(info.arrays.count(name)) << "missing cell array " << name;
    EXPECT_EQ(info.arrays.at(name).components, spec.first) << name;
    EXPECT_EQ(info.arrays.at(name).vtk_class, spec.second) << name;
  }
  const char* voigt[] = {"xx", "yy", "zz", "xy", "yz", "xz"};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(info.arrays.at("stress").component_names.at(k), voigt[k]);
    EXPECT_EQ(info.arrays.at("smoothed_stress").component_names.at(k), voigt[k]);
  }

  const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(info.cell_type.at(c), 9) << "cell " << c << " is not a VTK_QUAD";
    const std::vector<int>& ids = info.cell_points.at(c);
    ASSERT_EQ(ids.size(), 4u);
    double twice_area = 0.0;
    for (int k = 0; k < 4; ++k) {
      const Vec<2> corner = P.x[c] + P.F[c] * Vec<2>(sx[k] * P.half0[c][0], sy[k] * P.half0[c][1]);
      const Vec<2>& got = info.point.at(ids[k]);
      EXPECT_NEAR(got[0], corner[0], f32_tolerance(corner[0]) + 1e-15) << "cell " << c << " corner " << k;
      EXPECT_NEAR(got[1], corner[1], f32_tolerance(corner[1]) + 1e-15) << "cell " << c << " corner " << k;
      const Vec<2>& next = info.point.at(ids[(k + 1) % 4]);
      twice_area += got[0] * next[1] - next[0] * got[1];
    }
    EXPECT_GT(twice_area, 0.0) << "corners of cell " << c << " are not counter-clockwise";
    EXPECT_NEAR(0.5 * twice_area, P.volume(c), 1e-6);  // the voxel area is det(F) V0 (Float32 corners)

    const auto value = [&](const std::string& name, int k = 0) {
      return info.arrays.at(name).values.at({c, k});
    };
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(value("stress", k), f32(full_stress<2>(P.stress[c])[k])) << "stress component " << k;
      EXPECT_EQ(value("smoothed_stress", k), f32(smoothed[c][k]));
    }
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(value("velocity", k), f32(P.v[c][k]));
      EXPECT_EQ(value("displacement", k), f32(P.x[c][k] - P.x_ref[c][k]));
    }
    EXPECT_EQ(value("velocity", 2), 0.0);
    EXPECT_EQ(value("displacement", 2), 0.0);
    EXPECT_EQ(value("mean_stress_p"), f32(mean_stress(full_stress<2>(P.stress[c]))));
    EXPECT_EQ(value("deviatoric_stress_q"), f32(deviatoric_stress(full_stress<2>(P.stress[c]))));
    EXPECT_EQ(value("smoothed_p"), f32(mean_stress(smoothed[c])));
    EXPECT_EQ(value("smoothed_q"), f32(deviatoric_stress(smoothed[c])));
    EXPECT_EQ(value("volume"), f32(P.volume(c)));
    EXPECT_EQ(value("det_F"), f32(P.F[c].determinant()));
    EXPECT_EQ(value("plastic_shear_strain"), f32(P.state[c].plastic_shear_strain));
    EXPECT_EQ(value("yielding"), P.state[c].yielding);
    EXPECT_EQ(value("material_id"), P.material[c]);
    EXPECT_EQ(value("body_id"), P.body[c]);
  }
}

TEST_F(IoTest, VtuWithoutSmoothedStressAndEmpty) {
  const auto file = dir / "a.vtu";
  write_particles_vtu(file, two_particles());
  const VtuInfo info = read_vtu(file);
  EXPECT_EQ(info.cells, 2);
  EXPECT_EQ(info.arrays.size(), 18u);  // 11 + speed, F, 3 strains, principal stress and angle
  EXPECT_FALSE(info.arrays.count("smoothed_stress"));

  write_particles_vtu(file, Particles<2>{});  // overwrites atomically
  const VtuInfo empty = read_vtu(file);
  EXPECT_EQ(empty.cells, 0);
  EXPECT_EQ(empty.points, 0);
  expect_no_tmp_files();
}

TEST_F(IoTest, VtuSpanningSeveralBuffersReadsBack) {
  Particles<2> P;
  const int n = 70001;  // several fill chunks (16384 points) and zlib blocks (256 KiB)
  for (int i = 0; i < n; ++i) {
    P.add(Vec<2>(0.01 * (i % 300), 0.01 * (i / 300)), Vec<2>(i, -i), 1.0, 1e-4, Vec<2>(0.005, 0.005), i % 3,
          i % 5);
    P.stress[i][3] = 1.5 * i;
  }
  const auto file = dir / "big.vtu";
  write_particles_vtu(file, P);
  const VtuInfo info = read_vtu(file, "0 32767 32768 65536 70000");
  EXPECT_EQ(info.cells, n);
  EXPECT_EQ(info.points, 4L * n);
  for (int c : {0, 32767, 32768, 65536, 70000}) {
    EXPECT_EQ(info.cell_type.at(c), 9);
    EXPECT_EQ(info.cell_points.at(c), (std::vector<int>{4 * c, 4 * c + 1, 4 * c + 2, 4 * c + 3}));
    EXPECT_NEAR(info.point.at(4 * c + 2)[0], P.x[c][0] + 0.005, 4e-7);  // Float32 of x < 3
    EXPECT_EQ(info.arrays.at("velocity").values.at({c, 1}), -c);
    EXPECT_EQ(info.arrays.at("stress").values.at({c, 3}), 1.5 * c);
    EXPECT_EQ(info.arrays.at("material_id").values.at({c, 0}), c % 3);
    EXPECT_EQ(info.arrays.at("body_id").values.at({c, 0}), c % 5);
  }
}

TEST_F(IoTest, VtuRejectsMismatchedSmoothedStress) {
  std::vector<Sym3> smoothed(1, Sym3::Zero());
  EXPECT_THROW(write_particles_vtu(dir / "x.vtu", two_particles(), ParticleFields{&smoothed}),
               std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.vtu"));
  expect_no_tmp_files();
}
