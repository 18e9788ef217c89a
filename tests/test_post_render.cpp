// Pictures and the HTML report (`skred render`, `skred report`): pixels of a known
// two-particle state, the animation, the error messages, and the report in headless Chromium.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "io/pvd_writer.hpp"
#include "io/vtu_writer.hpp"
#include "io_test_util.hpp"

using namespace skred;
using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

const std::string kSkred = SKRED_BINARY;

std::pair<int, std::string> run_skred(const std::string& args) { return run_command(kSkred + " " + args); }

// Voxel A: a square at (0.5, 0.5), stress xx 2.5 kPa, body 0. Voxel B: sheared by F = [[1, 1],
// [0, 1]] at (1.5, 0.5), stress xx 10 kPa, body 1. `frames` copies with the voxels moving
// right by 0.2 m per frame (displacement 0 in the first frame).
void write_two_particles(const fs::path& dir, int frames = 1) {
  PvdWriter pvd(dir);
  const std::vector<MaterialStrength> strength = {{}};
  for (int f = 0; f < frames; ++f) {
    Particles<2> P;
    P.add(Vec<2>(0.5, 0.5), Vec<2>(1.0, 0.0), 1.0, 0.16, Vec<2>(0.2, 0.2), 0, 0);
    P.add(Vec<2>(1.5, 0.5), Vec<2>(0.0, -1.0), 1.0, 0.16, Vec<2>(0.2, 0.2), 0, 1);
    P.F[1] << 1.0, 1.0, 0.0, 1.0;
    P.stress[0][0] = 2500.0;  // pictures show stresses in kPa
    P.stress[1][0] = 10000.0;
    P.stress[1][1] = -4000.0;
    for (auto& x : P.x) x[0] += 0.2 * f;
    ParticleFields extra;
    extra.strength = &strength;
    const std::string name = "particles_00000" + std::to_string(f) + ".vtu";
    write_particles_vtu(dir / name, P, extra);
    pvd.add(0.25 * (f + 1), name);
  }
}

void expect_pixels(const std::string& mode, const fs::path& png, const fs::path& info) {
  const auto [status, out] = run_python("check_render.py", {mode, png.string(), info.string()});
  EXPECT_EQ(status, 0) << out;
}

}  // namespace

