// The declared parameter tables of the model folders (material/*/info.hpp) against the scenario
// parser that reads materials today (scenario/parser.cpp): the model names are the parser's,
// every declared key is accepted, every required one is needed, every fixed bound of a declared
// range is where the parser draws it, and a key that no table declares is rejected. Also the
// strength of each model for the relative yield function (Post eq. 66).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "material/strength.hpp"
#include "scenario/scenario.hpp"

using namespace skred;

namespace {

constexpr Model kModels[] = {Model::LinearElastic, Model::MohrCoulomb, Model::Tresca, Model::VonMises};

const ModelInfo& info_of(Model m) {
  Material mat;
  mat.model = m;
  return mat.info();
}

// Every declared parameter of a model: the elastic block, then the model's own.
std::vector<ParamSpec> specs_of(Model m) {
  std::vector<ParamSpec> out(std::begin(kElasticParamSpecs), std::end(kElasticParamSpecs));
  for (const ParamSpec& p : info_of(m).params) out.push_back(p);
  return out;
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

// A scenario with one material of model `m`: every declared key at its example value, except
// `skip` (left out) and `key` (set to `value`), plus an `extra` line.
std::string scenario(Model m, const std::string& skip, const std::string& key, double value,
                     const std::string& extra = "") {
  std::string t =
      "title = \"t\"\n[grid]\norigin = [0, 0]\nsize = [4.0, 2.0]\ncell_size = 0.5\n"
      "[[material]]\nname = \"soil\"\nmodel = \"";
  t += to_string(m);
  t += "\"\n";
  for (const ParamSpec& p : specs_of(m)) {
    if (p.key == skip) continue;
    double v = p.key == key ? value : p.example;
    if (key == "friction" && std::string(p.key) == "dilation") v = std::min(v, value);  // psi <= phi
    t += std::string(p.key) + " = " + number(v) + "\n";
  }
  t += extra;
  t += "[[body]]\nname = \"b\"\nmaterial = \"soil\"\nparticles_per_cell = 2\nshape = "
       "\"rectangle\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n"
       "[solver]\nend_time = 500.0\n[output]\ninterval = 0.1\n";  // (longer than one step at E = 1 mPa)
  return t;
}

// "" if the text parses, else the error message.
std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, "t.toml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

bool names_key(const std::string& what, const char* key) {
  return what.find(std::string(key) + "'") != std::string::npos;
}

}  // namespace

TEST(MaterialParams, NamesAreTheParsersAndTablesAreWellFormed) {
  for (Model m : kModels) {
    const ModelInfo& info = info_of(m);
    EXPECT_STREQ(info.name, to_string(m));
    EXPECT_GT(std::string(info.description).size(), 10u);
    std::set<std::string> keys;
    for (const ParamSpec& p : specs_of(m)) {
      SCOPED_TRACE(std::string(info.name) + "." + p.key);
      EXPECT_TRUE(keys.insert(p.key).second) << "duplicate key";
      EXPECT_LE(p.min, p.max);
      EXPECT_GT(std::string(p.doc).size(), 5u);
      EXPECT_GT(std::string(p.unit).size(), 0u);
      if (p.required) {
        EXPECT_TRUE(std::isnan(p.default_value)) << "a required key has no default";
      }
      for (double v : {p.example, p.default_value}) {
        if (std::isnan(v) || std::isinf(v)) continue;
        EXPECT_TRUE(p.min_open ? v > p.min : v >= p.min) << v;
        EXPECT_TRUE(p.max_open ? v < p.max : v <= p.max) << v;
      }
    }
  }
}

TEST(MaterialParams, DeclaredKeysAndBoundsAreTheParsers) {
  for (Model m : kModels) {
    const char* name = to_string(m);
    // Every declared key at its example value parses.
    EXPECT_EQ(error_of(scenario(m, "", "", 0.0)), "") << name;
    // A key no table of this model declares is rejected.
    EXPECT_TRUE(names_key(error_of(scenario(m, "", "", 0.0, "bogus = 1.0\n")), "bogus")) << name;
    for (const ParamSpec& p : specs_of(m)) {
      SCOPED_TRACE(std::string(name) + "." + p.key);
      // A required key is needed; an optional one may be left out (the void ratios in pairs).
      const std::string missing = error_of(scenario(m, p.key, "", 0.0));
      if (p.required) {
        EXPECT_TRUE(names_key(missing, p.key)) << missing;
      } else if (std::string(p.key).find("void_ratio") == std::string::npos) {
        EXPECT_EQ(missing, "");
      }
      // The fixed bounds: on a closed bound accepted, on an open one or beyond rejected.
      for (int side = 0; side < 2; ++side) {
        const double bound = side ? p.max : p.min;
        const bool open = side ? p.max_open : p.min_open;
        if (std::isinf(bound)) continue;
        const double beyond = bound + (side ? 1.0 : -1.0) * std::max(1.0, std::abs(bound));
        EXPECT_TRUE(names_key(error_of(scenario(m, "", p.key, beyond)), p.key)) << beyond;
        const std::string at = error_of(scenario(m, "", p.key, bound));
        // Keys bounded by another key at its example value (psi <= phi, c_r <= c_p,
        // e0 < e_max) may be refused at their fixed upper bound by that relation.
        const std::set<std::string> related = {"dilation", "residual_cohesion", "initial_void_ratio"};
        if (open) {
          EXPECT_TRUE(names_key(at, p.key)) << "at open bound " << bound << ": " << at;
        } else if (!(side == 1 && related.count(p.key))) {
          EXPECT_EQ(at, "") << "at closed bound " << bound;
        }
      }
    }
  }
}

TEST(MaterialParams, StrengthOfEachModelForTheRelativeYieldFunction) {
  Material mc;
  mc.model = Model::MohrCoulomb;
  mc.mohr_coulomb.friction = 0.5;
  mc.mohr_coulomb.cohesion = 7e3;
  Material tr = mc;
  tr.model = Model::Tresca;
  tr.prepare();  // phi = psi = 0
  Material vm;
  vm.model = Model::VonMises;
  vm.von_mises = {12e3, 3e3, -1e5};
  const std::vector<MaterialStrength> s = material_strengths({Material{}, mc, tr, vm});
  EXPECT_TRUE(std::isnan(s[0].friction) && std::isnan(s[0].cohesion));
  EXPECT_EQ(s[1].friction, 0.5);
  EXPECT_EQ(s[1].cohesion, 7e3);
  EXPECT_EQ(s[2].friction, 0.0);
  EXPECT_EQ(s[2].cohesion, 7e3);
  EXPECT_EQ(s[3].friction, 0.0);
  EXPECT_EQ(s[3].cohesion, 12e3);
  EXPECT_EQ(mc.friction_angle(), 0.5);
  EXPECT_EQ(vm.strength_cohesion(), 12e3);
}
