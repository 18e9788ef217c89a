// `skred report`: the self-contained HTML page of a real run, opened in Debian's headless
// Chromium. Chromium is installed by scripts/install-deps.sh, so its absence fails the test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

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
