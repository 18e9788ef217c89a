#include "app/python_post.hpp"

#include <fmt/core.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "app/exit_codes.hpp"

extern char** environ;

namespace skred {

namespace fs = std::filesystem;

std::string post_python() {
  const char* env = std::getenv("SKRED_PYTHON");
  return env && *env ? env : "/usr/bin/python3";
}

fs::path find_post_script(const fs::path& exe) {
  const fs::path dir = exe.parent_path();
  std::vector<fs::path> places = {dir / "python", dir / ".." / "share" / "skred" / "python"};
#ifdef SKRED_PYTHON_DIR
  places.emplace_back(SKRED_PYTHON_DIR);
#endif
  std::string looked;
  for (const fs::path& p : places) {
    std::error_code ec;
    if (fs::is_regular_file(p / "skred-post.py", ec)) return fs::weakly_canonical(p / "skred-post.py");
    looked += "\n  " + p.string();
  }
  throw std::runtime_error("cannot find the post-processing script skred-post.py; looked in:" + looked);
}

namespace {

// The command line `PYTHON -E -s -B skred-post.py ARGS...`, or an exit status (after printing
// why) if the script or Python is missing.
int post_command(const std::vector<std::string>& args, std::vector<std::string>& all) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  fs::path script;
  try {
    script = find_post_script(ec ? fs::path("skred") : exe);
  } catch (const std::exception& e) {
    fmt::print(stderr, "skred: {}\n", e.what());
    return exit_code::kError;
  }
  const std::string python = post_python();
  if (::access(python.c_str(), X_OK) != 0) {
    fmt::print(stderr,
               "skred: {} is needed to draw pictures but is missing or not executable ({}).\n"
               "install it with: apt-get install python3 python3-matplotlib python3-pil "
               "python3-vtk9   (or: bash scripts/install-deps.sh)\n",
               python, std::strerror(errno));
    return exit_code::kMissingPython;
  }
  all = {python, "-E", "-s", "-B", script.string()};
  all.insert(all.end(), args.begin(), args.end());
  return exit_code::kSuccess;
}

std::vector<char*> c_argv(std::vector<std::string>& all) {
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  return argv;
}

}  // namespace

int exec_post(const std::vector<std::string>& args) {
  std::vector<std::string> all;
  if (const int failed = post_command(args, all)) return failed;
  std::vector<char*> argv = c_argv(all);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(all[0].c_str(), argv.data());
  fmt::print(stderr, "skred: cannot run {}: {}\n", all[0], std::strerror(errno));
  return exit_code::kMissingPython;
}

int run_post(const std::vector<std::string>& args) {
  std::vector<std::string> all;
  if (const int failed = post_command(args, all)) return failed;
  std::vector<char*> argv = c_argv(all);
  std::fflush(stdout);
  std::fflush(stderr);
  pid_t pid = 0;
  if (const int err = ::posix_spawn(&pid, all[0].c_str(), nullptr, nullptr, argv.data(), environ)) {
    fmt::print(stderr, "skred: cannot run {}: {}\n", all[0], std::strerror(err));
    return exit_code::kMissingPython;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return exit_code::kError;
  return WIFEXITED(status) ? WEXITSTATUS(status) : exit_code::kError;
}

}  // namespace skred
