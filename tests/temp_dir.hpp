// A fresh temporary folder of its own for each test (mkdtemp: a unique name, so two test
// runs side by side never share or delete each other's files), removed at scope exit.
#pragma once
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace skred::test {

// A new, empty, uniquely named folder skred_<suite>.<test>_<tag>_XXXXXX under the system's
// temporary folder; the caller removes it.
inline std::filesystem::path fresh_temp_dir(const std::string& tag = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "skred_";
  name += info ? std::string(info->test_suite_name()) + "." + info->name() : "test";
  if (!tag.empty()) name += "_" + tag;
  for (char& c : name)
    if (c == '/') c = '_';
  std::string pattern = (std::filesystem::temp_directory_path() / (name + "_XXXXXX")).string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
  return pattern;
}

// fresh_temp_dir() removed at scope exit.
class TempDir {
 public:
  explicit TempDir(const std::string& tag = "") : path_(fresh_temp_dir(tag)) {}
  ~TempDir() {
    std::error_code ec;
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all, ec);
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& s) const { return path_ / s; }

 private:
  std::filesystem::path path_;
};

}  // namespace skred::test
