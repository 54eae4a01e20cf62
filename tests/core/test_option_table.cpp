#include <gtest/gtest.h>

#include "core/error.h"
#include "core/option_table.h"

using namespace plslam;

namespace {
struct Opts {
  int n = 3;
  double x = 0.5;
  bool on = true;
  std::string name = "a";
};
OptionTable table(Opts* o) {
  OptionTable t;
  t.bind("s.n", &o->n, "a count");
  t.bind("s.x", &o->x, "a number");
  t.bind("t.on", &o->on, "a switch");
  t.bind("t.name", &o->name, "a name");
  return t;
}
}  // namespace

TEST(OptionTable, AppliesYamlAndRefusesUnknownKeys) {
  Opts o;
  OptionTable t = table(&o);
  t.apply(parseYamlSubset("# comment\ns:\n  n: 7   # trailing\n  x: 1.5e-1\nt:\n  on: false\n  name: \"b c\"\n", "c.yaml"),
          "c.yaml");
  EXPECT_EQ(o.n, 7);
  EXPECT_DOUBLE_EQ(o.x, 0.15);
  EXPECT_FALSE(o.on);
  EXPECT_EQ(o.name, "b c");
  try {
    t.apply(parseYamlSubset("s:\n  m: 1\n", "c.yaml"), "c.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown option 's.m'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("c.yaml"), std::string::npos);
  }
}

TEST(OptionTable, RefusesWrongTypes) {
  Opts o;
  OptionTable t = table(&o);
  EXPECT_THROW(t.set("s.n", "1.5", "x"), ConfigError);
  EXPECT_THROW(t.set("s.n", "abc", "x"), ConfigError);
  EXPECT_THROW(t.set("s.x", "nan", "x"), ConfigError);
  EXPECT_THROW(t.set("t.on", "maybe", "x"), ConfigError);
  EXPECT_EQ(o.n, 3);  // untouched by refused values
}

TEST(OptionTable, EffectiveConfigurationRoundTrips) {
  Opts o;
  OptionTable t = table(&o);
  o.n = 11;
  o.name = "zz";
  const std::string yaml = t.toYaml("header");
  EXPECT_NE(yaml.find("# a count"), std::string::npos);
  Opts p;
  OptionTable u = table(&p);
  u.apply(parseYamlSubset(yaml, "effective.yaml"), "effective.yaml");
  EXPECT_EQ(p.n, 11);
  EXPECT_EQ(p.name, "zz");
}

TEST(YamlSubset, RefusesWhatItDoesNotSupport) {
  EXPECT_THROW(parseYamlSubset("a:\n  - 1\n", "y"), ConfigError);
  EXPECT_THROW(parseYamlSubset("a: [1, 2]\n", "y"), ConfigError);
  EXPECT_THROW(parseYamlSubset("a: 1\na: 2\n", "y"), ConfigError);
  EXPECT_THROW(parseYamlSubset("a: \"open\n", "y"), ConfigError);
  // yaml-cpp alone would read the rest of the file into the unclosed quote.
  try {
    parseYamlSubset("a: 1\nb: 'open\nc: 2\n", "my.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("my.yaml:2: quoted text is not closed"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parseYamlSubset("a: 'it''s \"x\"'\nb: \"q\\\"\"\n", "y").at("b"), "q\"");
  EXPECT_THROW(parseYamlSubset("just text\n", "y"), ConfigError);
  try {
    parseYamlSubset("a: 1\nb c: 2\n", "my.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("my.yaml:2"), std::string::npos) << e.what();
  }
  try {
    parseYamlSubset("s:\n  a: 1\n  b: [1, 2]\n", "my.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("my.yaml:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("s.b"), std::string::npos) << e.what();
  }
}

// What yaml-cpp reads that the hand-written reader refused: it is YAML.
TEST(YamlSubset, ReadsOrdinaryYaml) {
  EXPECT_EQ(parseYamlSubset("  a: 1\n", "y").at("a"), "1");  // a document indented as a whole
  const auto flow = parseYamlSubset("s: {n: 2, x: 'q # not a comment'}\n", "y");
  EXPECT_EQ(flow.at("s.n"), "2");
  EXPECT_EQ(flow.at("s.x"), "q # not a comment");
  EXPECT_EQ(parseYamlSubset("\xEF\xBB\xBFs:\n  t: |\n    two\n    lines\n", "y").at("s.t"), "two\nlines\n");
  EXPECT_TRUE(parseYamlSubset("# only a comment\n", "y").empty());
}

TEST(OptionTable, TextWithQuotesAndBackslashesRoundTrips) {
  Opts o;
  OptionTable t = table(&o);
  o.name = "a \"b\" \\c\n# d: e";
  Opts p;
  OptionTable u = table(&p);
  u.apply(parseYamlSubset(t.toYaml("header"), "effective.yaml"), "effective.yaml");
  EXPECT_EQ(p.name, o.name);
}
