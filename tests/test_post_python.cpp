// Python access (issue 13): python/ installs with Debian's pip and setuptools, offline
// (--no-build-isolation --no-index), into a folder of its own; the installed skred_post
// reads a real run's frames, series and summary, checked against the files as written
// (tests/scripts/check_python_api.py).
#include <gtest/gtest.h>

#include <filesystem>

#include "io_test_util.hpp"

using namespace skred::iotest;
namespace fs = std::filesystem;

TEST_F(IoTest, PythonPackageInstallsOfflineAndReadsARun) {
  require_python_vtk();
  const fs::path out = dir / "discs", scenario = dir / "discs.toml";
  {
    std::string text = read_text(fs::path(SKRED_SOURCE_DIR) / "examples" / "colliding_discs.toml");
    text.replace(text.find("end_time = 3.0"), 14, "end_time = 0.2");  // free flight, 3 frames
    text.replace(text.find("[output]\n"), 9,
                 "[output]\nfields = \"all\"\n");  // volume is not a default field
    std::ofstream(scenario) << text;
  }
  auto [s1, o1] = run_command(std::string(SKRED_BINARY) + " run " + shell_quote(scenario.string()) + " -o " +
                              shell_quote(out.string()) + " --threads 1");
  ASSERT_EQ(s1, 0) << o1;
  // pip builds in the source folder (build/, *.egg-info): install from a copy.
  const fs::path source = dir / "python", target = dir / "site";
  fs::copy(fs::path(SKRED_SOURCE_DIR) / "python", source,
           fs::copy_options::recursive | fs::copy_options::skip_symlinks);
  auto [s2, o2] = run_command(std::string(kPython) +
                              " -m pip install --no-build-isolation --no-deps --no-index --no-cache-dir"
                              " --disable-pip-version-check --root-user-action=ignore --target " +
                              shell_quote(target.string()) + " " + shell_quote(source.string()));
  ASSERT_EQ(s2, 0) << o2;
  EXPECT_TRUE(fs::exists(target / "skred_post" / "__init__.py"));
  auto [s3, o3] = run_python("check_python_api.py", {target.string(), out.string()});
  EXPECT_EQ(s3, 0) << o3;
}
