#include "run/output_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace skred {

namespace fs = std::filesystem;

namespace {

// PREFIX + `digits` digits + SUFFIX.
bool numbered(const std::string& name, const std::string& prefix, std::size_t digits,
              const std::string& suffix) {
  if (name.size() != prefix.size() + digits + suffix.size()) return false;
  if (name.compare(0, prefix.size(), prefix) != 0) return false;
  if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
  return std::all_of(name.begin() + static_cast<long>(prefix.size()),
                     name.end() - static_cast<long>(suffix.size()),
                     [](unsigned char c) { return std::isdigit(c); });
}

bool skred_file_name(std::string name) {
  if (name.size() > 4 && name.ends_with(".tmp")) name.resize(name.size() - 4);
  static const char* fixed[] = {"particles.pvd", "grid.pvd",       "series.csv",  "summary.json",
                                "scenario.toml", "checkpoint.skc", "report.html", "sweep.csv",
                                "refine.csv",    "fos.csv"};
  for (const char* f : fixed)
    if (name == f) return true;
  return numbered(name, "particles_", 6, ".vtu") || numbered(name, "grid_", 6, ".vtr");
}

}  // namespace

std::vector<fs::path> run_files(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file(ec) && skred_file_name(name)) {
      files.push_back(e.path());
    } else if (e.is_directory(ec) && name == "pictures") {
      for (const auto& p : fs::directory_iterator(e.path(), ec)) {
        const auto ext = p.path().extension();
        if (p.is_regular_file(ec) && (ext == ".png" || ext == ".gif")) files.push_back(p.path());
      }
    } else if (e.is_directory(ec) && numbered(name, "run_", 3, "")) {
      for (const fs::path& f : run_files(e.path())) files.push_back(f);
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

void prepare_output_folder(const fs::path& dir, bool overwrite, const fs::path& keep) {
  std::error_code ec;
  std::vector<fs::path> files = run_files(dir);
  std::erase_if(files, [&](const fs::path& f) { return !keep.empty() && fs::equivalent(f, keep, ec); });
  if (!files.empty() && !overwrite)
    throw std::runtime_error(
        fmt::format("'{}' holds an earlier run ({} of skred's files, e.g. {}); add --overwrite to replace it "
                    "or choose another folder",
                    dir.string(), files.size(), files.front().lexically_relative(dir).string()));
  for (const fs::path& f : files)
    if (!fs::remove(f, ec) && ec)
      throw std::runtime_error(fmt::format("cannot remove '{}': {}", f.string(), ec.message()));
  for (const char* sub : {"pictures"}) fs::remove(dir / sub, ec);  // only if now empty
  if (fs::is_directory(dir, ec))
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.is_directory() && numbered(e.path().filename().string(), "run_", 3, ""))
        fs::remove(e.path(), ec);  // only if now empty
  fs::create_directories(dir);
}

}  // namespace skred
