// `skred render` of a 3D run: a section z = const draws the voxels whose centres lie in the
// slab, cut through their centres (Post §5); points outside the slab are left out. The
// section through the two-voxel state of test_post_render.cpp, with a third voxel far off
// the plane on top of voxel A, must give exactly the 2D picture; and the top view runs.
#include <gtest/gtest.h>

#include <filesystem>

#include "io/pvd_writer.hpp"
#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"

using namespace skred;
using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

// Voxel A at (0.5, 0.5, 0.5), stress xx 2.5 kPa, body 0; voxel B at (1.5, 0.5, 0.5) sheared by
// F = [[1, 1, 0], [0, 1, 0], [0, 0, 1]], stress xx 10 kPa, body 1; voxel C at (0.5, 0.5, 3),
// stress xx 10 kPa: in front of A, outside the section z = 0.5.
void write_three_voxels(const fs::path& dir) {
  PvdWriter pvd(dir);
  const std::vector<MaterialStrength> strength = {{}};
  Particles<3> P;
  P.add(Vec<3>(0.5, 0.5, 0.5), Vec<3>(1.0, 0.0, 0.0), 1.0, 0.064, Vec<3>::Constant(0.2), 0, 0);
  P.add(Vec<3>(1.5, 0.5, 0.5), Vec<3>(0.0, -1.0, 0.0), 1.0, 0.064, Vec<3>::Constant(0.2), 0, 1);
  P.add(Vec<3>(0.5, 0.5, 3.0), Vec<3>(0.0, 0.0, 1.0), 1.0, 0.064, Vec<3>::Constant(0.2), 0, 0);
  P.F[1](0, 1) = 1.0;
  P.stress[0][0] = 2500.0;  // pictures show stresses in kPa
  P.stress[1][0] = 10000.0;
  P.stress[1][1] = -4000.0;
  P.stress[2][0] = 10000.0;
  ParticleFields extra;
  extra.strength = &strength;
  write_particles_vtu(dir / "particles_000000.vtu", P, extra);
  pvd.add(0.25, "particles_000000.vtu");
}

}  // namespace

TEST_F(IoTest, Render3DSectionDrawsTheVoxelsInTheSlab) {
  require_python_vtk();
  write_three_voxels(dir);
  const std::string skred = SKRED_BINARY, d = shell_quote(dir.string());
  const fs::path png = dir / "section.png", info = dir / "section.json";
  const auto [status, out] =
      run_command(skred + " render " + d + " --field stress:xx --range 0 10 --section-z 0.5 --slab 0.5 -o " +
                  shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;
  const auto [s2, o2] = run_python("check_render.py", {"field", png.string(), info.string()});
  EXPECT_EQ(s2, 0) << o2;  // A in viridis(0.25), not C's viridis(1) in front of it

  // Top view (x-z, from above) and a section that misses every point.
  const auto [s3, o3] = run_command(skred + " render " + d + " --view top --arrows --crosses -o " +
                                    shell_quote((dir / "top.png").string()));
  EXPECT_EQ(s3, 0) << o3;
  EXPECT_TRUE(fs::exists(dir / "top.png"));
  const auto [s4, o4] = run_command(skred + " render " + d + " --section-z 9 --slab 0.1");
  EXPECT_EQ(s4, 1) << o4;
  EXPECT_NE(o4.find("no voxel centre lies in the section"), std::string::npos) << o4;
  expect_no_tmp_files();
}
