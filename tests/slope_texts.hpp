// Variants of the examples' slopes as scenario text, shared by the limit-equilibrium and
// strength-reduction tests.
#pragma once
#include <stdexcept>
#include <string>

#include "scenario/scenario.hpp"

namespace skred::test {

// A [[material]] table of the slope example's elasticity and density with the given strength.
inline std::string mohr_coulomb_material(const std::string& name, double friction_deg, double cohesion) {
  return "[[material]]\nname = \"" + name +
         "\"\nmodel = \"mohr-coulomb\"\ndensity = 2000.0\nyoung = 40.0e6\npoisson = 0.42\nfriction = " +
         std::to_string(friction_deg) + "\ncohesion = " + std::to_string(cohesion) + "\ndilation = 0.0\n";
}

// examples/slope_collapse.toml at `cell_size` with its base layer (y < 4 m) a second body of
// material `base`, given as a [[material]] table (`material_table`).
inline std::string two_body_slope(const std::string& material_table, double cell_size = 0.5) {
  std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/slope_collapse.toml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("not in examples/slope_collapse.toml: " + from);
    text.replace(at, from.size(), to);
  };
  replace("vertices = [[0.0, 0.0], [60.0, 0.0], [60.0, 4.0], [30.28, 4.0], [16.0, 14.0], [0.0, 14.0]]",
          "vertices = [[0.0, 4.0], [30.28, 4.0], [16.0, 14.0], [0.0, 14.0]]\n\n[[body]]\nname = \"base\"\n"
          "material = \"base\"\nparticles_per_cell = 3\nshape = \"polygon\"\n"
          "vertices = [[0.0, 0.0], [60.0, 0.0], [60.0, 4.0], [0.0, 4.0]]");
  replace("cell_size = 0.5", "cell_size = " + std::to_string(cell_size));
  return text + "\n" + material_table;
}

}  // namespace skred::test
