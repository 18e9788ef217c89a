// The end-of-run summary (summary.json).
#pragma once
#include <filesystem>
#include <string>

namespace skred {

struct Summary {
  std::string status;  // "completed" or "unstable" or "error"
  std::string message;
  long steps;
  double simulated_time;
  double end_time;
  long particles;
  long cells;
  double wall_seconds;
  double particle_updates_per_second;
  int threads;
  std::string scenario;
  std::string interpolation;
  std::string scheme;
  double time_step;
};

// Writes `s` as one JSON object (keys named as the fields, in field order) atomically.
// Strings are escaped (quotes, backslashes, control characters; invalid UTF-8 bytes become
// U+FFFD); real numbers are written as the shortest decimal that reads back to the same
// double, and as null when not finite. Throws std::runtime_error on I/O failure.
void write_summary_json(const std::filesystem::path& file, const Summary& s);

// The JSON string literal (with the surrounding quotes) for `s`.
std::string json_string(const std::string& s);

}  // namespace skred
