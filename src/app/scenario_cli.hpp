// The `check` and `schema` subcommands: validate a scenario and print what it will cost
// (refusing one that cannot fit this machine), and print or regenerate the scenario key
// tables of docs/scenario.md from the schema (src/scenario/schema.hpp).
// Included by main.cpp only (it needs CLI11).
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "scenario/scenario.hpp"

namespace skred {

class ScenarioCommands {
 public:
  explicit ScenarioCommands(CLI::App& app);
  bool chosen() const { return *check_ || *schema_; }
  int run() const;

 private:
  CLI::App* check_ = nullptr;
  CLI::App* schema_ = nullptr;
  std::string scenario_;
  bool force_ = false;
  std::string update_;
};

// Throws ScenarioError with the figures when the scenario's estimated memory exceeds what
// this machine offers (`skred run` and `check` without --force).
void require_fits_machine(const std::string& file);
void require_fits_machine(const AnyScenario& s);

}  // namespace skred
