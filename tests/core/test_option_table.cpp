#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

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

TEST(OptionTable, AKeyWithoutAOneLineDocStringIsAProgrammingError) {
  int n = 0;
  OptionTable t;
  EXPECT_THROW(t.bind("s.n", &n, ""), std::logic_error);
  EXPECT_THROW(t.bind("s.n", &n, "  "), std::logic_error);
  EXPECT_THROW(t.bind("s.n", &n, "two\nlines"), std::logic_error);
  t.bind("s.n", &n, "a count");
  EXPECT_TRUE(t.has("s.n"));
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

TEST(OptionTable, ASectionBoundInTwoPlacesIsWrittenAsOneMapping) {
  int a = 1, b = 2, c = 3;
  OptionTable t;
  t.bind("first.a", &a, "a");
  t.bind("second.b", &b, "b");
  t.bind("first.c", &c, "c");
  const std::string yaml = t.toYaml();
  size_t sections = 0;
  for (size_t at = yaml.find("first:"); at != std::string::npos; at = yaml.find("first:", at + 1)) ++sections;
  EXPECT_EQ(sections, 1u) << yaml;
  EXPECT_LT(yaml.find("  c: 3"), yaml.find("second:")) << yaml;  // sections in the order they first appear
  int a2 = 0, b2 = 0, c2 = 0;
  OptionTable u;
  u.bind("first.a", &a2, "a");
  u.bind("second.b", &b2, "b");
  u.bind("first.c", &c2, "c");
  u.apply(parseYamlSubset(yaml, "effective.yaml"), "effective.yaml");
  EXPECT_EQ(std::make_tuple(a2, b2, c2), std::make_tuple(1, 2, 3));
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

TEST(OptionTable, RangedKeysRefuseValuesOutsideTheirRangeNamingTheKey) {
  int count = 3;
  double ratio = 0.5, sigma = 1.0;
  OptionTable t;
  t.bind("s.count", &count, "a count", atLeast(1));
  t.bind("s.ratio", &ratio, "a fraction", within(0, 1));
  t.bind("s.sigma", &sigma, "a sigma", above(0));
  t.set("s.count", "1", "c.yaml");
  t.set("s.ratio", "1", "c.yaml");
  EXPECT_EQ(count, 1);
  EXPECT_EQ(ratio, 1.0);
  for (const auto& [key, value, expected] : {std::tuple<std::string, std::string, std::string>{"s.count", "0", ">= 1"},
                                             {"s.ratio", "1.5", "in [0, 1]"},
                                             {"s.sigma", "0", "> 0"}}) {
    try {
      t.set(key, value, "c.yaml");
      ADD_FAILURE() << key << " = " << value << " was accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + key + "'"), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  }
  EXPECT_EQ(count, 1);  // refused values leave the field as it was
  EXPECT_EQ(ratio, 1.0);
  EXPECT_EQ(sigma, 1.0);
}

TEST(OptionTable, SeedsAreWholeNumbersAtLeastZero) {
  uint64_t seed = 1;
  OptionTable t;
  t.bind("s.seed", &seed, "a seed");
  t.set("s.seed", "18446744073709551615", "c.yaml");
  EXPECT_EQ(seed, 18446744073709551615ull);
  EXPECT_THROW(t.set("s.seed", "-1", "c.yaml"), ConfigError);
  EXPECT_THROW(t.set("s.seed", "1.5", "c.yaml"), ConfigError);
  EXPECT_THROW(t.set("s.seed", "18446744073709551616", "c.yaml"), ConfigError);
}

TEST(OptionTable, ListKeysReadCommaSeparatedItemsAndWriteThemBack) {
  std::vector<std::string> classes{"chair"};
  OptionTable t;
  t.bindList("s.classes", &classes, "class names");
  t.apply(parseYamlSubset("s:\n  classes: \"potted plant , cup,,tv \"\n", "c.yaml"), "c.yaml");
  EXPECT_EQ(classes, (std::vector<std::string>{"potted plant", "cup", "tv"}));
  std::vector<std::string> read_back;
  OptionTable u;
  u.bindList("s.classes", &read_back, "class names");
  u.apply(parseYamlSubset(t.toYaml(), "effective.yaml"), "effective.yaml");
  EXPECT_EQ(read_back, classes);
}
