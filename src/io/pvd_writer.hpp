// A ParaView collection index (particles.pvd, grid.pvd) listing every output file with its time.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>

namespace skred {

class PvdWriter {
 public:
  // The index is `folder`/`name` (particles.pvd unless told otherwise, e.g. grid.pvd).
  // Nothing is written until the first add(); never, for an empty `folder` (it only counts).
  explicit PvdWriter(const std::filesystem::path& folder, const std::string& name = "particles.pvd");

  // Appends a DataSet entry for `vtu_filename` (relative to the output folder, as ParaView
  // resolves it against the .pvd's directory) at simulated time `time`, then rewrites
  // the index atomically, so the index on disk is always complete and valid.
  // Throws std::invalid_argument for a non-finite time, std::runtime_error on I/O failure.
  void add(double time, const std::string& vtu_filename);

  const std::filesystem::path& file() const { return file_; }
  std::size_t size() const { return count_; }

 private:
  std::filesystem::path file_;
  std::string entries_;  // the formatted <DataSet .../> lines so far
  std::size_t count_ = 0;
};

}  // namespace skred