TEST_F(IoTest, RenderColoursVoxelsByFieldWithColourBar) {
  require_python_vtk();
  write_two_particles(dir);
  const fs::path png = dir / "two.png", info = dir / "two.json";
  const auto [status, out] =
      run_skred("render " + shell_quote(dir.string()) + " --field stress:xx --step 0 --range 0 10 -o " +
                shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;
  EXPECT_NE(out.find("wrote " + png.string()), std::string::npos) << out;
  expect_pixels("field", png, info);
}

TEST_F(IoTest, RenderShowsValuesWithoutStrengthAsGrey) {
  require_python_vtk();
  write_two_particles(dir);
  const fs::path png = dir / "nan.png", info = dir / "nan.json";
  const auto [status, out] = run_skred("render " + shell_quote(dir.string()) + " --field relative_yield -o " +
                                       shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;
  expect_pixels("nan", png, info);
}

TEST_F(IoTest, RenderCheckerboardFollowsTheReferenceConfiguration) {
  require_python_vtk();
  write_two_particles(dir);
  const fs::path png = dir / "checker.png", info = dir / "checker.json";
  const auto [status, out] = run_skred("render " + shell_quote(dir.string()) +
                                       " --checkerboard --pattern-width 1 --arrows --crosses -o " +
                                       shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;  // with the overlays: runs; the pixels are checked without them
  const auto [s2, o2] =
      run_skred("render " + shell_quote(dir.string()) + " --checkerboard --pattern-width 1 -o " +
                shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(s2, 0) << o2;
  expect_pixels("checker", png, info);
}

TEST_F(IoTest, RenderAllWritesEveryFrameAndAnAnimatedGif) {
  require_python_vtk();
  write_two_particles(dir, 3);
  const fs::path gif = dir / "anim.gif";
  const auto [status, out] = run_skred("render " + shell_quote(dir.string()) + " --all --field speed -o " +
                                       shell_quote(gif.string()));
  ASSERT_EQ(status, 0) << out;
  for (int f = 0; f < 3; ++f)
    EXPECT_TRUE(fs::exists(dir / "anim_frames" / ("frame_00000" + std::to_string(f) + ".png")));
  const auto [s2, o2] = run_command(std::string(kPython) +
                                    " -c 'import sys; from PIL import Image; im = Image.open(sys.argv[1]); "
                                    "print(im.format, im.n_frames, im.size)' " +
                                    shell_quote(gif.string()));
  ASSERT_EQ(s2, 0) << o2;
  const auto [s3, o3] = run_command(std::string(kPython) +
                                    " -c 'import sys; from PIL import Image; "
                                    "print(Image.open(sys.argv[1]).size)' " +
                                    shell_quote((dir / "anim_frames" / "frame_000000.png").string()));
  EXPECT_EQ(o2, "GIF 3 " + o3);  // the frames' size
  expect_no_tmp_files();
}

// An animation whose first frame is all zero (the displacement at the start): one colour
// range for all frames, from the data, 0 to the largest displacement (0.4 m), not the -1...
// of a flat frame's widened range; the first frame is drawn in the colour of 0.
TEST_F(IoTest, RenderAllTakesTheRangeFromTheDataWhenTheFirstFrameIsZero) {
  require_python_vtk();
  write_two_particles(dir, 3);
  const fs::path gif = dir / "u.gif", info = dir / "u.json";
  const auto [status, out] = run_skred("render " + shell_quote(dir.string()) + " --all -o " +
                                       shell_quote(gif.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;  // no --field: the displacement magnitude
  expect_pixels("zero", dir / "u_frames" / "frame_000000.png", info);  // vmin 0, vmax 0.4
}

// The picture follows the domain: the plot box has the aspect of its axis limits, the colour
// bar is as tall as the plot, and the rest of the image is only the margins (labels, title).
TEST_F(IoTest, RenderFollowsTheDomainsAspectRatio) {
  require_python_vtk();
  write_two_particles(dir);
  const fs::path png = dir / "flat.png", info = dir / "flat.json";
  const auto [status, out] = run_skred("render " + shell_quote(dir.string()) + " --field speed -o " +
                                       shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;
  expect_pixels("layout", png, info);
}

// --slip-circle draws summary.json's limit-equilibrium circle where it cut the ground (and
// only there), and says clearly when the run has none.
TEST_F(IoTest, RenderDrawsTheSlipCircleOfTheSummary) {
  require_python_vtk();
  write_two_particles(dir);
  const std::string d = shell_quote(dir.string());
  auto [s1, o1] = run_skred("render " + d + " --slip-circle");
  EXPECT_EQ(s1, 1) << o1;
  EXPECT_NE(o1.find("summary.json has no slip circle"), std::string::npos) << o1;
  std::ofstream(dir / "summary.json")
      << R"({"limit_equilibrium": 0.8, "slip_circle": [1.0, 1.9, 1.6, 0.2, 1.8]})";
  const fs::path png = dir / "circle.png", info = dir / "circle.json";
  const auto [status, out] =
      run_skred("render " + d + " --field stress:xx --step 0 --range 0 10 --slip-circle -o " +
                shell_quote(png.string()) + " --info " + shell_quote(info.string()));
  ASSERT_EQ(status, 0) << out;
  expect_pixels("circle", png, info);
}

TEST_F(IoTest, RenderAndReportFailClearly) {
  require_python_vtk();
  write_two_particles(dir);
  const std::string d = shell_quote(dir.string());
  auto [s1, o1] = run_skred("render " + d + " --field no_such_field");
  EXPECT_EQ(s1, 1) << o1;
  EXPECT_NE(o1.find("field 'no_such_field' is not in particles_000000.vtu; fields:"), std::string::npos)
      << o1;
  EXPECT_NE(o1.find("hencky_strain"), std::string::npos) << o1;
  auto [s2, o2] = run_skred("render " + d + " --field stress");
  EXPECT_EQ(s2, 1) << o2;
  EXPECT_NE(o2.find("choose one, e.g. stress:xx"), std::string::npos) << o2;
  auto [s3, o3] = run_skred("render " + d + " --step 7");
  EXPECT_EQ(s3, 1) << o3;
  EXPECT_NE(o3.find("step 7 out of range"), std::string::npos) << o3;
  auto [s4, o4] = run_skred("render " + d + " --stripes --checkerboard");
  EXPECT_NE(s4, 0) << o4;
  auto [s5, o5] = run_skred("render " + shell_quote((dir / "missing").string()));
  EXPECT_NE(s5, 0) << o5;
  fs::create_directories(dir / "empty");
  auto [s6, o6] = run_skred("report " + shell_quote((dir / "empty").string()));
  EXPECT_EQ(s6, 1) << o6;
  EXPECT_NE(o6.find("particles.pvd not found"), std::string::npos) << o6;
  // No Python: the message says what to install.
  auto [s7, o7] = run_command("SKRED_PYTHON=/nonexistent/python3 " + kSkred + " render " + d);
  EXPECT_EQ(s7, 6) << o7;  // README, "Exit codes": missing Python
  EXPECT_NE(o7.find("apt-get install python3 python3-matplotlib"), std::string::npos) << o7;
  // A missing module (matplotlib hidden): exit status 6 naming the Debian package.
  const std::string hide =
      std::string(kPython) +
      " -E -s -c 'import sys; sys.modules[\"matplotlib\"] = None; sys.path.insert(0, sys.argv[1]); "
      "from skred_post.deps import require_modules; require_modules()' " +
      shell_quote(std::string(SKRED_SOURCE_DIR) + "/python");
  auto [s8, o8] = run_command(hide);
  EXPECT_EQ(s8, 6) << o8;
  EXPECT_NE(o8.find("apt-get install python3-matplotlib"), std::string::npos) << o8;
}

// `render --series` of a two-stage run marks the stage boundary in every panel and names the
// stages (energies restart at each stage, so the reader must see where).
TEST_F(IoTest, SeriesPlotMarksTheStageBoundaries) {
  require_python_vtk();
  std::ofstream(dir / "series.csv") << "step,time,kinetic_energy,gravity_work,mean_speed,momentum_x,stage\n"
                                       "0,0,0,0,0,0,0\n10,0.5,1,2,0.1,1,0\n20,1,0.5,3,0.05,0.5,0\n"
                                       "30,1.5,0,0,0,0,1\n40,2,2,4,0.2,2,1\n";
  std::ofstream(dir / "summary.json")
      << R"({"status": "completed", "stages": [{"name": "settle"}, {"name": "slide"}]})";
  const auto [status, out] =
      run_python("check_series_stages.py", {std::string(SKRED_SOURCE_DIR) + "/python", dir.string()});
  EXPECT_EQ(status, 0) << out;
}
