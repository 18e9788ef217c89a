// The check of a build without MPI and PETSc (cmake -DSKRED_MPI=OFF; ctest runs it there, and
// the default build's suite configures and builds it: tests/scripts/one_process_build.sh).
// Such a build runs in one process and says so when started by an MPI launcher, refuses the
// implicit integrator naming the key, and runs the explicit one: the vibrating bar (R1) keeps
// its energy. Usage: skred_alone_check SKRED SOURCE_DIR. Exit 0 when every check holds.
#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "parallel/processes.hpp"
#include "parallel/star_forest.hpp"

namespace {

int failures = 0;

void expect(bool ok, const std::string& what) {
  fmt::print("{} {}\n", ok ? "ok:  " : "FAIL:", what);
  failures += !ok;
}

// Runs `command` (stderr to a file); its exit code and what it printed there.
std::pair<int, std::string> run(const std::string& command, const std::filesystem::path& dir) {
  const std::filesystem::path err = dir / "stderr.txt";
  const int status = std::system((command + " 2> " + err.string()).c_str());
  std::ifstream in(err);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    fmt::print(stderr, "usage: skred_alone_check SKRED SOURCE_DIR\n");
    return 2;
  }
  const std::string skred = argv[1], source = argv[2];
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "skred_alone_check";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  expect(!skred::built_with_mpi(), "this build says it has no MPI");
  const skred::Processes world = skred::Processes::world();
  expect(!world.distributed() && world.size() == 1, "its world is one process");
  {  // A one-process star forest: leaves are roots of this process.
    skred::StarForest f;
    const std::vector<int> rank = {0, 0, 0};
    const std::vector<long> index = {1, 0, 1};
    f.connect(world, 2, rank, index);
    double root[2] = {1.0, 2.0}, leaf[3] = {10.0, 20.0, 30.0};
    f.reduce(1, leaf, root);
    expect(root[0] == 21.0 && root[1] == 42.0, "a star forest adds its leaves into their roots");
    f.broadcast(1, root, leaf);
    expect(leaf[0] == 42.0 && leaf[1] == 21.0 && leaf[2] == 42.0, "and broadcasts its roots to them");
  }

  {
    const auto [code, text] = run(skred + " --version > " + (dir / "version.txt").string(), dir);
    std::ifstream in(dir / "version.txt");
    std::stringstream version;
    version << in.rdbuf();
    expect(code == 0 && version.str().find("built without MPI and PETSc") != std::string::npos,
           fmt::format("--version says it was built without MPI ({})", version.str()));
  }
  const std::string bar = source + "/examples/vibrating_bar.toml";
  {
    const auto [code, text] = run("OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 " + skred + " run " + bar +
                                      " -o " + (dir / "launched").string(),
                                  dir);
    expect(
        code == 4 && text.find("no MPI") != std::string::npos &&
            text.find("SKRED_MPI=OFF") != std::string::npos && !std::filesystem::exists(dir / "launched"),
        fmt::format("started by a launcher it refuses with exit 4 and says why (exit {}: {})", code, text));
  }
  {
    const std::string cut = source + "/examples/vertical_cut_implicit.toml";
    const auto [code, text] = run(skred + " run " + cut + " -o " + (dir / "implicit").string(), dir);
    expect(
        code == 5 && text.find("vertical_cut_implicit.toml:") != std::string::npos &&
            text.find("integrator") != std::string::npos && text.find("PETSc") != std::string::npos,
        fmt::format("the implicit integrator is refused with exit 5, naming file, line and key (exit {}: {})",
                    code, text));
  }
  {
    const auto [code, text] =
        run(skred + " run " + bar + " -o " + (dir / "bar").string() + " --threads 1", dir);
    expect(code == 0, fmt::format("the vibrating bar runs (exit {}: {})", code, text));
    std::ifstream series(dir / "bar" / "series.csv");
    std::string header, line, last;
    std::getline(series, header);
    std::vector<double> first, end;
    const auto total = [&](const std::string& row) {  // (total_energy: the 9th column)
      std::stringstream s(row);
      std::string cell;
      for (int c = 0; c < 9 && std::getline(s, cell, ','); ++c) {
      }
      return std::strtod(cell.c_str(), nullptr);
    };
    std::getline(series, line);
    const double e0 = total(line);
    while (std::getline(series, line)) last = line;
    const double e1 = last.empty() ? NAN : total(last);
    expect(header.find("total_energy") != std::string::npos && e0 > 0.0 && std::abs(e1 - e0) < 1e-3 * e0,
           fmt::format("and keeps its energy within 0.1 % (R1: {} J/m, then {})", e0, e1));
  }
  std::filesystem::remove_all(dir);
  return failures == 0 ? 0 : 1;
}
