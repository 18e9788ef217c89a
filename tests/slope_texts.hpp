// Variants of the examples' slopes as scenario text, shared by the limit-equilibrium and
// strength-reduction tests.
#pragma once
#include <numbers>
#include <stdexcept>
#include <string>

#include "bishop_reference.hpp"
#include "scenario/scenario.hpp"

namespace skred::test {

// Replaces the first `from` in `text` (an example's, named `source`) by `to`; throws when the
// example no longer holds `from`.
inline void replace_once(std::string& text, const std::string& from, const std::string& to,
                         const std::string& source) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("not in " + source + ": " + from);
  text.replace(at, from.size(), to);
}

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
    replace_once(text, from, to, "examples/slope_collapse.toml");
  };
  replace("vertices = [[0.0, 0.0], [60.0, 0.0], [60.0, 4.0], [30.28, 4.0], [16.0, 14.0], [0.0, 14.0]]",
          "vertices = [[0.0, 4.0], [30.28, 4.0], [16.0, 14.0], [0.0, 14.0]]\n\n[[body]]\nname = \"base\"\n"
          "material = \"base\"\nparticles_per_cell = 3\nshape = \"polygon\"\n"
          "vertices = [[0.0, 0.0], [60.0, 0.0], [60.0, 4.0], [0.0, 4.0]]");
  replace("cell_size = 0.5", "cell_size = " + std::to_string(cell_size));
  return text + "\n" + material_table;
}

// The slopes above as the ground of the independent Bishop reference (bishop_reference.hpp),
// drawn from their polygons (not from the MPM's points): a Mohr-Coulomb soil of density rho
// under g = 9.81 m/s^2 (the examples' gravity).
inline bishop::Soil reference_soil(double friction_deg, double cohesion, double density = 2000.0) {
  return {cohesion, friction_deg * std::numbers::pi / 180.0, density * 9.81};
}

// examples/slope_50m.toml: a 50 m slope at 35 deg from the crest (80, 70) to the toe (151.4, 20)
// over its 20 m base layer, rollers at x = 0 and 300 m, the firm floor at y = 0.
inline bishop::Ground slope_50m_ground(const bishop::Soil& soil) {
  const std::string text = read_scenario_text(std::string(SKRED_SOURCE_DIR) + "/examples/slope_50m.toml");
  if (text.find("vertices = [[0.0, 0.0], [300.0, 0.0], [300.0, 20.0], [151.4, 20.0], [80.0, 70.0], [0.0, "
                "70.0]]") == std::string::npos)
    throw std::runtime_error("examples/slope_50m.toml's polygon is not the one slope_50m_ground draws");
  return {{{0.0, 70.0}, {80.0, 70.0}, {151.4, 20.0}, {300.0, 20.0}}, 0.0, {{0.0, soil}}};
}

// two_body_slope: the 10 m slope of examples/slope_collapse.toml (crest (16, 14), toe (30.28, 4),
// walls at x = 0 and 60 m) with soil `top` above y = 4 m and `base` below, the floor at y = 0.
inline bishop::Ground two_body_slope_ground(const bishop::Soil& top, const bishop::Soil& base) {
  return {{{0.0, 14.0}, {16.0, 14.0}, {30.28, 4.0}, {60.0, 4.0}}, 0.0, {{0.0, base}, {4.0, top}}};
}

}  // namespace skred::test
