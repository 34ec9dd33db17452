#include "manyworlds/config/yaml.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

TEST(YamlTest, ScalarsKeepTheirTypes) {
  const auto j = ParseYaml(R"(
int: 42
neg: -7
hex: 0x1F
float: 0.5
exp: 1e-3
whole_float: 2.0
inf: -.inf
yes_bool: true
no_bool: False
nothing: null
tilde: ~
empty:
word: cartpole
quoted_int: "42"
single: 'true'
tagged: !!str 12
tagged_float: !!float 3
)");
  EXPECT_TRUE(j["int"].is_number_integer());
  EXPECT_EQ(j["int"], 42);
  EXPECT_EQ(j["neg"], -7);
  EXPECT_EQ(j["hex"], 31);
  EXPECT_TRUE(j["float"].is_number_float());
  EXPECT_DOUBLE_EQ(j["float"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["exp"].get<double>(), 1e-3);
  EXPECT_TRUE(j["whole_float"].is_number_float());
  EXPECT_TRUE(std::isinf(j["inf"].get<double>()));
  EXPECT_EQ(j["yes_bool"], true);
  EXPECT_EQ(j["no_bool"], false);
  EXPECT_TRUE(j["nothing"].is_null());
  EXPECT_TRUE(j["tilde"].is_null());
  EXPECT_TRUE(j["empty"].is_null());
  EXPECT_EQ(j["word"], "cartpole");
  EXPECT_EQ(j["quoted_int"], "42");
  EXPECT_EQ(j["single"], "true");
  EXPECT_EQ(j["tagged"], "12");
  EXPECT_TRUE(j["tagged_float"].is_number_float());
}

TEST(YamlTest, ListsAndMapsNest) {
  const auto j = ParseYaml("a:\n  b: [1, 2.5, x]\n  c:\n    - {d: 1}\n    - e\n");
  EXPECT_EQ(j, nlohmann::json::parse(R"({"a": {"b": [1, 2.5, "x"], "c": [{"d": 1}, "e"]}})"));
}

TEST(YamlTest, SyntaxErrorsNameSourceAndLine) {
  try {
    ParseYaml("a: 1\nb: [1, 2\nc: 3\n", "demo.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("demo.yaml:"), std::string::npos) << e.what();
  }
}

TEST(YamlTest, DuplicateKeysAreErrors) {
  try {
    ParseYaml("seed: 1\nepisodes: 2\nseed: 3\n", "x.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("x.yaml:3:1: duplicate key 'seed'"), std::string::npos)
        << e.what();
  }
}

TEST(YamlTest, HugeIntegersAreErrors) {
  EXPECT_THROW(ParseYaml("n: 123456789012345678901234567890"), ConfigError);
}

// What a hostile or broken file may hold fails as a ConfigError, never a
// crash: self-referencing aliases, alias bombs, scalars of 100,000 digits,
// nesting past 64 levels, bytes that are not UTF-8.
TEST(YamlTest, HostileInputIsAConfigErrorNotACrash) {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      ParseYaml(text);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("a: &x [1, *x]").find("deeper than 64"), std::string::npos);
  // NULs made yaml-cpp decode the text as UTF-16 (found by fuzz/yaml_fuzz.cc)
  EXPECT_NE(error_of(std::string("a\0\0nb: 1\n", 9)).find("NUL byte"), std::string::npos);
  // a key too long to be written back as an implicit key (fuzz/yaml_fuzz.cc)
  EXPECT_NE(error_of("'" + std::string(500, 'k') + "': 1").find("longer than 256"),
            std::string::npos);
  EXPECT_NE(error_of("\"a\\x02b\": 1").find("control character"), std::string::npos);
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'j'; ++c) {
    bomb += std::string(1, c) + ": &" + c + " [*" + char(c - 1) + ", *" + char(c - 1) + ", *" +
            char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) +
            ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" +
            char(c - 1) + "]\n";
  }
  EXPECT_NE(error_of(bomb).find("alias bomb"), std::string::npos);
  const std::string digits(100000, '1');
  const std::string huge = error_of("n: " + digits);
  EXPECT_NE(huge.find("out of range"), std::string::npos);
  EXPECT_LT(huge.size(), 200u) << "the message must not repeat the whole scalar";
  // a long scalar that is no number is a string, read without recursion
  EXPECT_EQ(ParseYaml("s: " + std::string(100000, 'a') + "1.5")["s"].get<std::string>().size(),
            100003u);
  EXPECT_EQ(ParseYaml("f: 1" + std::string(100000, '0') + ".5")["f"].is_string(), true);
  std::string deep = "x";
  for (int i = 0; i < 70; ++i) deep = "[" + deep + "]";
  EXPECT_NE(error_of("a: " + deep).find("deeper than 64"), std::string::npos);
  EXPECT_EQ(ParseYaml("a: [[[[1]]]]")["a"][0][0][0][0], 1);
  const std::string latin1 = error_of("name: caf\xe9\n");
  EXPECT_NE(latin1.find("UTF-8"), std::string::npos) << latin1;
  EXPECT_NE(error_of("name: \xed\xa0\x80\n").find("UTF-8"), std::string::npos);  // surrogate
  EXPECT_NE(error_of("name: \xc0\xaf\n").find("UTF-8"), std::string::npos);      // overlong
  EXPECT_NE(error_of("name: \xe2\x82").find("UTF-8"), std::string::npos);        // truncated
  EXPECT_EQ(ParseYaml("name: caf\xc3\xa9 \xf0\x9f\x98\x80")["name"], "caf\xc3\xa9 \xf0\x9f\x98\x80");
}

TEST(YamlTest, MissingFileIsAConfigError) {
  try {
    LoadYamlFile("/nonexistent/dir/x.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/x.yaml"), std::string::npos);
  }
}

TEST(YamlTest, DumpRoundTripsTypesAndAwkwardStrings) {
  const auto j = nlohmann::json::parse(R"({
    "episodes": 10, "lr": 0.0003, "whole": 1.0, "big": 1e20, "flag": true, "none": null,
    "envs": ["cartpole", "bandit"], "empty_list": [], "empty_map": {},
    "strings": ["true", "42", "123456789012345678901234567890", "0.5", "null", "", " lead",
                "a: b", "x # y", "-dash", "[x]",
                "multi\nline", "quote\"d", "ok/path.yaml", "with space"],
    "nested": {"list_of_maps": [{"a": 1, "b": {"c": [1, 2]}}, {"d": [[1], [2, 3]]}]},
    "1": "numeric key", "null": "null key"
  })");
  const std::string text = DumpYaml(j);
  EXPECT_EQ(ParseYaml(text), j) << text;
  EXPECT_NE(text.find("envs: [cartpole, bandit]\n"), std::string::npos) << text;
  EXPECT_NE(text.find("whole: 1.0\n"), std::string::npos) << text;
}

TEST(YamlTest, DumpOfScalarsAndEmptyTrees) {
  EXPECT_EQ(DumpYaml(nlohmann::json::object()), "{}\n");
  EXPECT_EQ(DumpYaml(3), "3\n");
  EXPECT_EQ(ParseYaml(DumpYaml("true")), "true");
}

TEST(YamlTest, LoadsAFile) {
  const auto path = std::filesystem::temp_directory_path() / "manyworlds_yaml_test.yaml";
  std::ofstream(path) << "seed: 3\nenvs: [a]\n";
  EXPECT_EQ(LoadYamlFile(path), nlohmann::json::parse(R"({"seed": 3, "envs": ["a"]})"));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace manyworlds
