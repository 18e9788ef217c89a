// 3D result files: a particle frame of hexahedral voxels (corners x_p + F_p (+-l0), Thesis
// eq. 3.6-3.12; Post §3, §5) read back with VTK's own reader (python3-vtk9), whose cell
// volumes must be det(F) V0, with the full 3D stress, F and vectors; the 3D grid file.
#include <gtest/gtest.h>
#include <Eigen/LU>

#include <map>
#include <sstream>
#include <tuple>

#include "io/grid_writer.hpp"
#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"
#include "vtu_test_util.hpp"

using namespace skred;
using namespace skred::iotest;

TEST_F(IoTest, Vtu3DRoundTripsHexahedraThroughVtkReader) {
  require_python_vtk();
  Particles<3> P;
  P.add(Vec<3>(1.0, 2.0, 3.0), Vec<3>(0.5, -0.25, 0.125), 3.0, 0.064, Vec<3>::Constant(0.2), 1, 0);
  P.add(Vec<3>(-1.0, 0.5, 0.25), Vec<3>(0.0, 1.0, -2.0), 2.0, 0.008, Vec<3>(0.1, 0.05, 0.2), 0, 3);
  P.F[0] << 1.0, 0.5, 0.1, 0.0, 1.0, 0.2, 0.0, -0.1, 1.1;  // general shear and stretch
  P.F[1] << 1.2, 0.0, 0.0, 0.0, 0.9, 0.0, 0.3, 0.0, 1.0;
  P.x[0] += Vec<3>(0.1, -0.2, 0.3);
  P.stress[0] << -1e5, -2e5, -3e5, 1e3, 2e3, 3e3;
  P.stress[1] << 7.25, -1.0 / 9.0, 2.5, -5.5, 0.125, 1e-3;
  const std::vector<Mat3> Fe = {P.F[0], Mat3::Identity()};
  ParticleFields extra;
  extra.elastic_F = &Fe;
  const auto file = dir / "particles_000000.vtu";
  write_particles_vtu(file, P, extra);
  expect_no_tmp_files();

  const auto [status, out] = run_python("read_vtu3.py", {file.string()});
  ASSERT_EQ(status, 0) << out;
  std::map<std::pair<int, int>, Vec<3>> corner;
  std::map<int, double> volume;
  std::map<int, int> type, npoints;
  std::map<std::tuple<std::string, int, int>, double> value;
  std::map<std::string, int> components;
  long cells = -1, points = -1;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "cells")
      in >> cells;
    else if (key == "points")
      in >> points;
    else if (key == "cell") {
      int c;
      std::string v;
      in >> c >> type[c] >> npoints[c] >> v;
      volume[c] = to_double(v);
    } else if (key == "corner") {
      int c, k;
      std::string x, y, z;
      in >> c >> k >> x >> y >> z;
      corner[{c, k}] = Vec<3>(to_double(x), to_double(y), to_double(z));
    } else if (key == "array") {
      std::string n;
      in >> n;
      in >> components[n];
    } else if (key == "value") {
      std::string n, v;
      int c, k;
      in >> n >> c >> k >> v;
      value[{n, c, k}] = to_double(v);
    }
  }
  ASSERT_EQ(cells, 2);
  ASSERT_EQ(points, 16);
  const double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                          {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  for (int c = 0; c < 2; ++c) {
    EXPECT_EQ(type[c], 12) << "cell " << c << " is not a VTK_HEXAHEDRON";
    ASSERT_EQ(npoints[c], 8);
    for (int k = 0; k < 8; ++k) {
      const Vec<3> a(s[k][0] * P.half0[c][0], s[k][1] * P.half0[c][1], s[k][2] * P.half0[c][2]);
      EXPECT_LT((corner[{c, k}] - (P.x[c] + P.F[c] * a)).norm(), 5e-7)
          << c << " " << k;  // Float32 of |x| < 4
    }
    // VTK's volume of the hexahedron is the voxel's current volume det(F) V0: the corners
    // are in VTK's order and the voxel is not inverted.
    EXPECT_NEAR(volume[c], P.volume(c), 1e-6) << c;  // from the Float32 corners
    EXPECT_EQ((value[{"volume", c, 0}]), f32(P.volume(c)));
    for (int k = 0; k < 6; ++k) EXPECT_EQ((value[{"stress", c, k}]), f32(P.stress[c][k])) << k;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ((value[{"velocity", c, k}]), f32(P.v[c][k]));
      EXPECT_EQ((value[{"displacement", c, k}]), f32(P.x[c][k] - P.x_ref[c][k]));
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        EXPECT_EQ((value[{"F", c, 3 * i + j}]), f32(P.F[c](i, j)));
        EXPECT_EQ((value[{"Fe", c, 3 * i + j}]), f32(Fe[c](i, j)));
      }
    EXPECT_EQ((value[{"mean_stress_p", c, 0}]), f32(mean_stress(P.stress[c])));
    EXPECT_EQ((value[{"deviatoric_stress_q", c, 0}]), f32(deviatoric_stress(P.stress[c])));
    EXPECT_EQ((value[{"body_id", c, 0}]), P.body[c]);
  }
  for (const char* name : {"principal_stress", "hencky_strain", "green_strain", "Fp", "speed"})
    EXPECT_TRUE(components.count(name)) << name;
}

TEST_F(IoTest, GridVtr3DHasThreeCoordinateArrays) {
  require_python_vtk();
  GridGeometry<3> g;
  g.h = 0.5;
  g.origin = Vec<3>(1.0, 0.0, -1.0);
  g.cells = {2, 1, 3};
  const std::size_t n = g.node_count();
  std::vector<double> mass(n);
  std::vector<Vec<3>> vel(n);
  std::vector<Sym3> stress(n, Sym3::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    mass[i] = static_cast<double>(i);
    vel[i] = Vec<3>(0.0, 0.0, static_cast<double>(i));
  }
  const auto file = dir / "grid_000000.vtr";
  write_grid_vtr(file, g, GridNodeFieldsOf<3>{mass, vel, stress});
  const auto [status, out] =
      run_command(std::string(kPython) +
                  " -c 'import sys; from vtkmodules.vtkIOXML import vtkXMLRectilinearGridReader as R; "
                  "r = R(); r.SetFileName(sys.argv[1]); r.Update(); o = r.GetOutput(); "
                  "print(o.GetDimensions(), o.GetZCoordinates().GetValue(0), "
                  "o.GetPointData().GetArray(\"velocity\").GetComponent(7, 2), "
                  "o.GetPointData().GetArray(\"mass\").GetValue(o.GetNumberOfPoints() - 1))' " +
                  shell_quote(file.string()));
  ASSERT_EQ(status, 0) << out;
  EXPECT_EQ(out, "(5, 4, 6) -1.5 7.0 " + std::to_string(n - 1) + ".0\n");
}
