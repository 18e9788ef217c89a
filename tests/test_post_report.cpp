// `skred report`: the self-contained HTML page of a real run, opened in Debian's headless
// Chromium. Chromium is installed by scripts/install-deps.sh, so its absence fails the test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "io_test_util.hpp"

using namespace skred::iotest;
namespace fs = std::filesystem;

namespace {

const char* kChromium = "/usr/bin/chromium";

void require_chromium() {
  if (::access(kChromium, X_OK) != 0)
    throw std::runtime_error(std::string(kChromium) +
                             " is missing: the report test opens the page in headless Chromium. "
                             "Install it with `apt-get install chromium` (scripts/install-deps.sh does).");
}

}  // namespace

TEST_F(IoTest, ReportOpensInHeadlessChromiumWithAllImages) {
  require_python_vtk();
  require_chromium();
  const fs::path out = dir / "discs";
  const std::string scenario = std::string(SKRED_SOURCE_DIR) + "/examples/colliding_discs.toml";
  auto [s1, o1] = run_command(std::string(SKRED_BINARY) + " run " + shell_quote(scenario) + " -o " +
                              shell_quote(out.string()) + " --threads 1");
  ASSERT_EQ(s1, 0) << o1;
  const fs::path html = dir / "report.html";
  auto [s2, o2] = run_command(std::string(SKRED_BINARY) + " report " + shell_quote(out.string()) + " -o " +
                              shell_quote(html.string()));
  ASSERT_EQ(s2, 0) << o2;
  // The flags keep Chromium off the network (the machine has none) and out of the sandbox
  // (tests run as root); a fresh profile per run.
  const fs::path dom = dir / "dom.html", log = dir / "chromium.log";
  const std::string chromium = std::string(kChromium) +
                               " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                               " --disable-background-networking --disable-component-update --disable-sync"
                               " --enable-logging=stderr --v=0 --user-data-dir=" +
                               shell_quote((dir / "profile").string()) + " --dump-dom " +
                               shell_quote("file://" + html.string()) + " > " + shell_quote(dom.string()) +
                               " 2> " + shell_quote(log.string());
  auto [s3, o3] = run_command("timeout 120 " + chromium);
  ASSERT_EQ(s3, 0) << o3 << read_text(log);
  auto [s4, o4] = run_python("check_report.py", {html.string(), dom.string(), log.string()});
  EXPECT_EQ(s4, 0) << o4;
  RecordProperty("report_bytes", std::to_string(fs::file_size(html)));
}

// A slope's report gives Bishop's factor of safety among the run's numbers and draws the
// critical circle over the last frame's plastic shear strain (the drawing itself is tested by
// IoTest.RenderDrawsTheSlipCircleOfTheSummary).
TEST_F(IoTest, ReportOfASlopeShowsBishopsCircle) {
  require_python_vtk();
  std::string text = read_text(fs::path(SKRED_SOURCE_DIR) / "examples" / "slope_50m.toml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"cell_size = 2.5", "cell_size = 5.0"},
                                 {"duration = 80.0", "duration = 5.0"}}) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  }
  const fs::path scenario = dir / "slope.toml", out = dir / "slope";
  std::ofstream(scenario) << text;
  auto [s1, o1] = run_command(std::string(SKRED_BINARY) + " run " + shell_quote(scenario.string()) + " -o " +
                              shell_quote(out.string()) + " --threads 1");
  ASSERT_EQ(s1, 0) << o1;
  auto [s2, o2] = run_command(std::string(SKRED_BINARY) + " report " + shell_quote(out.string()));
  ASSERT_EQ(s2, 0) << o2;
  const std::string html = read_text(out / "report.html");
  EXPECT_NE(html.find("Bishop&#x27;s factor of safety F (at the start)</th><td>0.58"), std::string::npos);
  EXPECT_NE(html.find("plastic_shear_strain with Bishop&#x27;s critical circle at the start (F = 0.58"),
            std::string::npos);
}
