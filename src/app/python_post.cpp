#include "app/python_post.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "app/exit_codes.hpp"

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

int exec_post(const std::vector<std::string>& args) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  fs::path script;
  try {
    script = find_post_script(ec ? fs::path("skred") : exe);
  } catch (const std::exception& e) {
    fmt::print(stderr, "skred: {}\n", e.what());
    return 1;
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
  std::vector<std::string> all = {python, "-E", "-s", "-B", script.string()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(python.c_str(), argv.data());
  fmt::print(stderr, "skred: cannot run {}: {}\n", python, std::strerror(errno));
  return exit_code::kMissingPython;
}

}  // namespace skred
