// Helpers shared by the result-file tests (test_io*.cpp): a scratch folder per test and
// running the checking scripts in tests/scripts with the system Python.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>
#include "temp_dir.hpp"

namespace skred::iotest {

// The Python that has VTK (Debian's python3-vtk9); a python3 earlier on PATH may not.
inline const char* kPython = "/usr/bin/python3";

inline std::string shell_quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return r + "'";
}

// Runs a shell command; returns its exit status and its stdout and stderr together.
inline std::pair<int, std::string> run_command(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed for: " + command);
  std::string out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

inline std::pair<int, std::string> run_python(const std::string& script,
                                              const std::vector<std::string>& args) {
  // Built with += : GCC 12 gives a false -Wrestrict for "literal" + std::string&& when inlined.
  std::string path = SKRED_SOURCE_DIR;
  path += "/tests/scripts/";
  path += script;
  std::string cmd = kPython;
  cmd += ' ';
  cmd += shell_quote(path);
  for (const std::string& a : args) {
    cmd += ' ';
    cmd += shell_quote(a);
  }
  return run_command(cmd);
}

// Fails the calling test (never skips it) when the system Python cannot import vtk.
inline void require_python_vtk() {
  static const std::pair<int, std::string> probe = run_command(std::string(kPython) + " -c 'import vtk'");
  if (probe.first != 0)
    throw std::runtime_error(std::string(kPython) +
                             " cannot import vtk, needed to check .vtu files with VTK's own "
                             "reader: install python3-vtk9 (apt-get install python3-vtk9). "
                             "Output: " +
                             probe.second);
}

inline double to_double(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0') throw std::runtime_error("not a number: '" + s + "'");
  return v;
}

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fresh scratch folder per test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  std::filesystem::path dir;

  void SetUp() override { dir = skred::test::fresh_temp_dir(); }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::permissions(dir, std::filesystem::perms::owner_all, ec);
    std::filesystem::remove_all(dir, ec);
  }

  void expect_no_tmp_files() const {
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
      EXPECT_NE(e.path().extension(), ".tmp") << "left behind: " << e.path();
  }
};

}  // namespace skred::iotest
