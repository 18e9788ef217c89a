// The scenario schema (src/scenario/schema.hpp): docs/scenario.md's key tables are generated
// from it, validation reads its ranges and defaults, and input no analysis needs (a key a
// million parts deep, a time step above the stable one) is refused with a located message.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scenario/estimate.hpp"
#include "scenario/scenario.hpp"
#include "scenario/schema.hpp"
#include "scenario_error.hpp"

using namespace skred;

namespace {

const std::string kSource = SKRED_SOURCE_DIR;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kMinimal = read(kSource + "/tests/data/minimal.toml");

using skred::test::error_of;

}  // namespace

TEST(Schema, DocsAreGeneratedFromTheSchema) {
  std::set<std::string> used;
  for (const char* doc : {"/docs/scenario.md", "/docs/scenario-3d.md"}) {
    const std::string text = read(kSource + doc);
    ASSERT_FALSE(text.empty()) << doc;
    const std::string generated = schema::update_generated_blocks(text);
    std::size_t at = 0;  // the first difference, for the message
    while (at < generated.size() && at < text.size() && generated[at] == text[at]) ++at;
    EXPECT_TRUE(generated == text) << doc << " differs from the schema near \""
                                   << text.substr(at < 40 ? 0 : at - 40, 80)
                                   << "\": run `build/skred schema --update " << doc + 1 << "`";
    for (const schema::Section& s : schema::sections())
      if (text.find("<!-- schema: " + s.title + " -->") != std::string::npos) used.insert(s.title);
  }
  for (const schema::Section& s : schema::sections())
    EXPECT_TRUE(used.count(s.title)) << "section " << s.title << " is in no document";
}

TEST(Schema, SectionsAreWellFormed) {
  for (const schema::Section& s : schema::sections()) {
    std::set<std::string> names;
    for (const schema::Key& k : s.keys) {
      SCOPED_TRACE(s.name + "." + k.name);
      EXPECT_TRUE(names.insert(k.name).second) << "declared twice";
      EXPECT_GT(std::string(k.doc).size(), 0u);
      if (k.type == schema::Type::Number) {
        EXPECT_GT(std::string(k.unit).size(), 0u);
      }
      if (k.type == schema::Type::Choice) {
        EXPECT_GE(schema::choices_of(k).size(), 2u);
      }
      if (k.def.kind == schema::DefaultKind::Value) {
        EXPECT_TRUE(k.range.contains(k.def.value));
      }
      EXPECT_LE(k.range.lo, k.range.hi);
    }
  }
}

TEST(Schema, RangesAndDefaultsComeFromTheSchema) {
  // A default of the schema reaches the scenario; its bounds are the parser's.
  const auto s = std::get<Scenario>(parse_any_scenario(kMinimal, "t.toml"));
  EXPECT_EQ(s.cfl, schema::section("solver").at("cfl").def.value);
  EXPECT_EQ(s.bodies[0].particles_per_cell, schema::section("body").at("particles_per_cell").def.value);
  const schema::Range cfl = schema::section("solver").at("cfl").range;
  EXPECT_NE(error_of(kMinimal + "cfl = " + std::to_string(cfl.hi * 1.01) + "\n"), "");
  EXPECT_EQ(error_of(kMinimal + "cfl = " + std::to_string(cfl.hi) + "\n"), "");
  const schema::Range v = schema::section("body").at("velocity").range;
  std::string fast = kMinimal;
  fast.replace(fast.find("max = [1.0, 1.0]"), 16,
               "max = [1.0, 1.0]\nvelocity = [0.0, " + std::to_string(v.hi * 2) + "]");
  EXPECT_NE(error_of(fast).find("body[0].velocity': component y must be"), std::string::npos)
      << error_of(fast);
}

