// The cells of the tables a batch of runs writes (sweep.csv, refine.csv): numbers with 12
// significant digits, text quoted when it must be, and how a run ended.
#pragma once
#include <fmt/format.h>

#include <cmath>
#include <string>

#include "run/simulation.hpp"

namespace skred {

// 12 significant digits, far beyond what a measure means, and short of the last bits of
// rounding noise (0.05, not 0.05000000000000004); "nan" when unset (pandas and numpy read it).
inline std::string table_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.12g}", v) : std::string("nan");
}

// A text field, quoted (RFC 4180) when it holds a comma, quote or line break.
inline std::string table_text(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// How a run of a batch ended: "completed", "left_grid" or "unstable".
inline std::string run_status(const RunResult& r) {
  return r.completed ? "completed" : r.left_grid ? "left_grid" : "unstable";
}

}  // namespace skred
