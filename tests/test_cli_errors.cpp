// `skred check FILE` on every malformed scenario in tests/bad_scenarios/: the command must
// exit with the documented code for an invalid scenario (5; a death by signal is no clean
// rejection) and name the offending key. Each file's first line is "# expect: <text>", the text
// that must appear in the command's output (usually the key path).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

struct RunResult {
  int exit_code = -1;  // -1 unless the command exited normally
  int signal = 0;      // the signal that killed it, if one did
  std::string output;
};

RunResult run(const std::string& command) {
  RunResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  r.signal = (status != -1 && WIFSIGNALED(status)) ? WTERMSIG(status) : 0;
  return r;
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string expected_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string first;
  std::getline(in, first);
  const std::string tag = "# expect: ";
  if (first.rfind(tag, 0) != 0) return {};
  first.erase(0, tag.size());
  while (!first.empty() && (first.back() == '\r' || first.back() == ' ')) first.pop_back();
  return first;
}

}  // namespace

TEST(CliErrors, CheckRejectsEveryBadScenarioNamingTheKey) {
  const std::filesystem::path dir = std::filesystem::path(SKRED_SOURCE_DIR) / "tests" / "bad_scenarios";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 15u);
  for (const auto& file : files) {
    SCOPED_TRACE(file.filename().string());
    const std::string expect = expected_text(file);
    ASSERT_FALSE(expect.empty()) << "first line must be '# expect: <key>'";
    const RunResult r = run(quote(SKRED_BINARY) + " check " + quote(file.string()) + " 2>&1");
    EXPECT_EQ(r.signal, 0) << r.output;
    EXPECT_EQ(r.exit_code, 5) << r.output;  // README, "Exit codes": invalid scenario
    EXPECT_NE(r.output.find(expect), std::string::npos) << "expected '" << expect << "' in output:\n"
                                                        << r.output;
    EXPECT_NE(r.output.find(file.filename().string()), std::string::npos) << r.output;
  }
}