TEST(Schema, ChoicesAreTheSchemas) {
  std::string t = kMinimal + "scheme = \"usx\"\n";
  const std::string e = error_of(t);
  for (const auto& c : schema::choices_of(schema::section("solver").at("scheme")))
    EXPECT_NE(e.find("\"" + c + "\""), std::string::npos) << e;
}

TEST(Schema, AKeyAMillionPartsDeepIsASyntaxErrorNotACrash) {
  std::string key = "a";
  for (int i = 0; i < 1000000; ++i) key += ".a";
  const std::string e = error_of("title = \"x\"\n" + key + " = 1\n");
  EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e.substr(0, 200);
  EXPECT_NE(e.find("dotted key with more than"), std::string::npos) << e.substr(0, 200);
  // Dots in values, strings and comments do not count.
  std::string values = kMinimal +
                       "# "
                       "a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p.q.r.s.t.u.v.w.x.y.z.a.b.c.d.e.f.g.h.i.j.k.l.m.n.o.p."
                       "q.r.s.t.u.v.w.x.y.z.a.b.c.d\n";
  EXPECT_EQ(error_of(values), "");
  EXPECT_EQ(error_of("title = \"" + std::string(200, '.') + "\"\n" + kMinimal), "");
}

// toml++ also parses a table header's dotted name, nested arrays and nested inline tables
// recursively: 50,000 levels of each are refused (a dotted name by check_key_depth, nested
// values by toml++'s own limit of 256) before the stack runs out, also under AddressSanitizer,
// whose larger frames overflow it sooner (scripts/sanitize.sh).
TEST(Schema, FiftyThousandNestingLevelsAreASyntaxErrorNotACrash) {
  const int n = 50000;
  std::string header = "[a", quoted = "\"a\"", tables = "a = ";
  for (int i = 0; i < n; ++i) {
    header += ".a";
    quoted += ".\"a\"";
    tables += "{b = ";
  }
  const std::vector<std::string> inputs = {header + "]\nb = 1\n", quoted + " = 1\n",
                                           "a = " + std::string(n, '[') + std::string(n, ']') + "\n",
                                           tables + "1" + std::string(n, '}') + "\n"};
  for (const std::string& body : inputs) {
    const std::string e = error_of("title = \"x\"\n" + body);
    EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e.substr(0, 200);
    EXPECT_NE(e.find("syntax error"), std::string::npos) << e.substr(0, 200);
  }
}

TEST(Schema, ATimeStepAboveTheStableOneIsRefusedUnlessAllowed) {
  const auto s = std::get<Scenario>(parse_any_scenario(kMinimal, "t.toml"));
  const double stable = stable_time_step(s);
  // Minimal: E = 2 MPa, nu = 0.25, rho = 1500: c = sqrt(2.4e6 / 1500) = 40 m/s, h = 0.5 m.
  EXPECT_NEAR(stable, 0.5 / 40.0, 1e-12);
  const std::string above = kMinimal + "time_step = " + std::to_string(stable * 1.2) + "\n";
  EXPECT_NE(error_of(above).find("solver.time_step': 0.015 s exceeds the stable time step"),
            std::string::npos)
      << error_of(above);
  EXPECT_EQ(error_of(above + "allow_unstable_time_step = true\n"), "");
  EXPECT_EQ(error_of(kMinimal + "time_step = " + std::to_string(stable * 0.99) + "\n"), "");
}

TEST(Schema, SizeEstimateMatchesTheGeneratedPoints) {
  const auto s = std::get<Scenario>(parse_any_scenario(kMinimal, "t.toml"));
  const ScenarioSize z = estimate_size(s);
  // A 1 x 1 m rectangle at h = 0.5 m and 2 x 2 points per cell: 16 points; 9 x 5 nodes.
  EXPECT_DOUBLE_EQ(z.points, 16.0);
  EXPECT_DOUBLE_EQ(z.nodes, 45.0);
  EXPECT_GT(z.memory_bytes, 16 * 300.0);
  EXPECT_GT(available_memory_bytes(), 1e8);
}
