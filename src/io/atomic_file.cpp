#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace skred {

namespace fs = std::filesystem;

fs::path temporary_path_for(const fs::path& file) {
  fs::path tmp = file;
  tmp += ".tmp";
  return tmp;
}

void write_file_atomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  const fs::path tmp = temporary_path_for(file);
  const auto remove_tmp = [&tmp] {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  };

  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) {
    const int err = errno;
    throw std::runtime_error(fmt::format("cannot write '{}': cannot create '{}'{}{}", file.string(),
                                         tmp.string(), err ? ": " : "", err ? std::strerror(err) : ""));
  }

  try {
    write(out);
    out.flush();
  } catch (...) {
    out.close();
    remove_tmp();
    throw;
  }
  out.close();
  if (out.fail()) {
    remove_tmp();
    throw std::runtime_error(
        fmt::format("cannot write '{}': writing '{}' failed (disk full?)", file.string(), tmp.string()));
  }

  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    remove_tmp();
    throw std::runtime_error(fmt::format("cannot write '{}': renaming '{}' onto it failed: {}", file.string(),
                                         tmp.string(), ec.message()));
  }
}

}  // namespace skred
