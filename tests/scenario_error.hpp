// The message a scenario text's parse throws (file "t.toml"), for the tests of bad input.
#pragma once
#include <string>

#include "scenario/scenario.hpp"

namespace skred::test {

// The ScenarioError's message of parsing `text` as "t.toml", "" when it parses.
inline std::string error_of(const std::string& text) {
  try {
    parse_any_scenario(text, "t.toml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

}  // namespace skred::test
